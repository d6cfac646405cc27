//! The reader of sprung's VTK frames (`sprung render` of a run folder) on
//! any text: `Ok` or an error, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sprung_io::export::read_vtk_frame;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = read_vtk_frame(text, std::path::Path::new("frame_000000.vtk"));
    }
});
