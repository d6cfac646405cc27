//! Numbers for the contact tests' motions, the same on every run.

use crate::units::{Real, Vec3};

/// xorshift64*: numbers uniform in [-1, 1), the same on every run.
pub(crate) struct Random(pub u64);

impl Random {
    /// The next number, in [-1, 1).
    pub fn symmetric(&mut self) -> Real {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11;
        2.0 * (bits as Real / (1u64 << 53) as Real) - 1.0
    }

    /// A vector of the next three numbers times `scale`, each within
    /// ±`scale`.
    pub fn vector(&mut self, scale: Real) -> Vec3 {
        scale * Vec3::new(self.symmetric(), self.symmetric(), self.symmetric())
    }
}
