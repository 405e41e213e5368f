//! Work shared by the calling thread and one helper from rayon's pool, where the caller never
//! waits for the helper to start.
//!
//! The sensitivity step is short (about a tenth of a millisecond at N = 10), as short as the
//! time a sleeping pool thread takes to wake. Handed to the pool as a whole (`rayon::scope`,
//! `rayon::join` from outside the pool), the step first waited for a worker to wake, and the
//! caller waited again to be woken at its end: measured with one pool thread, 315 µs against
//! 226 µs for the same work done on the calling thread alone. Here the caller starts at once
//! and the helper is offered the same tasks: each task is claimed by whichever thread asks
//! first, so a helper that wakes late (or a machine with one free core) costs nothing but the
//! offer, and a helper that wakes early halves the shared part.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::OnceLock;

/// Tasks `0..n`, each claimed once, by whichever thread asks first.
pub(crate) struct Claims {
    next: AtomicUsize,
    n: usize,
}

impl Claims {
    pub fn new(n: usize) -> Self {
        Self { next: AtomicUsize::new(0), n }
    }

    /// The next unclaimed task, or `None` when every task is taken.
    pub fn claim(&self) -> Option<usize> {
        let i = self.next.fetch_add(1, Ordering::Relaxed);
        (i < self.n).then_some(i)
    }
}

/// One task, claimed once: `run` gives its result to whichever thread claims it first.
pub(crate) struct Once<T> {
    claimed: AtomicBool,
    result: OnceLock<T>,
}

impl<T> Once<T> {
    pub fn new() -> Self {
        Self { claimed: AtomicBool::new(false), result: OnceLock::new() }
    }

    /// Runs `task` if no thread has claimed it yet.
    pub fn run(&self, task: impl FnOnce() -> T) {
        if !self.claimed.swap(true, Ordering::AcqRel) {
            // Only the claiming thread sets the result.
            let _ = self.result.set(task());
        }
    }

    /// The result, once the scope in which the task was run has ended.
    pub fn into_inner(self) -> Option<T> {
        self.result.into_inner()
    }
}

/// Runs `caller` on this thread while `helper` is offered to rayon's pool, and returns the
/// caller's result when both are done (the helper's panics reach the caller). Called from a pool
/// thread, the helper goes on that thread's own queue, and the thread runs it itself at the end
/// if nobody stole it.
pub(crate) fn with_helper<R>(helper: impl FnOnce() + Send, caller: impl FnOnce() -> R) -> R {
    rayon::in_place_scope(|scope| {
        scope.spawn(|_| helper());
        caller()
    })
}

/// A flag one thread raises and another reads: that a part has started, or has ended (normally
/// or by a panic, with the guard of [`Flag::raise_on_drop`]).
#[derive(Default)]
pub(crate) struct Flag(AtomicBool);

impl Flag {
    pub fn raise(&self) {
        self.0.store(true, Ordering::Release);
    }

    /// A guard that raises the flag when it is dropped, unwinding included.
    pub fn raise_on_drop(&self) -> impl Drop + '_ {
        struct Guard<'f>(&'f Flag);
        impl Drop for Guard<'_> {
            fn drop(&mut self) {
                self.0.raise();
            }
        }
        Guard(self)
    }

    pub fn raised(&self) -> bool {
        self.0.load(Ordering::Acquire)
    }
}

/// Polls `ready` (yielding between polls) until it gives a value, or until `other` (raised when
/// the other part ends) is raised and `ready` still gives none: then `None` (what `other` was to produce will not come).
pub(crate) fn wait<T>(other: &Flag, mut ready: impl FnMut() -> Option<T>) -> Option<T> {
    loop {
        if let Some(value) = ready() {
            return Some(value);
        }
        if other.raised() {
            return ready();
        }
        std::thread::yield_now();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tasks claimed by two threads: each runs once, whichever thread claims it; from outside
    /// any pool (the test's thread, with the global pool) and from inside pools of one, two and
    /// four threads.
    #[test]
    fn every_task_runs_once() {
        for threads in [0, 1, 2, 4] {
            let claims = Claims::new(50);
            let slots: Vec<OnceLock<usize>> = (0..50).map(|_| OnceLock::new()).collect();
            let runs = AtomicUsize::new(0);
            let work = || {
                while let Some(i) = claims.claim() {
                    runs.fetch_add(1, Ordering::Relaxed);
                    slots[i].set(i * i).unwrap();
                }
            };
            if threads == 0 {
                with_helper(work, work);
            } else {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
                pool.install(|| with_helper(work, work));
            }
            assert_eq!(runs.load(Ordering::Relaxed), 50);
            assert!(slots.iter().enumerate().all(|(i, s)| s.get() == Some(&(i * i))));
        }
        assert_eq!(Claims::new(0).claim(), None);
    }

    /// A wait ends with the value, or with `None` once the other part has ended without it.
    #[test]
    fn a_wait_ends_when_the_other_part_ends() {
        let (ended, slot) = (Flag::default(), OnceLock::new());
        std::thread::scope(|s| {
            s.spawn(|| {
                let _guard = ended.raise_on_drop();
                std::thread::sleep(std::time::Duration::from_millis(5));
                slot.set(3).unwrap();
            });
            assert_eq!(wait(&ended, || slot.get().copied()), Some(3));
        });
        let (ended, slot) = (Flag::default(), OnceLock::<usize>::new());
        let result = std::thread::scope(|s| {
            s.spawn(|| {
                // Its guard raises the flag while the panic unwinds.
                let failed = std::panic::catch_unwind(|| {
                    let _guard = ended.raise_on_drop();
                    panic!("the other part fails");
                });
                assert!(failed.is_err());
            });
            wait(&ended, || slot.get().copied())
        });
        assert_eq!(result, None);
    }

    /// A task claimed by both threads runs once.
    #[test]
    fn a_single_task_runs_once() {
        for _ in 0..100 {
            let task = Once::new();
            let runs = AtomicUsize::new(0);
            let run = || {
                task.run(|| runs.fetch_add(1, Ordering::Relaxed));
            };
            with_helper(run, run);
            assert_eq!(runs.load(Ordering::Relaxed), 1);
            assert_eq!(task.into_inner(), Some(0));
        }
    }

    /// A panic in the helper reaches the caller.
    #[test]
    fn the_helpers_panic_reaches_the_caller() {
        let result = std::panic::catch_unwind(|| with_helper(|| panic!("helper"), || 1));
        assert!(result.is_err());
    }
}
