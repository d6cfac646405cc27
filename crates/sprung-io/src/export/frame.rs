//! One frame as an unstructured grid: what the VTK writers (legacy `.vtk`
//! and XML `.vtu`) both write, built once from the world.
//!
//! - **Points**: the particles, with point data `velocity` (m/s), `pinned`
//!   (1 or 0) and `body` (the index of the particle's body, in the order
//!   of the scene; the names are in the series file).
//! - **Cells**, in this order: springs (lines, in the scene's order:
//!   body by body, each body's as its scene lists them, then the joins'
//!   springs; broken ones left out), rigid rods (lines, the joins' after the
//!   bodies'), the segments of 2D bodies (lines), the triangles of surfaces
//!   (those along a broken spring gone); cell data `kind` ([`CellKind`]: 0
//!   spring, 1 rod, 2 segment, 3 triangle, 4 join),
//!   `body`, `rest_length` (m; 0 where the cell is neither a spring nor a
//!   rod) and `strain` (`(d − L0) / L0`; for a segment or triangle, the
//!   mean strain of the springs along its edges, 0 where it has none), so
//!   a surface coloured by strain shows how stretched it is.
//! - **Field data**: `TIME` (s).

use std::collections::HashMap;

use sprung::{Real, World};

/// What a cell of a frame is (the `kind` cell array).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum CellKind {
    /// A spring: a line of two particles.
    Spring = 0,
    /// A rigid rod: a line of two particles.
    Rod = 1,
    /// A segment of a 2D body's outline: a line of two particles.
    Segment = 2,
    /// A triangle of a surface, counter-clockwise seen from outside.
    Triangle = 3,
    /// A join between bodies (a spring or a rod): a line of two particles.
    Join = 4,
}

impl CellKind {
    /// The kind numbered `value` in the `kind` array, if any.
    pub fn from_value(value: Real) -> Option<Self> {
        [
            CellKind::Spring,
            CellKind::Rod,
            CellKind::Segment,
            CellKind::Triangle,
            CellKind::Join,
        ]
        .into_iter()
        .find(|&k| k as u8 as Real == value)
    }
}

/// VTK's cell type numbers for a line and a triangle.
pub(crate) const VTK_LINE: u8 = 3;
/// See [`VTK_LINE`].
pub(crate) const VTK_TRIANGLE: u8 = 5;

/// A frame's cells and data, ready to be written.
#[derive(Debug, Default)]
pub(crate) struct Frame {
    /// Point indices of every cell, one after the other.
    pub connectivity: Vec<u32>,
    /// Where each cell's indices end in `connectivity`.
    pub offsets: Vec<u32>,
    /// VTK cell type of each cell.
    pub types: Vec<u8>,
    /// [`CellKind`] of each cell.
    pub kind: Vec<u8>,
    /// Body index of each cell.
    pub cell_body: Vec<i32>,
    /// Rest length of each cell (m).
    pub rest_length: Vec<Real>,
    /// Strain of each cell.
    pub strain: Vec<Real>,
    /// Body index of each point.
    pub point_body: Vec<i32>,
    /// 1 for a pinned point, else 0.
    pub pinned: Vec<u8>,
}

impl Frame {
    /// The frame of `world`'s current state.
    pub fn of(world: &World) -> Self {
        let mut frame = Frame::default();
        let position = &world.particles.position;
        let springs = &world.springs;
        let rods = &world.rods;
        let length = |a: u32, b: u32| position[a as usize].distance(position[b as usize]);
        let mut point_body = vec![-1; position.len()];
        for (index, body) in world.bodies.iter().enumerate() {
            point_body[body.particles.clone()].fill(index as i32);
        }
        let body_of = |particle: u32| point_body[particle as usize];
        // Strain by undirected edge, for the segments and triangles.
        let mut edge_strain: HashMap<(u32, u32), Real> = HashMap::new();
        let (join_springs, join_rods) = world.join_links();
        for s in world.springs_in_scene_order() {
            if springs.is_broken(s) {
                continue;
            }
            let [a, b] = springs.endpoints(s);
            let rest = springs.rest_length[s];
            let strain = (length(a, b) - rest) / rest;
            let kind = if join_springs.contains(&s) {
                CellKind::Join
            } else {
                edge_strain.insert((a.min(b), a.max(b)), strain);
                CellKind::Spring
            };
            frame.push(&[a, b], kind, body_of(a), rest, strain);
        }
        for r in 0..rods.len() {
            let (a, b, rest) = (rods.first[r], rods.second[r], rods.length[r]);
            let strain = (length(a, b) - rest) / rest;
            let kind = if join_rods.contains(&r) {
                CellKind::Join
            } else {
                CellKind::Rod
            };
            frame.push(&[a, b], kind, body_of(a), rest, strain);
        }
        let mean_strain = |corners: &[u32]| {
            let n = corners.len();
            let (sum, count) = (0..n)
                .filter_map(|k| {
                    let (a, b) = (corners[k], corners[(k + 1) % n]);
                    edge_strain.get(&(a.min(b), a.max(b)))
                })
                .fold((0.0, 0), |(sum, count), &s| (sum + s, count + 1));
            if count == 0 {
                0.0
            } else {
                sum / Real::from(count)
            }
        };
        for body in &world.bodies {
            for segment in &body.segments {
                let strain = mean_strain(segment);
                frame.push(segment, CellKind::Segment, body_of(segment[0]), 0.0, strain);
            }
        }
        for body in &world.bodies {
            for face in &body.faces {
                let strain = mean_strain(face);
                frame.push(face, CellKind::Triangle, body_of(face[0]), 0.0, strain);
            }
        }
        frame.pinned = (0..position.len())
            .map(|i| u8::from(world.particles.is_pinned(i)))
            .collect();
        frame.point_body = point_body;
        frame
    }

    fn push(&mut self, nodes: &[u32], kind: CellKind, body: i32, rest: Real, strain: Real) {
        self.connectivity.extend_from_slice(nodes);
        self.offsets.push(self.connectivity.len() as u32);
        self.types.push(if nodes.len() == 3 {
            VTK_TRIANGLE
        } else {
            VTK_LINE
        });
        self.kind.push(kind as u8);
        self.cell_body.push(body);
        self.rest_length.push(rest);
        self.strain.push(strain);
    }

    /// Number of cells.
    pub fn cells(&self) -> usize {
        self.types.len()
    }
}
