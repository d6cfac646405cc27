//! The wind velocity over space and time: a uniform mean, optional gusts
//! (a smooth variation of its strength in time) and optional turbulence (a
//! smooth velocity field in space and time). Both variations are sums of a
//! few sinusoids whose frequencies, directions and phases come from a
//! seeded generator, so a run repeats exactly for the same seed.

use crate::error::BuildError;
use crate::units::{Real, Vec3};

/// Gusts: the mean wind's strength varies as `1 + amplitude · g(t)`, with
/// `g` a sum of three sinusoids of periods near `period`, scaled so that
/// `|g| ≤ 1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gusts {
    /// Relative strength of the gusts, in [0, 1].
    pub amplitude: Real,
    /// Typical gust period (s), positive.
    pub period: Real,
}

/// Turbulence: a smooth field of amplitude about `amplitude` (m/s) that
/// varies over `length_scale` (m) and `time_scale` (s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Turbulence {
    /// Typical speed of the fluctuations (m/s).
    pub amplitude: Real,
    /// Distance over which they change (m), positive.
    pub length_scale: Real,
    /// Time over which they change (s), positive.
    pub time_scale: Real,
}

/// Number of sinusoidal modes of the turbulent field.
const TURBULENT_MODES: usize = 8;

/// One sinusoid of the turbulent field: its share of the wind is
/// `scale · cos(k·x - ω t + φ) · direction` ([`WindField::turbulence_scale`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TurbulentMode {
    /// The unit direction it blows along.
    pub direction: Vec3,
    /// Its wave vector `k` (1/m).
    pub wave_vector: Vec3,
    /// Its angular frequency `ω` (rad/s).
    pub frequency: Real,
    /// Its phase `φ` (rad).
    pub phase: Real,
}

/// The wind velocity field.
#[derive(Debug, Clone, PartialEq)]
pub struct WindField {
    /// Mean wind velocity (m/s).
    pub velocity: Vec3,
    gusts: Option<(Gusts, [(Real, Real); 3])>,
    turbulence: Option<(Turbulence, Vec<TurbulentMode>)>,
}

impl WindField {
    /// A uniform, steady wind of `velocity` (m/s).
    pub fn uniform(velocity: Vec3) -> Self {
        WindField {
            velocity,
            gusts: None,
            turbulence: None,
        }
    }

    /// The same wind with `gusts` and `turbulence` (either may be `None`),
    /// their random frequencies and phases drawn from `seed`.
    pub fn varying(
        velocity: Vec3,
        gusts: Option<Gusts>,
        turbulence: Option<Turbulence>,
        seed: u64,
    ) -> Self {
        let mut random = SplitMix64(seed);
        let gusts = gusts.map(|g| {
            // Periods spread over [0.5, 1.5] × period, random phases.
            let modes = [0; 3].map(|_| {
                let period = g.period * (0.5 + random.unit());
                (
                    std::f64::consts::TAU / period,
                    std::f64::consts::TAU * random.unit(),
                )
            });
            (g, modes)
        });
        let turbulence = turbulence.map(|t| {
            let modes = (0..TURBULENT_MODES)
                .map(|_| TurbulentMode {
                    direction: random.direction(),
                    wave_vector: random.direction() * (0.5 + 1.5 * random.unit()) / t.length_scale,
                    frequency: (0.5 + random.unit()) / t.time_scale,
                    phase: std::f64::consts::TAU * random.unit(),
                })
                .collect();
            (t, modes)
        });
        WindField {
            velocity,
            gusts,
            turbulence,
        }
    }

    /// Wind velocity at position `x` (m) and time `t` (s), in m/s: the
    /// gusting mean ([`WindField::gusting_at`]) plus each turbulent mode.
    pub fn velocity_at(&self, x: Vec3, t: Real) -> Vec3 {
        let mut wind = self.gusting_at(t);
        let scale = self.turbulence_scale();
        for mode in self.turbulent_modes() {
            let angle = mode.wave_vector.dot(x) - mode.frequency * t + mode.phase;
            wind += scale * angle.cos() * mode.direction;
        }
        wind
    }

    /// The mean velocity scaled by the gusts at time `t` (s), in m/s: the
    /// wind everywhere but for the turbulence.
    pub fn gusting_at(&self, t: Real) -> Vec3 {
        let mut wind = self.velocity;
        if let Some((gusts, modes)) = &self.gusts {
            let g: Real = modes
                .iter()
                .map(|(omega, phase)| (omega * t + phase).sin())
                .sum::<Real>()
                / 3.0;
            wind *= 1.0 + gusts.amplitude * g;
        }
        wind
    }

    /// The turbulent modes (none without turbulence).
    pub fn turbulent_modes(&self) -> &[TurbulentMode] {
        self.turbulence.as_ref().map_or(&[], |(_, modes)| modes)
    }

    /// The amplitude of each turbulent mode (m/s): the turbulence's
    /// amplitude times `√(2 / modes)`, so that the modes' sum has the
    /// amplitude as its root-mean-square speed.
    pub fn turbulence_scale(&self) -> Real {
        self.turbulence.as_ref().map_or(0.0, |(t, _)| {
            t.amplitude * (2.0 / TURBULENT_MODES as Real).sqrt()
        })
    }

    /// Check the parameters: a finite mean; gust amplitude in [0, 1] and a
    /// positive period; turbulence amplitude not negative and positive
    /// scales.
    pub fn validate(&self) -> Result<(), BuildError> {
        let bad = |field: &'static str, value: Real, reason: &'static str| {
            Err(BuildError::OutOfRange {
                field,
                value,
                reason,
            })
        };
        if !self.velocity.is_finite() {
            return bad(
                "wind.velocity",
                self.velocity.length(),
                "must be finite (m/s)",
            );
        }
        if let Some((g, _)) = &self.gusts {
            if !(g.amplitude.is_finite() && (0.0..=1.0).contains(&g.amplitude)) {
                return bad("gust.amplitude", g.amplitude, "must be in [0, 1]");
            }
            if !(g.period.is_finite() && g.period > 0.0) {
                return bad("gust.period", g.period, "must be positive (s)");
            }
        }
        if let Some((t, _)) = &self.turbulence {
            if !(t.amplitude.is_finite() && t.amplitude >= 0.0) {
                return bad(
                    "turbulence.amplitude",
                    t.amplitude,
                    "must be finite and not negative (m/s)",
                );
            }
            for (field, value) in [
                ("turbulence.length_scale", t.length_scale),
                ("turbulence.time_scale", t.time_scale),
            ] {
                if !(value.is_finite() && value > 0.0) {
                    return bad(field, value, "must be positive");
                }
            }
        }
        Ok(())
    }

    /// True when the wind is the same everywhere at all times.
    pub fn is_uniform(&self) -> bool {
        self.gusts.is_none() && self.turbulence.is_none()
    }
}

/// SplitMix64: a tiny, well-known generator, enough to place sinusoids
/// reproducibly from a seed.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> Real {
        (self.next() >> 11) as Real / (1u64 << 53) as Real
    }

    /// A uniformly distributed unit vector.
    fn direction(&mut self) -> Vec3 {
        let z = 2.0 * self.unit() - 1.0;
        let angle = std::f64::consts::TAU * self.unit();
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * angle.cos(), r * angle.sin(), z)
    }
}
