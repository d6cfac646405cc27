//! The gas bodies as the kernels read them: each closed surface's faces
//! (or a 2D loop's segments), the exact enclosed volume summed in a fixed
//! order, and the pressure `nRT / V` pushing each element outward
//! (docs/physics.md §4; `forces::GasPressure` in the engine).

use sprung::{Body, Gas, Real, World};

use crate::layout::adjacency;

/// Elements a workgroup sums into one partial volume (the kernels'
/// workgroup size): each body's elements are padded to a multiple of it,
/// so that no workgroup mixes two bodies.
pub const PART: usize = 64;

/// The most gas bodies a world on the GPU may have (their nRT values ride
/// in one 256-byte uniform slot a force evaluation, after the time and the
/// wind).
pub const MAX_GAS_BODIES: usize = 48;

/// Marks a segment (a 2D loop's element) in [`GasLayout::elements`]' third
/// index.
pub const SEGMENT: u32 = u32::MAX;

/// One gas body's share of the partial volumes (`GasBody` in the kernels).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GasBody {
    /// Its first partial volume.
    pub first: u32,
    /// How many.
    pub parts: u32,
}

/// The gas bodies of a world, laid out for the kernels.
#[derive(Debug, Clone, Default)]
pub struct GasLayout {
    /// Per element, its particles (a segment's third is [`SEGMENT`]) and its
    /// gas body's slot; each body's run padded to [`PART`] with elements
    /// whose particles are all one (they add nothing).
    pub elements: Vec<[u32; 4]>,
    /// Particle `i`'s elements are `element_links[element_first[i]..element_first[i + 1]]`
    /// (an element once for each of its corners).
    pub element_first: Vec<u32>,
    /// The elements around each particle, in the bodies' order.
    pub element_links: Vec<u32>,
    /// Per gas slot, its partial volumes.
    pub bodies: Vec<GasBody>,
    /// Per gas slot, the body's gas (its nRT schedule).
    pub gas: Vec<Gas>,
}

/// Whether `body` holds a gas that pushes (closed, with a surface).
fn pushes(body: &Body) -> bool {
    body.gas.is_some() && body.closed && (!body.faces.is_empty() || !body.segments.is_empty())
}

impl GasLayout {
    /// The gas bodies of `world` (those [`crate::support::check`] takes).
    pub fn of(world: &World) -> GasLayout {
        let mut layout = GasLayout::default();
        for body in &world.bodies {
            if !pushes(body) {
                continue;
            }
            let slot = layout.gas.len() as u32;
            let start = layout.elements.len();
            if body.faces.is_empty() {
                let segments = body.segments.iter();
                layout
                    .elements
                    .extend(segments.map(|&[a, b]| [a, b, SEGMENT, slot]));
            } else {
                let faces = body.faces.iter();
                layout
                    .elements
                    .extend(faces.map(|&[a, b, c]| [a, b, c, slot]));
            }
            let blank = body.particles.start as u32;
            while (layout.elements.len() - start) % PART != 0 {
                layout.elements.push([blank, blank, blank, slot]);
            }
            layout.bodies.push(GasBody {
                first: (start / PART) as u32,
                parts: ((layout.elements.len() - start) / PART) as u32,
            });
            layout.gas.extend(body.gas.clone());
        }
        let mut corners = Vec::new();
        for (k, e) in layout.elements.iter().enumerate() {
            let count = if e[0] == e[1] && e[1] == e[2] {
                0 // padding
            } else if e[2] == SEGMENT {
                2
            } else {
                3
            };
            corners.extend(e[..count].iter().map(|&p| (p, k as u32)));
        }
        (layout.element_first, layout.element_links) = adjacency(world.particles.len(), &corners);
        layout
    }
}

/// The nRT (J) of each gas slot's `gases` at `time` (s), as the engine
/// schedules it (`Gas::nrt_at`).
pub fn nrt_at(gases: &[Gas], time: Real) -> impl Iterator<Item = Real> + '_ {
    gases.iter().map(move |g| g.nrt_at(time))
}
