//! The values of the options a run takes from the command line or from a Python call, each checked
//! once, here: the CLI's value parsers (`spine-cli/src/parse.rs`) and flexspine's keyword
//! arguments call these same functions, so the ranges and the messages are the same. A message
//! says what is allowed; the caller names the option (`--starts`, `starts=`).

use crate::animation::{FRAMES, MAX_MAGNIFICATION, WIDTH};
use spine_design::Formulation;
use spine_dynamic_design::SearchMethod;

/// Longest time limit accepted, s (about 11.6 days).
pub const MAX_TIME_LIMIT: f64 = 1e6;

/// A whole number within `allowed` (the message gives the range, with `unit`).
fn within<T: PartialOrd + std::fmt::Display>(
    n: T,
    allowed: std::ops::RangeInclusive<T>,
    unit: &str,
) -> Result<T, String> {
    if allowed.contains(&n) {
        Ok(n)
    } else {
        Err(format!("allowed {}..={}{unit}, got {n}", allowed.start(), allowed.end()))
    }
}

/// Time limit: finite seconds in (0, [`MAX_TIME_LIMIT`]].
pub fn time_limit(seconds: f64) -> Result<std::time::Duration, String> {
    if !(seconds > 0.0 && seconds <= MAX_TIME_LIMIT) {
        return Err(format!("seconds must be > 0 and at most {MAX_TIME_LIMIT:e}, got {seconds}"));
    }
    Ok(std::time::Duration::from_secs_f64(seconds))
}

/// Extra seeded starts: within the bound every case file obeys ([`spine_case::MAX_STARTS`]).
pub fn starts(n: usize) -> Result<usize, String> {
    if n > spine_case::MAX_STARTS {
        return Err(format!("at most {}, got {n}", spine_case::MAX_STARTS));
    }
    Ok(n)
}

/// Seeded starts of each census along a sweep: 1 ..= [`spine_case::MAX_STARTS`] (no census:
/// leave the option out).
pub fn census_starts(n: usize) -> Result<usize, String> {
    if n == 0 {
        return Err("at least 1 seeded start (for no census, leave the option out)".into());
    }
    starts(n)
}

/// A census's target: a probability strictly between 0 and 1.
pub fn confidence(p: f64) -> Result<f64, String> {
    spine_case::check_confidence(p)
}

/// Worker processes: 1..=[`crate::workers::MAX_JOBS`].
pub fn jobs(n: usize) -> Result<usize, String> {
    within(n, 1..=crate::workers::MAX_JOBS, "")
}

/// The spacing of a sweep's censuses: at least every point, at most every 100 000th.
pub fn every(n: usize) -> Result<usize, String> {
    within(n, 1..=100_000, "")
}

/// A batch of a census to a stated confidence: 1..=MAX_STARTS / [`crate::CONFIDENCE_BATCH`].
pub fn batch(b: usize) -> Result<usize, String> {
    within(b, 1..=spine_case::MAX_STARTS / crate::CONFIDENCE_BATCH, "")
}

/// Frames of an animation, within [`FRAMES`].
pub fn frames(n: usize) -> Result<usize, String> {
    within(n, FRAMES, "")
}

/// Width of an animation, within [`WIDTH`] px.
pub fn frame_width(px: u32) -> Result<u32, String> {
    within(px, WIDTH, " px")
}

/// The magnification of an animation's displacements: in (0, [`MAX_MAGNIFICATION`]].
pub fn magnify(factor: f64) -> Result<f64, String> {
    if !(factor > 0.0 && factor <= MAX_MAGNIFICATION) {
        return Err(format!("a factor > 0 and ≤ {MAX_MAGNIFICATION:e}, got {factor}"));
    }
    Ok(factor)
}

/// Eq. (33)'s formulation by name: `full` or `reduced`.
pub fn formulation(name: &str) -> Result<Formulation, String> {
    [Formulation::Full, Formulation::Reduced]
        .into_iter()
        .find(|f| f.name() == name)
        .ok_or_else(|| format!("\"full\" or \"reduced\", got \"{}\"", spine_check::shown(name)))
}

/// Eq. (37)'s search by name: `ga`, `pattern` or `gradient`.
pub fn method(name: &str) -> Result<SearchMethod, String> {
    SearchMethod::from_name(name)
        .ok_or_else(|| format!("\"ga\", \"pattern\" or \"gradient\", got \"{}\"", spine_check::shown(name)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_inside_pass_and_outside_are_refused_with_the_range() {
        assert_eq!(starts(3), Ok(3));
        assert!(starts(spine_case::MAX_STARTS + 1).unwrap_err().starts_with("at most 100000"));
        assert!(confidence(1.0).is_err() && confidence(0.0).is_err() && confidence(f64::NAN).is_err());
        assert!(time_limit(0.0).is_err() && time_limit(f64::INFINITY).is_err());
        assert_eq!(time_limit(2.5), Ok(std::time::Duration::from_millis(2500)));
        assert!(jobs(0).is_err() && frames(1).is_err() && frame_width(10).is_err() && magnify(-1.0).is_err());
        assert_eq!(formulation("reduced"), Ok(Formulation::Reduced));
        assert!(formulation("dense").unwrap_err().contains("\"full\" or \"reduced\""));
        assert!(method("newton").is_err() && every(0).is_err() && batch(0).is_err());
    }
}
