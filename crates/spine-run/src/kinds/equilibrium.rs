//! Kind `equilibrium`: the passive (θ1) and loaded (θ2) equilibria of a given design, with their
//! stability certificates.

use serde::Serialize;
use spine_case::{EquilibriumCase, ValidEquilibrium};
use spine_model::energy::strain_energy;
use spine_model::kinematics::{link_lengths, node_positions};
use spine_model::Design;
use spine_solve::{solve_static, EquilibriumSolution, EquilibriumStatus, Stability};

/// One equilibrium of the result, with the node positions of its shape.
#[derive(Clone, Debug, Serialize)]
pub struct EquilibriumReport {
    /// How the path ended (`converged`, or where it stopped and why); the summary prints it.
    pub status: EquilibriumStatus,
    /// Fraction of the load reached (1 when the path completed).
    pub load_factor: f64,
    /// Link angles `θ_i`, rad.
    pub theta: Vec<f64>,
    /// Multiplier of the sliding constraint, N.
    pub lambda: f64,
    /// Node positions `(X_i, Y_i)`, m.
    pub nodes: Vec<[f64; 2]>,
    /// `U(θ)`, J.
    pub strain_energy: f64,
    /// `max_i |r_i|`, N·m.
    pub residual_norm: f64,
    /// `|Φ(θ)|`, m.
    pub constraint_violation: f64,
    pub tolerance_used: f64,
    pub stability: Stability,
    pub continuation_steps: usize,
    pub rejected_steps: usize,
    pub newton_iterations: usize,
    pub factorisations: usize,
    pub general_factorisations: usize,
}

/// The unloaded shape `θ0`.
#[derive(Clone, Debug, Serialize)]
pub struct Unloaded {
    pub nodes: Vec<[f64; 2]>,
}

/// `result.json` of kind `equilibrium`.
#[derive(Clone, Debug, Serialize)]
pub struct EquilibriumResult {
    pub title: String,
    pub n_links: usize,
    /// `L_x`, m.
    pub length_x: f64,
    pub link_lengths: Vec<f64>,
    pub design: Design,
    pub unloaded: Unloaded,
    pub passive: EquilibriumReport,
    /// `None` when the passive path did not reach its load.
    pub loaded: Option<EquilibriumReport>,
    /// `X_{N+1}(θ1) − L_x`, m.
    pub passive_end_displacement: f64,
    /// `X_{N+1}(θ2) − L_x`, m.
    pub end_displacement: Option<f64>,
    pub passive_seconds: f64,
    pub loaded_seconds: Option<f64>,
}

fn nodes(lengths: &[f64], theta: &[f64]) -> Vec<[f64; 2]> {
    node_positions(lengths, theta).into_iter().map(|(x, y)| [x, y]).collect()
}

impl EquilibriumReport {
    fn new(sol: &EquilibriumSolution, lengths: &[f64], design: &Design) -> Self {
        Self {
            status: sol.status,
            load_factor: sol.load_factor,
            theta: sol.state.theta.clone(),
            lambda: sol.state.lambda,
            nodes: nodes(lengths, &sol.state.theta),
            strain_energy: strain_energy(&sol.state.theta, &design.theta0, &design.stiffness),
            residual_norm: sol.residual_norm,
            constraint_violation: sol.constraint_violation,
            tolerance_used: sol.tolerance_used,
            stability: sol.stability,
            continuation_steps: sol.stats.continuation_steps,
            rejected_steps: sol.stats.rejected_steps,
            newton_iterations: sol.stats.newton_iterations,
            factorisations: sol.stats.factorisations,
            general_factorisations: sol.stats.general_factorisations,
        }
    }

    fn summary_line(&self, name: &str) -> String {
        let eig = self.stability.min_eigenvalue.map_or("none (rigid)".to_string(), |e| format!("{e:.6e} N·m/rad"));
        format!(
            "{name:<8} {}\n         residual {:.2e} N·m, |Φ| {:.2e} m, smallest projected stiffness {eig}, {} steps / {} Newton iterations",
            self.status, self.residual_norm, self.constraint_violation, self.continuation_steps, self.newton_iterations
        )
    }
}

/// θ1 and θ2 of the case's design by continuation.
pub fn run_equilibrium(case: &EquilibriumCase, valid: &ValidEquilibrium) -> EquilibriumResult {
    let p = &valid.problem;
    let sol = solve_static(p, &valid.options);
    let lengths = link_lengths(&p.structure.chain.spans, &p.design.theta0);
    EquilibriumResult {
        title: case.title.clone(),
        n_links: p.structure.chain.n_links(),
        length_x: p.structure.chain.length_x(),
        unloaded: Unloaded { nodes: nodes(&lengths, &p.design.theta0) },
        passive: EquilibriumReport::new(&sol.passive, &lengths, &p.design),
        loaded: sol.loaded.as_ref().map(|l| EquilibriumReport::new(l, &lengths, &p.design)),
        passive_end_displacement: sol.passive_end_displacement,
        end_displacement: sol.end_displacement,
        passive_seconds: sol.passive.stats.time_seconds,
        loaded_seconds: sol.loaded.as_ref().map(|l| l.stats.time_seconds),
        link_lengths: lengths,
        design: p.design.clone(),
    }
}

impl crate::KindOutput for EquilibriumResult {
    /// Both equilibria found and certified stable.
    fn is_clean(&self) -> bool {
        self.passive.status.is_stable() && self.loaded.as_ref().is_some_and(|l| l.status.is_stable())
    }
}

impl std::fmt::Display for EquilibriumResult {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "{} — {} links", if self.title.is_empty() { "equilibrium" } else { &self.title }, self.n_links)?;
        writeln!(f, "{}", self.passive.summary_line("passive"))?;
        match &self.loaded {
            Some(l) => writeln!(f, "{}", l.summary_line("loaded"))?,
            None => writeln!(f, "loaded   not attempted: the passive path did not reach its load")?,
        }
        match self.end_displacement {
            Some(d) => writeln!(
                f,
                "end displacement X(θ2) − L_x = {d:.9e} m (passive alone {:.9e} m)",
                self.passive_end_displacement
            ),
            None => writeln!(f, "end displacement: none (loaded path incomplete)"),
        }
    }
}

impl crate::RunKind for EquilibriumCase {
    type Output = EquilibriumResult;

    fn run(&self, _: &mut crate::RunContext<'_>) -> Result<EquilibriumResult, crate::RunError> {
        Ok(run_equilibrium(self, &self.validate()?))
    }
}
