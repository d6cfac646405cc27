//! Muscles: springs whose rest length is `L0 s(t)`, set before every
//! (sub)step at its start time, so the forces of the step (all the trial
//! states of RK4 and the implicit solves) see one rest length per step.

use crate::body::MuscleDrive;
use crate::springs::Springs;
use crate::units::Real;

/// One muscle: a spring of the world and its drive.
#[derive(Debug, Clone, PartialEq)]
pub struct Muscle {
    /// Index of the spring in the world's [`Springs`].
    pub spring: usize,
    /// Its rest length at factor 1, `L0` (m).
    pub rest_length: Real,
    /// How the factor changes in time.
    pub drive: MuscleDrive,
}

impl Muscle {
    /// The phase of its drive (rad), for drawing muscles by phase; 0 for a
    /// drive given as a function.
    pub fn phase(&self) -> Real {
        match self.drive {
            MuscleDrive::Sine { phase, .. } => phase,
            MuscleDrive::Function(_) => 0.0,
        }
    }
}

/// The world's muscles.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Muscles {
    /// Every muscle of every body.
    pub list: Vec<Muscle>,
}

impl Muscles {
    /// Set each muscle's spring to its rest length at `time` (s),
    /// `L0 s(time)` (m). A drive giving a factor that is not positive and
    /// finite is refused: the index of the muscle and the factor.
    pub fn apply(&self, time: Real, springs: &mut Springs) -> Result<(), (usize, Real)> {
        for (index, m) in self.list.iter().enumerate() {
            let factor = m.drive.factor(time);
            if !(factor.is_finite() && factor > 0.0) {
                return Err((index, factor));
            }
            springs.rest_length[m.spring] = m.rest_length * factor;
        }
        Ok(())
    }

    /// The rest length (m) of muscle `index` at `time` (s).
    pub fn rest_length_at(&self, index: usize, time: Real) -> Real {
        let m = &self.list[index];
        m.rest_length * m.drive.factor(time)
    }
}
