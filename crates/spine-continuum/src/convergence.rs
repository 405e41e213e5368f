//! The convergence study: the chain against the rod for a ladder of `N`, as a table and a figure.

use crate::compare::{critical_load, loaded, on_branch, CriticalLoad, NodeComparison};
use crate::elastica::{Elastica, ElasticaError};
use crate::rod::Rod;
use serde::Serialize;
use spine_plot::{Figure, Panel, Series};
use std::f64::consts::PI;

/// The study's rod: `L = 1 m`, `EI = 10 N·m²` (Euler's load `4π²·10 = 394.8 N`).
pub fn study_rod() -> Rod {
    Rod {
        length: 1.0,
        bending_stiffness: 10.0,
        end_force: 0.0,
        transverse_load: 0.0,
        mass_per_length: 0.0,
        gravity: 9.81,
    }
}

/// The two reference states: post-buckled at 1.1 Euler's load (buckled upward, from a guess
/// `0.9 sin(2πs/L)`), and loaded transversely (`q = −100 N/m`, `ρA = 2 kg/m`) with half Euler's
/// load pushing the end (from straight). Degree 64: the tests show degree 128 agrees to 1e-12.
pub fn reference_states(rod: &Rod) -> Result<(Elastica, Elastica), ElasticaError> {
    let euler = rod.euler_critical_load();
    let buckled = Rod { end_force: -1.1 * euler, ..rod.clone() };
    let buckled = Elastica::solve(&buckled, 64, |s| 0.9 * (2.0 * PI * s / rod.length).sin())?;
    let transverse = Rod { transverse_load: -100.0, mass_per_length: 2.0, end_force: -0.5 * euler, ..rod.clone() };
    let transverse = Elastica::solve(&transverse, 64, |_| 0.0)?;
    Ok((buckled, transverse))
}

/// One `N` of the study.
#[derive(Clone, Debug, Serialize)]
pub struct ConvergenceRow {
    pub critical_load: CriticalLoad,
    pub post_buckled: NodeComparison,
    pub transverse: NodeComparison,
}

/// The study at each `N` of `links`.
pub fn convergence(rod: &Rod, links: &[usize]) -> Result<Vec<ConvergenceRow>, ElasticaError> {
    let (buckled, transverse) = reference_states(rod)?;
    Ok(links
        .iter()
        .map(|&n| ConvergenceRow {
            critical_load: critical_load(rod, n),
            post_buckled: on_branch(&buckled, n),
            transverse: loaded(&transverse, n),
        })
        .collect())
}

/// A markdown table of the study.
pub fn table(rows: &[ConvergenceRow]) -> String {
    let mut out = String::from(
        "| N | P_cr chain (N) | rel. error | × N² | post-buckled node error / L | × N² | stable | transverse node error / L | × N² | stable |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let (c, b, t) = (&r.critical_load, &r.post_buckled, &r.transverse);
        out.push_str(&format!(
            "| {} | {:.9} | {:.3e} | {:.4} | {:.3e} | {:.4} | {} | {:.3e} | {:.4} | {} |\n",
            c.links,
            c.chain,
            c.relative_error,
            c.scaled_error,
            b.error,
            b.scaled_error,
            b.stable,
            t.error,
            t.scaled_error,
            t.stable
        ));
    }
    out
}

/// Errors against `N` on log axes, with the `1/N²` slope for comparison.
pub fn figure(rows: &[ConvergenceRow]) -> Figure {
    let pts = |f: &dyn Fn(&ConvergenceRow) -> f64| rows.iter().map(|r| (r.critical_load.links as f64, f(r))).collect();
    let first = rows.first().map_or(1.0, |r| r.critical_load.links as f64);
    // A factor 3 above the post-buckled line, so that the two do not overlap.
    let anchor = rows.first().map_or(1.0, |r| 3.0 * r.post_buckled.error);
    let slope = rows.iter().map(|r| r.critical_load.links as f64).map(|n| (n, anchor * (first / n).powi(2))).collect();
    let panel = Panel::new("chain against the rod", "N (links)", "error")
        .x_log()
        .y_log()
        .with(
            Series::line_markers(
                "critical load |P − 4π²EI/L²| / P_Euler",
                pts(&|r| r.critical_load.relative_error.abs()),
            )
            .colour(0),
        )
        .with(Series::line_markers("post-buckled nodes, max distance / L", pts(&|r| r.post_buckled.error)).colour(1))
        .with(
            Series::line_markers("transverse + weight nodes, max distance / L", pts(&|r| r.transverse.error)).colour(2),
        )
        .with(Series::dashed("1/N² slope", slope).colour(3));
    Figure::new("The chain converges to Euler's elastica at O(1/N²)", 1).with(panel)
}
