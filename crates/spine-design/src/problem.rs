//! The static design problem of eq. (33), independent of how it is solved.

use crate::objective::Objective;
use serde::Serialize;
use spine_model::{Design, LinkLoads, State, Structure};
use spine_solve::{solve_static, ContinuationOptions};

/// Bounds of the design (paper Sec. 5, "Geometrical and stiffness values").
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DesignBounds {
    /// `|θ0_i| ≤ theta0_max`, rad (paper: π/6).
    pub theta0_max: f64,
    /// `|θ0_i − θ0_{i+1}| ≤ relative_angle_max`, rad (paper: π/6).
    pub relative_angle_max: f64,
    /// `stiffness_min_j ≤ K_j ≤ stiffness_max_j`, N·m/rad, `N + 1` entries each (paper: 10², 10⁴).
    /// Equal bounds fix a spring (for example `K_{N+1} = 0`: no end spring).
    pub stiffness_min: Vec<f64>,
    pub stiffness_max: Vec<f64>,
    /// `height_min ≤ Y0_j ≤ height_max` for the interior nodes `j = 2..N`, m
    /// (paper: 0.01 m and 0.25 L_x).
    pub height_min: f64,
    pub height_max: f64,
    /// `ℓ`, m: the lower height bound ramps from 0 at the base and the end to `height_min` over
    /// this distance, `Y0_j ≥ height_min · min(1, x_j/ℓ, (L_x − x_j)/ℓ)` ([`height_floor`]);
    /// 0 (the paper's): the same bound at every interior node. A bound that is a function of `x`
    /// is a property of the rod, where a per-node number is not: node 2 sits at `x = a`, and
    /// `Y0_2 ≤ a tan θ0_max` falls below any fixed bound once `a` is small enough.
    pub height_ramp: f64,
}

/// The lower height bound at `x` (m) on a chain of horizontal length `length_x` (m), with
/// [`DesignBounds::height_ramp`] `ramp` and `height_min` (m), in any scalar (the sensitivities
/// differentiate it).
pub fn height_floor<T: spine_model::Scalar>(height_min: T, ramp: T, x: T, length_x: T) -> T {
    if ramp.re() <= 0.0 {
        return height_min;
    }
    let (start, end) = (x / ramp, (length_x - x) / ramp);
    let near = if start.re() <= end.re() { start } else { end };
    if near.re() < 1.0 {
        height_min * near
    } else {
        height_min
    }
}

/// The lower bound of each interior node's height `Y0_j`, `j = 2..N` (`N − 1` entries), m, on a
/// chain of horizontal spans `spans` ([`height_floor`] at each node's `x`), in any scalar.
pub fn height_floors<T: spine_model::Scalar>(height_min: T, ramp: T, spans: &[T]) -> Vec<T> {
    let length_x = spans.iter().fold(T::zero(), |sum, &a| sum + a);
    let mut x = T::zero();
    spans[..spans.len().saturating_sub(1)]
        .iter()
        .map(|&a| {
            x += a;
            height_floor(height_min, ramp, x, length_x)
        })
        .collect()
}

impl DesignBounds {
    /// [`height_floors`] of these bounds on a chain of horizontal spans `spans`, m.
    pub fn height_floors(&self, spans: &[f64]) -> Vec<f64> {
        height_floors(self.height_min, self.height_ramp, spans)
    }
}

/// Eq. (33): find `θ0` and `K` minimising the strain energy `J = U(θ1; θ0, K)` stored under the
/// passive load, subject to the equilibria `θ1` (passive) and `θ2` (passive + actuation), the end
/// constraint `Φ(θ0) = 0`, the end displacement `X_{N+1}(θ2) − L_x = δ_d` and the bounds.
#[derive(Clone, Debug)]
pub struct DesignProblem {
    /// The chain with its passive load and actuation.
    pub structure: Structure,
    /// Desired end displacement `δ_d`, m (negative: the end moves toward the base).
    pub delta_d: f64,
    pub bounds: DesignBounds,
    /// `C_K` of eq. (34): the optimiser's stiffness variable is `k = K / C_K`.
    pub stiffness_scale: f64,
    /// What is minimised: the paper's strain energy `J` or another criterion ([`Objective`]).
    pub objective: Objective,
    /// An extra constraint beyond the paper's: a budget `U(θ1) ≤ U_max` on the strain energy under
    /// the passive load, J (`None`: no budget). With [`Objective::TotalStiffness`] it poses the
    /// classic least-material design of a given stiffness.
    pub strain_energy_max: Option<f64>,
}

impl DesignProblem {
    pub fn n_links(&self) -> usize {
        self.structure.n_links()
    }

    /// Load resultants of the passive load, self-weight included.
    pub fn passive_loads(&self) -> LinkLoads {
        self.structure.passive_loads()
    }

    /// Load resultants of the passive load plus the actuation, self-weight included.
    pub fn total_loads(&self) -> LinkLoads {
        self.structure.total_loads()
    }

    /// Both equilibria (passive, loaded) of `design` by Newton's method at full load from nearby
    /// states (for example those of a slightly different design), or `None` when Newton does not
    /// converge there. Used for re-solves after small design changes (finite differences, the
    /// reduced-space Hessian).
    pub fn equilibria_near(
        &self,
        design: &Design,
        passive: &State,
        loaded: &State,
        continuation: &ContinuationOptions,
    ) -> Option<(State, State)> {
        Some((
            self.equilibrium_near(design, self.passive_loads(), passive, continuation)?,
            self.equilibrium_near(design, self.total_loads(), loaded, continuation)?,
        ))
    }

    /// One equilibrium of `design` under `loads` by Newton's method at full load from the nearby
    /// state `start` ([`Self::equilibria_near`]'s for one load state).
    pub fn equilibrium_near(
        &self,
        design: &Design,
        loads: LinkLoads,
        start: &State,
        continuation: &ContinuationOptions,
    ) -> Option<State> {
        let spans = &self.structure.chain.spans;
        let path = spine_solve::LoadPath { spans, design, from: loads.clone(), to: loads, start: start.clone() };
        let solution = spine_solve::solve_path(&path, continuation);
        (solution.load_factor == 1.0).then_some(solution.state)
    }

    /// The equilibrium `θ3` of `design` under the compliance's load case
    /// ([`Objective::Compliance`]), by continuation from the unloaded shape; `None` without that
    /// criterion or when the load path does not reach full load.
    pub fn probe_state(&self, design: &Design, continuation: &ContinuationOptions) -> Option<State> {
        let loads = self.objective.probe_loads(&self.structure.chain)?;
        let spans = &self.structure.chain.spans;
        let from = LinkLoads::zero(self.n_links());
        let path = spine_solve::LoadPath { spans, design, from, to: loads, start: State::unloaded(design) };
        let solution = spine_solve::solve_path(&path, continuation);
        (solution.load_factor == 1.0).then_some(solution.state)
    }

    /// The problem as the equilibrium solver sees it, for one design.
    pub fn static_problem(&self, design: &Design) -> spine_solve::StaticProblem {
        spine_solve::StaticProblem { structure: self.structure.clone(), design: design.clone() }
    }

    /// Projects a start design into the bounds on `θ0` and `K`; returns the projected design and
    /// one line per changed entry (the paper's 5-link start has `θ0 = ±π/5 > π/6` and
    /// `K_6 = 0 < 100`).
    pub fn project_start(&self, start: &Design) -> (Design, Vec<String>) {
        let b = &self.bounds;
        let mut notes = Vec::new();
        let mut design = start.clone();
        for (i, t) in design.theta0.iter_mut().enumerate() {
            let clamped = t.clamp(-b.theta0_max, b.theta0_max);
            if clamped != *t {
                notes.push(format!(
                    "theta0[{i}] = {t:.6} rad projected to {clamped:.6} rad (|theta0| <= {:.6})",
                    b.theta0_max
                ));
                *t = clamped;
            }
        }
        for (j, k) in design.stiffness.iter_mut().enumerate() {
            let clamped = k.clamp(b.stiffness_min[j], b.stiffness_max[j]);
            if clamped != *k {
                notes.push(format!(
                    "stiffness[{j}] = {k} N·m/rad projected to {clamped} N·m/rad (bounds {}..{})",
                    b.stiffness_min[j], b.stiffness_max[j]
                ));
                *k = clamped;
            }
        }
        (design, notes)
    }

    /// Unloaded node heights `Y0_j = Σ_{k<j} a_k tan θ0_k`, `j = 1..N+1`, m.
    pub fn node_heights(&self, theta0: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0];
        for (a, t) in self.structure.chain.spans.iter().zip(theta0) {
            y.push(y.last().unwrap() + a * t.tan());
        }
        y
    }
}

/// Start states of the full space: the equilibria of the start design by continuation when they
/// exist, else the unloaded shape with `λ = 0` (and a note saying so).
pub fn start_states(
    problem: &DesignProblem,
    start: &Design,
    continuation: &ContinuationOptions,
    notes: &mut Vec<String>,
) -> (State, State) {
    let solution = solve_static(&problem.static_problem(start), continuation);
    let passive_ok = solution.passive.load_factor == 1.0;
    let passive = if passive_ok { solution.passive.state.clone() } else { State::unloaded(start) };
    let loaded = match solution.loaded.filter(|l| l.load_factor == 1.0) {
        Some(l) => l.state,
        None => {
            notes.push("the start design has no loaded equilibrium on its load path; θ2 starts at θ1".into());
            passive.clone()
        }
    };
    if !passive_ok {
        notes.push("the start design has no passive equilibrium on its load path; θ1 starts at θ0".into());
    }
    (passive, loaded)
}
