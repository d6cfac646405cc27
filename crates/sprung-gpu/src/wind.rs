//! Wind as the kernels read it (docs/physics.md §3; `forces::Wind` in the
//! engine): every surface element of every body (faces, or a 2D loop's
//! segments) with its body's wind scale, gathered per particle; the
//! turbulent modes in the uniform block, the gusting mean and the modes'
//! phases in each force evaluation's stage slot.

use sprung::forces::{Wind, WindModel};
use sprung::{Real, World};

use crate::gas::SEGMENT;
use crate::layout::adjacency;

/// The turbulent modes the kernels hold (the engine's wind has 8).
pub const MAX_MODES: usize = 8;

/// A world's wind, laid out for the kernels.
#[derive(Debug, Clone, Default)]
pub struct WindLayout {
    /// Per element, its particles (a segment's third is [`SEGMENT`]) and
    /// its body, in [`WindLayout::scales`].
    pub elements: Vec<[u32; 4]>,
    /// Each body's wind scale.
    pub scales: Vec<f64>,
    /// Particle `i`'s elements are `links[first[i]..first[i + 1]]`.
    pub first: Vec<u32>,
    /// The elements around each particle (an element once a corner).
    pub links: Vec<u32>,
    /// The model (0: none, 1: simple, 2: area) and the modes in use.
    pub kind: [u32; 4],
    /// The simple model's coefficient (N·s/m) or the area model's air
    /// density (kg/m³), the lift, the modes' amplitude (m/s).
    pub coefficients: [f64; 4],
    /// Per mode, its direction then its wave vector (1/m).
    pub modes: [[f64; 4]; 2 * MAX_MODES],
    /// The wind, for its field's time-dependent parts.
    pub wind: Option<Wind>,
}

impl WindLayout {
    /// The wind of `world` (none: nothing to lay out).
    pub fn of(world: &World) -> WindLayout {
        let Some(wind) = world.forces.get::<Wind>() else {
            return WindLayout {
                first: vec![0; world.particles.len() + 1],
                ..WindLayout::default()
            };
        };
        let mut layout = WindLayout::default();
        for (index, body) in world.bodies.iter().enumerate() {
            layout
                .scales
                .push(wind.body_scale.get(index).copied().unwrap_or(1.0));
            let slot = index as u32;
            let faces = body.faces.iter().map(|&[a, b, c]| [a, b, c, slot]);
            let segments = body.segments.iter().map(|&[a, b]| [a, b, SEGMENT, slot]);
            layout.elements.extend(faces.chain(segments));
        }
        let mut corners = Vec::new();
        for (k, e) in layout.elements.iter().enumerate() {
            let count = if e[2] == SEGMENT { 2 } else { 3 };
            corners.extend(e[..count].iter().map(|&p| (p, k as u32)));
        }
        (layout.first, layout.links) = adjacency(world.particles.len(), &corners);
        let modes = wind.field.turbulent_modes();
        layout.kind = match wind.model {
            WindModel::Simple { .. } => [1, modes.len().min(MAX_MODES) as u32, 0, 0],
            WindModel::Area { .. } => [2, modes.len().min(MAX_MODES) as u32, 0, 0],
        };
        let (coefficient, lift) = match wind.model {
            WindModel::Simple { coefficient } => (coefficient, 0.0),
            WindModel::Area { air_density, lift } => (air_density, lift),
        };
        let scale = wind.field.turbulence_scale();
        layout.coefficients = [coefficient, lift, scale, 0.0];
        for (k, mode) in modes.iter().enumerate().take(MAX_MODES) {
            layout.modes[2 * k] = mode.direction.extend(0.0).into();
            layout.modes[2 * k + 1] = mode.wave_vector.extend(0.0).into();
        }
        layout.wind = Some(wind.clone());
        layout
    }

    /// The stage slot's wind at `time` (s): the gusting mean (m/s), then
    /// each mode's phase less its turns so far, `φ - ω t` (rad), taken in
    /// f64 and reduced to one turn so that f32 holds it to its precision
    /// however late the run.
    pub fn stage(wind: Option<&Wind>, time: Real) -> [f64; 12] {
        let mut values = [0f64; 12];
        let Some(wind) = wind else {
            return values;
        };
        let mean = wind.field.gusting_at(time);
        values[..3].copy_from_slice(&mean.to_array());
        for (k, mode) in wind
            .field
            .turbulent_modes()
            .iter()
            .enumerate()
            .take(MAX_MODES)
        {
            let phase = (mode.phase - mode.frequency * time).rem_euclid(std::f64::consts::TAU);
            values[4 + k] = phase;
        }
        values
    }
}
