//! A design case's criterion (field `objective`): the paper's strain energy by default, or one of
//! the built-ins of [`spine_design::Objective`].

use crate::error::CaseError;
use crate::per_item::PerItem;
use crate::specs::axial_forces;
use serde::{Deserialize, Serialize};
use spine_design::{DesignProblem, Formulation, Objective};
use spine_model::{Design, NodalLoads};

/// `"strain_energy"` (default, the paper's `J`), `"total_stiffness"`,
/// `{"peak_moment": {"exponent": 8, "reference": 40.0}}` or
/// `{"compliance": {"p_y": [...], "p_x": 0}}` (docs/objectives.md).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ObjectiveSpec {
    /// The paper's `J = U(θ1)`, J (eq. (33)).
    #[default]
    StrainEnergy,
    /// `Σ K`, N·m/rad: the material a design uses.
    TotalStiffness,
    /// A smooth maximum (`p`-norm) of the joint moments of both equilibria.
    PeakMoment(PeakMomentSpec),
    /// The compliance `Pᵀu` under a second load case `P` acting alone.
    Compliance(ComplianceSpec),
}

/// `p`-norm settings of `peak_moment`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PeakMomentSpec {
    /// The norm's exponent `p`: even, 2..=64 (default 8).
    #[serde(default = "eight")]
    pub exponent: u32,
    /// `M_ref`, N·m (> 0): the moments' unit in the NLP. Default: the largest joint moment of the
    /// start design's two equilibria, so that the sum starts near one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference: Option<f64>,
}

fn eight() -> u32 {
    8
}

/// The second load case of `compliance`, N: transverse forces `p_y` (one number for every node or
/// `N + 1`) and axial forces `p_x` (one number at the end node or `N + 1`), both default 0.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ComplianceSpec {
    #[serde(default)]
    pub p_y: PerItem,
    #[serde(default)]
    pub p_x: PerItem,
}

/// The largest exponent of `peak_moment` (`x^64` of a ratio of 2 is 1.8e19: beyond, the sum's
/// terms leave double precision's comfortable range).
pub const MAX_EXPONENT: u32 = 64;

impl ObjectiveSpec {
    /// The criterion for `problem` (whose objective is still the default), checked; errors name
    /// `objective.FIELD`. The default `M_ref` of `peak_moment` comes from `start`'s equilibria.
    pub fn resolve(&self, problem: &DesignProblem, start: &Design) -> Result<Objective, CaseError> {
        let n = problem.n_links();
        Ok(match self {
            ObjectiveSpec::StrainEnergy => Objective::StrainEnergy,
            ObjectiveSpec::TotalStiffness => Objective::TotalStiffness,
            ObjectiveSpec::PeakMoment(PeakMomentSpec { exponent, reference }) => {
                let field = "objective.peak_moment";
                if !(*exponent >= 2 && *exponent <= MAX_EXPONENT && exponent % 2 == 0) {
                    return Err(CaseError::invalid(
                        format!("{field}.exponent"),
                        format!("must be an even number from 2 to {MAX_EXPONENT}, got {exponent}"),
                    ));
                }
                let reference = match reference {
                    Some(r) => crate::specs::positive(&format!("{field}.reference"), *r, "N·m")?,
                    None => start_peak_moment(problem, start).ok_or_else(|| {
                        CaseError::invalid(
                            format!("{field}.reference"),
                            "the start design has no equilibria (or no moment) to take the default from; give M_ref, a number > 0 N·m",
                        )
                    })?,
                };
                Objective::PeakMoment { exponent: *exponent, reference }
            }
            ObjectiveSpec::Compliance(ComplianceSpec { p_y, p_x }) => {
                let field = "objective.compliance";
                let p_y = p_y.expand(&format!("{field}.p_y"), n + 1, "one per node, N + 1")?;
                let p_x = axial_forces(&format!("{field}.p_x"), p_x, n)?;
                // Forces at the base do nothing, and a vertical force at the slider only loads it.
                let works = p_x[1..].iter().any(|&f| f != 0.0) || p_y[1..n].iter().any(|&f| f != 0.0);
                if !works {
                    return Err(CaseError::invalid(
                        field,
                        "the load case moves nothing: give a nonzero p_y at an interior node (1..N-1) or a nonzero p_x beyond the base",
                    ));
                }
                Objective::Compliance { load: NodalLoads { p_x, p_y } }
            }
        })
    }
}

/// The largest `|M_j|` (N·m) of `start`'s two equilibria (projected into the bounds, reached by
/// continuation), when both exist and it is positive.
fn start_peak_moment(problem: &DesignProblem, start: &Design) -> Option<f64> {
    let (design, _) = problem.project_start(start);
    let solution = spine_solve::solve_static(&problem.static_problem(&design), &Default::default());
    let loaded = solution.loaded.filter(|l| l.load_factor == 1.0)?;
    (solution.passive.load_factor == 1.0).then_some(())?;
    let peak = [&solution.passive.state, &loaded.state]
        .into_iter()
        .flat_map(|s| spine_design::objective::joint_moments(&design, s))
        .fold(0.0f64, |m, x| m.max(x.abs()));
    (peak > 0.0 && peak.is_finite()).then_some(peak)
}

/// Extra constraints of a design case (field `constraints`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ConstraintsSpec {
    /// `U(θ1) ≤ strain_energy_max`, J (> 0): a budget on the paper's strain energy under the
    /// passive load, e.g. with `"objective": "total_stiffness"` the least material that keeps
    /// the design this stiff.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub strain_energy_max: Option<f64>,
}

impl ConstraintsSpec {
    pub fn is_empty(&self) -> bool {
        self.strain_energy_max.is_none()
    }

    /// The budget, checked; errors name `constraints.FIELD`.
    pub fn validate(&self) -> Result<Option<f64>, CaseError> {
        self.strain_energy_max.map(|u| crate::specs::positive("constraints.strain_energy_max", u, "J")).transpose()
    }
}

/// The reduced space minimises the paper's `J` under the paper's constraints only: its gradient is
/// the hand adjoint of the strain energy (Appendices I–II) and its rows are the paper's. Errors
/// name `formulation`.
pub fn check_formulation(formulation: Formulation, problem: &DesignProblem) -> Result<(), CaseError> {
    if formulation != Formulation::Reduced {
        return Ok(());
    }
    if problem.objective != Objective::StrainEnergy {
        return Err(CaseError::invalid(
            "formulation",
            format!(
                "\"reduced\" minimises the paper's strain energy only (its gradient is the hand adjoint of J); objective \"{}\" needs \"full\"",
                problem.objective.name()
            ),
        ));
    }
    if problem.strain_energy_max.is_some() {
        return Err(CaseError::invalid(
            "formulation",
            "\"reduced\" has the paper's constraints only; constraints.strain_energy_max needs \"full\"",
        ));
    }
    Ok(())
}
