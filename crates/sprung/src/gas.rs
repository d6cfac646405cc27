//! The ideal gas inside a closed body (docs/physics.md §4): `P = nRT / V`, with
//! `nRT` (J) following a schedule in time.
//!
//! Switching the full pressure on at once blows a body apart, so `nRT`
//! ramps linearly from 0 to its target over `ramp_time` ("pumping"). After
//! the ramp it may follow keyframes (inflate, deflate: linear between them,
//! held after the last) and leak exponentially at `leak_rate` from
//! `leak_start` on, so a balloon can slowly deflate and sag.

use crate::error::BuildError;
use crate::units::Real;

/// How the enclosed volume is measured for the pressure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum VolumeModel {
    /// The exact volume (area in 2D) by the divergence theorem. The default,
    /// and the only one for which `E_gas = -nRT ln V` is a potential.
    #[default]
    Exact,
    /// The volume of the axis-aligned bounding box (its area in 2D): a crude
    /// estimate, for comparison.
    BoundingBox,
    /// The volume of the ellipsoid inscribed in the bounding box,
    /// `π/6 · w h d` (the ellipse `π/4 · w h` in 2D): for comparison.
    BoundingEllipsoid,
}

impl VolumeModel {
    /// The name used in scene files.
    pub fn name(self) -> &'static str {
        match self {
            VolumeModel::Exact => "exact",
            VolumeModel::BoundingBox => "bounding_box",
            VolumeModel::BoundingEllipsoid => "bounding_ellipsoid",
        }
    }

    /// The model named `name`, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        [
            VolumeModel::Exact,
            VolumeModel::BoundingBox,
            VolumeModel::BoundingEllipsoid,
        ]
        .into_iter()
        .find(|m| m.name() == name)
    }
}

/// The gas of one body: its `nRT` over time and how its volume is measured.
#[derive(Debug, Clone, PartialEq)]
pub struct Gas {
    /// Target `nRT` reached at the end of the ramp (J).
    pub nrt: Real,
    /// Time over which `nRT` ramps linearly from 0 to `nrt` (s); 0 switches
    /// it on at once.
    pub ramp_time: Real,
    /// Later `(time (s), nRT (J))` keyframes, in increasing time, all after
    /// the ramp: `nRT` goes linearly between them and holds the last.
    pub keyframes: Vec<(Real, Real)>,
    /// Exponential leak rate (1/s): `nRT` is multiplied by
    /// `exp(-leak_rate (t - leak_start))` after `leak_start`.
    pub leak_rate: Real,
    /// When the leak starts (s).
    pub leak_start: Real,
    /// How the volume is measured.
    pub volume_model: VolumeModel,
}

impl Gas {
    /// A gas that ramps to `nrt` (J) over `ramp_time` (s) and stays there.
    ///
    /// ```
    /// use sprung::Gas;
    ///
    /// let gas = Gas::new(200.0, 0.5);
    /// assert_eq!(gas.nrt_at(0.0), 0.0);
    /// assert_eq!(gas.nrt_at(0.25), 100.0); // halfway up the ramp
    /// assert_eq!(gas.nrt_at(10.0), 200.0);
    /// // A leak from t = 1 s at 0.1/s: e⁻¹ of it left 10 s later.
    /// let leaking = Gas { leak_rate: 0.1, leak_start: 1.0, ..gas };
    /// assert_eq!(leaking.nrt_at(11.0), 200.0 * (-1.0_f64).exp());
    /// ```
    pub fn new(nrt: Real, ramp_time: Real) -> Self {
        Gas {
            nrt,
            ramp_time,
            keyframes: Vec::new(),
            leak_rate: 0.0,
            leak_start: 0.0,
            volume_model: VolumeModel::Exact,
        }
    }

    /// `nRT` at time `t` (J).
    pub fn nrt_at(&self, t: Real) -> Real {
        let scheduled = if t < self.ramp_time {
            self.nrt * (t / self.ramp_time).max(0.0)
        } else {
            let mut previous = (self.ramp_time, self.nrt);
            let mut value = self.nrt;
            for &(time, nrt) in &self.keyframes {
                if t < time {
                    let fraction = (t - previous.0) / (time - previous.0);
                    value = previous.1 + fraction * (nrt - previous.1);
                    break;
                }
                previous = (time, nrt);
                value = nrt;
            }
            value
        };
        if self.leak_rate > 0.0 && t > self.leak_start {
            scheduled * (-self.leak_rate * (t - self.leak_start)).exp()
        } else {
            scheduled
        }
    }

    /// Check the parameters: finite, `nrt` and keyframe values not negative,
    /// ramp and leak not negative, keyframes after the ramp and increasing.
    pub fn validate(&self) -> Result<(), BuildError> {
        let non_negative = [
            ("gas.nrt", self.nrt),
            ("gas.ramp_time", self.ramp_time),
            ("gas.leak_rate", self.leak_rate),
            ("gas.leak_start", self.leak_start),
        ];
        for (field, value) in non_negative {
            if !(value.is_finite() && value >= 0.0) {
                return Err(BuildError::OutOfRange {
                    field,
                    value,
                    reason: "must be finite and not negative",
                });
            }
        }
        let mut last_time = self.ramp_time;
        for &(time, nrt) in &self.keyframes {
            if !(time.is_finite() && time > last_time) {
                return Err(BuildError::OutOfRange {
                    field: "gas.schedule",
                    value: time,
                    reason: "keyframe times must be finite, after the ramp, and increasing (s)",
                });
            }
            if !(nrt.is_finite() && nrt >= 0.0) {
                return Err(BuildError::OutOfRange {
                    field: "gas.schedule",
                    value: nrt,
                    reason: "keyframe nRT values must be finite and not negative (J)",
                });
            }
            last_time = time;
        }
        Ok(())
    }
}
