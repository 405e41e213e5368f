//! The figure of the design study: the optimal profiles of several `N` on one axis each, and
//! `J*(N)` on a log axis with the Richardson limit.

use crate::design_study::RodStudy;
use spine_plot::{Figure, Panel, Series};

/// At most this many levels' profiles are drawn (spread over the study, the finest always).
pub const MAX_PROFILES: usize = 5;

/// The levels whose profiles are drawn: up to [`MAX_PROFILES`], evenly spread, the last included.
pub fn drawn_levels(count: usize) -> Vec<usize> {
    if count <= MAX_PROFILES {
        return (0..count).collect();
    }
    let mut picked: Vec<usize> =
        (0..MAX_PROFILES).map(|k| (k * (count - 1) + (MAX_PROFILES - 1) / 2) / (MAX_PROFILES - 1)).collect();
    picked.dedup();
    picked
}

/// `θ0(x)`, `EI(x)` (log) and `J*(N)` (log `N`).
pub fn figure(study: &RodStudy) -> Figure {
    let mut theta = Panel::new("optimal unloaded shape", "x (m)", "θ0 (rad)");
    let mut stiffness = Panel::new("optimal bending stiffness", "x (m)", "EI (N·m²)").y_log();
    for (colour, &k) in drawn_levels(study.levels.len()).iter().enumerate() {
        let level = &study.levels[k];
        let label = format!("N = {}", level.links);
        let shape = level.x_links.iter().copied().zip(level.result.design.theta0.iter().copied()).collect();
        theta = theta.with(Series::line(label.clone(), shape).colour(colour));
        let ei = level.x_joints.iter().copied().zip(level.bending_stiffness.iter().copied()).collect();
        stiffness = stiffness.with(Series::line(label, ei).colour(colour));
    }
    let points: Vec<(f64, f64)> = study.levels.iter().map(|l| (l.links as f64, 1e3 * l.result.objective)).collect();
    let (low, high) = study.levels.iter().fold((f64::INFINITY, 0.0f64), |(l, h), v| {
        let n = v.links as f64;
        (l.min(n), h.max(n))
    });
    let range = |p: Panel| if high > low { p.x_range(low / 1.5, high * 1.5) } else { p };
    let mut objective = range(Panel::new("optimal strain energy", "N (links)", "J* (mJ)").x_log())
        .with(Series::line_markers("J*(N)", points));
    let mut figure = Figure::new("Eq. (33) for one rod as N grows", 2).with(theta).with(stiffness);
    if let Some(r) = &study.richardson {
        let line = vec![(low, 1e3 * r.limit), (high, 1e3 * r.limit)];
        objective = objective.with(Series::dashed(format!("Richardson J*∞, order {:.2}", r.order), line).colour(3));
        let gap: Vec<(f64, f64)> = study
            .levels
            .iter()
            .map(|l| (l.links as f64, ((l.result.objective - r.limit) / r.limit).abs()))
            .filter(|(_, g)| *g > 0.0)
            .collect();
        let distance = range(Panel::new("distance to the limit", "N (links)", "|J*(N) − J*∞| / J*∞").x_log().y_log())
            .with(Series::line_markers("|J*(N) − J*∞| / J*∞", gap).colour(1));
        figure = figure.with(objective).with(distance);
    } else {
        figure = figure.with(objective);
    }
    figure
}

#[cfg(test)]
mod tests {
    #[test]
    fn drawn_levels_spread_and_keep_the_finest() {
        assert_eq!(super::drawn_levels(3), vec![0, 1, 2]);
        let picked = super::drawn_levels(9);
        assert_eq!(picked.len(), super::MAX_PROFILES);
        assert_eq!((picked[0], *picked.last().unwrap()), (0, 8));
    }
}
