//! Generalized pattern search on the `2n` coordinate directions, with the mesh size measured as a
//! fraction of each variable's range.

use crate::{Bounds, Evaluation, Progress, SearchResult, SearchStatus};
use serde::{Deserialize, Serialize};
use spine_check::{require, FieldError};

/// Pattern search settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
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

impl PatternSettings {
    /// Checks every setting.
    pub fn validate(&self) -> Result<(), FieldError> {
        let m = self.initial_mesh;
        require(m > 0.0 && m <= 1.0, "initial_mesh", || format!("must be in (0, 1], got {m}"))?;
        let t = self.mesh_tolerance;
        require(t.is_finite() && t >= 1e-12 && t <= m, "mesh_tolerance", || {
            format!("must be in [1e-12, initial_mesh = {m}], got {t}")
        })?;
        let e = self.expansion;
        require(e.is_finite() && e >= 1.0, "expansion", || format!("must be a finite number ≥ 1, got {e}"))?;
        let c = self.contraction;
        require(c > 0.0 && c < 1.0, "contraction", || format!("must be in (0, 1), got {c}"))?;
        let e = self.max_evaluations;
        require((1..=MAX_EVALUATIONS).contains(&e), "max_evaluations", || {
            format!("must be between 1 and {MAX_EVALUATIONS}, got {e}")
        })
    }
}

/// Most evaluations a pattern search may be given.
pub const MAX_EVALUATIONS: usize = 10_000_000;

/// Minimises `f` over `bounds` from `start` (clamped into the bounds). Polls `+e_1, −e_1, +e_2, …` in
/// that fixed order, so runs are deterministic; a trial outside the bounds is clamped onto them.
pub fn pattern_search(
    f: &mut dyn FnMut(&[f64]) -> Evaluation,
    bounds: &Bounds,
    start: &[f64],
    settings: &PatternSettings,
    progress: &mut dyn FnMut(Progress),
) -> Result<SearchResult, FieldError> {
    settings.validate()?;
    let n = bounds.dim();
    let mut x: Vec<f64> = (0..n).map(|i| bounds.clamp(i, start[i])).collect();
    let mut best = f(&x);
    let mut evaluations = 1;
    let mut mesh = settings.initial_mesh;
    let mut history = vec![Progress { iteration: 0, evaluations, best }];
    progress(history[0]);
    let mut iteration = 0;
    let status = loop {
        if let Some(reason) = spine_stop::check() {
            break reason.into();
        }
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
    Ok(SearchResult { status, x, best, evaluations, iterations: iteration, history })
}
