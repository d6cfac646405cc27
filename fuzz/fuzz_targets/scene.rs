//! The scene loader on any text: `Ok` or an error, never a panic. Meshes
//! come from the bundled demo meshes, so scenes that name them load them.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sprung_io::demos::Bundled;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let path = std::path::Path::new("scenes/fuzz.toml");
        if let Ok(scene) = sprung_io::parse_scene_with(text, path, &Bundled) {
            let _ = scene.world.stable_time_step();
            let _ = scene.world.energies();
        }
    }
});
