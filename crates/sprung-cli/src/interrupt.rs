//! SIGINT (Ctrl-C) and SIGTERM: a run stops at the end of its current step
//! (which the engine ends as soon as it validly can, `sprung::interrupt`),
//! keeps every row and frame it recorded, and exits with the conventional
//! status 128 + the signal (130, 143). A second signal of either kind ends
//! the process at once with that status.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

use signal_hook::consts::{SIGINT, SIGTERM};

/// Whether a signal came, and which.
struct Received {
    any: Arc<AtomicBool>,
    which: Arc<AtomicUsize>,
}

static RECEIVED: OnceLock<Option<Received>> = OnceLock::new();

/// Install the handlers (once per process); `false` when the system
/// refused them (the run then goes on without them).
pub fn install() -> bool {
    RECEIVED
        .get_or_init(|| {
            let any = Arc::new(AtomicBool::new(false));
            let which = Arc::new(AtomicUsize::new(0));
            for signal in [SIGINT, SIGTERM] {
                let exit = 128 + signal as u32;
                // The second signal: exit at once. Registered first, so it
                // sees the flag as the earlier signal left it.
                signal_hook::flag::register_conditional_shutdown(
                    signal,
                    exit as i32,
                    Arc::clone(&any),
                )
                .ok()?;
                signal_hook::flag::register(signal, Arc::clone(&any)).ok()?;
                signal_hook::flag::register_usize(signal, Arc::clone(&which), signal as usize)
                    .ok()?;
            }
            // The engine ends the step under way as soon as it validly
            // can once the flag is up, so the run stops within a fraction
            // of a second whatever stage it is in.
            sprung::interrupt::watch(Arc::clone(&any));
            Some(Received { any, which })
        })
        .is_some()
}

/// Exit quietly with status 141 (128 + SIGPIPE) when what reads the
/// output goes away (`sprung check scene.toml | head -2`), as command-line
/// tools do, instead of failing to print (Rust ignores SIGPIPE, so a
/// write to the closed pipe would panic). The process ends at once, as if
/// killed: a run's outputs stay as a kill leaves them (the rows so far in
/// `diagnostics.csv.partial`, which `--resume` goes on from).
pub fn quiet_on_broken_pipe() {
    #[cfg(unix)]
    {
        use signal_hook::consts::SIGPIPE;
        let always = Arc::new(AtomicBool::new(true));
        // Refused (no handler): the old behaviour stays.
        let _ = signal_hook::flag::register_conditional_shutdown(SIGPIPE, 128 + SIGPIPE, always);
    }
}

/// The signal received since [`install`], if any.
pub fn received() -> Option<Signal> {
    let received = RECEIVED.get()?.as_ref()?;
    if !received.any.load(Ordering::SeqCst) {
        return None;
    }
    match received.which.load(Ordering::SeqCst) as i32 {
        SIGTERM => Some(Signal::Terminate),
        _ => Some(Signal::Interrupt),
    }
}

/// A signal that stops a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Signal {
    /// SIGINT (Ctrl-C): exit status 130.
    Interrupt,
    /// SIGTERM: exit status 143.
    Terminate,
}

impl Signal {
    /// The conventional exit status, 128 + the signal number.
    pub fn exit_code(self) -> u8 {
        match self {
            Signal::Interrupt => 130,
            Signal::Terminate => 143,
        }
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            Signal::Interrupt => "SIGINT",
            Signal::Terminate => "SIGTERM",
        }
    }
}
