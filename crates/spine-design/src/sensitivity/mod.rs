//! Sensitivities of an eq. (33) optimum to the problem's parameters: how `θ0*`, `K*`, the states
//! `θ1*`, `θ2*` (and their `λ`) and `J*` move when a load, `δ_d`, `C_K`, the span or a bound
//! changes, by the implicit function theorem on the KKT conditions at the solution.
//!
//! * The active set is read from the primal-dual solution ([`crate::optimality::active_set`]): a
//!   bound is active when its multiplier exceeds its gap.
//! * The KKT matrix reduced to the free variables and active rows is factorised once
//!   ([`crate::optimality`]); its inertia certifies second-order sufficiency (positive on the free
//!   variables, one negative eigenvalue per active row, none zero), the smallest singular value of
//!   the active rows' Jacobian measures LICQ, and the smallest active multiplier against the
//!   smallest inactive gap measures strict complementarity ([`Conditions`]).
//! * A parameter's rates of the NLP's gradient, constraints, objective and bounds are exact
//!   (`rates`): the problem's numbers carried as duals along the parameter's [`ProblemTangent`]
//!   (the scaled bounds `K/C_K` included), and the elements whose constants move differentiated by
//!   one tangent-jet pass each, on the optimum's own assembled patterns. No problem is rebuilt and
//!   nothing is differenced.
//! * Where a bound is weakly active (strict complementarity fails), the derivative is one-sided:
//!   for an increase and for a decrease of the parameter, the active set among the weak bounds that
//!   keeps the linearised KKT conditions feasible (the QP of the degenerate set, by enumeration).

mod baseline;
mod derivative;
mod rates;
mod shared;
mod step;

pub use baseline::KktBaseline;

use crate::full_space::Multipliers;
use crate::layout::Layout;
use crate::numbers::ProblemTangent;
use crate::optimality::active_set::{ActiveSet, Bound, Side};
use crate::optimality::system::ActiveSystem;
use crate::problem::DesignProblem;
use serde::Serialize;

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
    /// gap of an inactive one, and the weakly active bounds
    /// ([`crate::optimality::active_set::WEAK_MULTIPLIER`],
    /// [`crate::optimality::active_set::WEAK_GAP`]).
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
/// The calling thread starts at once and one helper from rayon's pool is offered the same work
/// (`shared`, `step`): while the caller evaluates the optimum, identifies its active set and
/// factorises the reduced KKT matrix, the helper takes the parameters' rates (they need the
/// problem's elements, not the sparsity patterns, so they start at once on elements of their
/// own) and then LICQ's measure; the caller takes whatever is left. Each parameter's solve is
/// then shared the same way. A helper that wakes late costs nothing but the offer.
pub fn sensitivities(optimum: &Optimum<'_>, parameters: &[Parameter]) -> Result<SensitivityReport, SensitivityError> {
    step::Work::new(optimum, parameters).run()
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
