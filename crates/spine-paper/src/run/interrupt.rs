//! A request to stop, from outside the run (the CLI's Ctrl-C and SIGTERM handler, a Python
//! KeyboardInterrupt): Ipopt stops at its next iteration through its user-stop hook, a multi-start
//! before its next start, and the run returns [`super::RunError::Interrupted`].

use std::sync::atomic::{AtomicBool, Ordering};

static STOP: AtomicBool = AtomicBool::new(false);

/// Asks every run in this process to stop at its next check.
pub fn request_stop() {
    STOP.store(true, Ordering::SeqCst);
}

/// Whether a stop was requested.
pub fn stop_requested() -> bool {
    STOP.load(Ordering::SeqCst)
}
