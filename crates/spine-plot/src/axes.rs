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

/// Data ranges of a panel (bars include 0 and their half widths).
pub(crate) fn ranges(panel: &Panel, plot_px: (f64, f64)) -> ((f64, f64), (f64, f64)) {
    let has_bars = panel.series.iter().any(|s| s.style == Style::Bars);
    let xs = panel.series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
    let ys = panel.series.iter().flat_map(|s| s.points.iter().map(|p| p.1)).chain(has_bars.then_some(0.0));
    let mut x = finite_range(xs).unwrap_or((0.0, 1.0));
    if has_bars {
        x = (x.0 - 0.5, x.1 + 0.5);
    }
    let mut x = panel.x_range.unwrap_or_else(|| if has_bars { x } else { padded(x) });
    let mut y = panel.y_range.unwrap_or_else(|| padded(finite_range(ys).unwrap_or((0.0, 1.0))));
    if panel.equal_aspect {
        // Widen the axis whose metres per pixel are fewer, about its centre.
        let (sx, sy) = ((x.1 - x.0) / plot_px.0, (y.1 - y.0) / plot_px.1);
        if sx > sy {
            let c = 0.5 * (y.0 + y.1);
            let half = 0.5 * sx * plot_px.1;
            y = (c - half, c + half);
        } else {
            let c = 0.5 * (x.0 + x.1);
            let half = 0.5 * sy * plot_px.0;
            x = (c - half, c + half);
        }
    }
    (x, y)
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

/// How many ticks an axis asks for: one per whole number on a counting or logarithmic axis with
/// few of them, plotters' default otherwise.
pub(crate) fn tick_count(scale: Scale, (lo, hi): (f64, f64)) -> usize {
    let whole = (hi.floor() - lo.ceil()) as i64 + 1;
    match scale {
        Scale::Integer | Scale::Log10 if (1..=12).contains(&whole) => (hi - lo).ceil().max(1.0) as usize + 1,
        _ => 10,
    }
}
