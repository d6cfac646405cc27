//! The elements of continuous collision detection: the surface points,
//! triangles, edges, 2D segments and loose particles of the bodies that
//! collide, gathered per body, and which pairs of them the narrow phase
//! tests.

use std::ops::Range;

use crate::body::Body;
use crate::contact::geometry::{closest_between_segments, closest_on_segment, closest_on_triangle};
use crate::units::{Real, Vec3};

/// What an element is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kind {
    /// A particle on a surface, or a loose one (`true`: of a body without
    /// a surface, a ball of the contact radius).
    Point(bool),
    /// A triangle of a surface (3D).
    Triangle,
    /// A segment of a 2D loop.
    Segment,
    /// An edge of a surface (3D).
    Edge,
}

/// An element: its kind, particles (the first `count`) and body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Element {
    pub kind: Kind,
    pub particles: [u32; 3],
    pub body: u32,
}

impl Element {
    /// The element's particles.
    pub fn particles(&self) -> &[u32] {
        let count = match self.kind {
            Kind::Point(_) => 1,
            Kind::Segment | Kind::Edge => 2,
            Kind::Triangle => 3,
        };
        &self.particles[..count]
    }

    fn shares_a_particle(&self, other: &Element) -> bool {
        self.particles()
            .iter()
            .any(|p| other.particles().contains(p))
    }
}

/// The elements of the bodies that take part, gathered per stage.
#[derive(Debug, Clone, Default)]
pub(super) struct Elements {
    pub list: Vec<Element>,
    /// Per body that collides, the range of its elements in `list`, and
    /// of its particles.
    pub spans: Vec<Range<usize>>,
    pub span_particles: Vec<Range<usize>>,
    /// Per span, whether its body collides with itself.
    pub span_own: Vec<bool>,
    /// Per body, its span (`u32::MAX` for a body that does not collide).
    pub span_of_body: Vec<u32>,
    /// Per body, whether it collides with itself.
    pub self_colliding: Vec<bool>,
    /// Scratch: which particles of a body were already gathered.
    seen: Vec<bool>,
    /// What the elements were gathered from (per body: its particles, the
    /// addresses and lengths of its faces, edges and segments, its contact
    /// flags), and how many times they were gathered.
    gathered_from: Vec<[usize; 9]>,
    pub generation: u64,
    /// Whether any pair of the elements can meet.
    meet: bool,
}

/// What a body's elements are gathered from.
fn key_of(body: &Body) -> [usize; 9] {
    [
        body.particles.start,
        body.particles.end,
        body.faces.as_ptr() as usize,
        body.faces.len(),
        body.edges.as_ptr() as usize,
        body.edges.len(),
        body.segments.as_ptr() as usize ^ (body.segments.len() << 1),
        usize::from(body.contact.collide),
        usize::from(body.contact.self_collision),
    ]
}

impl Elements {
    /// Gather the elements of the bodies that collide (every body's
    /// `contact.collide`); returns whether any pair of them can meet (two
    /// colliding bodies, or one colliding with itself).
    pub fn gather(&mut self, bodies: &[Body]) -> bool {
        let same = self.gathered_from.len() == bodies.len()
            && self
                .gathered_from
                .iter()
                .zip(bodies)
                .all(|(key, body)| *key == key_of(body));
        if same {
            return self.meet;
        }
        self.gathered_from.clear();
        self.gathered_from.extend(bodies.iter().map(key_of));
        self.generation += 1;
        self.list.clear();
        self.spans.clear();
        self.span_particles.clear();
        self.span_own.clear();
        self.span_of_body.clear();
        self.self_colliding.clear();
        let mut colliding = 0;
        let mut self_colliding = false;
        for (b, body) in bodies.iter().enumerate() {
            let collides = body.contact.collide;
            let own = collides && body.contact.self_collision;
            self.self_colliding.push(own);
            if !collides {
                self.span_of_body.push(u32::MAX);
                continue;
            }
            self.span_of_body.push(self.spans.len() as u32);
            colliding += 1;
            self_colliding |= own;
            let first = self.list.len();
            self.gather_body(body, b as u32);
            self.spans.push(first..self.list.len());
            self.span_particles.push(body.particles.clone());
            self.span_own.push(own);
        }
        self.meet = colliding >= 2 || self_colliding;
        self.meet
    }

    /// The elements of one colliding body.
    fn gather_body(&mut self, body: &Body, b: u32) {
        let element = |kind, particles| Element {
            kind,
            particles,
            body: b,
        };
        if body.faces.is_empty() && body.segments.is_empty() {
            let loose = body
                .particles
                .clone()
                .map(|i| element(Kind::Point(true), [i as u32; 3]));
            self.list.extend(loose);
            return;
        }
        self.gather_vertices(body, b);
        for &[i, j, k] in &body.faces {
            self.list.push(element(Kind::Triangle, [i, j, k]));
        }
        for &[i, j] in &body.edges {
            self.list.push(element(Kind::Edge, [i, j, j]));
        }
        for &[i, j] in &body.segments {
            self.list.push(element(Kind::Segment, [i, j, j]));
        }
    }

    /// The particles on `body`'s surface, each once, as points.
    fn gather_vertices(&mut self, body: &Body, b: u32) {
        let Range { start, end } = body.particles;
        self.seen.clear();
        self.seen.resize(end - start, false);
        let faces = body.faces.iter().flat_map(|f| f.iter());
        let segments = body.segments.iter().flat_map(|s| s.iter());
        for &i in faces.chain(segments) {
            let local = i as usize - start;
            if !std::mem::replace(&mut self.seen[local], true) {
                self.list.push(Element {
                    kind: Kind::Point(false),
                    particles: [i; 3],
                    body: b,
                });
            }
        }
    }

    /// Whether elements `a` and `b` form a pair the tests look at, and in
    /// which order (point first, then the element it may hit).
    pub fn pair(&self, a: usize, b: usize) -> Option<(usize, usize)> {
        let (ea, eb) = (&self.list[a], &self.list[b]);
        let same = ea.body == eb.body;
        let own = same && self.self_colliding[ea.body as usize];
        let ordered = match (ea.kind, eb.kind) {
            (Kind::Point(p), Kind::Point(q)) => (p && q && !same).then_some((a, b)),
            (Kind::Point(_), Kind::Triangle | Kind::Segment) => Some((a, b)),
            (Kind::Triangle | Kind::Segment, Kind::Point(_)) => Some((b, a)),
            (Kind::Edge, Kind::Edge) => Some((a, b)),
            _ => None,
        }?;
        if same && (!own || ea.shares_a_particle(eb)) {
            return None;
        }
        Some(ordered)
    }
}

/// The distance (m) between elements `a` (a point, or an edge) and `b` at
/// `position`.
pub(super) fn distance(a: &Element, b: &Element, position: &[Vec3]) -> Real {
    let x = |i: u32| position[i as usize];
    let [p, q, _] = a.particles.map(x);
    let [u, v, w] = b.particles.map(x);
    let closest = match (a.kind, b.kind) {
        (Kind::Point(_), Kind::Triangle) => {
            let [l, m, n] = closest_on_triangle(p, u, v, w);
            l * u + m * v + n * w
        }
        (Kind::Point(_), Kind::Segment) => u + closest_on_segment(p, u, v) * (v - u),
        (Kind::Edge, Kind::Edge) => {
            let (s, t) = closest_between_segments(p, q, u, v);
            return ((p + s * (q - p)) - (u + t * (v - u))).length();
        }
        _ => u,
    };
    (p - closest).length()
}
