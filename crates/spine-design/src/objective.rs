//! The design criterion of an eq. (33)-type problem: the paper's strain energy, or a built-in
//! criterion of the user's choice (case field `objective`). Every criterion is a sum of local
//! elements generic over the scalar ([`spine_model::local`]), so the assembly gives its exact
//! gradient and Hessian; [`Objective::value`] evaluates the same sum directly from the design and
//! the equilibria, the reference the assembled objective is tested against.

use serde::Serialize;
use spine_model::chain::spring_links;
use spine_model::{Design, LinkLoads, NodalLoads, State};

/// What eq. (33) minimises. The constraints (both equilibria, `Φ(θ0) = 0`, the end displacement
/// `δ_d`, the bounds) are the paper's whatever the criterion.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "name")]
pub enum Objective {
    /// The paper's `J = U(θ1) = ½ Σ_j K_j (Δθ1_j − Δθ0_j)²` (eq. (33)), J: the strain energy stored
    /// under the passive load.
    #[default]
    StrainEnergy,
    /// `Σ_j K_j`, N·m/rad: the springs' total stiffness, a measure of the material a design uses.
    TotalStiffness,
    /// A smooth maximum of the joint moments `M_j = K_j (Δθ_j − Δθ0_j − Δθ_{j−1} + Δθ0_{j−1})`,
    /// N·m, of both equilibria (`θ1` and `θ2`, springs `1..N+1`): the NLP minimises
    /// `Σ (M_j / M_ref)^p` over the `2(N + 1)` moments, whose `p`-th root is the `p`-norm of the
    /// moments in units of `M_ref` (at least the largest `|M_j| / M_ref`, at most `(2N + 2)^{1/p}`
    /// times it). Minimising the sum minimises the norm.
    PeakMoment {
        /// `p`, even, 2..=64.
        exponent: u32,
        /// `M_ref`, N·m (> 0): scales the moments so that the sum is of order one.
        reference: f64,
    },
    /// The compliance `c = Σ_j P_j · (r_j(θ3) − r_j(θ0))`, J, under a second load case `P`
    /// acting alone (no self-weight, no passive load): the work of `P` on the node displacements
    /// at its own equilibrium `θ3`, a third state of the NLP. For small loads `c = Pᵀ K⁻¹ P`, twice
    /// the strain energy that `P` stores; smaller is stiffer against `P`.
    Compliance {
        /// The second load case's nodal forces, N (`N + 1` per component).
        load: NodalLoads,
    },
}

/// The equilibria a criterion is measured on.
pub struct Equilibria<'a> {
    pub passive: &'a State,
    pub loaded: &'a State,
    /// `θ3`, the equilibrium under [`Objective::Compliance`]'s load (only for that criterion).
    pub probe: Option<&'a State>,
}

impl Objective {
    /// The case-file name of the criterion.
    pub fn name(&self) -> &'static str {
        match self {
            Objective::StrainEnergy => "strain_energy",
            Objective::TotalStiffness => "total_stiffness",
            Objective::PeakMoment { .. } => "peak_moment",
            Objective::Compliance { .. } => "compliance",
        }
    }

    /// The objective's symbol and unit in printed output (`J` and ` J` for the paper's).
    pub fn symbol_and_unit(&self) -> (&'static str, &'static str) {
        match self {
            Objective::StrainEnergy => ("J", " J"),
            Objective::TotalStiffness => ("Σ K", " N·m/rad"),
            Objective::PeakMoment { .. } => ("Σ (M/M_ref)^p", ""),
            Objective::Compliance { .. } => ("Pᵀu", " J"),
        }
    }

    /// Whether the NLP has the third state `θ3` (the compliance's load case).
    pub fn has_probe(&self) -> bool {
        matches!(self, Objective::Compliance { .. })
    }

    /// The second load case's link resultants (eq. (48), no self-weight), when there is one.
    pub fn probe_loads(&self, chain: &spine_model::Chain) -> Option<LinkLoads> {
        match self {
            Objective::Compliance { load } => Some(LinkLoads::from_nodal(chain, load, false)),
            _ => None,
        }
    }

    /// The NLP's objective at `design` and its equilibria on the chain of `spans` (m): the sum its
    /// elements add up to, evaluated directly (`NaN` when the compliance's `θ3` is missing).
    pub fn value(&self, spans: &[f64], design: &Design, states: &Equilibria<'_>) -> f64 {
        match self {
            Objective::StrainEnergy => {
                spine_model::energy::strain_energy(&states.passive.theta, &design.theta0, &design.stiffness)
            }
            Objective::TotalStiffness => design.stiffness.iter().sum(),
            Objective::PeakMoment { exponent, reference } => [states.passive, states.loaded]
                .iter()
                .flat_map(|s| joint_moments(design, s))
                .map(|m| (m / reference).powi(*exponent as i32))
                .sum(),
            Objective::Compliance { load } => match states.probe {
                Some(probe) => compliance(load, spans, design, probe),
                None => f64::NAN,
            },
        }
    }
}

/// The `N + 1` joint moments `M_j = K_j ((θ_j − θ0_j) − (θ_{j−1} − θ0_{j−1}))`, N·m, of `state`
/// (a missing neighbour, beyond the base or the end, counts as zero deflection).
pub fn joint_moments(design: &Design, state: &State) -> Vec<f64> {
    let n = design.theta0.len();
    let deflection = |i: Option<usize>| i.map_or(0.0, |i| state.theta[i] - design.theta0[i]);
    (0..=n)
        .map(|j| {
            let (prev, this) = spring_links(n, j);
            design.stiffness[j] * (deflection(this) - deflection(prev))
        })
        .collect()
}

/// The work `Σ_j P_j · (r_j(θ3) − r_j(θ0))`, J, of the compliance's load `P` at `θ3`, from the
/// node positions (eq. (1)) of the chain of `spans`.
fn compliance(load: &NodalLoads, spans: &[f64], design: &Design, probe: &State) -> f64 {
    let lengths = spine_model::kinematics::link_lengths(spans, &design.theta0);
    let loaded = spine_model::kinematics::node_positions(&lengths, &probe.theta);
    let unloaded = spine_model::kinematics::node_positions(&lengths, &design.theta0);
    (0..loaded.len())
        .map(|j| load.p_x[j] * (loaded[j].0 - unloaded[j].0) + load.p_y[j] * (loaded[j].1 - unloaded[j].1))
        .sum()
}

/// Every criterion's measure of a design, whichever one it was optimised for: to compare designs
/// across criteria (result field `measures`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Measures {
    /// The paper's `J = U(θ1)`, J.
    pub strain_energy: f64,
    /// `Σ K`, N·m/rad.
    pub total_stiffness: f64,
    /// `max |M_j|` over the springs of both equilibria, N·m.
    pub peak_moment: f64,
    /// The compliance under the second load case, J (only with [`Objective::Compliance`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub compliance: Option<f64>,
}

impl Measures {
    /// The measures of `design` and its equilibria on the chain of `spans` (m), for a problem
    /// optimised for `objective` (its compliance load, if any).
    pub fn of(objective: &Objective, spans: &[f64], design: &Design, states: &Equilibria<'_>) -> Self {
        let moments = [states.passive, states.loaded].into_iter().flat_map(|s| joint_moments(design, s));
        Measures {
            strain_energy: Objective::StrainEnergy.value(spans, design, states),
            total_stiffness: Objective::TotalStiffness.value(spans, design, states),
            peak_moment: moments.fold(0.0, |m, x| m.max(x.abs())),
            compliance: match (objective, states.probe) {
                (Objective::Compliance { load }, Some(p)) => Some(compliance(load, spans, design, p)),
                _ => None,
            },
        }
    }
}
