//! Scene files, meshes and exports.
