//! The figure of a followed sweep: `J*` (followed and best known) and the design against the
//! parameter, with the events marked.

use crate::sweep_census::CensusPoint;
use spine_design::sweep::{EventKind, SweepResult};
use spine_plot::{Figure, Panel, Series};

/// (a) `J*` followed and best known, events as markers on the followed curve; (b) `θ0*` per link;
/// (c) `K*` per spring (log scale).
pub fn figure(title: &str, s: &SweepResult, census: &[CensusPoint]) -> Figure {
    let name = &s.parameter;
    let objective: Vec<(f64, f64)> = s.points.iter().map(|p| (p.parameter, p.objective)).collect();
    let mut a = Panel::new("(a) optimum value J* along the sweep", name.as_str(), "J* (J)")
        .with(Series::line_markers("followed optimum", objective.clone()));
    let best: Vec<(f64, f64)> = census.iter().filter_map(|c| Some((c.parameter, c.best_objective?))).collect();
    if !best.is_empty() {
        a = a.with(Series::markers("best known (multi-start)", best).colour(3));
    }
    for (k, (label, kinds)) in [
        ("bound becomes active / inactive", &[EventKind::BoundActive, EventKind::BoundInactive][..]),
        ("fold / second order restored", &[EventKind::Fold, EventKind::SecondOrderRestored][..]),
        ("stability lost / restored", &[EventKind::StabilityLost, EventKind::StabilityRestored][..]),
        ("jump to another optimum", &[EventKind::Jump][..]),
    ]
    .into_iter()
    .enumerate()
    {
        let marks: Vec<(f64, f64)> = s
            .events
            .iter()
            .filter(|e| kinds.contains(&e.kind))
            .map(|e| (e.parameter, interpolate(&objective, e.parameter)))
            .collect();
        if !marks.is_empty() {
            a = a.with(Series::markers(format!("event: {label}"), marks).colour(4 + k));
        }
    }
    let n = s.points.first().map_or(0, |p| p.design.theta0.len());
    let mut b = Panel::new("(b) unloaded link angles θ₀*", name.as_str(), "θ₀* (rad)");
    for i in 0..n {
        b = b.with(
            Series::line(format!("θ0_{}", i + 1), s.points.iter().map(|p| (p.parameter, p.design.theta0[i])).collect())
                .colour(i),
        );
    }
    let mut c = Panel::new("(c) spring stiffnesses K*", name.as_str(), "K* (N·m/rad)").y_log();
    for j in 0..=n {
        c = c.with(
            Series::line(
                format!("K_{}", j + 1),
                s.points.iter().map(|p| (p.parameter, p.design.stiffness[j])).collect(),
            )
            .colour(j),
        );
    }
    Figure::new(format!("{title}: the optimum followed along {name}"), 3).with(a).with(b).with(c)
}

/// `y` at `x` on the polyline `points` (sorted either way in `x`).
fn interpolate(points: &[(f64, f64)], x: f64) -> f64 {
    for w in points.windows(2) {
        let ((x0, y0), (x1, y1)) = (w[0], w[1]);
        if (x0 - x) * (x1 - x) <= 0.0 && x0 != x1 {
            return y0 + (y1 - y0) * (x - x0) / (x1 - x0);
        }
    }
    points.first().map_or(0.0, |p| p.1)
}
