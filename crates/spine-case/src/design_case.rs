//! `"kind": "design"`: the static design problem of eq. (33).

use crate::error::CaseError;
use crate::objective_spec::{check_formulation, ConstraintsSpec, ObjectiveSpec};
use crate::per_item::check_finite;
use crate::per_item::PerItem;
use crate::specs::{non_negative, positive, ChainSpec, LoadSpec, Notes};
use serde::{Deserialize, Serialize};
use spine_design::knife_edge::KnifeEdgeSettings;
use spine_design::refine::Refine;
use spine_design::solve::Solver;
use spine_design::{DesignBounds, DesignProblem, Formulation, SolverPreset, SolverSettings};
use spine_model::{Design, Structure};
use std::f64::consts::{FRAC_PI_2, FRAC_PI_6};

/// Bounds of the design; every field defaults to the paper's value (Sec. 5).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BoundsSpec {
    /// `|θ0_i| ≤ theta0_max`, rad, in (0, π/2) (default π/6).
    #[serde(default = "pi_over_six")]
    pub theta0_max: f64,
    /// `|θ0_i − θ0_{i+1}| ≤ relative_angle_max`, rad, > 0 (default π/6).
    #[serde(default = "pi_over_six")]
    pub relative_angle_max: f64,
    /// Lower stiffness bound, N·m/rad: one number or `N + 1` (default 100).
    #[serde(default = "k_min")]
    pub stiffness_min: PerItem,
    /// Upper stiffness bound, N·m/rad: one number or `N + 1` (default 10⁴).
    #[serde(default = "k_max")]
    pub stiffness_max: PerItem,
    /// Interior node heights, m: `height_min ≤ Y0_j ≤ height_max` (defaults 0.01 m and 0.25 L_x).
    #[serde(default = "y_min")]
    pub height_min: f64,
    #[serde(default)]
    pub height_max: Option<f64>,
    /// `ℓ`, m (default 0): the lower height bound ramps from 0 at the base and the end to
    /// `height_min` over this distance, `Y0_j ≥ height_min · min(1, x_j/ℓ, (L_x − x_j)/ℓ)`, so
    /// that it is a function of `x` (a rod's bound) rather than one number per node; 0 is the
    /// paper's bound, the same at every interior node. At most `L_x / 2`.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub height_ramp: f64,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

fn pi_over_six() -> f64 {
    FRAC_PI_6
}
fn k_min() -> PerItem {
    PerItem::Uniform(1e2)
}
fn k_max() -> PerItem {
    PerItem::Uniform(1e4)
}
fn y_min() -> f64 {
    0.01
}

impl Default for BoundsSpec {
    fn default() -> Self {
        BoundsSpec {
            theta0_max: FRAC_PI_6,
            relative_angle_max: FRAC_PI_6,
            stiffness_min: k_min(),
            stiffness_max: k_max(),
            height_min: y_min(),
            height_max: None,
            height_ramp: 0.0,
        }
    }
}

/// The optimiser's start design; it may lie outside the bounds (it is projected, and the result
/// says so) but must have `N` angles with `|θ0| < π/2` and `N + 1` stiffnesses ≥ 0.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StartSpec {
    pub theta0: Vec<f64>,
    pub stiffness: PerItem,
}

/// Multi-start settings (overridden by `--starts` and `--seed`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MultiStartSpec {
    /// Number of extra seeded feasible starts (0: only `start`). With `confidence`, the most
    /// seeded starts the census may use (0: [`MAX_STARTS`]).
    #[serde(default)]
    pub starts: usize,
    #[serde(default)]
    pub seed: u64,
    /// Run the census to a stated confidence: seeded starts are added in batches until the
    /// Boender–Rinnooy Kan estimate of P(a better optimum unseen) is at most this (0 < P < 1), or
    /// `starts` is reached.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub confidence: Option<f64>,
    /// Ipopt's `mu_strategy` for the seeded starts only (the case's own start keeps
    /// `solver.barrier_strategy`): `"adaptive"` (default) or `"monotone"`. A census samples local
    /// minima, and from random starts the adaptive barrier reaches one in about half the
    /// iterations (design10, 300 starts: 47.5 against 88.3 on average, none at the iteration
    /// limit against 2; docs/design.md, "Censuses to a stated confidence").
    #[serde(default = "adaptive")]
    pub barrier_strategy: spine_design::BarrierStrategy,
}

fn adaptive() -> spine_design::BarrierStrategy {
    spine_design::BarrierStrategy::Adaptive
}

impl Default for MultiStartSpec {
    fn default() -> Self {
        Self { starts: 0, seed: 0, confidence: None, barrier_strategy: adaptive() }
    }
}

/// `"kind": "design"`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DesignCase {
    #[serde(default)]
    pub title: String,
    #[serde(default)]
    pub notes: Notes,
    pub chain: ChainSpec,
    /// Passive transverse loads `p_y` and the actuating axial force `p_x` at the end.
    pub loads: LoadSpec,
    /// Desired end displacement `δ_d`, m (negative: toward the base).
    pub delta_d: f64,
    /// `C_K` of eq. (34) (> 0): the optimiser's stiffness variable is `K / C_K`.
    #[serde(default = "one")]
    pub stiffness_scale: f64,
    #[serde(default)]
    pub bounds: BoundsSpec,
    pub start: StartSpec,
    /// What eq. (33) minimises: the paper's strain energy (default) or a built-in criterion
    /// (docs/objectives.md).
    #[serde(default, skip_serializing_if = "is_default_objective")]
    pub objective: ObjectiveSpec,
    /// Extra constraints beyond the paper's (docs/objectives.md).
    #[serde(default, skip_serializing_if = "ConstraintsSpec::is_empty")]
    pub constraints: ConstraintsSpec,
    /// "full" (default) or "reduced" (the paper's objective only).
    #[serde(default = "full")]
    pub formulation: Formulation,
    #[serde(default)]
    pub multistart: MultiStartSpec,
    #[serde(default)]
    pub solver: SolverSettings,
    /// "exact" (default: `formulation` and `solver` as written) or "fmincon-like" (the paper's
    /// kind of optimiser: the reduced space, L-BFGS, fmincon's default stopping rules; it replaces
    /// `formulation` and those fields of `solver`).
    #[serde(default, skip_serializing_if = "is_exact")]
    pub preset: SolverPreset,
    /// Also solve from the same start with the "fmincon-like" preset (no census) and report it
    /// beside this case's design: which conclusions come from the optimiser, which from eq. (33).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub fmincon_like_beside: bool,
    /// Knife edges: the run from `start` (and the fmincon-like run beside it) is repeated from
    /// starts moved by a tiny seeded amount, and the result reports every optimum they reach
    /// (docs/design.md, "Knife edges"). Default: 2 antithetic pairs moved by 1e-6.
    #[serde(default, skip_serializing_if = "is_default_knife_edge")]
    pub knife_edge: KnifeEdgeSettings,
}

fn is_default_knife_edge(k: &KnifeEdgeSettings) -> bool {
    *k == KnifeEdgeSettings::default()
}

fn is_exact(p: &SolverPreset) -> bool {
    *p == SolverPreset::Exact
}

fn is_default_objective(o: &ObjectiveSpec) -> bool {
    *o == ObjectiveSpec::StrainEnergy
}

pub(crate) fn one() -> f64 {
    1.0
}
pub(crate) fn full() -> Formulation {
    Formulation::Full
}

/// Most seeded starts of a multi-start (each is a full Ipopt solve).
pub const MAX_STARTS: usize = 100_000;

/// A checked design case.
#[derive(Clone, Debug)]
pub struct ValidDesign {
    pub problem: DesignProblem,
    pub start: Design,
    pub formulation: Formulation,
    pub multistart: MultiStartSpec,
    pub settings: SolverSettings,
    /// The preset `formulation` and `settings` come from.
    pub preset: SolverPreset,
    /// Solve with the fmincon-like preset beside this case ([`DesignCase::fmincon_like_beside`]).
    pub fmincon_like_beside: bool,
    /// The moved starts of a knife-edge check ([`DesignCase::knife_edge`]).
    pub knife_edge: KnifeEdgeSettings,
}

impl ValidDesign {
    /// How this case is solved: its preset over its formulation and settings (the preset is
    /// applied already, and applying it again changes nothing).
    pub fn solver(&self) -> Solver {
        Solver::new(self.preset, self.formulation, &self.settings)
    }

    /// This case solved with `preset` applied over its formulation and settings, without a census.
    pub fn with_preset(&self, preset: SolverPreset) -> Self {
        let (formulation, settings) = preset.apply(self.formulation, &self.settings);
        Self {
            formulation,
            settings,
            preset,
            multistart: MultiStartSpec::default(),
            fmincon_like_beside: false,
            ..self.clone()
        }
    }
}

/// A census's target P(a better optimum unseen) ≤ P, wherever it is read (the case file's
/// `multistart.confidence`, `--confidence`, flexspine's `confidence=`, a shard's overrides): a
/// probability strictly between 0 and 1. At 0 the census could never end; at 1 or above it has
/// ended before it starts.
pub fn check_confidence(p: f64) -> Result<f64, String> {
    if p > 0.0 && p < 1.0 {
        Ok(p)
    } else {
        Err(format!("must be a probability strictly between 0 and 1 (e.g. 0.01), got {p}"))
    }
}

impl DesignCase {
    pub fn validate(&self) -> Result<ValidDesign, CaseError> {
        let mut chain = self.chain.validate()?;
        let n = chain.n_links();
        let (passive, actuation) = self.loads.resolve(&mut chain)?;
        if !self.delta_d.is_finite() {
            return Err(CaseError::invalid(
                "delta_d",
                format!("must be a finite displacement (m), got {}", self.delta_d),
            ));
        }
        crate::specs::check_reach("delta_d", self.delta_d, chain.length_x())?;
        positive("stiffness_scale", self.stiffness_scale, "(C_K)")?;

        let bounds = self.bounds.validate(n, chain.length_x())?;
        let start = self.start.validate(n)?;

        if self.multistart.starts > MAX_STARTS {
            return Err(CaseError::invalid(
                "multistart.starts",
                format!("must be at most {MAX_STARTS}, got {}", self.multistart.starts),
            ));
        }
        if let Some(p) = self.multistart.confidence {
            check_confidence(p).map_err(|m| CaseError::invalid("multistart.confidence", m))?;
        }
        crate::specs::check_runs_memory("multistart.starts", self.multistart.starts + 1, n)?;
        self.solver.validate().map_err(|e| e.under("solver"))?;
        self.knife_edge.validate().map_err(|e| e.under("knife_edge"))?;
        let (formulation, settings) = self.preset.apply(self.formulation, &self.solver);
        if matches!(settings.refine, Refine::Ladder(_)) && formulation == Formulation::Reduced {
            return Err(CaseError::invalid(
                "solver.refine",
                "mesh sequencing needs formulation \"full\"; use \"off\" or \"auto\" with \"reduced\"",
            ));
        }

        let mut problem = DesignProblem {
            structure: Structure { chain, passive, actuation },
            delta_d: self.delta_d,
            bounds,
            stiffness_scale: self.stiffness_scale,
            objective: Default::default(),
            strain_energy_max: self.constraints.validate()?,
        };
        problem.objective = self.objective.resolve(&problem, &start)?;
        check_formulation(formulation, &problem).map_err(|e| match self.preset {
            SolverPreset::Exact => e,
            SolverPreset::FminconLike => {
                CaseError::invalid("preset", format!("\"fmincon-like\" solves in the reduced space: {e}"))
            }
        })?;
        if self.fmincon_like_beside {
            check_formulation(Formulation::Reduced, &problem).map_err(|e| {
                CaseError::invalid(
                    "fmincon_like_beside",
                    format!("the fmincon-like solve needs the reduced space: {e}"),
                )
            })?;
        }
        Ok(ValidDesign {
            problem,
            start,
            formulation,
            multistart: self.multistart.clone(),
            settings,
            preset: self.preset,
            fmincon_like_beside: self.fmincon_like_beside,
            knife_edge: self.knife_edge.clone(),
        })
    }
}

impl BoundsSpec {
    /// The bounds of eq. (33) for `n` links over `length_x` (m), checked; errors name
    /// `bounds.FIELD`.
    pub fn validate(&self, n: usize, length_x: f64) -> Result<DesignBounds, CaseError> {
        let b = self;
        if !(b.theta0_max > 0.0 && b.theta0_max < FRAC_PI_2) {
            return Err(CaseError::invalid(
                "bounds.theta0_max",
                format!("must be in (0, π/2) rad, got {}", b.theta0_max),
            ));
        }
        positive("bounds.relative_angle_max", b.relative_angle_max, "rad")?;
        let stiffness_min = b.stiffness_min.expand("bounds.stiffness_min", n + 1, "one per spring, N + 1")?;
        let stiffness_max = b.stiffness_max.expand("bounds.stiffness_max", n + 1, "one per spring, N + 1")?;
        non_negative("bounds.stiffness_min", &stiffness_min, "N·m/rad")?;
        check_finite("bounds.stiffness_max", &stiffness_max)?;
        if let Some(j) = (0..=n).find(|&j| stiffness_max[j] < stiffness_min[j]) {
            return Err(CaseError::invalid(
                format!("bounds.stiffness_max[{j}]"),
                format!("must be ≥ stiffness_min[{j}] = {}, got {}", stiffness_min[j], stiffness_max[j]),
            ));
        }
        let height_max = b.height_max.unwrap_or(0.25 * length_x);
        if !b.height_min.is_finite() {
            return Err(CaseError::invalid("bounds.height_min", "must be a finite height (m)"));
        }
        if !(height_max.is_finite() && height_max > b.height_min) {
            return Err(CaseError::invalid(
                "bounds.height_max",
                format!("must be a finite height (m) > height_min = {}, got {height_max}", b.height_min),
            ));
        }
        if !(b.height_ramp.is_finite() && (0.0..=0.5 * length_x).contains(&b.height_ramp)) {
            return Err(CaseError::invalid(
                "bounds.height_ramp",
                format!("must be a length (m) in [0, L_x / 2 = {}], got {}", 0.5 * length_x, b.height_ramp),
            ));
        }
        Ok(DesignBounds {
            theta0_max: b.theta0_max,
            relative_angle_max: b.relative_angle_max,
            stiffness_min,
            stiffness_max,
            height_min: b.height_min,
            height_max,
            height_ramp: b.height_ramp,
        })
    }
}

impl StartSpec {
    /// The start design for `n` links, checked; errors name `start.FIELD`.
    pub fn validate(&self, n: usize) -> Result<Design, CaseError> {
        if self.theta0.len() != n {
            return Err(CaseError::invalid(
                "start.theta0",
                format!("expected {n} entries (one per link), got {}", self.theta0.len()),
            ));
        }
        check_finite("start.theta0", &self.theta0)?;
        if let Some(i) = self.theta0.iter().position(|t| t.abs() >= FRAC_PI_2) {
            return Err(CaseError::invalid(
                format!("start.theta0[{i}]"),
                format!("must satisfy |θ0| < π/2 rad, got {}", self.theta0[i]),
            ));
        }
        let stiffness = self.stiffness.expand("start.stiffness", n + 1, "one per spring, N + 1")?;
        non_negative("start.stiffness", &stiffness, "N·m/rad")?;
        Ok(Design { theta0: self.theta0.clone(), stiffness })
    }
}
