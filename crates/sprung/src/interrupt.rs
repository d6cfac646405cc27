//! A request, from outside the engine, to finish the step under way as
//! soon as it validly can: a program stopping on SIGINT or SIGTERM (`sprung
//! run`) sets a flag it handed to [`watch`], and the engine's long loops
//! poll it. An implicit solve then stops iterating (the step is taken
//! less accurately and counted as unconverged, as a solve that reached its
//! iteration limit), and the CCD that no particle passes through a
//! surface takes its fail-safe (the colliding bodies keep where they
//! started the step, [`crate::contact::ccd`]), so the step ends in a
//! valid state within a fraction of a second, whatever stage it was in,
//! and the program stops after it.
//!
//! The flag is the process's: every world polls the same one.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

static WATCHED: OnceLock<Arc<AtomicBool>> = OnceLock::new();

/// Poll `flag` from now on: while it is `true`, each step finishes as
/// soon as it validly can. The first flag given stays; `false` where one
/// was already watched (it then goes on being polled).
pub fn watch(flag: Arc<AtomicBool>) -> bool {
    WATCHED.set(flag).is_ok()
}

/// Whether a stop was asked for: the watched flag is set.
pub fn requested() -> bool {
    WATCHED
        .get()
        .is_some_and(|flag| flag.load(Ordering::Relaxed))
}
