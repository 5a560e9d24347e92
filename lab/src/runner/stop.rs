//! Stopping cleanly on SIGINT and SIGTERM.
//!
//! [`install`] (called once by the binary) makes both signals set a flag
//! instead of killing the process; a second signal of either kind exits at
//! once with `128 + signal`. The runner polls the flag before each cell and
//! before each chunk of realisations inside a cell ([`super::Ctx`]), so a
//! stopped run ends within one chunk: every finished cell is already in the
//! state folder, no output file is written, and the same command resumes.
//! SIGTERM is what batch schedulers (Slurm at a time limit, `timeout`,
//! systemd) send, and SIGINT is Ctrl-C; the handlers are installed even where
//! SIGINT was inherited as ignored (background jobs of a non-interactive
//! shell), so both stop the same way in any shell.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

use signal_hook::consts::{SIGINT, SIGTERM};

use crate::{LabError, Result};

struct Flags {
    stop: Arc<AtomicBool>,
    signal: Arc<AtomicUsize>,
}

static FLAGS: OnceLock<Flags> = OnceLock::new();

fn flags() -> &'static Flags {
    FLAGS.get_or_init(|| Flags {
        stop: Arc::new(AtomicBool::new(false)),
        signal: Arc::new(AtomicUsize::new(0)),
    })
}

/// Installs the SIGINT and SIGTERM handlers (idempotent).
///
/// # Errors
/// A [`LabError::Message`] if the operating system refuses a handler.
pub fn install() -> Result<()> {
    // The outcome is kept (and cloned) as a message: an I/O error is not
    // `Clone`.
    static DONE: OnceLock<Result<(), String>> = OnceLock::new();
    DONE.get_or_init(|| {
        let f = flags();
        for sig in [SIGINT, SIGTERM] {
            let name = signal_name(sig);
            // Order matters: the exit check runs before the flag is set, so
            // the first signal only sets it and the second one exits.
            signal_hook::flag::register_conditional_shutdown(sig, 128 + sig, Arc::clone(&f.stop))
                .map_err(|e| format!("cannot install the {name} handler: {e}"))?;
            signal_hook::flag::register_usize(sig, Arc::clone(&f.signal), sig as usize)
                .map_err(|e| format!("cannot install the {name} handler: {e}"))?;
            signal_hook::flag::register(sig, Arc::clone(&f.stop))
                .map_err(|e| format!("cannot install the {name} handler: {e}"))?;
        }
        Ok(())
    })
    .clone()
    .map_err(LabError::Message)
}

/// The signal that asked the run to stop, if one did.
#[must_use]
pub fn requested() -> Option<i32> {
    let f = flags();
    if f.stop.load(Ordering::Relaxed) {
        let s = f.signal.load(Ordering::Relaxed);
        Some(i32::try_from(s).unwrap_or(SIGTERM))
    } else {
        None
    }
}

/// `SIGINT`, `SIGTERM`, or `signal N`.
#[must_use]
pub fn signal_name(sig: i32) -> String {
    match sig {
        SIGINT => "SIGINT".into(),
        SIGTERM => "SIGTERM".into(),
        s => format!("signal {s}"),
    }
}

/// The error a cell returns when the run was asked to stop (replaced by the
/// runner's [`LabError::Stopped`]).
pub(crate) const STOPPED: &str = "stopped by a signal";

/// `Err(STOPPED)` once a stop was requested.
pub(crate) fn check() -> Result<()> {
    match requested() {
        Some(_) => Err(LabError::Message(STOPPED.into())),
        None => Ok(()),
    }
}
