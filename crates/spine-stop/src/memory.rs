//! The memory a run may take: one budget for the process ([`budget`]), which every structure that
//! grows with the input (the integrator's stored steps, a multi-start's results, a sweep's points,
//! a shard's runs) is checked against before it is made ([`fits`]). Rust ends the process when an
//! allocation fails, so a run that would need more is refused, with the fields that decide its
//! size (exit code 2), or stopped with what it reached (exit code 3), never aborted.
//!
//! The budget is the smallest of [`DEFAULT_BUDGET`], [`ADDRESS_SPACE_SHARE`] of the process's
//! address-space limit (`ulimit -v`, `prlimit --as`; the allocator, the libraries, thread stacks
//! and a growing vector's old and new buffers share it) and [`MACHINE_SHARE`] of the machine's
//! memory. It is read once, from Linux's `/proc` (elsewhere only the default holds).
//!
//! ```
//! let budget = spine_stop::memory::budget();
//! assert!(budget > 0 && budget <= spine_stop::memory::DEFAULT_BUDGET);
//! assert!(spine_stop::memory::fits(1e3).is_ok());
//! let e = spine_stop::memory::fits(1e30).unwrap_err();
//! assert!(e.contains("memory budget"), "{e}");
//! ```

use std::sync::OnceLock;

/// The budget where nothing smaller is set, bytes (4 GiB).
pub const DEFAULT_BUDGET: usize = 4 << 30;
/// The share of an address-space limit a run's growing data may take.
pub const ADDRESS_SPACE_SHARE: f64 = 0.35;
/// The share of the machine's memory a run's growing data may take.
pub const MACHINE_SHARE: f64 = 0.5;

/// The process's memory budget, bytes (module docs).
pub fn budget() -> usize {
    static BUDGET: OnceLock<usize> = OnceLock::new();
    *BUDGET.get_or_init(|| {
        let mut budget = DEFAULT_BUDGET as f64;
        if let Some(limit) = address_space_limit() {
            budget = budget.min(ADDRESS_SPACE_SHARE * limit as f64);
        }
        if let Some(total) = machine_memory() {
            budget = budget.min(MACHINE_SHARE * total as f64);
        }
        (budget as usize).max(1 << 20)
    })
}

/// `Ok` when `bytes` fit in [`budget`]; else what they would take against the budget, for a
/// message that names the fields deciding the size.
pub fn fits(bytes: f64) -> Result<(), String> {
    let budget = budget();
    if bytes.is_finite() && bytes <= budget as f64 {
        Ok(())
    } else {
        Err(format!(
            "would need about {} of memory, more than the memory budget of {} ({})",
            shown_bytes(bytes),
            shown_bytes(budget as f64),
            "the least of 4 GiB, 35 % of the address-space limit and half the machine's memory"
        ))
    }
}

/// Bytes as a person reads them: `3.2 GB`, `512 MB`, `1e+15 B` beyond a petabyte.
pub fn shown_bytes(bytes: f64) -> String {
    match bytes {
        b if !b.is_finite() || b >= 1e15 => format!("{b:.1e} B"),
        b if b >= 1e9 => format!("{:.1} GB", b / 1e9),
        b if b >= 1e6 => format!("{:.0} MB", b / 1e6),
        b if b >= 1e3 => format!("{:.0} kB", b / 1e3),
        b => format!("{b:.0} B"),
    }
}

/// The soft address-space limit, bytes (`None`: unlimited, or not Linux).
fn address_space_limit() -> Option<u64> {
    let limits = std::fs::read_to_string("/proc/self/limits").ok()?;
    let line = limits.lines().find(|l| l.starts_with("Max address space"))?;
    line.trim_start_matches("Max address space").split_whitespace().next()?.parse().ok()
}

/// The machine's memory, bytes (`MemTotal`; `None` off Linux).
fn machine_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kb: u64 = line.trim_start_matches("MemTotal:").split_whitespace().next()?.parse().ok()?;
    Some(kb * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_read_plainly_and_the_budget_is_bounded() {
        assert_eq!(shown_bytes(3.2e9), "3.2 GB");
        assert_eq!(shown_bytes(5.12e8), "512 MB");
        assert_eq!(shown_bytes(2e16), "2.0e16 B");
        assert!(budget() <= DEFAULT_BUDGET && budget() >= 1 << 20);
        assert!(fits(f64::NAN).is_err() && fits(f64::INFINITY).is_err());
    }
}
