//! # spine-check: the one shape of a validation error
//!
//! Every options type of the workspace checks itself where it is defined (`validate`) and says
//! what is wrong as a [`FieldError`]: the field's path as a case file spells it and a message
//! saying what is allowed and what was given. A section checked by shared code is placed under its
//! section with [`FieldError::under`], so that the user reads the full path
//! (`simulation.integrator.rtol`), whatever crate found the fault.
//!
//! ```
//! use spine_check::{require, FieldError};
//!
//! fn check_rtol(rtol: f64) -> Result<(), FieldError> {
//!     require(rtol > 0.0 && rtol < 1.0, "rtol", || format!("must be in (0, 1), got {rtol}"))
//! }
//! let e = check_rtol(2.0).unwrap_err().under("simulation.integrator");
//! assert_eq!(e.to_string(), "simulation.integrator.rtol: must be in (0, 1), got 2");
//! ```
#![forbid(unsafe_code)]

/// A value outside what is allowed: the field's path (`chain.links`, `runs[1].case.delta_d`) and
/// what is allowed, with what was given. Shown on one line, the path shortened to
/// [`FIELD_CHARS`] and the message to [`MESSAGE_CHARS`] characters, control characters escaped
/// ([`shown_within`]): a case file's key or value never clears a terminal or fills a log.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{}: {}", shown_within(field, FIELD_CHARS), shown_within(&short_numbers(message), MESSAGE_CHARS))]
pub struct FieldError {
    /// The field's path as a case file spells it (empty: the whole object).
    pub field: String,
    pub message: String,
}

impl FieldError {
    pub fn new(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self { field: field.into(), message: message.into() }
    }

    /// The same error inside the section `prefix`: `rtol` becomes `simulation.integrator.rtol`,
    /// `[2]` becomes `damping[2]`, an empty field becomes `prefix` itself.
    pub fn under(self, prefix: &str) -> Self {
        let field = if self.field.is_empty() {
            prefix.to_string()
        } else if prefix.is_empty() || self.field.starts_with('[') {
            format!("{prefix}{}", self.field)
        } else {
            format!("{prefix}.{}", self.field)
        };
        Self { field, ..self }
    }
}

/// `Ok` when `ok`, else the error of `field` with the message `message()` (built only then).
pub fn require(ok: bool, field: &str, message: impl FnOnce() -> String) -> Result<(), FieldError> {
    if ok {
        Ok(())
    } else {
        Err(FieldError::new(field, message()))
    }
}

/// Longest field path an error shows, in characters.
pub const FIELD_CHARS: usize = 120;
/// Longest message an error shows, in characters.
pub const MESSAGE_CHARS: usize = 400;

/// `text` as a one-line message quotes it: at most 60 characters ([`shown_within`]).
pub fn shown(text: &str) -> String {
    shown_within(text, 60)
}

/// `text` on one line: control characters (newlines, escape sequences) written as escapes
/// (`\n`, `\u{1b}`), and cut to its first and last characters around ` … ` when longer than
/// `max` characters (with the number of characters left out).
///
/// ```
/// assert_eq!(spine_check::shown_within("a\u{1b}[2Jb", 40), "a\\u{1b}[2Jb");
/// let long = "x".repeat(1000);
/// assert_eq!(spine_check::shown_within(&long, 20).chars().count() < 60, true);
/// ```
pub fn shown_within(text: &str, max: usize) -> String {
    let escaped = |c: char| -> String {
        if c.is_control() || is_bidi_control(c) {
            c.escape_default().collect()
        } else {
            c.to_string()
        }
    };
    let count = text.chars().count();
    if count <= max {
        return text.chars().map(escaped).collect();
    }
    let head: String = text.chars().take(max / 2).map(escaped).collect();
    let tail: String = text.chars().skip(count - max / 2).map(escaped).collect();
    format!("{head} … ({} characters left out) … {tail}", count - 2 * (max / 2))
}

/// `text` with every number longer than 12 characters in [`short`] form (`got
/// 0.000…0003086` becomes `got 3.08642e-202`): a value echoed from a case file never fills a
/// message with digits.
///
/// ```
/// let long = format!("got {}", 3.086419725308642e-202);
/// assert_eq!(spine_check::short_numbers(&long), "got 3.08642e-202");
/// assert_eq!(spine_check::short_numbers("runs[1].x: got 0.25"), "runs[1].x: got 0.25");
/// ```
pub fn short_numbers(text: &str) -> String {
    shorten(text, 12, false)
}

/// Whether `c` reorders the text around it on a terminal (the Unicode bidirectional controls:
/// embeddings, overrides, isolates and marks): an echoed name holding one could show other text
/// than it is, so every echo writes them as escapes, like control characters.
pub fn is_bidi_control(c: char) -> bool {
    matches!(c, '\u{061c}' | '\u{200e}' | '\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
}

/// Text as the workspace prints it for a person (stdout summaries, claims, notes): every number
/// longer than 20 characters in [`short`] form (a value printed in full: `1e300` is 301 digits;
/// numbers a summary formats itself, `7.6031243587e-3`, are kept), except whole numbers of at most
/// 20 digits (counts, seeds and start numbers are exact), and control characters other than the
/// line breaks and bidirectional controls escaped ([`is_bidi_control`]).
///
/// ```
/// let line = format!("reach {} s, J = 7.6031243587e-3 J, seed 18446744073709551615\n", 1e300);
/// assert_eq!(spine_check::readable(&line), "reach 1e300 s, J = 7.6031243587e-3 J, seed 18446744073709551615\n");
/// assert_eq!(spine_check::readable("a\u{202e}b\u{1b}[2J\n"), "a\\u{202e}b\\u{1b}[2J\n");
/// ```
pub fn readable(text: &str) -> String {
    shorten(text, 20, true)
        .chars()
        .map(|c| {
            if (c.is_control() && c != '\n' && c != '\t') || is_bidi_control(c) {
                c.escape_default().collect()
            } else {
                c.to_string()
            }
        })
        .collect()
}

/// Every number longer than `longest` characters in [`short`] form; with `keep_integers`, whole
/// numbers of at most 20 digits are kept.
fn shorten(text: &str, longest: usize, keep_integers: bool) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < chars.len() {
        let starts = chars[i].is_ascii_digit()
            || (chars[i] == '-' && chars.get(i + 1).is_some_and(|c| c.is_ascii_digit()))
                && (i == 0 || !chars[i - 1].is_alphanumeric());
        if !starts || (i > 0 && (chars[i - 1].is_alphanumeric() || chars[i - 1] == '_')) {
            out.push(chars[i]);
            i += 1;
            continue;
        }
        let mut j = i + 1;
        while j < chars.len() {
            let c = chars[j];
            let sign_after_e = (c == '-' || c == '+') && matches!(chars[j - 1], 'e' | 'E');
            if c.is_ascii_digit() || c == '.' || c == 'e' || c == 'E' || sign_after_e {
                j += 1;
            } else {
                break;
            }
        }
        let token: String = chars[i..j].iter().collect();
        let digits = token.trim_start_matches('-');
        let exact_integer = keep_integers && digits.len() <= 20 && digits.bytes().all(|b| b.is_ascii_digit());
        match token.parse::<f64>() {
            Ok(x) if token.len() > longest && !exact_integer => out.push_str(&short(x)),
            _ => out.push_str(&token),
        }
        i = j;
    }
    out
}

/// A number in a short form for a message: as Rust prints it (plainly or in scientific form) when
/// that is at most 10 characters, else to 6 significant digits without trailing zeros: plainly
/// from a thousandth to a million, in scientific form beyond.
///
/// ```
/// assert_eq!(spine_check::short(0.25), "0.25");
/// assert_eq!(spine_check::short(1e-322), "1e-322");
/// assert_eq!(spine_check::short(1.0 / 3.0), "0.333333");
/// assert_eq!(spine_check::short(-0.9999999999999999), "-1");
/// assert_eq!(spine_check::short(1e4 / 12.0), "833.333");
/// assert_eq!(spine_check::short(3.086419725308642e-202), "3.08642e-202");
/// assert_eq!(spine_check::short(-1e300), "-1e300");
/// ```
pub fn short(x: f64) -> String {
    let plain = format!("{x}");
    if plain.len() <= 10 {
        return plain;
    }
    let exact = format!("{x:e}");
    if exact.len() <= 10 {
        return exact;
    }
    let sci = format!("{x:.5e}");
    // Six significant digits read plainly between a thousandth and a million (`833.333`, `-1`).
    if let Some(exponent) = sci.split_once('e').and_then(|(_, e)| e.parse::<i32>().ok()) {
        if (-3..=5).contains(&exponent) {
            let plain = format!("{x:.*}", (5 - exponent) as usize);
            return plain.trim_end_matches('0').trim_end_matches('.').to_string();
        }
    }
    match sci.split_once('e') {
        Some((mantissa, exponent)) if mantissa.contains('.') => {
            format!("{}e{exponent}", mantissa.trim_end_matches('0').trim_end_matches('.'))
        }
        _ => sci,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn under_places_the_field_in_its_section() {
        let e = FieldError::new("rtol", "must be > 0");
        assert_eq!(e.clone().under("simulation.integrator").field, "simulation.integrator.rtol");
        assert_eq!(FieldError::new("[2]", "m").under("damping").field, "damping[2]");
        assert_eq!(FieldError::new("", "m").under("forcing").field, "forcing");
        assert_eq!(e.under("").field, "rtol");
        assert!(require(true, "x", || unreachable!()).is_ok());
    }

    #[test]
    fn errors_show_on_one_short_line() {
        let key = format!("\u{1b}[2J{}", "k".repeat(10_000));
        let e = FieldError::new(key, format!("unknown field; allowed a, b\n{}", "v".repeat(10_000)));
        let text = e.to_string();
        assert!(!text.contains('\n') && !text.contains('\u{1b}'), "{text}");
        assert!(text.chars().count() < FIELD_CHARS + MESSAGE_CHARS + 120, "{}", text.len());
        assert!(text.contains("\\u{1b}[2J") && text.contains("characters left out"), "{text}");
    }
}
