//! Generalized pattern search on the `2n` coordinate directions, with the mesh size measured as a
//! fraction of each variable's range.

use crate::{Bounds, Evaluation, Progress, SearchResult, SearchStatus};
use serde::{Deserialize, Serialize};

/// Pattern search settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PatternSettings {
    /// First mesh size, as a fraction of each variable's range.
    pub initial_mesh: f64,
    /// Stop when the mesh is below this fraction.
    pub mesh_tolerance: f64,
    /// Mesh factor after a successful poll (≥ 1) and after a failed one (in (0, 1)).
    pub expansion: f64,
    pub contraction: f64,
    /// Evaluation budget.
    pub max_evaluations: usize,
    /// Poll all directions and move to the best (`true`) or take the first improvement (`false`).
    pub complete_poll: bool,
}

impl Default for PatternSettings {
    fn default() -> Self {
        Self {
            initial_mesh: 0.25,
            mesh_tolerance: 1e-6,
            expansion: 2.0,
            contraction: 0.5,
            max_evaluations: 100_000,
            complete_poll: false,
        }
    }
}

/// Minimises `f` over `bounds` from `start` (clamped into the bounds). Polls `+e_1, −e_1, +e_2, …` in
/// that fixed order, so runs are deterministic; a trial outside the bounds is clamped onto them.
pub fn pattern_search(
    f: &mut dyn FnMut(&[f64]) -> Evaluation,
    bounds: &Bounds,
    start: &[f64],
    settings: &PatternSettings,
    progress: &mut dyn FnMut(Progress),
) -> SearchResult {
    let n = bounds.dim();
    let mut x: Vec<f64> = (0..n).map(|i| bounds.clamp(i, start[i])).collect();
    let mut best = f(&x);
    let mut evaluations = 1;
    let mut mesh = settings.initial_mesh;
    let mut history = vec![Progress { iteration: 0, evaluations, best }];
    progress(history[0]);
    let mut iteration = 0;
    let status = loop {
        if mesh < settings.mesh_tolerance {
            break SearchStatus::MeshConverged;
        }
        if evaluations >= settings.max_evaluations {
            break SearchStatus::EvaluationLimit;
        }
        iteration += 1;
        let mut winner: Option<(Vec<f64>, Evaluation)> = None;
        'poll: for i in 0..n {
            for sign in [1.0, -1.0] {
                let mut trial = x.clone();
                trial[i] = bounds.clamp(i, x[i] + sign * mesh * bounds.width(i));
                if trial[i] == x[i] {
                    continue;
                }
                let value = f(&trial);
                evaluations += 1;
                let beats = match &winner {
                    Some((_, w)) => value.better_than(w),
                    None => value.better_than(&best),
                };
                if beats {
                    winner = Some((trial, value));
                    if !settings.complete_poll {
                        break 'poll;
                    }
                }
                if evaluations >= settings.max_evaluations {
                    break 'poll;
                }
            }
        }
        match winner {
            Some((trial, value)) => {
                x = trial;
                best = value;
                mesh = (mesh * settings.expansion).min(1.0);
            }
            None => mesh *= settings.contraction,
        }
        let p = Progress { iteration, evaluations, best };
        history.push(p);
        progress(p);
    };
    SearchResult { status, x, best, evaluations, iterations: iteration, history }
}
