//! What every mesh target does: read `data` as `format`, then run the
//! closed-surface check on what was read; `Ok` or an error, never a panic.

use sprung_io::mesh::{closed_surface, parse_mesh, MeshFormat};

pub fn check(data: &[u8], format: MeshFormat, path: &str) {
    let path = std::path::Path::new(path);
    if let Ok(meshes) = parse_mesh(data, format, path) {
        for mesh in &meshes {
            let _ = closed_surface(mesh, path);
        }
    }
}
