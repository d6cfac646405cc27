//! The glTF structure of the animation ([`super::Animation`]): the spans
//! of frames a body's meshes play, the accessors their channels read, what
//! every mesh of a body shares (attributes, indices, material, a morph
//! target per frame), the animation's channels, and the nodes of the
//! bodies.

use std::ops::Range;

use gltf::json::{self, validation::Checked::Valid};

use super::animation::{Track, FRAMES_PER_MESH};
use super::glb::{material, Builder};
use super::tearing::Drawn;

/// The frames each mesh of a body plays, for `frames` recorded frames:
/// one span of them all when they fit a mesh, else spans of
/// [`FRAMES_PER_MESH`] frames after their first, each span's last frame
/// the next one's first.
fn spans(frames: usize) -> Vec<Range<usize>> {
    if frames <= FRAMES_PER_MESH + 1 {
        return std::iter::once(0..frames).collect();
    }
    (0..frames - 1)
        .step_by(FRAMES_PER_MESH)
        .map(|start| start..(start + FRAMES_PER_MESH + 1).min(frames))
        .collect()
}

/// The accessors a span's channels read, shared by every body: its
/// frames' times, and where there are several spans, the keys and values
/// of its scale (shown during its span, hidden outside).
struct Clock {
    times: json::Index<json::Accessor>,
    scale: Option<(json::Index<json::Accessor>, json::Index<json::Accessor>)>,
}

impl Clock {
    fn new(file: &mut Builder, times: &[f32], spans: &[Range<usize>], span: usize) -> Self {
        let scalar = json::accessor::Type::Scalar;
        let range = spans[span].clone();
        let own = file.floats(&times[range.clone()], scalar, None, true);
        let scale = (spans.len() > 1).then(|| {
            // Step keys: hidden from the start, shown from its first frame,
            // hidden again from its last (the next span's first).
            let mut keys = vec![(times[0], 0.0)];
            keys.push((times[range.start], 1.0));
            if span + 1 < spans.len() {
                keys.push((times[range.end - 1], 0.0));
            }
            if span == 0 {
                keys.remove(0);
            }
            let at: Vec<f32> = keys.iter().map(|k| k.0).collect();
            let scales: Vec<f32> = keys.iter().flat_map(|k| [k.1; 3]).collect();
            let at = file.floats(&at, scalar, None, true);
            let scales = file.floats(&scales, json::accessor::Type::Vec3, None, false);
            (at, scales)
        });
        Clock { times: own, scale }
    }
}

/// What every mesh of one body shares: its attributes, indices, material
/// and mode, and a morph target per frame from [`Track::first_target`] on.
struct Geometry {
    attributes: std::collections::BTreeMap<
        json::validation::Checked<json::mesh::Semantic>,
        json::Index<json::Accessor>,
    >,
    indices: Option<json::Index<json::Accessor>>,
    mode: json::mesh::Mode,
    material: json::Index<json::Material>,
    targets: Vec<json::mesh::MorphTarget>,
    first_target: usize,
}

/// The two materials of the file, each made when a body first uses it.
#[derive(Default)]
struct Materials {
    surface: Option<json::Index<json::Material>>,
    springs: Option<json::Index<json::Material>>,
}

impl Geometry {
    fn of(file: &mut Builder, track: &Track, materials: &mut Materials) -> Self {
        let flat = |v: &[[f32; 3]]| v.iter().flatten().copied().collect::<Vec<f32>>();
        let vec3 = json::accessor::Type::Vec3;
        let target = Some(json::buffer::Target::ArrayBuffer);
        let vertices = track.elements.vertices(&track.particles);
        let mut attributes = std::collections::BTreeMap::new();
        let positions = if track.own_vertices() {
            file.zeros(vertices, vec3, true)
        } else {
            file.floats(&flat(&track.base), vec3, target, true)
        };
        attributes.insert(Valid(json::mesh::Semantic::Positions), positions);
        let surface = track.surface();
        if surface {
            attributes.insert(
                Valid(json::mesh::Semantic::Normals),
                file.floats(&flat(&track.base_normals), vec3, target, false),
            );
        }
        let turned = |file: &mut Builder, turned: &[[f32; 3]]| {
            if turned.is_empty() {
                file.zeros(vertices, vec3, false)
            } else {
                file.floats(&flat(turned), vec3, target, false)
            }
        };
        let targets = track
            .moves
            .iter()
            .zip(&track.normal_moves)
            .map(|(moved, normals)| json::mesh::MorphTarget {
                positions: Some(file.floats(&flat(moved), vec3, target, true)),
                normals: surface.then(|| turned(file, normals)),
                tangents: None,
            })
            .collect();
        let (mode, material) = match track.elements.drawn {
            Drawn::Triangles => (
                json::mesh::Mode::Triangles,
                *materials.surface.get_or_insert_with(|| {
                    file.root
                        .push(material("surface", [0.55, 0.72, 0.9, 1.0], true))
                }),
            ),
            drawn => (
                if drawn == Drawn::Lines {
                    json::mesh::Mode::Lines
                } else {
                    json::mesh::Mode::Points
                },
                *materials.springs.get_or_insert_with(|| {
                    file.root
                        .push(material("springs", [0.25, 0.25, 0.3, 1.0], false))
                }),
            ),
        };
        // Own vertices are drawn in order (no indices).
        let corners = &track.elements.corners;
        let indices = (!track.own_vertices() && !corners.is_empty()).then(|| file.indices(corners));
        Geometry {
            attributes,
            indices,
            mode,
            material,
            targets,
            first_target: track.first_target(),
        }
    }

    /// The targets of the frames `span`: the frames, and the first's index.
    fn targets_of(&self, span: &Range<usize>) -> Range<usize> {
        span.start.max(self.first_target)..span.end.max(self.first_target)
    }

    /// The mesh of the frames `span`, named `name`: the first's target at
    /// full weight by default (the shared vertices' mesh is frame 0).
    fn mesh(&self, file: &mut Builder, name: &str, span: &Range<usize>) -> json::Index<json::Mesh> {
        let frames = self.targets_of(span);
        let targets: Vec<json::mesh::MorphTarget> = frames
            .clone()
            .map(|f| self.targets[f - self.first_target].clone())
            .collect();
        let names: Vec<String> = frames
            .clone()
            .map(|k| format!("\"frame_{k:06}\""))
            .collect();
        let extras = format!("{{\"targetNames\":[{}]}}", names.join(","));
        let mut weights = vec![0.0; targets.len()];
        if frames.start == span.start && !weights.is_empty() {
            weights[0] = 1.0;
        }
        let count = targets.len();
        file.root.push(json::Mesh {
            extensions: None,
            extras: json::extras::RawValue::from_string(extras).ok(),
            name: Some(name.to_string()),
            primitives: vec![json::mesh::Primitive {
                attributes: self.attributes.clone(),
                extensions: None,
                extras: None,
                indices: self.indices,
                material: Some(self.material),
                mode: Valid(self.mode),
                targets: (count > 0).then_some(targets),
            }],
            weights: (count > 0).then_some(weights),
        })
    }

    /// The weights of the mesh of frames `span` at each of their times:
    /// frame `k`'s target 1 at frame `k`'s time, every other 0 (a sparse
    /// accessor of keys × targets zeros with a one a key stored).
    fn weights(&self, file: &mut Builder, span: &Range<usize>) -> json::Index<json::Accessor> {
        let frames = self.targets_of(span);
        let count = frames.len();
        let ones: Vec<u32> = frames
            .clone()
            .map(|f| ((f - span.start) * count + f - frames.start) as u32)
            .collect();
        file.sparse_floats(span.len() * count, &ones, &vec![1.0; ones.len()])
    }
}

/// The animation's channels, with their samplers.
struct Channels(json::Animation);

impl Channels {
    fn new() -> Self {
        Channels(json::Animation {
            extensions: None,
            extras: None,
            channels: Vec::new(),
            name: Some("sprung".into()),
            samplers: Vec::new(),
        })
    }

    /// Drive `property` of `node` by `output` at the times `input`.
    fn add(
        &mut self,
        node: json::Index<json::Node>,
        property: json::animation::Property,
        (input, output): (json::Index<json::Accessor>, json::Index<json::Accessor>),
        interpolation: json::animation::Interpolation,
    ) {
        self.0.samplers.push(json::animation::Sampler {
            extensions: None,
            extras: None,
            input,
            interpolation: Valid(interpolation),
            output,
        });
        self.0.channels.push(json::animation::Channel {
            sampler: json::Index::new(self.0.samplers.len() as u32 - 1),
            target: json::animation::Target {
                extensions: None,
                extras: None,
                node,
                path: Valid(property),
            },
            extensions: None,
            extras: None,
        });
    }
}

/// The nodes of a file being built, body by body: the spans of frames,
/// their clocks, the materials and the animation's channels they share.
pub(super) struct Nodes {
    spans: Vec<Range<usize>>,
    clocks: Vec<Clock>,
    channels: Channels,
    materials: Materials,
}

impl Nodes {
    /// The nodes of an animation of frames at `times` (s, increasing).
    pub fn new(file: &mut Builder, times: &[f32]) -> Self {
        // No frame recorded (a run that stopped before its first): no node.
        let spans = if times.is_empty() {
            Vec::new()
        } else {
            spans(times.len())
        };
        let clocks = (0..spans.len())
            .map(|s| Clock::new(file, times, &spans, s))
            .collect();
        Nodes {
            spans,
            clocks,
            channels: Channels::new(),
            materials: Materials::default(),
        }
    }

    /// The node of `track`'s body: the mesh node of its one span, or a
    /// node over a mesh node a span (named `BODY frames FIRST-LAST`, every
    /// one but the first hidden when the animation is not played), each
    /// with its channels; `None` with no frame.
    pub fn body(&mut self, file: &mut Builder, track: &Track) -> Option<json::Index<json::Node>> {
        if self.spans.is_empty() {
            return None;
        }
        let geometry = Geometry::of(file, track, &mut self.materials);
        let mut children = Vec::new();
        for (s, (span, clock)) in self.spans.iter().zip(&self.clocks).enumerate() {
            let name = if self.spans.len() == 1 {
                track.name.clone()
            } else {
                format!("{} frames {}-{}", track.name, span.start, span.end - 1)
            };
            let mesh = geometry.mesh(file, &name, span);
            let node = file.root.push(json::Node {
                mesh: Some(mesh),
                name: Some(name),
                scale: (s > 0).then_some([0.0; 3]),
                ..Default::default()
            });
            children.push(node);
            if !geometry.targets_of(span).is_empty() {
                let weights = geometry.weights(file, span);
                self.channels.add(
                    node,
                    json::animation::Property::MorphTargetWeights,
                    (clock.times, weights),
                    json::animation::Interpolation::Linear,
                );
            }
            if let Some(scale) = clock.scale {
                self.channels.add(
                    node,
                    json::animation::Property::Scale,
                    scale,
                    json::animation::Interpolation::Step,
                );
            }
        }
        Some(if children.len() == 1 {
            children[0]
        } else {
            file.root.push(json::Node {
                name: Some(track.name.clone()),
                children: Some(children),
                ..Default::default()
            })
        })
    }

    /// Put the animation (if anything moves) and the scene of the bodies'
    /// `nodes` into the file.
    pub fn finish(self, file: &mut Builder, nodes: Vec<json::Index<json::Node>>) {
        if !self.channels.0.channels.is_empty() {
            file.root.push(self.channels.0);
        }
        let scene = file.root.push(json::Scene {
            extensions: None,
            extras: None,
            name: Some("sprung".into()),
            nodes,
        });
        file.root.scene = Some(scene);
    }
}
