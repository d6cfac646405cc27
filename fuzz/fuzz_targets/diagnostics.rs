//! The `diagnostics.csv` reader of `sprung plot` on any text: `Ok` or an
//! error, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sprung_view::plot::DiagnosticsTable;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = DiagnosticsTable::parse(text, std::path::Path::new("diagnostics.csv"));
    }
});
