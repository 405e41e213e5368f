//! The clock behind this crate's replacements of Ipopt's `CpuTime()` and `WallclockTime()`
//! (`ffi.rs`, where the C symbols are defined), and how often Ipopt read each.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;
use std::time::Instant;

/// Reads of the replaced `Ipopt::CpuTime()` and `Ipopt::WallclockTime()` in this process (0 where
/// the library binds its own clocks): the test that the replacements are used.
pub(crate) static CPU_TIME_CALLS: AtomicUsize = AtomicUsize::new(0);
pub(crate) static WALL_CLOCK_CALLS: AtomicUsize = AtomicUsize::new(0);

/// Seconds of the monotonic clock since the first read of either clock, counted in `calls`.
pub(crate) fn read(calls: &AtomicUsize) -> f64 {
    static START: OnceLock<Instant> = OnceLock::new();
    calls.fetch_add(1, Ordering::Relaxed);
    START.get_or_init(Instant::now).elapsed().as_secs_f64()
}
