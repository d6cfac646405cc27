//! The surfaces of the bodies (triangles, 2D segments) scheduled for the
//! threads, for the forces that add into their vertices (gas pressure,
//! wind).

use crate::body::Body;
use crate::parallel::{Schedule, ScheduleCache};

/// Per body (by index), its faces and segments in blocks
/// ([`Schedule`]), made again when a body's surface changes.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Surfaces {
    bodies: Vec<(ScheduleCache<3>, ScheduleCache<2>)>,
}

impl Surfaces {
    fn of(&mut self, index: usize) -> &mut (ScheduleCache<3>, ScheduleCache<2>) {
        if self.bodies.len() <= index {
            self.bodies.resize(index + 1, Default::default());
        }
        &mut self.bodies[index]
    }

    /// The triangles of body `index` (`body`), among `particles` particles.
    pub fn faces(&mut self, index: usize, body: &Body, particles: usize) -> &Schedule<3> {
        self.of(index).0.get(&body.faces, particles)
    }

    /// The segments of body `index` (`body`), among `particles` particles.
    pub fn segments(&mut self, index: usize, body: &Body, particles: usize) -> &Schedule<2> {
        self.of(index).1.get(&body.segments, particles)
    }
}
