//! The engine's numbers: one real type and one vector type, in SI units
//! throughout (m, s, kg, N, J, Pa; in 2D, areas in m² and pressures in
//! N/m). Every room imports them from here, the ground floor.

/// The one real number type of the engine (SI units throughout).
pub type Real = f64;
/// A 3D vector of [`Real`]; 2D scenes use z = 0.
pub type Vec3 = glam::DVec3;
