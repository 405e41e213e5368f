//! The values of the command-line options, each checked where it is parsed: a message naming
//! the allowed range, which clap prints with the option's name (exit code 2).

/// Longest `--time-limit` accepted, s (about 11.6 days).
const MAX_TIME_LIMIT: f64 = 1e6;

/// `--time-limit`: finite seconds in (0, [`MAX_TIME_LIMIT`]].
pub(crate) fn parse_time_limit(text: &str) -> Result<std::time::Duration, String> {
    let s: f64 = text.parse().map_err(|e| format!("{e}"))?;
    if !(s > 0.0 && s <= MAX_TIME_LIMIT) {
        return Err(format!("seconds must be > 0 and at most {MAX_TIME_LIMIT:e}, got {}", spine_check::shown(text)));
    }
    Ok(std::time::Duration::from_secs_f64(s))
}

/// A whole number within `allowed` (the message gives the range, with `unit`).
fn parse_within<T>(text: &str, allowed: std::ops::RangeInclusive<T>, unit: &str) -> Result<T, String>
where
    T: std::str::FromStr + PartialOrd + std::fmt::Display,
    T::Err: std::fmt::Display,
{
    let n: T = text.parse().map_err(|e| format!("{e}"))?;
    if !allowed.contains(&n) {
        return Err(format!("allowed {}..={}{unit}", allowed.start(), allowed.end()));
    }
    Ok(n)
}

/// `--frames`: within [`spine_run::animation::FRAMES`].
pub(crate) fn parse_frames(text: &str) -> Result<usize, String> {
    parse_within(text, spine_run::animation::FRAMES, "")
}

/// `--frame-width`: within [`spine_run::animation::WIDTH`].
pub(crate) fn parse_frame_width(text: &str) -> Result<u32, String> {
    parse_within(text, spine_run::animation::WIDTH, " px")
}

/// `--magnify`: a factor in (0, [`spine_run::animation::MAX_MAGNIFICATION`]].
pub(crate) fn parse_magnify(text: &str) -> Result<f64, String> {
    let m: f64 = text.parse().map_err(|e| format!("{e}"))?;
    let max = spine_run::animation::MAX_MAGNIFICATION;
    if !(m > 0.0 && m <= max) {
        return Err(format!("a factor > 0 and ≤ {max:e}, got {text}"));
    }
    Ok(m)
}

/// `--jobs`: 1..=[`spine_run::workers::MAX_JOBS`].
pub(crate) fn parse_jobs(text: &str) -> Result<usize, String> {
    parse_within(text, 1..=spine_run::workers::MAX_JOBS, "")
}

/// `--census-every`: a spacing of at least 1 point.
pub(crate) fn parse_every(text: &str) -> Result<usize, String> {
    parse_within(text, 1..=100_000, "")
}

/// `--batch`: a batch of a census to a stated confidence, 1..=MAX_STARTS / 100.
pub(crate) fn parse_batch(text: &str) -> Result<usize, String> {
    let most = spine_case::MAX_STARTS / spine_run::CONFIDENCE_BATCH;
    match text.trim().parse::<usize>() {
        Ok(b) if (1..=most).contains(&b) => Ok(b),
        _ => Err(format!("a batch number 1..={most} expected")),
    }
}

/// `--confidence`: a probability strictly between 0 and 1.
pub(crate) fn parse_confidence(text: &str) -> Result<f64, String> {
    let p: f64 = text.parse().map_err(|e| format!("{e}"))?;
    if !(p > 0.0 && p < 1.0) {
        return Err(format!("a probability strictly between 0 and 1 (e.g. 0.01), got {p}"));
    }
    Ok(p)
}

/// `--starts`: a count within the bound every case file obeys ([`spine_case::MAX_STARTS`]).
pub(crate) fn parse_starts(text: &str) -> Result<usize, String> {
    let n: usize = text.parse().map_err(|e| format!("{e}"))?;
    if n > spine_case::MAX_STARTS {
        return Err(format!("at most {}", spine_case::MAX_STARTS));
    }
    Ok(n)
}
