//! Scene files, meshes and exports.

pub mod mesh;
