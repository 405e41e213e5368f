//! Numbers for a person to read: a quantity with its unit and a precision that fits it, a list of
//! values. Never Rust's debug form (`Some(…)`, `[0.1, …]` with every digit).

use std::fmt::Write as _;

/// The axis label of the end node's motion, `X_{N+1} − L_x` of the paper, in the figures' one
/// notation (Unicode subscripts where the font has them).
pub const END_DISPLACEMENT: &str = "end node X − Lₓ (m)";

/// `value` with `decimals` decimals and its unit, or `missing` (e.g. "not reached") when there is
/// none.
///
/// ```
/// use spine_run::text::quantity;
/// assert_eq!(quantity(Some(-0.02000000000000013), 6, "m", "none"), "-0.020000 m");
/// assert_eq!(quantity(None, 3, "s", "not reached"), "not reached");
/// ```
pub fn quantity(value: Option<f64>, decimals: usize, unit: &str, missing: &str) -> String {
    value.map_or_else(|| missing.to_string(), |v| format!("{v:.decimals$} {unit}"))
}

/// `values` as `[a, b, …]`, each with `decimals` decimals.
///
/// ```
/// assert_eq!(spine_run::text::list(&[0.1234567, -2.0], 3), "[0.123, -2.000]");
/// ```
pub fn list(values: &[f64], decimals: usize) -> String {
    let mut text = String::from("[");
    for (i, v) in values.iter().enumerate() {
        let _ = write!(text, "{}{v:.decimals$}", if i == 0 { "" } else { ", " });
    }
    text.push(']');
    text
}

/// Items as a person reads a list: `a, b, c` (each by its `Display`).
///
/// ```
/// assert_eq!(spine_run::text::joined(&[3, 5]), "3, 5");
/// ```
pub fn joined<T: std::fmt::Display>(items: &[T]) -> String {
    items.iter().map(ToString::to_string).collect::<Vec<_>>().join(", ")
}
