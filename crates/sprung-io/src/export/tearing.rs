//! The vertices of a body in the glTF animation ([`super::Animation`]):
//! shared, one per particle, for a body that cannot tear; or its own per
//! element, for a body with springs that can break (`break_strain`), so
//! that its pieces part in players that keep a mesh's topology fixed
//! (glTF's morph targets), and an element gone (a face along a broken
//! spring, as the frame files leave it out; a broken spring drawn as a
//! line) collapses, all its corners at its centroid: a triangle of no
//! area, a line of no length, from the frame it went on.

use std::ops::Range;

use sprung::{Body, Vec3, World};

/// What a body is drawn as.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Drawn {
    /// Its faces, as triangles with normals.
    Triangles,
    /// Lines along its springs and rods (a body without faces).
    Lines,
    /// Points (a body of loose particles: no face, spring or rod).
    Points,
}

/// A body's elements as the animation draws them: its faces, or lines
/// along its springs and rods, at the start of the run.
#[derive(Debug)]
pub(super) struct Elements {
    /// What they are.
    pub drawn: Drawn,
    /// Their corners, local particle indices, one element after the other
    /// (3 a triangle, 2 a line; empty for points).
    pub corners: Vec<u32>,
    /// For a body that can tear, what tells which elements are still
    /// there; `None` for one that cannot (shared vertices).
    pub tearing: Option<Tearing>,
}

/// What tells which elements of a body that can tear are still there.
#[derive(Debug)]
pub(super) enum Tearing {
    /// The body's faces at the start (world indices), in order: faces only
    /// go, in order kept, so those left are a subsequence of these.
    Faces(Vec<[u32; 3]>),
    /// Per line the spring it draws; `None` for a rigid rod, which never
    /// breaks.
    Lines(Vec<Option<usize>>),
}

/// Whether any of `body`'s springs can break (has a break strain).
fn can_tear(world: &World, body: &Body) -> bool {
    body.springs
        .clone()
        .any(|s| world.limits.break_strain(s).is_finite())
}

impl Elements {
    /// `body`'s elements in `world` as it is now (at the first frame).
    pub fn of(world: &World, body: &Body) -> Self {
        let start = body.particles.start as u32;
        let tears = can_tear(world, body);
        if !body.faces.is_empty() {
            let corners = body.faces.iter().flatten().map(|&i| i - start).collect();
            return Elements {
                drawn: Drawn::Triangles,
                corners,
                tearing: tears.then(|| Tearing::Faces(body.faces.clone())),
            };
        }
        // Springs and rigid rods, as pairs of line ends.
        let rods = &world.rods;
        let lines: Vec<(Option<usize>, [u32; 2])> = body
            .springs_in_scene_order()
            .map(|s| (Some(s), world.springs.endpoints(s)))
            .chain(
                body.rods
                    .clone()
                    .map(|r| (None, [rods.first[r], rods.second[r]])),
            )
            .collect();
        let corners = lines.iter().flat_map(|(_, e)| *e).map(|i| i - start);
        Elements {
            drawn: if lines.is_empty() {
                Drawn::Points
            } else {
                Drawn::Lines
            },
            corners: corners.collect(),
            tearing: tears.then(|| Tearing::Lines(lines.iter().map(|&(s, _)| s).collect())),
        }
    }

    /// Corners an element has: 3 a triangle, 2 a line, 1 a point.
    pub fn per_element(&self) -> usize {
        match self.drawn {
            Drawn::Triangles => 3,
            Drawn::Lines => 2,
            Drawn::Points => 1,
        }
    }

    /// The vertices of the body in the file: a corner each where the body
    /// can tear, else a particle each.
    pub fn vertices(&self, particles: &Range<usize>) -> usize {
        match self.tearing {
            Some(_) => self.corners.len(),
            None => particles.len(),
        }
    }
}

impl Tearing {
    /// Per element, whether `body` still has it now.
    pub fn present(&self, world: &World, body: &Body) -> Vec<bool> {
        match self {
            Tearing::Faces(faces) => {
                let mut left = body.faces.iter().peekable();
                faces
                    .iter()
                    .map(|face| {
                        let here = left.peek() == Some(&face);
                        if here {
                            left.next();
                        }
                        here
                    })
                    .collect()
            }
            Tearing::Lines(springs) => springs
                .iter()
                .map(|s| s.is_none_or(|s| !world.springs.is_broken(s)))
                .collect(),
        }
    }
}

/// Each corner's position (m) in single precision: `corners` (local
/// indices into `here`, `per_element` an element) where the element is
/// `present`, else every corner of it at the element's centroid, so that
/// its corners are one point exactly.
pub(super) fn corner_positions(
    corners: &[u32],
    per_element: usize,
    present: &[bool],
    here: &[Vec3],
) -> Vec<[f32; 3]> {
    let mut out = Vec::with_capacity(corners.len());
    for (element, &there) in corners.chunks_exact(per_element).zip(present) {
        let at = |i: u32| here[i as usize];
        if there {
            out.extend(element.iter().map(|&i| single(at(i))));
        } else {
            let sum: Vec3 = element.iter().map(|&i| at(i)).sum();
            let centroid = single(sum / per_element as f64);
            out.extend(std::iter::repeat_n(centroid, per_element));
        }
    }
    out
}

/// A vector in single precision.
pub(super) fn single(v: Vec3) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

#[cfg(test)]
mod tests {
    use sprung::{build, IntegratorKind, World};

    use super::{corner_positions, single, Drawn, Elements};
    use crate::export::Animation;

    /// A rope whose springs can break has two vertices a spring; a broken
    /// spring's two ends are at its midpoint from then on (a line of no
    /// length, the `f32` of the midpoint both), the others at their
    /// particles; the animation records and writes it.
    #[test]
    fn a_broken_spring_is_a_line_of_no_length() {
        let mut world = World::new(IntegratorKind::SymplecticEuler);
        let mut rope = build::rope(4, 1.0).expect("a rope").with_stiffness(100.0);
        rope.limits.break_strain = Some(0.5);
        world.add_body("rope", rope).expect("added");
        let elements = Elements::of(&world, &world.bodies[0]);
        assert_eq!(elements.drawn, Drawn::Lines);
        let tearing = elements.tearing.as_ref().expect("the rope can break");
        let mut animation = Animation::new(&world);
        animation.record(&world);
        let first = world.bodies[0].springs_in_scene_order().next();
        world.springs.break_spring(first.expect("a spring"));
        animation.record(&world);
        let present = tearing.present(&world, &world.bodies[0]);
        let lines = elements.corners.len() / 2;
        assert_eq!(present.len(), lines);
        assert_eq!(present.iter().filter(|&&p| !p).count(), 1, "{present:?}");
        assert!(!present[0], "{present:?}");
        let position = &world.particles.position;
        let corners = corner_positions(&elements.corners, 2, &present, position);
        let [a, b] = [0, 1].map(|k| position[elements.corners[k] as usize]);
        assert_eq!([corners[0], corners[1]], [single((a + b) / 2.0); 2]);
        for (corner, &i) in corners.iter().zip(&elements.corners).skip(2) {
            assert_eq!(*corner, single(position[i as usize]));
        }
        assert!(animation.to_glb().is_ok());
    }
}
