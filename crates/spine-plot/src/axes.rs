//! Axis ranges, scales and tick labels (linear, counting, logarithmic).

use crate::panel::{Panel, Scale};
use crate::series::Style;

pub(crate) fn finite_range(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    values.filter(|v| v.is_finite()).fold(None, |acc, v| match acc {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}

pub(crate) fn padded((lo, hi): (f64, f64)) -> (f64, f64) {
    let span = hi - lo;
    let pad = if span > 0.0 { 0.05 * span } else { 0.05 * lo.abs().max(1e-3) };
    (lo - pad, hi + pad)
}

/// Axis ranges of a panel in axis coordinates: fixed where the panel fixes them, else the data
/// with a 5 % margin; bars on a linear axis include 0 and their half widths; a logarithmic axis
/// starts at the decade below its smallest value (bars stand on it).
pub(crate) fn ranges(panel: &Panel) -> ((f64, f64), (f64, f64)) {
    let has_bars = panel.series.iter().any(|s| s.style == Style::Bars);
    let xs = panel.series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
    let from_zero = has_bars && panel.y_scale != Scale::Log10;
    let ys = panel.series.iter().flat_map(|s| s.points.iter().map(|p| p.1)).chain(from_zero.then_some(0.0));
    let data_x = finite_range(xs).unwrap_or((0.0, 1.0));
    let x = panel.x_range.unwrap_or_else(|| {
        if has_bars {
            (data_x.0 - 0.5, data_x.1 + 0.5)
        } else {
            fitted(panel.x_scale, data_x)
        }
    });
    let y = panel.y_range.unwrap_or_else(|| fitted(panel.y_scale, finite_range(ys).unwrap_or((0.0, 1.0))));
    (x, y)
}

/// A data range with its margin: 5 % on each side, or on a logarithmic axis from the decade
/// below the smallest value to 5 % above the largest. A value within a tenth of a decade above a
/// decade (K = 100 at its bound, 100.0000001 from an interior-point solver) counts as on it, so
/// it is drawn a decade above the axis, not on it.
fn fitted(scale: Scale, (lo, hi): (f64, f64)) -> (f64, f64) {
    match scale {
        Scale::Log10 => {
            let bottom = (lo - 0.1).ceil() - 1.0;
            (bottom, hi + 0.05 * (hi - bottom))
        }
        Scale::Linear | Scale::Integer => padded((lo, hi)),
    }
}

/// `v` on the axis: `log10 v` on a logarithmic one (NaN for `v ≤ 0`, which is then skipped).
pub(crate) fn mapped(scale: Scale, v: f64) -> f64 {
    match scale {
        Scale::Log10 if v > 0.0 => v.log10(),
        Scale::Log10 => f64::NAN,
        Scale::Linear | Scale::Integer => v,
    }
}

/// The panel in axis coordinates (logarithmic axes mapped to `log10`).
pub(crate) fn in_axis_coordinates(panel: &Panel) -> Panel {
    let mut out = panel.clone();
    let (sx, sy) = (panel.x_scale, panel.y_scale);
    for s in &mut out.series {
        for p in &mut s.points {
            *p = (mapped(sx, p.0), mapped(sy, p.1));
        }
    }
    out.x_range = panel.x_range.map(|(a, b)| (mapped(sx, a), mapped(sx, b)));
    out.y_range = panel.y_range.map(|(a, b)| (mapped(sy, a), mapped(sy, b)));
    out
}

pub(crate) const SUPERSCRIPTS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];

/// The label of tick `v` on an axis of `scale` spanning `span` (axis units).
pub(crate) fn tick_label(scale: Scale, v: f64, span: f64) -> String {
    let whole = (v - v.round()).abs() <= 1e-9 * span.max(1.0);
    match scale {
        Scale::Integer if whole => format!("{}", v.round() as i64),
        Scale::Log10 if whole => {
            let k = v.round() as i64;
            let digits: String =
                k.unsigned_abs().to_string().chars().map(|c| SUPERSCRIPTS[c as usize - '0' as usize]).collect();
            format!("10{}{digits}", if k < 0 { "⁻" } else { "" })
        }
        Scale::Integer | Scale::Log10 => String::new(),
        Scale::Linear => {
            // Enough decimals for ticks a tenth of the span apart; "-0" is "0".
            let decimals = if span > 0.0 { (-(span / 10.0).log10()).ceil().clamp(0.0, 12.0) as usize } else { 3 };
            let text = format!("{v:.decimals$}");
            if text.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
                text.trim_start_matches('-').to_string()
            } else {
                text
            }
        }
    }
}

/// How many ticks an axis `length_px` long asks for: one per whole number on a counting or
/// logarithmic axis with few of them, else one per `spacing_px` (2 to 10).
pub(crate) fn tick_count(scale: Scale, (lo, hi): (f64, f64), length_px: f64, spacing_px: f64) -> usize {
    let whole = (hi.floor() - lo.ceil()) as i64 + 1;
    match scale {
        Scale::Integer | Scale::Log10 if (1..=12).contains(&whole) => (hi - lo).ceil().max(1.0) as usize + 1,
        _ => ((length_px / spacing_px).floor() as usize).clamp(2, 10),
    }
}
