//! A binary glTF file (`.glb`) being built: its JSON model and its one
//! binary buffer growing together, with the accessors the animation
//! ([`super::Animation`]) writes: floats with their bounds, zeros (one
//! view of zeros a size, shared), sparse scalars and vertex indices.

use gltf::json::{self, validation::Checked::Valid, validation::USize64};

/// The JSON model and its binary buffer, growing together.
#[derive(Default)]
pub(super) struct Builder {
    /// The JSON model.
    pub root: json::Root,
    bin: Vec<u8>,
    /// Views of zeros already written, by their length in bytes.
    zero_views: std::collections::HashMap<usize, json::Index<json::buffer::View>>,
}

/// A material of `colour` (linear RGBA), not metallic, rough.
pub(super) fn material(name: &str, colour: [f32; 4], double_sided: bool) -> json::Material {
    json::Material {
        name: Some(name.into()),
        double_sided,
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor(colour),
            metallic_factor: json::material::StrengthFactor(0.0),
            roughness_factor: json::material::StrengthFactor(0.8),
            ..Default::default()
        },
        ..Default::default()
    }
}

/// The accessor fields every accessor here shares: `count` elements of
/// `kind` in `component`s, without view, bounds or sparse storage.
fn accessor(
    count: usize,
    component: json::accessor::ComponentType,
    kind: json::accessor::Type,
) -> json::Accessor {
    json::Accessor {
        buffer_view: None,
        byte_offset: None,
        count: USize64::from(count),
        component_type: Valid(json::accessor::GenericComponentType(component)),
        extensions: None,
        extras: None,
        type_: Valid(kind),
        min: None,
        max: None,
        name: None,
        normalized: false,
        sparse: None,
    }
}

/// The number of floats in an element of `kind`.
fn components(kind: json::accessor::Type) -> usize {
    match kind {
        json::accessor::Type::Scalar => 1,
        json::accessor::Type::Vec2 => 2,
        json::accessor::Type::Vec3 => 3,
        json::accessor::Type::Vec4 | json::accessor::Type::Mat2 => 4,
        json::accessor::Type::Mat3 => 9,
        json::accessor::Type::Mat4 => 16,
    }
}

impl Builder {
    /// A view of `bytes` appended to the buffer (aligned to 4 bytes).
    fn view(
        &mut self,
        bytes: &[u8],
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::buffer::View> {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: target.map(Valid),
            extensions: None,
            extras: None,
        })
    }

    /// An accessor of `values` in elements of `kind`; with `bounds`, their
    /// per-component minimum and maximum (which glTF asks of positions and
    /// animation times).
    pub fn floats(
        &mut self,
        values: &[f32],
        kind: json::accessor::Type,
        target: Option<json::buffer::Target>,
        bounds: bool,
    ) -> json::Index<json::Accessor> {
        let components = components(kind);
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, target);
        let mut accessor = accessor(
            values.len() / components,
            json::accessor::ComponentType::F32,
            kind,
        );
        accessor.buffer_view = Some(view);
        if bounds && !values.is_empty() {
            let mut min = vec![f32::INFINITY; components];
            let mut max = vec![f32::NEG_INFINITY; components];
            for tuple in values.chunks_exact(components) {
                for (k, &v) in tuple.iter().enumerate() {
                    min[k] = min[k].min(v);
                    max[k] = max[k].max(v);
                }
            }
            accessor.min = Some(json::Value::from(min));
            accessor.max = Some(json::Value::from(max));
        }
        self.root.push(accessor)
    }

    /// An accessor of `count` elements of `kind`, all zero; with `bounds`,
    /// its minimum and maximum (zeros). Accessors of zeros of one size
    /// share a view. (glTF reads an accessor without a view as zeros, but
    /// some readers, the `gltf` crate among them, refuse one.)
    pub fn zeros(
        &mut self,
        count: usize,
        kind: json::accessor::Type,
        bounds: bool,
    ) -> json::Index<json::Accessor> {
        let length = 4 * count * components(kind);
        let view = match self.zero_views.get(&length) {
            Some(&view) => view,
            None => {
                let target = Some(json::buffer::Target::ArrayBuffer);
                let view = self.view(&vec![0; length], target);
                *self.zero_views.entry(length).or_insert(view)
            }
        };
        let mut accessor = accessor(count, json::accessor::ComponentType::F32, kind);
        accessor.buffer_view = Some(view);
        if bounds {
            let zero = vec![0.0f32; components(kind)];
            accessor.min = Some(json::Value::from(zero.clone()));
            accessor.max = Some(json::Value::from(zero));
        }
        self.root.push(accessor)
    }

    /// An accessor of `len` scalars, all zero but at `indices` (ascending),
    /// which hold `values`: a glTF sparse accessor with no view of its own.
    pub fn sparse_floats(
        &mut self,
        len: usize,
        indices: &[u32],
        values: &[f32],
    ) -> json::Index<json::Accessor> {
        let mut accessor = accessor(
            len,
            json::accessor::ComponentType::F32,
            json::accessor::Type::Scalar,
        );
        if indices.is_empty() {
            return self.root.push(accessor);
        }
        let index_bytes: Vec<u8> = indices.iter().flat_map(|v| v.to_le_bytes()).collect();
        let value_bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let index_view = self.view(&index_bytes, None);
        let value_view = self.view(&value_bytes, None);
        accessor.sparse = Some(json::accessor::sparse::Sparse {
            count: USize64::from(indices.len()),
            indices: json::accessor::sparse::Indices {
                buffer_view: index_view,
                byte_offset: USize64(0),
                component_type: Valid(json::accessor::IndexComponentType(
                    json::accessor::ComponentType::U32,
                )),
                extensions: None,
                extras: Default::default(),
            },
            values: json::accessor::sparse::Values {
                buffer_view: value_view,
                byte_offset: USize64(0),
                extensions: None,
                extras: Default::default(),
            },
            extensions: None,
            extras: Default::default(),
        });
        self.root.push(accessor)
    }

    /// An accessor of vertex indices.
    pub fn indices(&mut self, values: &[u32]) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, Some(json::buffer::Target::ElementArrayBuffer));
        let mut accessor = accessor(
            values.len(),
            json::accessor::ComponentType::U32,
            json::accessor::Type::Scalar,
        );
        accessor.buffer_view = Some(view);
        self.root.push(accessor)
    }

    /// The `.glb` bytes: the JSON with its one buffer, and the buffer.
    pub fn finish(mut self) -> Result<Vec<u8>, String> {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        if self.bin.len() as u64 > u32::MAX as u64 / 2 {
            return Err(format!(
                "the animation would take {} bytes, more than a .glb file holds; record fewer frames (--every)",
                self.bin.len()
            ));
        }
        self.root.push(json::Buffer {
            byte_length: USize64::from(self.bin.len()),
            name: None,
            uri: None,
            extensions: None,
            extras: None,
        });
        self.root.asset = json::Asset {
            generator: Some(format!("sprung {}", env!("CARGO_PKG_VERSION"))),
            ..Default::default()
        };
        let json = self.root.to_vec().map_err(|e| e.to_string())?;
        let glb = gltf::binary::Glb {
            header: gltf::binary::Header {
                magic: *b"glTF",
                version: 2,
                length: 0,
            },
            json: json.into(),
            bin: Some(self.bin.into()),
        };
        glb.to_vec().map_err(|e| e.to_string())
    }
}
