//! The clock behind this crate's replacements of Ipopt's `CpuTime()` and `WallclockTime()`
//! (`ffi.rs`, where the C symbols are defined), and how often Ipopt read each.
//!
//! Debian's Ipopt 3.11 reads both clocks at every start and stop of its timed tasks, about 140
//! reads per iteration: even at the monotonic clock's 20 ns a read, 4 % of a design10 census
//! (2026-11-28). So with 3.11 each thread reads the real clock at every [`REFRESH`]-th read and
//! returns its last reading in between: the clock stays monotonic and lags by at most 15 reads (a
//! few microseconds of Ipopt's work), which is what its timing statistics and `max_cpu_time` see.
//! Each solve starts with a fresh reading ([`refresh`]): without it, a thread's first reads of a
//! solve returned its last reading of the solve before, and Ipopt's statistics counted the time
//! between the two solves as its own (0.31 s of "CPU secs in IPOPT" for a 4 ms solve, 2026-11-29).

use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;
use std::time::Instant;

/// The two replaced clocks.
#[derive(Clone, Copy)]
pub(crate) enum Clock {
    Cpu = 0,
    Wall = 1,
}

/// Reads of the replaced `Ipopt::CpuTime()` and `Ipopt::WallclockTime()` in this process (0 where
/// the library binds its own clocks; counted at each thread's refreshes): the test that the
/// replacements are used.
static READS: [AtomicUsize; 2] = [AtomicUsize::new(0), AtomicUsize::new(0)];

/// How many times Ipopt has read `clock` (up to each thread's last refresh).
pub(crate) fn reads(clock: Clock) -> usize {
    READS[clock as usize].load(Ordering::Relaxed)
}

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

/// Makes this thread's next read a real reading (at the start of a solve).
pub(crate) fn refresh() {
    LAST.with(|last| last.set((0, last.get().1)));
}

/// Seconds of the monotonic clock since the first read in the process, refreshed at every
/// [`REFRESH`]-th read on this thread; the read is counted for `clock`.
pub(crate) fn read(clock: Clock) -> f64 {
    static START: OnceLock<Instant> = OnceLock::new();
    UNCOUNTED.with(|u| {
        let mut counts = u.get();
        counts[clock as usize] += 1;
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
        let counts = UNCOUNTED.with(|u| u.replace([0, 0]));
        for (total, count) in READS.iter().zip(counts) {
            total.fetch_add(count, Ordering::Relaxed);
        }
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
        let before = reads(Clock::Cpu);
        let first = read(Clock::Cpu);
        std::thread::sleep(std::time::Duration::from_millis(2));
        let mut previous = first;
        let mut moved = false;
        for _ in 0..REFRESH {
            let now = read(Clock::Cpu);
            assert!(now >= previous);
            moved |= now > first + 1e-3;
            previous = now;
        }
        assert!(moved, "no fresh reading within {REFRESH} reads");
        assert!(reads(Clock::Cpu) - before >= REFRESH as usize);
    }

    /// After [`refresh`] the next read is a real one, however few reads came since the last.
    #[test]
    fn a_refresh_makes_the_next_read_fresh() {
        let _ = read(Clock::Wall);
        let stale = read(Clock::Wall);
        std::thread::sleep(std::time::Duration::from_millis(5));
        refresh();
        let fresh = read(Clock::Wall);
        assert!(fresh >= stale + 4e-3, "{stale} then {fresh}");
    }
}
