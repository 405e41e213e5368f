//! "Valid only for loading patterns with lower frequency" (Sec. 5.2.2) over a sweep of pulse
//! periods: the same eq. (33) + eq. (35) design under pulse trains of several periods (a figure's
//! extra damping runs), held at each to the motion the design is for: the end reaches the static
//! loaded displacement and returns to the passive one (within 1 % of the swing,
//! [`follows_its_static_states`]) and keeps up with the pulses ([`keeps_up`]).

use super::dynamic::{follows_its_static_states, keeps_up};
use serde_json::{json, Value};
use spine_dynamics::PeriodicResponse;
use spine_run::text::quantity;
use spine_run::{Claim, Table};

/// One period of the sweep: the run's name and its settled response.
pub(super) struct SweepPoint<'a> {
    pub name: &'a str,
    pub response: &'a PeriodicResponse,
}

/// The sweep's claim, its table (`frequency_sweep.csv`) and summary; `None` with fewer than two
/// periods (one period cannot show "only").
pub(super) fn frequency_sweep(points: &mut [SweepPoint<'_>]) -> Option<(Claim, Table, Value)> {
    if points.len() < 2 {
        return None;
    }
    points.sort_by(|a, b| a.response.period.total_cmp(&b.response.period));
    let rows: Vec<(f64, bool, Option<f64>, Option<f64>)> = points
        .iter()
        .map(|p| {
            let (keeps, _, _) = keeps_up(p.response);
            let keeps = keeps && p.response.settled && follows_its_static_states(p.response);
            (p.response.period, keeps, p.response.reach_time, p.response.return_time)
        })
        .collect();
    // "Only at lower frequency": it fails at the shortest period, holds at the longest, and once it
    // holds it holds at every longer period (one threshold).
    let first_kept = rows.iter().position(|r| r.1);
    let threshold = first_kept.is_some_and(|k| k > 0 && rows[k..].iter().all(|r| r.1));
    let measured = rows
        .iter()
        .map(|(period, keeps, reach, back)| {
            format!(
                "{period} s: {} (reach {}, return {})",
                if *keeps { "keeps up" } else { "does not" },
                quantity(*reach, 4, "s", "not reached"),
                quantity(*back, 4, "s", "not reached")
            )
        })
        .collect::<Vec<_>>()
        .join("; ");
    let claim = Claim::new(
        "frequency sweep",
        "the response keeps up with the pulses (\"valid only for loading patterns with lower frequency\")",
        "over the sweep of pulse periods, \"keeps up\": a settled period reaches the static loaded displacement and returns to the passive one (each within 1 % of the swing), reach (90 %) shorter than the on-time and return shorter than the off-time; it does not at the shortest period, does at the longest, and does at every period above the first where it does",
        threshold,
        measured,
    );
    let table = Table::new()
        .numbers("period_s", rows.iter().map(|r| r.0))
        .labels("keeps_up", rows.iter().map(|r| r.1))
        .optional("reach_time_s", rows.iter().map(|r| r.2))
        .optional("return_time_s", rows.iter().map(|r| r.3));
    let summary = json!(points
        .iter()
        .zip(&rows)
        .map(|(p, r)| json!({ "run": p.name, "period": r.0, "keeps_up": r.1, "reach_time": r.2, "return_time": r.3 }))
        .collect::<Vec<_>>());
    Some((claim, table, summary))
}
