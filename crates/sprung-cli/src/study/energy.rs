//! The energy criterion of `sprung study stability`: in a scene without
//! driving forces, a trial whose total energy rises above its start by
//! more than the margin is unstable.

use sprung::{Energies, Real, Vec3, World};

/// The energy criterion: a trial is unstable if its total energy ever
/// rises above its start by more than `margin` × the energy scale, the
/// larger of `start_scale` and the largest change over the trial of the
/// terms whose zero is arbitrary (gravity: the origin; gas, `-nRT ln V`:
/// the unit of volume), so that a body released where those terms are
/// zero (a rope lying along y = 0) still has a margin in proportion to its
/// motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnergyCheck {
    /// The allowed rise, a fraction of the scale.
    pub margin: Real,
    /// The sum of the sizes of the energy terms at the start (J).
    pub start_scale: Real,
}

/// A trial's energy against its start.
pub(super) struct EnergyWatch {
    check: EnergyCheck,
    start: Energies,
    /// The scale cannot grow (no gravity, no gas): the first step past
    /// the margin ends the trial.
    fixed: bool,
    /// The largest change so far of the gravity and gas terms (J).
    exchange: Real,
    /// The largest rise so far (J) and its step.
    worst: (Real, u64),
}

impl EnergyWatch {
    pub(super) fn new(check: EnergyCheck, world: &World) -> Self {
        EnergyWatch {
            check,
            start: world.energies(),
            fixed: world.gravity() == Vec3::ZERO && world.bodies.iter().all(|b| b.gas.is_none()),
            exchange: 0.0,
            worst: (0.0, 0),
        }
    }

    /// Look at the energy after `step`: why the trial has failed, once
    /// that is certain.
    pub(super) fn observe(&mut self, world: &World, step: u64) -> Option<String> {
        let now = world.energies();
        let rise = now.total() - self.start.total();
        if !rise.is_finite() {
            return Some(format!("energy not finite at step {step}"));
        }
        let term = |e: &Energies, name| e.get(name).unwrap_or(0.0);
        let change = (term(&now, "gravity") - term(&self.start, "gravity")).abs()
            + (term(&now, "gas") - term(&self.start, "gas")).abs();
        self.exchange = self.exchange.max(change);
        if rise > self.worst.0 {
            self.worst = (rise, step);
        }
        if self.fixed {
            self.verdict()
        } else {
            None
        }
    }

    /// Why the trial failed, judged on the largest rise and the final
    /// scale; `None` if it passed.
    pub(super) fn verdict(&self) -> Option<String> {
        let limit = self.check.margin * self.check.start_scale.max(self.exchange);
        let (rise, step) = self.worst;
        (rise > limit).then(|| {
            format!(
                "energy {rise:.3e} J above its start at step {step}, {:.3}× the allowed {limit:.3e} J",
                rise / limit
            )
        })
    }
}
