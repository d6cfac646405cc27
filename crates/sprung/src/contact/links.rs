//! Which particles of a self-colliding body are too near each other in the
//! mesh to collide: a particle does not collide with an element of its own
//! body that holds one of them.
//!
//! Two particles are near when a spring joins them, or a path along the
//! body's springs with a total rest length of at most the *exclusion
//! radius*, twice the contact thickness plus the body's longest edge.
//! Without it, a flat sheet
//! at rest would find its own neighbours within the contact's reach: those
//! joined by a spring are kept at their distance by the spring already,
//! and once the thickness reaches the particle spacing, particles a few
//! springs apart would push each other along the sheet, fighting its
//! springs (and every particle would pair with every triangle around it).
//! The radius is about the thickness, so a fold whose layers come within
//! the thickness of each other is still caught away from its crease, which
//! the bending springs hold. A particle has at most [`MOST_NEAR`] near
//! particles (the nearest): a thickness of many particle spacings leaves
//! the farther ones of its radius colliding.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashSet};

use crate::body::{Body, BodyContact};
use crate::springs::Springs;
use crate::units::Real;

/// Most particles near one particle: a thickness so large that the
/// radius covers more stops there (the nearest ones are left out), so the
/// lists cannot grow as the square of a body's particles.
const MOST_NEAR: usize = 256;

/// Per particle of a self-colliding body, the particles near it in the
/// mesh (sorted), in compressed rows.
#[derive(Debug, Clone, Default)]
pub(super) struct Links {
    start: Vec<usize>,
    list: Vec<u32>,
    /// What they were built from: the springs' topology, the particles,
    /// the bodies' flags, the contact thickness (m), and the rest lengths
    /// of the self-colliding bodies' springs (their bits, folded), which
    /// muscles change.
    built_for: Option<(u64, usize, Vec<BodyContact>, Real, u64)>,
}

/// The bits of the rest lengths of the self-colliding bodies' springs,
/// folded into one number (FNV-1a).
fn rest_lengths_key(bodies: &[Body], springs: &Springs) -> u64 {
    bodies
        .iter()
        .filter(|b| b.contact.collide && b.contact.self_collision)
        .flat_map(|b| springs.rest_length[b.springs.clone()].iter())
        .fold(0xcbf2_9ce4_8422_2325, |key, length| {
            (key ^ length.to_bits()).wrapping_mul(0x0000_0100_0000_01b3)
        })
}

impl Links {
    /// Rebuild from the springs of the self-colliding bodies for a contact
    /// `thickness` (m), unless those are what they were built from.
    pub(super) fn build(
        &mut self,
        bodies: &[Body],
        springs: &Springs,
        particles: usize,
        thickness: Real,
    ) {
        let rest = rest_lengths_key(bodies, springs);
        let unchanged =
            self.built_for
                .as_ref()
                .is_some_and(|(topology, count, flags, h, lengths)| {
                    *topology == springs.topology()
                        && *count == particles
                        && *h == thickness
                        && *lengths == rest
                        && flags.iter().eq(bodies.iter().map(|b| &b.contact))
                });
        if unchanged {
            return;
        }
        self.built_for = Some((
            springs.topology(),
            particles,
            bodies.iter().map(|b| b.contact).collect(),
            thickness,
            rest,
        ));
        self.start.clear();
        self.start.resize(particles + 1, 0);
        self.list.clear();
        let mut graph = Graph::default();
        let mut search = Nearest::default();
        for body in bodies {
            if !(body.contact.collide && body.contact.self_collision) {
                continue;
            }
            graph.build(body, springs);
            let radius = 2.0 * thickness + longest_edge(body, springs);
            for local in 0..body.particles.len() {
                let from = self.list.len();
                let global = |near: u32| (body.particles.start + near as usize) as u32;
                search.within(&graph, local as u32, radius, |near| {
                    self.list.push(global(near));
                });
                let joined = graph.neighbours(local as u32).iter();
                self.list.extend(joined.map(|&(near, _)| global(near)));
                self.list[from..].sort_unstable();
                let kept = dedup_sorted(&mut self.list[from..]);
                self.list.truncate(from + kept);
                self.start[body.particles.start + local + 1] = self.list.len() - from;
            }
        }
        for i in 0..particles {
            self.start[i + 1] += self.start[i];
        }
    }

    /// Whether particles `a` and `b` are the same or near in the mesh.
    pub(super) fn linked(&self, a: u32, b: u32) -> bool {
        a == b
            || self.start.get(a as usize + 1).is_some_and(|&end| {
                self.list[self.start[a as usize]..end]
                    .binary_search(&b)
                    .is_ok()
            })
    }
}

/// Move the distinct values of the sorted `values` to its front; returns
/// how many there are.
fn dedup_sorted(values: &mut [u32]) -> usize {
    let mut kept = 0;
    for i in 0..values.len() {
        if kept == 0 || values[i] != values[kept - 1] {
            values[kept] = values[i];
            kept += 1;
        }
    }
    kept
}

/// The longest rest length (m) of a spring along an edge of the body's
/// surface (a segment in 2D); the longest of its springs if none is.
fn longest_edge(body: &Body, springs: &Springs) -> Real {
    let key = |i: u32, j: u32| (i.min(j), i.max(j));
    let edges: HashSet<(u32, u32)> = body
        .edges
        .iter()
        .chain(&body.segments)
        .map(|&[i, j]| key(i, j))
        .collect();
    let (first, second) = (springs.first(), springs.second());
    let along = body
        .springs
        .clone()
        .filter(|&s| edges.contains(&key(first[s], second[s])))
        .map(|s| springs.rest_length[s])
        .fold(0.0, Real::max);
    if along > 0.0 {
        along
    } else {
        body.springs
            .clone()
            .map(|s| springs.rest_length[s])
            .fold(0.0, Real::max)
    }
}

/// A body's springs as a graph over its particles (local indices), with
/// their rest lengths (m), in compressed rows.
#[derive(Debug, Default)]
struct Graph {
    start: Vec<u32>,
    to: Vec<(u32, Real)>,
}

impl Graph {
    fn build(&mut self, body: &Body, springs: &Springs) {
        let n = body.particles.len();
        let base = body.particles.start as u32;
        let inside = |i: u32| body.particles.contains(&(i as usize));
        let (first, second) = (springs.first(), springs.second());
        let ends = || {
            body.springs
                .clone()
                .filter(move |&s| inside(first[s]) && inside(second[s]) && !springs.is_broken(s))
                // Lengths that are not positive (or not numbers) count as
                // zero, so the search never goes round a shortening loop.
                .map(move |s| {
                    let rest = springs.rest_length[s];
                    let rest = if rest > 0.0 { rest } else { 0.0 };
                    (first[s] - base, second[s] - base, rest)
                })
        };
        self.start.clear();
        self.start.resize(n + 1, 0);
        for (i, j, _) in ends() {
            self.start[i as usize + 1] += 1;
            self.start[j as usize + 1] += 1;
        }
        for i in 0..n {
            self.start[i + 1] += self.start[i];
        }
        self.to.clear();
        self.to.resize(self.start[n] as usize, (0, 0.0));
        let mut fill = self.start.clone();
        for (i, j, rest) in ends() {
            for (a, b) in [(i, j), (j, i)] {
                self.to[fill[a as usize] as usize] = (b, rest);
                fill[a as usize] += 1;
            }
        }
    }

    fn neighbours(&self, i: u32) -> &[(u32, Real)] {
        &self.to[self.start[i as usize] as usize..self.start[i as usize + 1] as usize]
    }
}

/// Dijkstra's search from one particle, limited to a radius, with buffers
/// kept from one search to the next.
#[derive(Debug, Default)]
struct Nearest {
    /// Per particle, the search that last reached it (plus one) and its
    /// distance then (m).
    reached: Vec<(u32, Real)>,
    heap: BinaryHeap<Reverse<(u64, u32)>>,
    searches: u32,
}

impl Nearest {
    /// Call `near` with every particle other than `from` within `radius`
    /// (m) of it along the graph's springs, nearest first, and at most
    /// [`MOST_NEAR`] of them.
    fn within(&mut self, graph: &Graph, from: u32, radius: Real, mut near: impl FnMut(u32)) {
        let n = graph.start.len().saturating_sub(1);
        if self.reached.len() != n {
            self.reached.clear();
            self.reached.resize(n, (0, 0.0));
            self.searches = 0;
        }
        self.searches += 1;
        let stamp = self.searches;
        // Distances are not negative, so their bits order as they do.
        let key = |d: Real| d.to_bits();
        self.heap.clear();
        self.reached[from as usize] = (stamp, 0.0);
        self.heap.push(Reverse((key(0.0), from)));
        let mut found = 0;
        while let Some(Reverse((bits, i))) = self.heap.pop() {
            let distance = Real::from_bits(bits);
            if distance > self.reached[i as usize].1 {
                continue;
            }
            if i != from {
                if found == MOST_NEAR {
                    break;
                }
                near(i);
                found += 1;
            }
            for &(j, rest) in graph.neighbours(i) {
                let through = distance + rest;
                let (seen, best) = self.reached[j as usize];
                if through <= radius && (seen != stamp || through < best) {
                    self.reached[j as usize] = (stamp, through);
                    self.heap.push(Reverse((key(through), j)));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::build::{self, ClothSprings};
    use crate::{integrate::IntegratorKind, units::Vec3, world::World};

    /// A flat cloth of `n × n` particles over 1 m, colliding with itself.
    fn cloth(n: usize) -> World {
        let mut cloth = build::cloth(n, n, 1.0, 1.0, ClothSprings::default()).unwrap();
        cloth.contact.self_collision = true;
        let mut world = World::new(IntegratorKind::SymplecticEuler);
        world.add_body("cloth", cloth).unwrap();
        world
    }

    #[test]
    fn a_cloth_cut_in_two_links_no_particle_across_the_cut() {
        // 11 × 11 particles 0.1 m apart, cut between columns 4 and 5 by
        // breaking every spring across: particles on either side of the
        // cut were linked (joined by a spring, or near along them) and are
        // not any more, so the pieces collide; those on one side still are.
        let mut world = cloth(11);
        let n = world.particles.len();
        let mut links = Links::default();
        links.build(&world.bodies, &world.springs, n, 0.01);
        let column = |p: u32| p % 11;
        assert!(links.linked(4, 5) && links.linked(15, 5));
        let across: Vec<usize> = (0..world.springs.len())
            .filter(|&s| {
                let [a, b] = world.springs.endpoints(s);
                column(a).min(column(b)) <= 4 && column(a).max(column(b)) >= 5
            })
            .collect();
        across.iter().for_each(|&s| world.springs.break_spring(s));
        links.build(&world.bodies, &world.springs, n, 0.01);
        for a in 0..n as u32 {
            for b in 0..n as u32 {
                if a != b && (column(a) <= 4) != (column(b) <= 4) {
                    assert!(!links.linked(a, b), "{a} and {b} across the cut");
                }
            }
        }
        assert!(links.linked(4, 3) && links.linked(5, 6));
    }

    #[test]
    fn near_particles_are_those_joined_or_within_the_radius_of_a_flat_sheet() {
        // 11 × 11 particles 0.1 m apart: structural springs 0.1 m, shear
        // 0.141 m (the longest edge), bending 0.2 m.
        let world = cloth(11);
        let spacing = 0.1;
        let position = &world.particles.position;
        for thickness in [0.01, 0.05, 0.12] {
            let mut links = Links::default();
            links.build(&world.bodies, &world.springs, position.len(), thickness);
            let radius = 2.0 * thickness + spacing * Real::sqrt(2.0);
            let centre = 5 * 11 + 5;
            for other in 0..position.len() as u32 {
                // On a flat sheet the shortest path along structural,
                // shear and bending springs is within 9% of the straight
                // line (a knight's move: 0.1 + 0.141 against 0.224), so
                // particles clearly inside or outside the radius are
                // classified as the straight line says.
                let distance = position[centre].distance(position[other as usize]);
                let near = links.linked(centre as u32, other);
                let springs = &world.springs;
                let joined = (0..springs.len()).any(|s| {
                    let ends = [springs.first()[s], springs.second()[s]];
                    ends.contains(&(centre as u32)) && ends.contains(&other)
                });
                if joined {
                    assert!(near, "h {thickness}: {other} is joined by a spring");
                    continue;
                }
                if distance <= radius * 0.9 {
                    assert!(near, "h {thickness}: {other} at {distance} m is near");
                }
                if distance > radius * 1.001 {
                    assert!(!near, "h {thickness}: {other} at {distance} m is far");
                }
            }
        }
    }

    #[test]
    fn a_huge_thickness_keeps_the_lists_short_and_rest_lengths_rebuild_them() {
        let mut world = cloth(41);
        let n = world.particles.len();
        let mut links = Links::default();
        links.build(&world.bodies, &world.springs, n, 100.0);
        // Each particle: its MOST_NEAR nearest, plus those joined by a
        // spring (12 at most in the builder's cloth).
        for i in 0..n {
            assert!(links.start[i + 1] - links.start[i] <= MOST_NEAR + 12);
        }
        // A changed rest length (a muscle's) is seen: the lists are built
        // again from the new lengths (springs a third as long, against the
        // same thickness: more particles within the radius).
        links.build(&world.bodies, &world.springs, n, 0.01);
        let near = |links: &Links| links.list.len();
        let before = near(&links);
        for rest in &mut world.springs.rest_length {
            *rest /= 3.0;
        }
        links.build(&world.bodies, &world.springs, n, 0.01);
        assert!(near(&links) > before);
    }

    #[test]
    fn a_thick_contact_leaves_a_flat_sheet_at_rest() {
        // Thickness 2.5 times the particle spacing: without the exclusion
        // radius, neighbours a few springs apart push each other along
        // the sheet. At rest and weightless it must stay exactly at rest.
        let mut world = cloth(21);
        world.set_gravity(Vec3::ZERO);
        world.contacts.settings.thickness = 0.125;
        let start = world.particles.position.clone();
        for _ in 0..50 {
            world.step(1e-3).unwrap();
        }
        assert_eq!(world.active_contacts(), 0);
        assert_eq!(world.particles.position, start);
    }
}
