//! What one picture shows: the particle positions of a moment
//! ([`Snapshot`]) and what joins them ([`Model`]: springs with their rest
//! lengths, faces, closed 2D outlines, pinned particles), taken from a
//! running [`World`] or read back from a VTK frame.

use std::collections::BTreeMap;
use std::sync::Arc;

use sprung::{Real, Shape, Vec3, World};
use sprung_io::export::{CellKind, VtkFrame};

/// The topology drawn: shared by every snapshot of a run that keeps it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Model {
    /// Springs as pairs of particle indices.
    pub springs: Vec<[u32; 2]>,
    /// Rest length of each spring (m); NaN where unknown (drawn grey).
    pub rest_length: Vec<Real>,
    /// Triangles (particle indices, counter-clockwise seen from outside).
    pub faces: Vec<[u32; 3]>,
    /// Closed 2D outlines (particle indices in order around the loop),
    /// filled faintly under the springs.
    pub outlines: Vec<Vec<u32>>,
    /// Whether each particle is pinned (`inverse_mass == 0`).
    pub pinned: Vec<bool>,
    /// Rigid rods as pairs of particle indices (drawn thick and dark).
    pub rods: Vec<[u32; 2]>,
    /// Per spring, the phase (rad) of its muscle, NaN for a plain spring
    /// (muscles are coloured by phase); empty when unknown.
    pub muscle_phase: Vec<Real>,
}

/// One moment of a run, ready to draw.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// Simulated time (s), when known.
    pub time: Option<Real>,
    /// Particle positions (m).
    pub position: Vec<Vec3>,
    /// Springs, faces and pins.
    pub model: Arc<Model>,
    /// The colliders' shapes at this moment (planes drawn as a faint floor,
    /// spheres as grey balls); empty for frames read from files.
    pub colliders: Vec<Shape>,
}

impl Model {
    /// The springs, faces, 2D outlines and pins of `world`.
    pub fn of_world(world: &World) -> Self {
        let springs = &world.springs;
        let mut outlines = Vec::new();
        for body in world.bodies.iter().filter(|b| b.closed && b.is_planar()) {
            outlines.extend(chain_loops(&body.segments));
        }
        // In the scene's order, as the frames list them: the whole
        // springs of the bodies; the joins' springs are drawn as rods.
        let (join_springs, _) = world.join_links();
        let mut order = world.springs_in_scene_order();
        order.retain(|&s| !springs.is_broken(s) && !join_springs.contains(&s));
        let join_lines = (0..world.joins.len())
            .filter(|&j| !world.join_broken(j))
            .filter_map(|j| match world.joins[j].link {
                sprung::tearing::JoinLink::Spring(_) => Some(world.joins[j].particles),
                sprung::tearing::JoinLink::Rod(_) => None,
            });
        let phase = muscle_phases(world);
        Model {
            springs: order.iter().map(|&s| springs.endpoints(s)).collect(),
            rest_length: order.iter().map(|&s| springs.rest_length[s]).collect(),
            faces: world
                .bodies
                .iter()
                .flat_map(|b| b.faces.iter().copied())
                .collect(),
            outlines,
            pinned: (0..world.particles.len())
                .map(|i| world.particles.is_pinned(i))
                .collect(),
            rods: (0..world.rods.len())
                .map(|r| [world.rods.first[r], world.rods.second[r]])
                .chain(join_lines)
                .collect(),
            muscle_phase: if phase.is_empty() {
                phase
            } else {
                order.iter().map(|&s| phase[s]).collect()
            },
        }
    }

    /// The model of a VTK frame: `LINES` as springs (a polyline as one
    /// spring per piece), the `rest_length` cell scalars if present (else
    /// NaN), `POLYGONS` as triangle fans, the lines of `kind` segment (or
    /// flagged by the `outline` cell scalars of older frames) chained into
    /// 2D loops, lines of `kind` rod (or flagged by `rod`) as rods, and the
    /// `pinned` point scalars.
    pub fn from_vtk(frame: &VtkFrame) -> Self {
        let rest = frame.line_scalars("rest_length");
        let outline = frame.line_scalars("outline");
        let rod = frame.line_scalars("rod");
        // sprung's unstructured grids say what each cell is.
        let kind = frame.line_scalars("kind");
        let is = |cell: usize, wanted: CellKind| {
            kind.is_some_and(|k| CellKind::from_value(k[cell]) == Some(wanted))
        };
        let mut rods = Vec::new();
        let mut springs = Vec::with_capacity(frame.lines.len());
        let mut rest_length = Vec::with_capacity(frame.lines.len());
        let mut outline_edges = Vec::new();
        for (cell, line) in frame.lines.iter().enumerate() {
            let single = line.len() == 2;
            if single
                && (is(cell, CellKind::Rod)
                    || is(cell, CellKind::Join)
                    || rod.is_some_and(|r| r[cell] != 0.0))
            {
                rods.push([line[0], line[1]]);
                continue;
            }
            if single && is(cell, CellKind::Segment) {
                outline_edges.push([line[0], line[1]]);
                continue;
            }
            for pair in line.windows(2) {
                springs.push([pair[0], pair[1]]);
                let length = rest.filter(|_| single).map_or(Real::NAN, |r| r[cell]);
                rest_length.push(length);
            }
            if single && outline.is_some_and(|o| o[cell] != 0.0) {
                outline_edges.push([line[0], line[1]]);
            }
        }
        let mut faces = Vec::new();
        for polygon in frame.polygons.iter().filter(|p| p.len() >= 3) {
            for k in 1..polygon.len() - 1 {
                faces.push([polygon[0], polygon[k], polygon[k + 1]]);
            }
        }
        let pinned = match frame.point_scalars("pinned") {
            Some(values) => values.iter().map(|&v| v != 0.0).collect(),
            None => vec![false; frame.points.len()],
        };
        Model {
            springs,
            rest_length,
            faces,
            outlines: chain_loops(&outline_edges),
            pinned,
            rods,
            muscle_phase: Vec::new(),
        }
    }
}

impl Snapshot {
    /// The current state of `world`, drawn with `model` (from
    /// [`Model::of_world`] on the same world).
    pub fn of_world(world: &World, model: &Arc<Model>) -> Self {
        let time = world.time();
        Snapshot {
            time: Some(time),
            position: world.particles.position.clone(),
            model: Arc::clone(model),
            colliders: world.colliders.iter().map(|c| c.shape_at(time)).collect(),
        }
    }

    /// A VTK frame; `previous` is reused when the frame's model equals it,
    /// so a run's snapshots share one model.
    pub fn from_vtk(frame: &VtkFrame, previous: Option<&Arc<Model>>) -> Self {
        let model = Model::from_vtk(frame);
        let model = match previous {
            Some(shared) if **shared == model => Arc::clone(shared),
            _ => Arc::new(model),
        };
        Snapshot {
            time: frame.time,
            position: frame.points.clone(),
            model,
            colliders: Vec::new(),
        }
    }
}

/// Per spring of `world`, its muscle's phase (rad; 0 for a muscle driven
/// by a function), NaN for a plain spring; empty without muscles.
fn muscle_phases(world: &World) -> Vec<Real> {
    if world.muscles.list.is_empty() {
        return Vec::new();
    }
    let mut phase = vec![Real::NAN; world.springs.len()];
    for muscle in &world.muscles.list {
        phase[muscle.spring] = muscle.phase();
    }
    phase
}

/// Chain undirected edges into closed loops of particle indices. Edges
/// that do not close a loop (a dangling chain) are left out; the result
/// does not depend on the order of equal edges.
pub fn chain_loops(edges: &[[u32; 2]]) -> Vec<Vec<u32>> {
    let mut neighbours: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
    for &[a, b] in edges.iter().filter(|[a, b]| a != b) {
        neighbours.entry(a).or_default().push(b);
        neighbours.entry(b).or_default().push(a);
    }
    let mut used: BTreeMap<(u32, u32), bool> = edges
        .iter()
        .map(|&[a, b]| ((a.min(b), a.max(b)), false))
        .collect();
    let mut loops = Vec::new();
    let starts: Vec<u32> = neighbours.keys().copied().collect();
    for start in starts {
        let mut path = vec![start];
        let mut current = start;
        loop {
            let next = neighbours.get(&current).and_then(|n| {
                n.iter()
                    .copied()
                    .find(|&m| used.get(&(current.min(m), current.max(m))) == Some(&false))
            });
            let Some(next) = next else { break };
            used.insert((current.min(next), current.max(next)), true);
            if next == start {
                if path.len() >= 3 {
                    loops.push(std::mem::take(&mut path));
                }
                break;
            }
            path.push(next);
            current = next;
        }
    }
    loops
}
