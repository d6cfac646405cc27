//! The GPU step's floating-point type, f32 or f64 (where the adapter has
//! `SHADER_F64`), and the bytes of the kernels' data in it: the kernels
//! are one WGSL source over an alias `real`, and every host value is kept
//! in f64 until it is written for the GPU.

/// The floating-point type of the state and the arithmetic on the GPU.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub enum Precision {
    /// f32: every GPU has it, and it is the fastest (the default).
    #[default]
    F32,
    /// f64, as the engine: on adapters with wgpu's `SHADER_F64` (Vulkan's
    /// `shaderFloat64`: most desktop GPUs, lavapipe; not WebGPU).
    F64,
}

impl Precision {
    /// Bytes of one value.
    pub fn size(self) -> usize {
        match self {
            Precision::F32 => 4,
            Precision::F64 => 8,
        }
    }

    /// Its name: `f32` or `f64`.
    pub fn name(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
        }
    }

    /// What the kernels' source is prefixed with: the alias `real`, a test
    /// for a coordinate that is not finite, and the cosine.
    pub(crate) fn prelude(self) -> &'static str {
        match self {
            Precision::F32 => PRELUDE_F32,
            Precision::F64 => PRELUDE_F64,
        }
    }

    /// `values` in this precision, native-endian as the GPU reads them.
    pub(crate) fn bytes(self, values: &[f64]) -> Vec<u8> {
        let mut bytes = Vec::with_capacity(values.len() * self.size());
        self.extend(&mut bytes, values);
        bytes
    }

    /// Append `values` in this precision to `bytes`.
    pub(crate) fn extend(self, bytes: &mut Vec<u8>, values: &[f64]) {
        match self {
            Precision::F32 => {
                for &v in values {
                    bytes.extend_from_slice(&(v as f32).to_ne_bytes());
                }
            }
            Precision::F64 => {
                for &v in values {
                    bytes.extend_from_slice(&v.to_ne_bytes());
                }
            }
        }
    }

    /// The values in `bytes` (written in this precision), widened to f64.
    pub(crate) fn read(self, bytes: &[u8]) -> Vec<f64> {
        match self {
            Precision::F32 => bytes
                .chunks_exact(4)
                .map(|b| f64::from(f32::from_ne_bytes([b[0], b[1], b[2], b[3]])))
                .collect(),
            Precision::F64 => bytes
                .chunks_exact(8)
                .map(|b| f64::from_ne_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]))
                .collect(),
        }
    }
}

impl std::fmt::Display for Precision {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// f32: a coordinate is not finite when its exponent's bits are all set
/// (a comparison may be folded away by the shader compiler).
const PRELUDE_F32: &str = "alias real = f32;

fn not_finite(v: vec3<real>) -> bool {
    let bits = bitcast<vec3<u32>>(v) & vec3<u32>(0x7f800000u);
    return any(bits == vec3<u32>(0x7f800000u));
}

fn cosine(x: real) -> real {
    return cos(x);
}
";

/// f64: WGSL has no bit casts of 64-bit words, so a coordinate is tested
/// narrowed to f32, where NaN and infinity stay so (and a coordinate past
/// 3.4·10³⁸ m or m/s counts as blown up too, far past any `max_distance`
/// a scene sets); SPIR-V's standard functions have no f64 cosine, so one
/// reduced to [0, π/2] and summed as its Taylor series to x²⁰ (the
/// remainder (π/2)²²/22! ≈ 2·10⁻¹⁷, below f64's rounding).
const PRELUDE_F64: &str = "alias real = f64;

fn not_finite(v: vec3<real>) -> bool {
    let bits = bitcast<vec3<u32>>(vec3<f32>(v)) & vec3<u32>(0x7f800000u);
    return any(bits == vec3<u32>(0x7f800000u));
}

fn cosine(x: real) -> real {
    let tau: real = 6.283185307179586;
    let pi: real = 3.141592653589793;
    var y = abs(x - tau * round(x / tau));
    var sign: real = 1.0;
    if y > 0.5 * pi {
        y = pi - y;
        sign = -1.0;
    }
    let y2 = y * y;
    var term: real = 1.0;
    var sum: real = 1.0;
    for (var k = 1; k <= 10; k++) {
        let n = real(2 * k);
        term *= -y2 / ((n - 1.0) * n);
        sum += term;
    }
    return sign * sum;
}
";
