//! The broad phase of continuous collision detection: the elements that
//! may collide (surface points, triangles, edges, 2D segments, loose
//! particles), the box each sweeps over the step, and the pairs of boxes
//! that overlap, by sorting the boxes along the axis the scene spreads
//! most on and sweeping (sort and sweep; Baraff 1992).

use std::ops::Range;

use crate::body::Body;
use crate::contact::geometry::{closest_between_segments, closest_on_segment, closest_on_triangle};
use crate::{Real, Vec3};

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
fn distance(a: &Element, b: &Element, position: &[Vec3]) -> Real {
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

/// The broad phase: candidate pairs of elements, found by a sweep over
/// boxes grown by a margin about where the particles were (the *anchor*),
/// and kept for the following stages while the bodies' particles stay
/// within the margin of where they were, less their bodies' common moves
/// (see `within_margin`): a pair whose boxes grown so far apart did not
/// overlap cannot have come within the gap since. Each stage hands on the
/// cached pairs whose distance when found, less the particles' moves
/// since, is within the gap.
#[derive(Debug, Clone, Default)]
pub(super) struct Sweep {
    /// Per element, the box it sweeps this step, grown by the gap or the
    /// radius (low and high corners, m).
    boxes: Vec<(Vec3, Vec3)>,
    /// The cached pairs (point or first edge first) and the elements they
    /// were found among.
    pairs: Vec<(u32, u32, Real)>,
    /// The generation of the elements they were found among.
    generation: u64,
    /// Per particle, how far (m) it strayed from its body's mean move
    /// since the anchor over this step's path.
    stray: Vec<Real>,
    /// Per element, the farthest any of its particles strayed (m).
    slack: Vec<Real>,
    /// The reach (m) of surface pairs (the gap) and of two loose
    /// particles (twice the radius).
    reach: (Real, Real),
    /// Where the particles were when the pairs were found (m), and half
    /// the margin (m) the boxes were grown by beyond the gap.
    anchor: Vec<Vec3>,
    half_margin: Real,
    /// Per body, its mean move since the anchor and the farthest a
    /// particle strays from it (m; scratch).
    moves: Vec<(Vec3, Real)>,
    /// Scratch of the sweep: per body's span of elements, its box; the
    /// elements sorted along x; the two sides of a pair of bodies.
    body_box: Vec<(Vec3, Vec3)>,
    order: Vec<u32>,
    merged: Vec<(Real, bool, u32)>,
}

impl Sweep {
    /// The candidate pairs for a step from `start` to `end` (m) among
    /// `elements`, found again where the particles have left the margin
    /// (`thickness`, m, sets its least size); then each element's swept
    /// box this step, grown by `gap` (m), or `radius` (m) for loose
    /// particles.
    #[allow(clippy::too_many_arguments)]
    pub fn prepare(
        &mut self,
        elements: &Elements,
        start: &[Vec3],
        end: &[Vec3],
        thickness: Real,
        gap: Real,
        radius: Real,
    ) {
        self.reach = (gap, 2.0 * radius);
        let valid = self.generation == elements.generation
            && self.anchor.len() == start.len()
            && self.within_margin(elements, start, end);
        if !valid {
            let moved = start
                .iter()
                .zip(end)
                .map(|(a, b)| (*a - *b).length_squared())
                .fold(0.0, Real::max)
                .sqrt();
            self.half_margin = thickness.max(2.0 * moved);
            self.anchor.clear();
            self.anchor.extend_from_slice(start);
            self.generation = elements.generation;
            self.build(elements, gap, radius);
            self.within_margin(elements, start, end);
        }
    }

    /// Whether the cached pairs still hold every pair that can come within
    /// the gap on the paths from `start` to `end`: per body, its particles'
    /// mean move since the anchor `T` and the farthest any strays from it
    /// `D` (m); two elements of bodies `a` and `b` have come closer by at
    /// most `D_a + D_b + |T_a − T_b|` since the pairs were found, which
    /// must stay within the margin (twice its half). A body that moves as
    /// one piece (a falling cloth) keeps its pairs with itself.
    fn within_margin(&mut self, elements: &Elements, start: &[Vec3], end: &[Vec3]) -> bool {
        self.moves.clear();
        self.stray.resize(start.len(), 0.0);
        for particles in &elements.span_particles {
            let count = particles.len().max(1) as Real;
            let shift = particles
                .clone()
                .map(|i| end[i] - self.anchor[i])
                .sum::<Vec3>()
                / count;
            let mut most: Real = 0.0;
            for i in particles.clone() {
                let (a, b) = (
                    start[i] - self.anchor[i] - shift,
                    end[i] - self.anchor[i] - shift,
                );
                let stray = a.length_squared().max(b.length_squared()).sqrt();
                self.stray[i] = stray;
                most = most.max(stray);
            }
            self.moves.push((shift, most));
        }
        let margin = 2.0 * self.half_margin;
        let spans = elements.spans.len();
        (0..spans).all(|i| {
            let (ti, di) = self.moves[i];
            (!elements.span_own[i] || 2.0 * di <= margin)
                && (i + 1..spans).all(|j| {
                    let (tj, dj) = self.moves[j];
                    di + dj + (ti - tj).length() <= margin
                })
        })
    }

    /// Call `meet(a, b)` on every cached pair that may come within the
    /// gap (two loose particles: twice the radius) this step, in the
    /// cache's order: its distance when found, less how far its
    /// particles have strayed from their bodies' moves since and how far
    /// those moves part, is within it.
    pub fn overlaps(&mut self, elements: &Elements, mut meet: impl FnMut(usize, usize)) {
        let stray = &self.stray;
        self.slack.clear();
        self.slack.extend(elements.list.iter().map(|e| {
            e.particles()
                .iter()
                .map(|&i| stray[i as usize])
                .fold(0.0, Real::max)
        }));
        let (gap, balls) = self.reach;
        for &(a, b, distance) in &self.pairs {
            let (ea, eb) = (&elements.list[a as usize], &elements.list[b as usize]);
            let mut closest = distance - self.slack[a as usize] - self.slack[b as usize];
            let mut reach = gap;
            if ea.body != eb.body {
                let (sa, sb) = (
                    elements.span_of_body[ea.body as usize] as usize,
                    elements.span_of_body[eb.body as usize] as usize,
                );
                closest -= (self.moves[sa].0 - self.moves[sb].0).length();
                if ea.kind == Kind::Point(true) && eb.kind == Kind::Point(true) {
                    reach = balls;
                }
            }
            if closest <= reach {
                meet(a as usize, b as usize);
            }
        }
    }

    /// Find the pairs: the boxes about the anchors, each body's elements
    /// sorted along x, then every two bodies whose boxes overlap swept
    /// against each other over the region they share, and each body that
    /// collides with itself against itself.
    fn build(&mut self, elements: &Elements, gap: Real, radius: Real) {
        let half = self.half_margin;
        let anchor = &self.anchor;
        self.boxes.clear();
        self.boxes.extend(elements.list.iter().map(|e| {
            let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
            for &i in e.particles() {
                lo = lo.min(anchor[i as usize]);
                hi = hi.max(anchor[i as usize]);
            }
            let grow = half
                + if e.kind == Kind::Point(true) {
                    radius
                } else {
                    gap
                };
            (lo - grow, hi + grow)
        }));
        let boxes = &self.boxes;
        self.order.clear();
        self.order.extend(0..elements.list.len() as u32);
        self.body_box.clear();
        for span in &elements.spans {
            let key = |i: &u32| boxes[*i as usize].0.x;
            self.order[span.clone()].sort_by(|a, b| key(a).total_cmp(&key(b)).then(a.cmp(b)));
            let union = boxes[span.clone()]
                .iter()
                .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), b| {
                    (lo.min(b.0), hi.max(b.1))
                });
            self.body_box.push(union);
        }
        self.pairs.clear();
        let spans = &elements.spans;
        for i in 0..spans.len() {
            if elements.span_own[i] {
                self.sweep(elements, i, i);
            }
            for j in i + 1..spans.len() {
                self.sweep(elements, i, j);
            }
        }
    }

    /// Sweep the elements of span `i` against those of span `j` (the
    /// same span: against each other) over the region their boxes share.
    fn sweep(&mut self, elements: &Elements, i: usize, j: usize) {
        let (bi, bj) = (self.body_box[i], self.body_box[j]);
        let (lo, hi) = (bi.0.max(bj.0), bi.1.min(bj.1));
        if !lo.cmple(hi).all() {
            return;
        }
        let boxes = &self.boxes;
        let inside = |e: u32| {
            let b = boxes[e as usize];
            b.0.cmple(hi).all() && lo.cmple(b.1).all()
        };
        self.merged.clear();
        let (si, sj) = (&elements.spans[i], &elements.spans[j]);
        for (side, span) in [(false, si), (true, sj)] {
            if side && i == j {
                break;
            }
            let kept = self.order[span.clone()]
                .iter()
                .copied()
                .filter(|&e| inside(e));
            self.merged
                .extend(kept.map(|e| (boxes[e as usize].0.x, side, e)));
        }
        if i != j {
            self.merged
                .sort_by(|a, b| a.0.total_cmp(&b.0).then(a.2.cmp(&b.2)));
        }
        for (k, &(_, side, a)) in self.merged.iter().enumerate() {
            let (alo, ahi) = boxes[a as usize];
            for &(low, other, b) in &self.merged[k + 1..] {
                if low > ahi.x {
                    break;
                }
                if i != j && other == side {
                    continue;
                }
                let (blo, bhi) = boxes[b as usize];
                if alo.cmple(bhi).all() && blo.cmple(ahi).all() {
                    if let Some((p, q)) = elements.pair(a as usize, b as usize) {
                        let list = &elements.list;
                        let d = distance(&list[p], &list[q], &self.anchor);
                        self.pairs.push((p as u32, q as u32, d));
                    }
                }
            }
        }
    }
}
