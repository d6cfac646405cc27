//! The state-file reader (`--resume`) on any bytes, for a small world: an
//! error, or a state that `restore_state` takes or refuses; never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sprung::{build, IntegratorKind, World};
use sprung_io::state::decode_state;

fuzz_target!(|data: &[u8]| {
    let mut world = World::new(IntegratorKind::Verlet);
    let rope = build::rope(4, 1.0).expect("a valid rope");
    world.add_body("rope", rope).expect("a valid body");
    let path = std::path::Path::new("state.bin");
    if let Ok(state) = decode_state(data, &world, path) {
        let _ = world.restore_state(&state);
    }
});
