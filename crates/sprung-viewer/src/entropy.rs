//! Random bytes for getrandom's `custom` backend on the web (selected in
//! `.cargo/config.toml` for `wasm32-unknown-unknown`): macroquad's loader
//! offers no JavaScript for getrandom, and the only thing that asks is the
//! mesh loader's hash maps (tobj → ahash) for seeds, which need no secrecy.
//! So the bytes come from splitmix64 over a counter.

use std::sync::atomic::{AtomicU64, Ordering};

static STATE: AtomicU64 = AtomicU64::new(0x5EED_5EED_5EED_5EED);

/// Fill `len` bytes at `dest` (getrandom 0.3's custom-backend hook).
///
/// # Safety
/// getrandom calls it with `dest` valid for writes of `len` bytes.
#[no_mangle]
unsafe extern "Rust" fn __getrandom_v03_custom(
    dest: *mut u8,
    len: usize,
) -> Result<(), getrandom::Error> {
    for i in 0..len {
        let mut z = STATE
            .fetch_add(0x9E37_79B9_7F4A_7C15, Ordering::Relaxed)
            .wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        // SAFETY: the caller gives `len` writable bytes at `dest`.
        unsafe { dest.add(i).write((z ^ (z >> 31)) as u8) };
    }
    Ok(())
}
