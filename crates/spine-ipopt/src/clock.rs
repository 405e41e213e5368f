//! The clock behind this crate's replacements of Ipopt's `CpuTime()` and `WallclockTime()`
//! (`ffi.rs`, where the C symbols are defined), and how often Ipopt read each.
//!
//! Debian's Ipopt 3.11 reads both clocks at every start and stop of its timed tasks, about 140
//! reads per iteration: even at the monotonic clock's 20 ns a read, 4 % of a design10 census
//! (2026-11-28). So with 3.11 each thread reads the real clock at every [`REFRESH`]-th read and
//! returns its last reading in between: the clock stays monotonic and lags by at most 15 reads (a
//! few microseconds of Ipopt's work), which is what its timing statistics and `max_cpu_time` see.

use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;
use std::time::Instant;

/// Reads of the replaced `Ipopt::CpuTime()` and `Ipopt::WallclockTime()` in this process (0 where
/// the library binds its own clocks; counted in steps of [`REFRESH`] per thread): the test that
/// the replacements are used.
pub(crate) static CPU_TIME_CALLS: AtomicUsize = AtomicUsize::new(0);
pub(crate) static WALL_CLOCK_CALLS: AtomicUsize = AtomicUsize::new(0);

/// One read in this many reads the real clock: 16 with Ipopt 3.11, whose timed tasks read it
/// about 140 times an iteration; every read with later versions, which read it a few times a
/// solve (a clock refreshed every 16th read would be stale there for a whole short solve, and
/// `max_cpu_time` would not see it pass).
pub(crate) const REFRESH: u32 = if is_3_11(crate::IPOPT_VERSION) { 16 } else { 1 };

const fn is_3_11(version: &str) -> bool {
    let v = version.as_bytes();
    v.len() >= 4 && v[0] == b'3' && v[1] == b'.' && v[2] == b'1' && v[3] == b'1'
}

thread_local! {
    /// This thread's reads since its last real reading, that reading, and the reads of each clock
    /// not yet counted.
    static LAST: Cell<(u32, f64)> = const { Cell::new((0, 0.0)) };
    static UNCOUNTED: Cell<[usize; 2]> = const { Cell::new([0, 0]) };
}

/// Seconds of the monotonic clock since the first read in the process, refreshed at every
/// [`REFRESH`]-th read on this thread; the read is counted in `calls`.
pub(crate) fn read(calls: &'static AtomicUsize) -> f64 {
    static START: OnceLock<Instant> = OnceLock::new();
    let which = usize::from(!std::ptr::eq(calls, &CPU_TIME_CALLS));
    UNCOUNTED.with(|u| {
        let mut counts = u.get();
        counts[which] += 1;
        u.set(counts);
    });
    LAST.with(|last| {
        let (reads, seconds) = last.get();
        if reads % REFRESH != 0 {
            last.set((reads + 1, seconds));
            return seconds;
        }
        let seconds = START.get_or_init(Instant::now).elapsed().as_secs_f64();
        last.set((reads + 1, seconds));
        UNCOUNTED.with(|u| {
            let counts = u.replace([0, 0]);
            CPU_TIME_CALLS.fetch_add(counts[0], Ordering::Relaxed);
            WALL_CLOCK_CALLS.fetch_add(counts[1], Ordering::Relaxed);
        });
        seconds
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The clock never runs backwards, moves within [`REFRESH`] reads, and counts every read up
    /// to the last refresh.
    #[test]
    fn the_clock_is_monotonic_and_refreshes() {
        let before = CPU_TIME_CALLS.load(Ordering::Relaxed);
        let first = read(&CPU_TIME_CALLS);
        std::thread::sleep(std::time::Duration::from_millis(2));
        let mut previous = first;
        let mut moved = false;
        for _ in 0..REFRESH {
            let now = read(&CPU_TIME_CALLS);
            assert!(now >= previous);
            moved |= now > first + 1e-3;
            previous = now;
        }
        assert!(moved, "no fresh reading within {REFRESH} reads");
        assert!(CPU_TIME_CALLS.load(Ordering::Relaxed) - before >= REFRESH as usize);
    }
}
