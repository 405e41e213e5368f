//! The values of the command-line options: the text parsed, then checked by the same function
//! that checks flexspine's keyword arguments ([`spine_run::option_values`]); clap prints the
//! message with the option's name (exit code 2).

use spine_run::option_values as values;

/// The text as a number of type `T`, then `check`ed.
fn parsed<T: std::str::FromStr, U>(text: &str, check: impl Fn(T) -> Result<U, String>) -> Result<U, String>
where
    T::Err: std::fmt::Display,
{
    let value: T = text.trim().parse().map_err(|e| format!("{e}: {}", spine_check::shown(text)))?;
    check(value)
}

/// `--time-limit`: finite seconds in (0, [`values::MAX_TIME_LIMIT`]].
pub(crate) fn parse_time_limit(text: &str) -> Result<std::time::Duration, String> {
    parsed(text, values::time_limit)
}

/// `--frames`.
pub(crate) fn parse_frames(text: &str) -> Result<usize, String> {
    parsed(text, values::frames)
}

/// `--frame-width`.
pub(crate) fn parse_frame_width(text: &str) -> Result<u32, String> {
    parsed(text, values::frame_width)
}

/// `--magnify`.
pub(crate) fn parse_magnify(text: &str) -> Result<f64, String> {
    parsed(text, values::magnify)
}

/// `--jobs`.
pub(crate) fn parse_jobs(text: &str) -> Result<usize, String> {
    parsed(text, values::jobs)
}

/// `--census-every`.
pub(crate) fn parse_every(text: &str) -> Result<usize, String> {
    parsed(text, values::every)
}

/// `--batch`.
pub(crate) fn parse_batch(text: &str) -> Result<usize, String> {
    parsed(text, values::batch)
}

/// `--confidence`.
pub(crate) fn parse_confidence(text: &str) -> Result<f64, String> {
    parsed(text, values::confidence)
}

/// `--starts`.
pub(crate) fn parse_starts(text: &str) -> Result<usize, String> {
    parsed(text, values::starts)
}

/// `--formulation`.
pub(crate) fn parse_formulation(text: &str) -> Result<spine_design::Formulation, String> {
    values::formulation(text)
}

/// `--method`.
pub(crate) fn parse_method(text: &str) -> Result<spine_dynamic_design::SearchMethod, String> {
    values::method(text)
}

/// `--census` (a sweep's censuses).
pub(crate) fn parse_census(text: &str) -> Result<usize, String> {
    parsed(text, values::census_starts)
}
