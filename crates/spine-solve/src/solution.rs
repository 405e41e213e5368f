//! What an equilibrium solve reports: its status, the solution with its stability certificate, and
//! the solver's counts.

use crate::stability::Stability;
use serde::Serialize;
use spine_model::State;

/// How a path ended.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum EquilibriumStatus {
    /// Full load reached; the path and the final equilibrium are stable.
    Stable,
    /// Full load reached, but the path lost stability at `critical_load_factor` (bifurcation): the
    /// returned equilibrium is unstable and not what the structure would do.
    Unstable { critical_load_factor: f64 },
    /// The path cannot pass `load_factor`: a fold (limit point, snap-through), located to
    /// `critical_load_tolerance`. The returned state is the last stable equilibrium traced before
    /// it (its own load factor is the solution's `load_factor`).
    LimitPoint { load_factor: f64 },
    /// Newton failed and the step could not be reduced further, away from any detected fold.
    NewtonFailed { load_factor: f64 },
    /// `max_steps` continuation steps were used up at `load_factor`.
    StepLimit { load_factor: f64 },
    /// The run's wall-clock limit passed (`spine_stop`) at `load_factor`.
    TimeLimit { load_factor: f64 },
    /// A stop was requested from outside (Ctrl-C) at `load_factor`.
    Interrupted { load_factor: f64 },
}

impl EquilibriumStatus {
    /// Full load reached and the equilibrium is stable: the only status a design may rely on.
    pub fn is_stable(&self) -> bool {
        matches!(self, Self::Stable)
    }
}

impl std::fmt::Display for EquilibriumStatus {
    /// One line for people.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let text: String = match *self {
            Self::Stable => "converged, stable".into(),
            Self::Unstable { critical_load_factor } => format!(
                "converged at full load but UNSTABLE: stability lost at {:.6} of the load (buckling)",
                critical_load_factor
            ),
            Self::LimitPoint { load_factor } => {
                format!("NOT converged: limit point (snap-through) at {load_factor:.6} of the load")
            }
            Self::NewtonFailed { load_factor } => {
                format!("NOT converged: Newton failed at {load_factor:.6} of the load")
            }
            Self::StepLimit { load_factor } => {
                format!("NOT converged: continuation step limit at {load_factor:.6} of the load")
            }
            Self::TimeLimit { load_factor } => {
                format!("NOT converged: the time limit passed at {load_factor:.6} of the load")
            }
            Self::Interrupted { load_factor } => format!("NOT converged: interrupted at {load_factor:.6} of the load"),
        };
        f.write_str(&text)
    }
}

/// Work done by one path.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct SolveStats {
    pub continuation_steps: usize,
    pub rejected_steps: usize,
    pub newton_iterations: usize,
    /// Factorisations that needed the general sparse LU instead of the `O(N)` block elimination.
    pub general_factorisations: usize,
    pub factorisations: usize,
    /// Wall time, s.
    pub time_seconds: f64,
}

/// An equilibrium found along a load path.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EquilibriumSolution {
    pub state: State,
    /// Fraction of the load reached (1 when the path completed).
    pub load_factor: f64,
    /// `max_i |r_i|` over the joint rows, N·m.
    pub residual_norm: f64,
    /// `|Φ(θ)|`, m.
    pub constraint_violation: f64,
    /// The convergence threshold Newton used at the returned state (see `residual_tolerance`).
    pub tolerance_used: f64,
    pub stability: Stability,
    pub status: EquilibriumStatus,
    pub stats: SolveStats,
}
