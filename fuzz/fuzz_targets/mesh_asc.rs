//! The ASC reader and the closed-surface check on any bytes.
#![no_main]

#[path = "common/mesh.rs"]
mod mesh;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| mesh::check(data, sprung_io::mesh::MeshFormat::Asc, "fuzz.asc"));
