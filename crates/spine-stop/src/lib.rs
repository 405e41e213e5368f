//! When a long computation stops early, and how much memory it may take before it must.
//!
//! Modules: `memory`: the process's memory budget, which every structure that grows with the input
//! is checked against before it is made.
//!
//! Two reasons, one check: a request from outside the run ([`request_interrupt`]: the CLI's
//! Ctrl-C and SIGTERM handler, Python's `KeyboardInterrupt`), which holds for the whole process,
//! and a wall-clock time limit ([`with_time_limit`]), which holds for the calling thread while its
//! closure runs (runs on other threads, e.g. parallel tests, keep their own). Every loop whose
//! length the input decides calls [`check`] once per iteration: Ipopt through its intermediate
//! callback, the integrator and equilibrium continuation once per step, the searches once per
//! generation or poll, a multi-start before each start. A loop that sees `Some(reason)` ends as
//! soon as it can with what it has and says why in its status (`time_limit` or `interrupted`).
//!
//! ```
//! use std::time::Duration;
//! let ((steps, reason), reached) = spine_stop::with_time_limit(Some(Duration::from_millis(20)), || {
//!     let mut steps = 0u64;
//!     loop {
//!         if let Some(reason) = spine_stop::check() {
//!             return (steps, reason);
//!         }
//!         steps += 1;
//!     }
//! });
//! assert_eq!(reason, spine_stop::StopReason::TimeLimit);
//! assert!(steps > 0 && reached);
//! assert_eq!(spine_stop::check(), None); // the limit ended with its closure
//! ```
#![forbid(unsafe_code)]

pub mod memory;

use serde::Serialize;
use std::cell::Cell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Why a computation stopped before it finished.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// A stop was requested from outside ([`request_interrupt`]).
    Interrupted,
    /// The run's wall-clock time limit passed ([`with_time_limit`]).
    TimeLimit,
}

impl StopReason {
    /// The snake_case name written in results (`interrupted`, `time_limit`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Interrupted => "interrupted",
            Self::TimeLimit => "time_limit",
        }
    }
}

static INTERRUPT: AtomicBool = AtomicBool::new(false);

thread_local! {
    static DEADLINE: Cell<Option<Instant>> = const { Cell::new(None) };
    static TIME_LIMIT_SEEN: Cell<bool> = const { Cell::new(false) };
}

/// Asks every computation in this process to stop at its next check. Stays set until
/// [`clear_interrupt`].
pub fn request_interrupt() {
    INTERRUPT.store(true, Ordering::SeqCst);
}

/// Withdraws a request to stop (a Python session goes on after a `KeyboardInterrupt`).
pub fn clear_interrupt() {
    INTERRUPT.store(false, Ordering::SeqCst);
}

/// Whether a stop was requested from outside.
pub fn interrupt_requested() -> bool {
    INTERRUPT.load(Ordering::SeqCst)
}

/// Whether the computation should stop now, and why (an outside request first).
pub fn check() -> Option<StopReason> {
    if interrupt_requested() {
        return Some(StopReason::Interrupted);
    }
    let deadline = DEADLINE.with(Cell::get)?;
    if Instant::now() >= deadline {
        TIME_LIMIT_SEEN.with(|s| s.set(true));
        return Some(StopReason::TimeLimit);
    }
    None
}

/// This thread's deadline, if it runs under a time limit: what a thread that works for it takes
/// along ([`with_deadline`]).
pub fn deadline() -> Option<Instant> {
    DEADLINE.with(Cell::get)
}

/// Runs `f` on this thread under `deadline` (the [`deadline`] of the thread it works for, e.g. a
/// pool thread evaluating part of a GA generation). Returns `f`'s value and whether some loop
/// inside saw the deadline pass.
pub fn with_deadline<R>(deadline: Option<Instant>, f: impl FnOnce() -> R) -> (R, bool) {
    with_time_limit(deadline.map(|d| d.saturating_duration_since(Instant::now())), f)
}

/// Runs `f` with a wall-clock limit of `limit` on this thread (`None`: no limit of its own).
/// Limits nest: the inner one never extends the outer one. Returns `f`'s value and whether some
/// loop inside saw the limit pass (that loop ended early and says so in its own status).
pub fn with_time_limit<R>(limit: Option<Duration>, f: impl FnOnce() -> R) -> (R, bool) {
    let outer = DEADLINE.with(Cell::get);
    let seen = TIME_LIMIT_SEEN.with(|s| s.replace(false));
    let mine = limit.and_then(|d| Instant::now().checked_add(d));
    let deadline = match (outer, mine) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    };
    // Restores the outer limit even if `f` unwinds.
    struct Restore(Option<Instant>, bool);
    impl Drop for Restore {
        fn drop(&mut self) {
            DEADLINE.with(|d| d.set(self.0));
            let inner = TIME_LIMIT_SEEN.with(Cell::get);
            TIME_LIMIT_SEEN.with(|s| s.set(self.1 || inner));
        }
    }
    let _restore = Restore(outer, seen);
    DEADLINE.with(|d| d.set(deadline));
    let value = f();
    (value, time_limit_reached())
}

/// How long a finishing step may run past a time limit that has passed ([`finishing`]).
pub const FINISHING_GRACE: Duration = Duration::from_millis(300);

/// Runs `f`, one finishing step that makes a stopped run's result usable (re-simulating the best
/// point a search found before its time limit passed), with at least [`FINISHING_GRACE`] from now
/// when the run has a limit: the later of the run's own deadline and now plus the grace, so that
/// no run overshoots its limit by more than the grace (and a loop's last step). A finishing step
/// cut by the grace ends as any stopped loop does, and says so. An outside stop still holds; the
/// run's limit is back when `f` returns.
pub fn finishing<R>(f: impl FnOnce() -> R) -> R {
    struct Restore(Option<Instant>);
    impl Drop for Restore {
        fn drop(&mut self) {
            DEADLINE.with(|d| d.set(self.0));
        }
    }
    let outer = DEADLINE.with(Cell::get);
    let grace = outer.map(|d| d.max(Instant::now() + FINISHING_GRACE));
    let _restore = Restore(DEADLINE.with(|d| d.replace(grace)));
    f()
}

/// Whether some loop on this thread saw the time limit pass inside the innermost
/// [`with_time_limit`] running now.
pub fn time_limit_reached() -> bool {
    TIME_LIMIT_SEEN.with(Cell::get)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_limit_never_stops_and_limits_nest_and_end_with_their_closure() {
        assert_eq!(check(), None);
        with_time_limit(None, || assert_eq!(check(), None));
        let ((), reached) = with_time_limit(Some(Duration::from_secs(3600)), || {
            assert_eq!(check(), None);
            // An inner limit already passed stops; the outer one is back afterwards.
            let ((), inner) =
                with_time_limit(Some(Duration::ZERO), || assert_eq!(check(), Some(StopReason::TimeLimit)));
            assert!(inner);
            assert_eq!(check(), None);
            assert!(time_limit_reached(), "the inner stop is reported to the outer run");
        });
        assert!(reached);
        // A fresh run starts without the earlier one's stop.
        let ((), reached) = with_time_limit(Some(Duration::from_secs(3600)), || assert!(!time_limit_reached()));
        assert!(!reached);
        // An inner, longer limit does not extend an outer one that passed.
        let (((), _), reached) = with_time_limit(Some(Duration::ZERO), || {
            with_time_limit(Some(Duration::from_secs(3600)), || assert_eq!(check(), Some(StopReason::TimeLimit)))
        });
        assert!(reached);
        assert_eq!(check(), None);
    }

    #[test]
    fn a_finishing_step_runs_within_its_grace_and_the_limit_is_back_afterwards() {
        let ((), reached) = with_time_limit(Some(Duration::ZERO), || {
            assert_eq!(finishing(check), None, "a finishing step has its grace");
            // The grace ends: a finishing loop longer than it is stopped like any other.
            let clock = Instant::now();
            let stopped = finishing(|| loop {
                if let Some(reason) = check() {
                    break reason;
                }
            });
            assert_eq!(stopped, StopReason::TimeLimit);
            let took = clock.elapsed();
            assert!(took >= FINISHING_GRACE && took < FINISHING_GRACE + Duration::from_millis(500), "{took:?}");
            assert_eq!(check(), Some(StopReason::TimeLimit));
        });
        assert!(reached);
        // Without a limit a finishing step has none either.
        assert_eq!(finishing(check), None);
        assert_eq!(finishing(deadline), None);
    }

    #[test]
    fn a_limit_on_one_thread_does_not_stop_another() {
        with_time_limit(Some(Duration::ZERO), || {
            assert_eq!(check(), Some(StopReason::TimeLimit));
            let other = std::thread::spawn(check).join().unwrap();
            assert_eq!(other, None);
        });
    }

    #[test]
    fn time_limit_reached_is_false_when_the_loop_finished_in_time() {
        let ((), reached) = with_time_limit(Some(Duration::from_secs(3600)), || assert_eq!(check(), None));
        assert!(!reached);
    }
}
