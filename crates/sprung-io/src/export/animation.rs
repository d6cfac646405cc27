//! A run as one binary glTF animation (`animation.glb`, `--format gltf`),
//! which Blender's glTF importer plays and web viewers (three.js, Babylon,
//! `<model-viewer>`) show.
//!
//! Each body is a node with one mesh: a surface as triangles with smooth
//! normals, a rope, lattice or 2D body as lines along its springs and
//! rods, a body of loose particles as points. The
//! first recorded frame is the mesh; every later frame `k` is a morph
//! target (its positions, and for surfaces its normals, less the first
//! frame's), named `frame_00000k` (`extras.targetNames`, Blender's shape
//! keys). One animation drives the targets' weights: at frame `k`'s time
//! target `k` has weight 1 and the others 0, linearly in between, so the
//! mesh passes through every recorded state at its simulated time.
//!
//! glTF stores single precision: positions come back to about 1e-7 of
//! their size (1e-6 m within 8 m of the origin), times to 1e-7 relative.
//! The weights are stored sparse (only the one weight of 1 per frame), so
//! a file grows linearly in its frames (see [`Animation::estimated_bytes`]).

use std::ops::Range;
use std::path::Path;

use gltf::json::{self, validation::Checked::Valid, validation::USize64};
use sprung::surface::unit_vertex_normals;
use sprung::{Real, Vec3, World};

use super::AtomicFile;

/// One body's recorded motion.
#[derive(Debug)]
struct Track {
    name: String,
    particles: Range<usize>,
    /// Triangles, local indices (empty for a body drawn as lines).
    triangles: Vec<u32>,
    /// Lines along the springs, local indices (bodies without faces).
    lines: Vec<u32>,
    /// The first frame's positions (m) and unit normals.
    base: Vec<[f32; 3]>,
    base_normals: Vec<[f32; 3]>,
    /// Each later frame's positions and normals, less the first frame's.
    moves: Vec<Vec<[f32; 3]>>,
    normal_moves: Vec<Vec<[f32; 3]>>,
}

/// The frames of a run gathered for one glTF file.
#[derive(Debug)]
pub struct Animation {
    tracks: Vec<Track>,
    times: Vec<Real>,
}

fn single(v: Vec3) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

impl Animation {
    /// An animation of `world`'s bodies, with no frame yet.
    pub fn new(world: &World) -> Self {
        let springs = &world.springs;
        let tracks = world
            .bodies
            .iter()
            .map(|body| {
                let start = body.particles.start as u32;
                let triangles = body.faces.iter().flatten().map(|&i| i - start).collect();
                // Springs and rigid rods, as pairs of line ends.
                let rods = &world.rods;
                let lines = if body.faces.is_empty() {
                    body.springs_in_scene_order()
                        .flat_map(|s| springs.endpoints(s))
                        .chain(
                            body.rods
                                .clone()
                                .flat_map(|r| [rods.first[r], rods.second[r]]),
                        )
                        .map(|i| i - start)
                        .collect()
                } else {
                    Vec::new()
                };
                Track {
                    name: body.name.clone(),
                    particles: body.particles.clone(),
                    triangles,
                    lines,
                    base: Vec::new(),
                    base_normals: Vec::new(),
                    moves: Vec::new(),
                    normal_moves: Vec::new(),
                }
            })
            .collect();
        Animation {
            tracks,
            times: Vec::new(),
        }
    }

    /// Bytes a run of `frames` recorded frames of `world` takes in memory
    /// and in the file, about: positions and normals per particle and
    /// frame, and per body and frame a time, a weight and its index.
    pub fn estimated_bytes(world: &World, frames: u64) -> u64 {
        let per_frame = 24 * world.particles.len() as u64 + 12 * world.bodies.len() as u64;
        per_frame.saturating_mul(frames)
    }

    /// Record `world`'s current state as the next frame.
    pub fn record(&mut self, world: &World) {
        let position = &world.particles.position;
        let faces = super::all_faces(world);
        let all_normals = unit_vertex_normals(&faces, position);
        for track in &mut self.tracks {
            // Unit normals of a surface's particles.
            let normals: Vec<[f32; 3]> = if track.triangles.is_empty() {
                Vec::new()
            } else {
                all_normals[track.particles.clone()]
                    .iter()
                    .map(|&n| single(n))
                    .collect()
            };
            let here = &position[track.particles.clone()];
            if self.times.is_empty() {
                track.base = here.iter().map(|&x| single(x)).collect();
                track.base_normals = normals;
                continue;
            }
            // The move from the stored (single) base, taken in double.
            let moved = here
                .iter()
                .zip(&track.base)
                .map(|(x, b)| single(*x - Vec3::new(b[0].into(), b[1].into(), b[2].into())))
                .collect();
            track.moves.push(moved);
            let turned = normals
                .iter()
                .zip(&track.base_normals)
                .map(|(n, b)| [n[0] - b[0], n[1] - b[1], n[2] - b[2]])
                .collect();
            track.normal_moves.push(turned);
        }
        self.times.push(world.time());
    }

    /// Frames recorded.
    pub fn frames(&self) -> usize {
        self.times.len()
    }

    /// The animation as the bytes of a `.glb` file.
    pub fn to_glb(&self) -> Result<Vec<u8>, String> {
        let mut file = Builder::default();
        let frames = self.times.len();
        // Single precision, kept strictly increasing (as glTF asks of an
        // animation's times) where two rows' times round to the same float.
        let mut times: Vec<f32> = Vec::with_capacity(self.times.len());
        for &t in &self.times {
            let t = t as f32;
            times.push(match times.last() {
                Some(&before) if t <= before => before.next_up(),
                _ => t,
            });
        }
        let input = file.floats(&times, 1, json::accessor::Type::Scalar, None, true);
        let mut nodes = Vec::new();
        let mut animation = json::Animation {
            extensions: None,
            extras: None,
            channels: Vec::new(),
            name: Some("sprung".into()),
            samplers: Vec::new(),
        };
        // The two materials, each made when a body first uses it.
        let (mut surface, mut springs) = (None, None);
        for track in &self.tracks {
            let flat = |v: &[[f32; 3]]| v.iter().flatten().copied().collect::<Vec<f32>>();
            let vec3 = json::accessor::Type::Vec3;
            let target = Some(json::buffer::Target::ArrayBuffer);
            let mut attributes = std::collections::BTreeMap::new();
            attributes.insert(
                Valid(json::mesh::Semantic::Positions),
                file.floats(&flat(&track.base), 3, vec3, target, true),
            );
            let surface_body = !track.triangles.is_empty();
            if surface_body {
                attributes.insert(
                    Valid(json::mesh::Semantic::Normals),
                    file.floats(&flat(&track.base_normals), 3, vec3, target, false),
                );
            }
            let targets: Vec<json::mesh::MorphTarget> = track
                .moves
                .iter()
                .zip(&track.normal_moves)
                .map(|(moved, turned)| json::mesh::MorphTarget {
                    positions: Some(file.floats(&flat(moved), 3, vec3, target, true)),
                    normals: surface_body
                        .then(|| file.floats(&flat(turned), 3, vec3, target, false)),
                    tangents: None,
                })
                .collect();
            let (indices, mode, material) = if surface_body {
                let material = *surface.get_or_insert_with(|| {
                    file.root
                        .push(material("surface", [0.55, 0.72, 0.9, 1.0], true))
                });
                (&track.triangles, json::mesh::Mode::Triangles, material)
            } else {
                let material = *springs.get_or_insert_with(|| {
                    file.root
                        .push(material("springs", [0.25, 0.25, 0.3, 1.0], false))
                });
                // A body of loose particles (no springs, no rods): points.
                let mode = if track.lines.is_empty() {
                    json::mesh::Mode::Points
                } else {
                    json::mesh::Mode::Lines
                };
                (&track.lines, mode, material)
            };
            let indices = (!indices.is_empty()).then(|| file.indices(indices));
            let names: Vec<String> = (1..frames).map(|k| format!("\"frame_{k:06}\"")).collect();
            let extras = json::extras::RawValue::from_string(format!(
                "{{\"targetNames\":[{}]}}",
                names.join(",")
            ))
            .map_err(|e| e.to_string())?;
            let count = targets.len();
            let mesh = file.root.push(json::Mesh {
                extensions: None,
                extras: Some(extras),
                name: Some(track.name.clone()),
                primitives: vec![json::mesh::Primitive {
                    attributes,
                    extensions: None,
                    extras: None,
                    indices,
                    material: Some(material),
                    mode: Valid(mode),
                    targets: (count > 0).then_some(targets),
                }],
                weights: (count > 0).then(|| vec![0.0; count]),
            });
            let node = file.root.push(json::Node {
                mesh: Some(mesh),
                name: Some(track.name.clone()),
                ..Default::default()
            });
            nodes.push(node);
            if count > 0 {
                // Frame k (k ≥ 1) is target k − 1 at full weight, every
                // other weight 0: a sparse accessor of `frames × count`
                // zeros with the `frames − 1` ones stored (linear in the
                // frames, where the dense weights grow as their square).
                let ones: Vec<u32> = (1..frames).map(|k| (k * count + k - 1) as u32).collect();
                let output = file.sparse_floats(frames * count, &ones, &vec![1.0; ones.len()]);
                let sampler = json::animation::Sampler {
                    extensions: None,
                    extras: None,
                    input,
                    interpolation: Valid(json::animation::Interpolation::Linear),
                    output,
                };
                animation.samplers.push(sampler);
                animation.channels.push(json::animation::Channel {
                    sampler: json::Index::new(animation.samplers.len() as u32 - 1),
                    target: json::animation::Target {
                        extensions: None,
                        extras: None,
                        node,
                        path: Valid(json::animation::Property::MorphTargetWeights),
                    },
                    extensions: None,
                    extras: None,
                });
            }
        }
        if !animation.channels.is_empty() {
            file.root.push(animation);
        }
        let scene = file.root.push(json::Scene {
            extensions: None,
            extras: None,
            name: Some("sprung".into()),
            nodes,
        });
        file.root.scene = Some(scene);
        file.finish()
    }

    /// Write the animation to `path`, atomically.
    pub fn write(&self, path: &Path) -> std::io::Result<()> {
        let bytes = self.to_glb().map_err(std::io::Error::other)?;
        AtomicFile::write(path, &bytes)
    }
}

fn material(name: &str, colour: [f32; 4], double_sided: bool) -> json::Material {
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

/// The JSON model and its binary buffer, growing together.
#[derive(Default)]
struct Builder {
    root: json::Root,
    bin: Vec<u8>,
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

    /// An accessor of `values` in tuples of `components` floats; with
    /// `bounds`, their per-component minimum and maximum (which glTF asks
    /// of positions and animation times).
    fn floats(
        &mut self,
        values: &[f32],
        components: usize,
        kind: json::accessor::Type,
        target: Option<json::buffer::Target>,
        bounds: bool,
    ) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, target);
        let (min, max) = if bounds && !values.is_empty() {
            let mut min = vec![f32::INFINITY; components];
            let mut max = vec![f32::NEG_INFINITY; components];
            for tuple in values.chunks_exact(components) {
                for (k, &v) in tuple.iter().enumerate() {
                    min[k] = min[k].min(v);
                    max[k] = max[k].max(v);
                }
            }
            (Some(json::Value::from(min)), Some(json::Value::from(max)))
        } else {
            (None, None)
        };
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(values.len() / components),
            component_type: Valid(json::accessor::GenericComponentType(
                json::accessor::ComponentType::F32,
            )),
            extensions: None,
            extras: None,
            type_: Valid(kind),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// An accessor of `len` scalars, all zero but at `indices` (ascending),
    /// which hold `values`: a glTF sparse accessor with no view of its own.
    fn sparse_floats(
        &mut self,
        len: usize,
        indices: &[u32],
        values: &[f32],
    ) -> json::Index<json::Accessor> {
        let index_bytes: Vec<u8> = indices.iter().flat_map(|v| v.to_le_bytes()).collect();
        let value_bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let index_view = self.view(&index_bytes, None);
        let value_view = self.view(&value_bytes, None);
        let sparse = json::accessor::sparse::Sparse {
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
        };
        self.root.push(json::Accessor {
            buffer_view: None,
            byte_offset: None,
            count: USize64::from(len),
            component_type: Valid(json::accessor::GenericComponentType(
                json::accessor::ComponentType::F32,
            )),
            extensions: None,
            extras: None,
            type_: Valid(json::accessor::Type::Scalar),
            min: None,
            max: None,
            name: None,
            normalized: false,
            sparse: (!indices.is_empty()).then_some(sparse),
        })
    }

    /// An accessor of vertex indices.
    fn indices(&mut self, values: &[u32]) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, Some(json::buffer::Target::ElementArrayBuffer));
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(values.len()),
            component_type: Valid(json::accessor::GenericComponentType(
                json::accessor::ComponentType::U32,
            )),
            extensions: None,
            extras: None,
            type_: Valid(json::accessor::Type::Scalar),
            min: None,
            max: None,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// The `.glb` bytes: the JSON with its one buffer, and the buffer.
    fn finish(mut self) -> Result<Vec<u8>, String> {
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
