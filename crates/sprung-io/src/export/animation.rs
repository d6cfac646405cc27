//! A run as one binary glTF animation (`animation.glb`, `--format gltf`),
//! which Blender's glTF importer plays and web viewers (three.js, Babylon,
//! `<model-viewer>`) show.
//!
//! Each body is a node with a mesh: a surface as triangles with smooth
//! normals, a rope, lattice or 2D body as lines along its springs and
//! rods, a body of loose particles as points. Its recorded frames are the
//! mesh's morph targets (their positions, and for surfaces their normals),
//! named `frame_00000k` (`extras.targetNames`, Blender's shape keys); one
//! animation drives the targets' weights: at frame `k`'s time target `k`
//! has weight 1 and the others 0, linearly in between, so the mesh passes
//! through every recorded state at its simulated time.
//!
//! - **Vertices** ([`super::tearing`]): a body that cannot tear has a
//!   vertex per particle, the first frame as its mesh and every later frame
//!   a target less the first. A body whose springs can break has its own
//!   vertices per face (or line), at the origin in the mesh and every frame
//!   a target as it is, a face gone (as the frame files leave it out) with
//!   its three corners at one point: the pieces part and the faces along a
//!   tear vanish at the frame they go in a player whose topology is fixed.
//! - **Long runs**: a mesh plays at most [`FRAMES_PER_MESH`] frames after
//!   its first. A longer run's body is a node with a child mesh node per
//!   span of frames (each span's last frame the next one's first, their
//!   accessors shared), shown by a step animation of its scale (1 during its
//!   span, 0 outside): an importer that keys every target at every time of
//!   its channel (Blender) does frames × [`FRAMES_PER_MESH`] keys, not
//!   frames², and a renderer holds a bounded number of targets a mesh.
//!
//! glTF stores single precision: positions come back to about 1e-7 of
//! their size (1e-6 m within 8 m of the origin), times to 1e-7 relative.
//! The weights are stored sparse (only the one weight of 1 per frame), so
//! a file grows linearly in its frames (see [`Animation::estimated_bytes`]).

use std::ops::Range;
use std::path::Path;

use sprung::surface::unit_vertex_normals;
use sprung::{Real, Vec3, World};

use super::glb::Builder;
use super::meshes::Nodes;
use super::tearing::{corner_positions, single, Drawn, Elements};
use super::AtomicFile;

/// Frames a mesh plays at most after its first (a longer run's body is
/// cut into spans of this many, see the module's documentation).
pub const FRAMES_PER_MESH: usize = 64;

/// Bytes of JSON a frame's morph target adds to the file, about, for a
/// surface (two accessors, their views, its names) and for lines or
/// points (one): measured 445 and 311 on the tear scene's 101 frames,
/// with room for the longer indices of longer runs.
const JSON_PER_TARGET: [u64; 2] = [480, 340];

/// One body's recorded motion.
#[derive(Debug)]
pub(super) struct Track {
    pub name: String,
    pub particles: Range<usize>,
    pub elements: Elements,
    /// The first frame's positions (m), for shared vertices (own vertices
    /// lie at the origin in the mesh: none kept).
    pub base: Vec<[f32; 3]>,
    /// The first frame's unit normals, by vertex (surfaces only).
    pub base_normals: Vec<[f32; 3]>,
    /// The positions of each frame that is a target (shared vertices: the
    /// frames after the first, less the first frame's; own vertices: every
    /// frame, as they are).
    pub moves: Vec<Vec<[f32; 3]>>,
    /// Those frames' normals less the first frame's (surfaces only; empty:
    /// all zero).
    pub normal_moves: Vec<Vec<[f32; 3]>>,
}

/// The frames of a run gathered for one glTF file.
#[derive(Debug)]
pub struct Animation {
    tracks: Vec<Track>,
    times: Vec<Real>,
}

impl Track {
    fn new(world: &World, body: &sprung::Body) -> Self {
        Track {
            name: body.name.clone(),
            particles: body.particles.clone(),
            elements: Elements::of(world, body),
            base: Vec::new(),
            base_normals: Vec::new(),
            moves: Vec::new(),
            normal_moves: Vec::new(),
        }
    }

    /// Whether the body is drawn as triangles (with normals).
    pub fn surface(&self) -> bool {
        self.elements.drawn == Drawn::Triangles
    }

    /// Whether the body has its own vertices per element (it can tear).
    pub fn own_vertices(&self) -> bool {
        self.elements.tearing.is_some()
    }

    /// The first frame that is a morph target: 0 for own vertices (the
    /// mesh is at the origin), 1 for shared (frame 0 is the mesh).
    pub fn first_target(&self) -> usize {
        usize::from(!self.own_vertices())
    }

    /// Record the body's state now; `normals` are the world's unit vertex
    /// normals (empty where no body is a surface).
    fn record(&mut self, world: &World, body: &sprung::Body, normals: &[Vec3], first: bool) {
        let here = &world.particles.position[self.particles.clone()];
        let normals: Vec<[f32; 3]> = if self.surface() {
            normals[self.particles.clone()]
                .iter()
                .map(|&n| single(n))
                .collect()
        } else {
            Vec::new()
        };
        let Some(tearing) = &self.elements.tearing else {
            self.record_shared(here, normals, first);
            return;
        };
        let present = tearing.present(world, body);
        let per_element = self.elements.per_element();
        let corners = &self.elements.corners;
        self.moves
            .push(corner_positions(corners, per_element, &present, here));
        if !self.surface() || first {
            // The first frame's normals are the mesh's (their move is 0);
            // lines have none.
            if self.surface() {
                self.base_normals = corners.iter().map(|&i| normals[i as usize]).collect();
            }
            self.normal_moves.push(Vec::new());
            return;
        }
        // A gone face's corners keep the first frame's normals (finite).
        let mut turned = Vec::with_capacity(corners.len());
        for (element, &there) in corners.chunks_exact(per_element).zip(&present) {
            for &i in element {
                let b = self.base_normals[turned.len()];
                let n = if there { normals[i as usize] } else { b };
                turned.push([n[0] - b[0], n[1] - b[1], n[2] - b[2]]);
            }
        }
        self.normal_moves.push(turned);
    }

    /// [`Track::record`] for shared vertices.
    fn record_shared(&mut self, here: &[Vec3], normals: Vec<[f32; 3]>, first: bool) {
        if first {
            self.base = here.iter().map(|&x| single(x)).collect();
            self.base_normals = normals;
            return;
        }
        // The move from the stored (single) base, taken in double.
        let moved = here
            .iter()
            .zip(&self.base)
            .map(|(x, b)| single(*x - Vec3::new(b[0].into(), b[1].into(), b[2].into())))
            .collect();
        self.moves.push(moved);
        let turned = normals
            .iter()
            .zip(&self.base_normals)
            .map(|(n, b)| [n[0] - b[0], n[1] - b[1], n[2] - b[2]])
            .collect();
        self.normal_moves.push(turned);
    }
}

impl Animation {
    /// An animation of `world`'s bodies, with no frame yet.
    pub fn new(world: &World) -> Self {
        let tracks = world.bodies.iter().map(|b| Track::new(world, b)).collect();
        Animation {
            tracks,
            times: Vec::new(),
        }
    }

    /// Bytes a run of `frames` recorded frames of `world` takes in memory
    /// and in the file, about: per vertex and frame its position, and for
    /// surfaces its normal, 12 bytes each (a vertex per particle for a body
    /// that cannot tear, a corner per face or line for one that can); per
    /// body and frame a time, a weight and its index, and the JSON of its
    /// morph target.
    pub fn estimated_bytes(world: &World, frames: u64) -> u64 {
        let per_frame: u64 = world
            .bodies
            .iter()
            .map(|body| {
                let elements = Elements::of(world, body);
                let vertices = elements.vertices(&body.particles) as u64;
                let surface = elements.drawn == Drawn::Triangles;
                let floats = if surface { 6 } else { 3 };
                4 * floats * vertices + 12 + JSON_PER_TARGET[usize::from(!surface)]
            })
            .sum();
        per_frame.saturating_mul(frames)
    }

    /// Record `world`'s current state as the next frame.
    pub fn record(&mut self, world: &World) {
        let position = &world.particles.position;
        let surfaces = self.tracks.iter().any(Track::surface);
        let normals = if surfaces {
            unit_vertex_normals(&super::all_faces(world), position)
        } else {
            Vec::new()
        };
        let first = self.times.is_empty();
        for (track, body) in self.tracks.iter_mut().zip(&world.bodies) {
            track.record(world, body, &normals, first);
        }
        self.times.push(world.time());
    }

    /// Frames recorded.
    pub fn frames(&self) -> usize {
        self.times.len()
    }

    /// The times in single precision, kept strictly increasing (as glTF
    /// asks of an animation's times) where two rows' times round to the
    /// same float.
    fn single_times(&self) -> Vec<f32> {
        let mut times: Vec<f32> = Vec::with_capacity(self.times.len());
        for &t in &self.times {
            let t = t as f32;
            times.push(match times.last() {
                Some(&before) if t <= before => before.next_up(),
                _ => t,
            });
        }
        times
    }

    /// The animation as the bytes of a `.glb` file.
    pub fn to_glb(&self) -> Result<Vec<u8>, String> {
        let mut file = Builder::default();
        let mut nodes = Nodes::new(&mut file, &self.single_times());
        let bodies = self.tracks.iter().filter_map(|t| nodes.body(&mut file, t));
        let bodies: Vec<_> = bodies.collect();
        nodes.finish(&mut file, bodies);
        file.finish()
    }

    /// Write the animation to `path`, atomically.
    pub fn write(&self, path: &Path) -> std::io::Result<()> {
        let bytes = self.to_glb().map_err(std::io::Error::other)?;
        AtomicFile::write(path, &bytes)
    }
}

#[cfg(test)]
mod tests {
    use sprung::{build, IntegratorKind, World};

    use super::Animation;

    /// The budget's estimate is the file's size, about: not below it, and
    /// within a fifth above it (the file's header, base mesh and indices
    /// are not counted; each frame's targets are), for a cloth that can
    /// tear (its own vertices per face) and one that cannot, beside a rope.
    #[test]
    fn the_estimate_is_the_size_of_the_file() {
        for break_strain in [None, Some(0.25)] {
            let mut world = World::new(IntegratorKind::SymplecticEuler);
            let mut cloth = build::cloth(8, 6, 1.0, 0.6, Default::default())
                .expect("a cloth")
                .with_stiffness(100.0);
            cloth.limits.break_strain = break_strain;
            world.add_body("cloth", cloth).expect("added");
            let rope = build::rope(5, 1.0).expect("a rope").with_stiffness(100.0);
            world.add_body("rope", rope).expect("added");
            let mut animation = Animation::new(&world);
            let frames = 300;
            // As a run asks it: before its first step.
            let estimate = Animation::estimated_bytes(&world, frames);
            for _ in 0..frames {
                animation.record(&world);
                world.step(1e-3).expect("a step");
            }
            let size = animation.to_glb().expect("a file").len() as u64;
            assert!(
                size <= estimate && estimate <= size + size / 5,
                "break strain {break_strain:?}: {size} bytes, estimated {estimate}"
            );
        }
    }
}
