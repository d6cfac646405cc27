//! The STL reader and the topology checks on any bytes: `Ok` or an
//! error, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sprung_io::mesh::{closed_surface, parse_mesh, MeshFormat};

fuzz_target!(|data: &[u8]| {
    let path = std::path::Path::new("fuzz.stl");
    if let Ok(meshes) = parse_mesh(data, MeshFormat::Stl, path) {
        for mesh in &meshes {
            let _ = closed_surface(mesh, path);
        }
    }
});
