//! The faces of the bodies (triangles, 2D segments) as the forces that
//! add into their vertices (gas pressure, wind) take them: a short list in
//! its stored order, a long one in blocks for the threads.

use std::ops::AddAssign;

use crate::body::Body;
use crate::parallel::{self, Schedule, ScheduleCache, Writer, CHUNK};

/// Per body (by index), its faces and segments in blocks
/// ([`Schedule`]), made again when a body's surface changes; kept only for
/// surfaces of more than [`CHUNK`] elements.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Surfaces {
    bodies: Vec<(ScheduleCache<3>, ScheduleCache<2>)>,
}

/// A body's surface elements (`W` particles each) as a force adds them.
pub enum Surface<'a, const W: usize> {
    /// At most [`CHUNK`] elements: one thread takes them in their stored
    /// order (a schedule would run them on one thread too, and checking
    /// whether it still fits the body's list each step would cost as much
    /// as the force), adding into entries that start at particle `first`.
    InOrder {
        /// The elements.
        members: &'a [[u32; W]],
        /// The particle of the first entry added into.
        first: usize,
    },
    /// More: in the blocks of the schedule.
    Scheduled(&'a Schedule<W>),
}

impl<const W: usize> Surface<'_, W> {
    /// Call `f(element, writer)` for every element; the writer adds into
    /// `out` at the element's particles (see [`Schedule::scatter`]). Each
    /// particle receives its contributions in an order fixed by the
    /// elements, whatever the number of threads.
    #[inline(always)]
    pub fn scatter<T: Send + Copy + AddAssign>(
        &self,
        out: &mut [T],
        f: impl Fn(usize, &Writer<'_, T, W>) + Sync,
    ) {
        match self {
            Surface::InOrder { members, first } => {
                parallel::scatter_in_order(members, out, *first, f);
            }
            Surface::Scheduled(schedule) => schedule.scatter(out, f),
        }
    }
}

/// The surface of a body that encloses something: its segments in 2D, its
/// faces otherwise.
pub enum BodySurface<'a> {
    /// A 2D loop.
    Segments(Surface<'a, 2>),
    /// Triangles.
    Faces(Surface<'a, 3>),
}

/// Whether a force can add `body`'s surface into the body's own entries
/// alone, on a thread of its own ([`own_surface`]): at most [`CHUNK`]
/// elements, naming the body's particles only (the builders' and meshes'
/// bodies always do; a list changed by hand may not).
pub fn on_its_own(body: &Body) -> bool {
    let own = |p: &u32| body.particles.contains(&(*p as usize));
    if body.is_planar() {
        body.segments.len() <= CHUNK && body.segments.iter().flatten().all(own)
    } else {
        body.faces.len() <= CHUNK && body.faces.iter().flatten().all(own)
    }
}

/// `body`'s surface in its stored order, adding into the body's own
/// entries (`out[body.particles]`); for bodies [`on_its_own`].
pub fn own_surface(body: &Body) -> BodySurface<'_> {
    let first = body.particles.start;
    if body.is_planar() {
        BodySurface::Segments(Surface::InOrder {
            members: &body.segments,
            first,
        })
    } else {
        BodySurface::Faces(Surface::InOrder {
            members: &body.faces,
            first,
        })
    }
}

impl Surfaces {
    fn of(&mut self, index: usize) -> &mut (ScheduleCache<3>, ScheduleCache<2>) {
        if self.bodies.len() <= index {
            self.bodies.resize(index + 1, Default::default());
        }
        &mut self.bodies[index]
    }

    /// The triangles of body `index` (`body`), among `particles` particles,
    /// adding into entries of all of them.
    pub fn faces<'a>(
        &'a mut self,
        index: usize,
        body: &'a Body,
        particles: usize,
    ) -> Surface<'a, 3> {
        world_wide(&mut self.of(index).0, &body.faces, particles)
    }

    /// The segments of body `index` (`body`), among `particles` particles,
    /// adding into entries of all of them.
    pub fn segments<'a>(
        &'a mut self,
        index: usize,
        body: &'a Body,
        particles: usize,
    ) -> Surface<'a, 2> {
        world_wide(&mut self.of(index).1, &body.segments, particles)
    }

    /// The enclosing surface of body `index` ([`BodySurface`]), among
    /// `particles` particles, adding into entries of all of them.
    pub fn surface<'a>(
        &'a mut self,
        index: usize,
        body: &'a Body,
        particles: usize,
    ) -> BodySurface<'a> {
        if body.is_planar() {
            BodySurface::Segments(self.segments(index, body, particles))
        } else {
            BodySurface::Faces(self.faces(index, body, particles))
        }
    }
}

/// `members` (elements among `particles` particles), adding into entries of
/// all the particles: in their order when few, else through `cache`'s
/// schedule.
fn world_wide<'a, const W: usize>(
    cache: &'a mut ScheduleCache<W>,
    members: &'a [[u32; W]],
    particles: usize,
) -> Surface<'a, W> {
    if members.len() <= CHUNK {
        Surface::InOrder { members, first: 0 }
    } else {
        Surface::Scheduled(cache.get(members, particles))
    }
}
