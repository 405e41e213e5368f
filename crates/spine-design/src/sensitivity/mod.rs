//! Sensitivities of an eq. (33) optimum to the problem's parameters: how `θ0*`, `K*`, the states
//! `θ1*`, `θ2*` (and their `λ`) and `J*` move when a load, `δ_d`, `C_K`, the span or a bound
//! changes, by the implicit function theorem on the KKT conditions at the solution.
//!
//! * The active set is read from the primal-dual solution ([`active_set`]): a bound is active when
//!   its multiplier exceeds its gap.
//! * The KKT matrix reduced to the free variables and active rows is factorised once
//!   ([`system`]); its inertia certifies second-order sufficiency (positive on the free
//!   variables, one negative eigenvalue per active row, none zero), the smallest singular value of
//!   the active rows' Jacobian measures LICQ, and the smallest active multiplier against the
//!   smallest inactive gap measures strict complementarity ([`Conditions`]).
//! * A parameter's rates of the NLP's gradient, constraints, objective and bounds are exact
//!   ([`rates`]): the problem's numbers carried as duals along the parameter's [`ProblemTangent`]
//!   (the scaled bounds `K/C_K` included), and the elements whose constants move differentiated by
//!   one tangent-jet pass each, on the optimum's own assembled patterns. No problem is rebuilt and
//!   nothing is differenced.
//! * Where a bound is weakly active (strict complementarity fails), the derivative is one-sided:
//!   for an increase and for a decrease of the parameter, the active set among the weak bounds that
//!   keeps the linearised KKT conditions feasible (the QP of the degenerate set, by enumeration).

mod active_set;
mod baseline;
mod derivative;
mod point;
mod polish;
mod rates;
mod smallest_eigenvalue;
mod system;

pub use active_set::{ActiveSet, Bound, Side, WEAK_GAP, WEAK_MULTIPLIER};
pub use baseline::KktBaseline;
pub use polish::{polish, POLISH_TOLERANCE};

use crate::full_space::{Layout, Multipliers};
use crate::{DesignProblem, ProblemTangent};
use derivative::{derivative, one_sided, weak_candidates};
use rates::rates;
use rayon::prelude::*;
use serde::Serialize;
pub(crate) use system::{dependent_rows, ActiveSystem, Matrices};

/// At most this many weakly active bounds are enumerated for one-sided derivatives (2^k systems).
pub const MAX_WEAK: usize = 8;

/// A converged full-space optimum: Ipopt's point and multipliers in `layout`'s order.
pub struct Optimum<'a> {
    pub problem: &'a DesignProblem,
    pub layout: Layout,
    pub x: &'a [f64],
    pub multipliers: &'a Multipliers,
}

/// One parameter: its name (the case file's field path), its value, and the rates of the
/// problem's numbers along it.
#[derive(Clone, Debug)]
pub struct Parameter {
    pub name: String,
    pub value: f64,
    pub tangent: ProblemTangent,
}

/// Why sensitivities could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SensitivityError {
    /// The parameter's tangent is not shaped as the problem (a parameter must not change the
    /// number of links).
    #[error("parameter `{0}`: its rates are not shaped as the problem (a parameter must not change its size)")]
    Size(String),
}

/// The conditions the derivatives rest on, with the numbers that show them.
#[derive(Clone, Debug, Serialize)]
pub struct Conditions {
    /// Variables fixed by an active bound, free variables, active constraint rows.
    pub active_variable_bounds: usize,
    pub free_variables: usize,
    pub active_rows: usize,
    /// LICQ: the smallest singular value of the active rows' Jacobian on the free variables
    /// (`None` above 250 000 entries, where only the inertia below speaks for it), and the active
    /// rows that depend linearly on others (LICQ fails where there are any).
    pub licq_smallest_singular_value: Option<f64>,
    pub dependent_rows: Vec<usize>,
    /// Strict complementarity: the smallest multiplier of an active inequality bound, the smallest
    /// gap of an inactive one, and the weakly active bounds ([`WEAK_MULTIPLIER`], [`WEAK_GAP`]).
    pub smallest_active_multiplier: Option<f64>,
    pub smallest_inactive_gap: Option<f64>,
    pub weakly_active: Vec<String>,
    /// The inertia of the reduced KKT matrix (positive, negative, zero) and whether it is that of
    /// a strict local minimum with independent active rows (second-order sufficiency and LICQ).
    pub reduced_kkt_inertia: Option<[usize; 3]>,
    pub second_order_sufficient: bool,
    /// All of the above: the derivatives are two-sided and exact.
    pub hold: bool,
}

/// Derivatives of the optimum with respect to one parameter (per unit of the parameter).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Derivative {
    /// `dθ0*/dp` (rad), `dK*/dp` (N·m/rad), `dθ1*/dp`, `dθ2*/dp` (rad), `dλ1*/dp`, `dλ2*/dp` (N).
    pub theta0: Vec<f64>,
    pub stiffness: Vec<f64>,
    pub theta1: Vec<f64>,
    pub theta2: Vec<f64>,
    pub lambda1: f64,
    pub lambda2: f64,
    /// `dJ*/dp` (J) by the envelope theorem (`∂L/∂p` at the solution) and directly
    /// (`∂f/∂p + ∇f · dx/dp`); the two agree where the conditions hold.
    pub objective: f64,
    pub objective_direct: f64,
}

/// The sensitivity to one parameter.
#[derive(Clone, Debug, Serialize)]
pub struct ParameterSensitivity {
    pub name: String,
    pub value: f64,
    /// The derivative where the conditions hold.
    pub derivative: Option<Derivative>,
    /// Where a bound is weakly active: the one-sided derivatives for an increase and a decrease.
    pub increase: Option<Derivative>,
    pub decrease: Option<Derivative>,
    /// Why no derivative is given, where that is not the conditions above.
    pub note: Option<String>,
}

/// Everything `spine sensitivity` reports.
#[derive(Clone, Debug, Serialize)]
pub struct SensitivityReport {
    pub conditions: Conditions,
    /// The inequality bounds that hold strictly at the optimum, named as
    /// [`Layout::variable_label`] / [`Layout::row_label`] with the side: `K[3] upper`,
    /// `theta0[1]-theta0[2] lower`. (Weakly active bounds are in `conditions.weakly_active`.)
    pub active: Vec<String>,
    pub parameters: Vec<ParameterSensitivity>,
}

/// The sensitivities of the optimum to each parameter.
///
/// The whole step is handed to rayon's pool at once (one wake-up). Inside it, two halves run side
/// by side: the evaluation, the active set and the factorisation of the reduced KKT matrix (with
/// LICQ's measure offered to whichever thread is free), and every parameter's rates, which need
/// the problem's elements but not their sparsity patterns (so they start at once, on elements of
/// their own); then each parameter's solve. Handed over piece by piece from outside the pool, each
/// hand-over cost a wake-up of the pool's threads (tens of µs here, as much as the work at N = 10).
pub fn sensitivities(optimum: &Optimum<'_>, parameters: &[Parameter]) -> Result<SensitivityReport, SensitivityError> {
    rayon::scope(|_| step(optimum, parameters))
}

/// What the optimum's factorised KKT system is built from: its evaluation, matrices and active
/// set, the system and LICQ's measure.
struct Prepared {
    at: point::Evaluation,
    matrices: Matrices,
    set: ActiveSet,
    system: ActiveSystem,
    licq: Option<f64>,
}

fn prepare(optimum: &Optimum<'_>) -> Prepared {
    let (layout, x) = (optimum.layout, optimum.x);
    let assembled = crate::full_space::assemble(optimum.problem, layout.states);
    let (at, matrices) = Matrices::of(&assembled, optimum.problem, layout, x, &optimum.multipliers.constraints);
    let set = ActiveSet::identify(x, &at, &matrices.jacobian_pattern, optimum.multipliers);
    // Rows that depend on others are left out of the system (their multipliers are not unique);
    // each derivative is then checked against them.
    let jacobian = (&matrices.jacobian_pattern[..], &matrices.jacobian[..]);
    let (system, licq) = rayon::join(
        || ActiveSystem::new(&matrices, layout, set.variables.clone(), set.rows.clone()),
        || system::smallest_singular_value(layout.num_variables(), &set.variables, &set.rows, jacobian),
    );
    Prepared { at, matrices, set, system, licq }
}

fn step(optimum: &Optimum<'_>, parameters: &[Parameter]) -> Result<SensitivityReport, SensitivityError> {
    let layout = optimum.layout;
    let (Prepared { at, matrices, set, system, licq }, rates) = rayon::join(
        || prepare(optimum),
        || {
            let elements = crate::full_space::groups(&crate::numbers::Numbers::of(optimum.problem), layout.states);
            parameters.iter().map(|p| rates(optimum, &elements, &p.name, &p.tangent)).collect::<Result<Vec<_>, _>>()
        },
    );
    let rates = rates?;
    let conditions = conditions(&set, &system, layout, licq);
    let weak = set.weak_variables.len() + set.weak_rows.len();
    let candidates = (weak > 0 && weak <= MAX_WEAK).then(|| weak_candidates(optimum, &matrices, &set));
    let step = Step { optimum, at: &at, matrices: &matrices, system: &system };
    let two_sided = weak == 0 && conditions.second_order_sufficient;
    // The parameters are independent: each on its own, in parallel, in order.
    let out = parameters
        .par_iter()
        .zip(&rates)
        .map(|(parameter, rates)| step.differentiate(parameter, rates, two_sided, candidates.as_ref()))
        .collect();
    Ok(SensitivityReport { conditions, active: active_labels(&set, layout), parameters: out })
}

/// What every parameter's derivative is formed from: the optimum, its evaluation, matrices and
/// factorised system.
struct Step<'s, 'a> {
    optimum: &'s Optimum<'a>,
    at: &'s point::Evaluation,
    matrices: &'s Matrices,
    system: &'s ActiveSystem,
}

impl Step<'_, '_> {
    /// The sensitivity to one parameter whose NLP data moves at `rates`: two-sided where
    /// `two_sided` (the conditions hold but for dependent rows, which it is checked against),
    /// one-sided over the weak `candidates`.
    fn differentiate(
        &self,
        parameter: &Parameter,
        rates: &rates::Rates,
        two_sided: bool,
        candidates: Option<&derivative::WeakCandidates>,
    ) -> ParameterSensitivity {
        let (optimum, matrices, at) = (self.optimum, self.matrices, self.at);
        let mut note = None;
        let solution = two_sided.then(|| derivative(optimum, matrices, self.system, rates, at, false)).flatten();
        let derivative = solution.and_then(|s| match s.broken_row {
            Some(row) => {
                note = Some(format!(
                    "the active rows are dependent (LICQ fails) and constraint row {row} cannot follow the parameter: no two-sided derivative"
                ));
                None
            }
            None => Some(s.derivative),
        });
        let (increase, decrease) = match candidates {
            Some(c) => {
                (one_sided(optimum, matrices, c, rates, at, 1.0), one_sided(optimum, matrices, c, rates, at, -1.0))
            }
            None => (None, None),
        };
        ParameterSensitivity {
            name: parameter.name.clone(),
            value: parameter.value,
            derivative,
            increase,
            decrease,
            note,
        }
    }
}

/// The strictly active inequality bounds by name and side (equalities left out).
fn active_labels(set: &ActiveSet, layout: Layout) -> Vec<String> {
    let side = |b: &Bound| match b.side {
        Side::Lower => Some("lower"),
        Side::Upper => Some("upper"),
        Side::Both => None,
    };
    let variables =
        set.variables.iter().filter_map(|b| Some(format!("{} {}", layout.variable_label(b.index), side(b)?)));
    let rows = set.rows.iter().filter_map(|b| Some(format!("{} {}", layout.row_label(b.index), side(b)?)));
    variables.chain(rows).collect()
}

/// LICQ, strict complementarity and second-order sufficiency, with their numbers.
fn conditions(set: &ActiveSet, system: &ActiveSystem, layout: Layout, licq: Option<f64>) -> Conditions {
    let weakly_active: Vec<String> = set
        .weak_variables
        .iter()
        .map(|b| {
            format!(
                "variable {} {} ({} bound): multiplier {:.1e}, gap {:.1e}",
                b.index,
                layout.variable_label(b.index),
                b.side,
                b.multiplier,
                b.gap
            )
        })
        .chain(set.weak_rows.iter().map(|b| {
            format!(
                "constraint row {} {} ({} bound): multiplier {:.1e}, gap {:.1e}",
                b.index,
                layout.row_label(b.index),
                b.side,
                b.multiplier,
                b.gap
            )
        }))
        .collect();
    let second_order_sufficient = system.certified().is_some();
    let dependent = &system.dependent;
    let finite = |v: f64| v.is_finite().then_some(v);
    Conditions {
        active_variable_bounds: set.variables.len(),
        free_variables: layout.num_variables() - set.variables.len(),
        active_rows: set.rows.len(),
        licq_smallest_singular_value: licq,
        dependent_rows: dependent.clone(),
        smallest_active_multiplier: finite(set.smallest_active_multiplier),
        smallest_inactive_gap: finite(set.smallest_inactive_gap),
        reduced_kkt_inertia: system.kkt.as_ref().map(|k| [k.inertia.positive, k.inertia.negative, k.inertia.zero]),
        second_order_sufficient,
        hold: second_order_sufficient && weakly_active.is_empty() && dependent.is_empty(),
        weakly_active,
    }
}
