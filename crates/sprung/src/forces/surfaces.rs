//! The surfaces of the bodies (triangles, 2D segments) as the forces that
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
    /// as the force).
    InOrder(&'a [[u32; W]]),
    /// More: in the blocks of the schedule.
    Scheduled(&'a Schedule<W>),
}

impl<const W: usize> Surface<'_, W> {
    /// Call `f(element, writer)` for every element; the writer adds into
    /// `out` at the element's particles (see [`Schedule::scatter`]). Each
    /// particle receives its contributions in an order fixed by the
    /// elements, whatever the number of threads.
    pub fn scatter<T: Send + Copy + AddAssign>(
        &self,
        out: &mut [T],
        f: impl Fn(usize, &Writer<'_, T, W>) + Sync,
    ) {
        match self {
            Surface::InOrder(members) => parallel::scatter_in_order(members, out, f),
            Surface::Scheduled(schedule) => schedule.scatter(out, f),
        }
    }
}

impl Surfaces {
    fn of(&mut self, index: usize) -> &mut (ScheduleCache<3>, ScheduleCache<2>) {
        if self.bodies.len() <= index {
            self.bodies.resize(index + 1, Default::default());
        }
        &mut self.bodies[index]
    }

    /// The triangles of body `index` (`body`), among `particles` particles.
    pub fn faces<'a>(
        &'a mut self,
        index: usize,
        body: &'a Body,
        particles: usize,
    ) -> Surface<'a, 3> {
        if body.faces.len() <= CHUNK {
            Surface::InOrder(&body.faces)
        } else {
            Surface::Scheduled(self.of(index).0.get(&body.faces, particles))
        }
    }

    /// The segments of body `index` (`body`), among `particles` particles.
    pub fn segments<'a>(
        &'a mut self,
        index: usize,
        body: &'a Body,
        particles: usize,
    ) -> Surface<'a, 2> {
        if body.segments.len() <= CHUNK {
            Surface::InOrder(&body.segments)
        } else {
            Surface::Scheduled(self.of(index).1.get(&body.segments, particles))
        }
    }
}
