//! Mesh sequencing for eq. (33): solve a coarse discretisation of the same structure first, then
//! warm-start each finer chain from the previous optimum, up to the chain asked for.
//!
//! A cold solve of eq. (33) needs about `2N` Ipopt iterations (hundreds of bounds become active
//! one after the other); from a coarse optimum most active bounds are already right and the fine
//! level needs a few dozen to a few hundred.
//!
//! # Coarsening ([`coarsen`])
//! A chain of `M < N` links is made by grouping consecutive fine links (coarse node `c` is fine
//! node `b_c`, `b_c = ⌊c N / M⌉`), so it is the same structure discretised more coarsely:
//!
//! * spans and link masses add up; gravity, `δ_d` and the angle and height bounds are kept;
//! * nodal forces (passive and actuation) are shared between the two coarse nodes around them
//!   in proportion to their distance (hat functions in `X`), so resultant forces are kept;
//! * a torsional spring `K` over a span `h` stands for a bending stiffness `EI ≈ K h`, so the
//!   stiffness bounds and `C_K` of eq. (34) are scaled by `h_fine / h_coarse` (the mean span at
//!   the node): the optimiser's variable `k = K / C_K` means the same at every level.
//!
//! # Prolongation ([`prolong`])
//! The coarse optimum becomes a fine start that satisfies every design constraint: fine node
//! heights interpolate the coarse ones linearly in `X`, so each fine `θ0` equals its coarse link's
//! angle, `Φ(θ0) = 0` holds and no bound or relative angle is exceeded; the springs keep the
//! coarse chain's compliance (each coarse `1/K` spread over its node's stretch of chain and
//! gathered again over the fine nodes' stretches, so springs between a soft and a stiff coarse
//! one act in series); states are interpolated at link midpoints and then made exact
//! equilibria of the fine design by Newton's method at full load (falling back to load
//! continuation from `θ0`). Each warm level starts Ipopt close to the boundary
//! (`mu_init`, `bound_push`, `bound_frac`: [`WarmStart`]).

mod level;
mod mesh;
mod multipliers;

pub use level::{prepare_level, restore_end_displacement, solution_parts, warm_states, LevelSetup, LevelStart};
pub use mesh::{coarse_nodes, coarsen, interpolate, prolong, restrict};
pub use multipliers::prolong_multipliers;

use serde::{Deserialize, Serialize};
use spine_check::{require, FieldError};

/// The ladder of chain sizes: start at `from` links, multiply by `factor` until the next size
/// would reach the chain's own `N`, then solve `N` itself.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Ladder {
    /// Links of the coarsest chain (≥ 2).
    pub from: usize,
    /// Growth factor between levels (> 1, at most 16).
    #[serde(default = "two")]
    pub factor: f64,
}

fn two() -> f64 {
    2.0
}

/// The case-file field `solver.refine`: `"auto"` (default), `"off"`, or a [`Ladder`]
/// such as `{ "from": 50, "factor": 2 }`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(untagged)]
pub enum Refine {
    Mode(RefineMode),
    Ladder(Ladder),
}

/// The named refinement choices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum RefineMode {
    /// [`AUTO_LADDER`] from [`AUTO_FROM_LINKS`] links on (measured: below it a cold solve is as
    /// fast), off below.
    Auto,
    /// One cold solve at the chain's own `N`.
    Off,
}

impl Default for Refine {
    fn default() -> Self {
        Refine::Mode(RefineMode::Auto)
    }
}

/// `"auto"` refines chains of at least this many links.
pub const AUTO_FROM_LINKS: usize = 100;
/// `"auto"`'s ladder.
pub const AUTO_LADDER: Ladder = Ladder { from: 50, factor: 2.0 };

impl Ladder {
    /// Why the ladder is not usable, naming the field.
    pub fn validate(&self) -> Result<(), FieldError> {
        require(self.from >= 2, "from", || format!("must be at least 2 links, got {}", self.from))?;
        require(self.factor.is_finite() && self.factor > 1.0 && self.factor <= 16.0, "factor", || {
            format!("must be a number in (1, 16], got {}", self.factor)
        })
    }

    /// The chain sizes to solve, coarsest first, ending with `n` (just `[n]` when `from ≥ n`).
    pub fn levels(&self, n: usize) -> Vec<usize> {
        let mut levels = Vec::new();
        let mut size = self.from as f64;
        while (size.round() as usize) < n && levels.len() < 64 {
            let m = size.round() as usize;
            if levels.last() != Some(&m) {
                levels.push(m);
            }
            size *= self.factor;
        }
        levels.push(n);
        levels
    }
}

/// Why a command-line `--refine` is not a refinement.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ParseRefineError {
    /// Not one of the forms.
    #[error("expected off, auto, FROM or FROM:FACTOR (e.g. 50:2), got {0:?}")]
    Form(String),
    /// A ladder out of its ranges.
    #[error("{} {}", .0.field, .0.message)]
    Ladder(FieldError),
}

impl std::str::FromStr for Refine {
    type Err = ParseRefineError;
    /// The command-line form: `off`, `auto`, `FROM` or `FROM:FACTOR` (e.g. `50:2`).
    fn from_str(text: &str) -> Result<Self, ParseRefineError> {
        let refine = match text {
            "off" => Refine::Mode(RefineMode::Off),
            "auto" => Refine::Mode(RefineMode::Auto),
            _ => {
                let (from, factor) = text.split_once(':').unwrap_or((text, "2"));
                let bad = || ParseRefineError::Form(text.to_string());
                let ladder =
                    Ladder { from: from.parse().map_err(|_| bad())?, factor: factor.parse().map_err(|_| bad())? };
                ladder.validate().map_err(ParseRefineError::Ladder)?;
                Refine::Ladder(ladder)
            }
        };
        Ok(refine)
    }
}

impl Refine {
    /// The ladder to use for a chain of `n` links, if any.
    pub fn ladder(&self, n: usize) -> Option<Ladder> {
        match *self {
            Refine::Mode(RefineMode::Off) => None,
            Refine::Mode(RefineMode::Auto) => (n >= AUTO_FROM_LINKS).then_some(AUTO_LADDER),
            Refine::Ladder(l) => (l.from < n).then_some(l),
        }
    }
}

/// Ipopt options of a warm level (case-file field `solver.warm_start`): start the barrier small
/// and the point close to its bounds, so that Ipopt keeps the active set of the coarse optimum
/// instead of pushing every variable into the interior first. Carrying the multipliers over
/// (`multipliers: true`) saved iterations at some sizes and cost them at others (docs/design.md),
/// so it is off by default.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct WarmStart {
    pub mu_init: f64,
    pub bound_push: f64,
    pub bound_frac: f64,
    /// Start from the prolonged multipliers ([`prolong_multipliers`], Ipopt's
    /// `warm_start_init_point`), with bound multipliers of inactive bounds lifted to
    /// `mult_bound_push`.
    pub multipliers: bool,
    pub mult_bound_push: f64,
    /// Restore the end displacement `δ_d` on each prolonged design before Ipopt starts
    /// ([`restore_end_displacement`]; default on).
    pub restore_end_displacement: bool,
    /// Ipopt's `tol` at the coarse levels, which only prepare the next start (default 1e-5; never
    /// tighter than `solver.tolerance`). The chain itself is solved to `solver.tolerance`.
    pub coarse_tolerance: f64,
    /// Iterations after which the finest level, not yet converged, is restarted from its current
    /// iterate with fresh multipliers and a fresh filter (`mu_init` = `solver.tolerance`/10), at
    /// most [`MAX_RESTARTS`] times; 0: never (default 200, a safety net: with the barrier schedule no
    /// level of fourteen sizes from 500 to 10⁴ links took more than 121). See docs/design.md,
    /// "Mesh sequencing".
    pub restart_after: usize,
    /// The ladder's barrier schedule ([`BarrierSchedule`], default `{ "mu": 3e-3, "exponent": 2 }`);
    /// `null`: every coarse level is solved to its optimum and every warm level starts at
    /// `mu_init` (the ladder before 2026-11-29).
    pub barrier: Option<BarrierSchedule>,
}

/// The barrier parameter each level of a ladder is solved to (docs/design.md, "The ladder's
/// barrier schedule"): level `m` of a ladder from `from` links is solved to the barrier problem of
/// `μ_m = mu · (from / m)^exponent` (Ipopt's `mu_target`; `μ_m` is Ipopt's scaled barrier
/// parameter, dimensionless), and a warm level starts at its own `μ_m` (`mu_init`, bound
/// multipliers `μ_m / slack`); the chain itself starts at `μ_N` and is solved to `tolerance`.
///
/// A coarse optimum is bang-bang with sharp edges that a finer chain places elsewhere, so a warm
/// level started from it wanders until its edges have moved; a barrier solution is smooth on the
/// scale of the barrier, and one whose barrier shrinks with the mesh (`exponent` 2: four times per
/// doubling) is a start the next level only sharpens.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BarrierSchedule {
    /// `μ` of the coarsest level, in (0, 0.1].
    pub mu: f64,
    /// How fast `μ` falls with the number of links, in [0, 4].
    pub exponent: f64,
}

impl BarrierSchedule {
    /// `μ_m` of level `m` of a ladder from `from` links, never below `floor`.
    pub fn mu_at(&self, from: usize, m: usize, floor: f64) -> f64 {
        (self.mu * (from as f64 / m as f64).powf(self.exponent)).max(floor)
    }

    /// Why the schedule is not usable, naming the field.
    pub fn validate(&self) -> Result<(), FieldError> {
        let (mu, exponent) = (self.mu, self.exponent);
        require(mu.is_finite() && mu > 0.0 && mu <= 0.1, "mu", || format!("must be a number in (0, 0.1], got {mu}"))?;
        require(exponent.is_finite() && (0.0..=4.0).contains(&exponent), "exponent", || {
            format!("must be a number in [0, 4], got {exponent}")
        })
    }
}

/// The default [`BarrierSchedule`] (docs/design.md: fourteen sizes from 500 to 10⁴ links).
pub const DEFAULT_BARRIER: BarrierSchedule = BarrierSchedule { mu: 3e-3, exponent: 2.0 };

/// Most restarts of the finest level ([`WarmStart::restart_after`]); the last one runs to
/// Ipopt's own end.
pub const MAX_RESTARTS: usize = 20;

impl Default for WarmStart {
    fn default() -> Self {
        WarmStart {
            mu_init: 1e-6,
            bound_push: 1e-8,
            bound_frac: 1e-8,
            multipliers: false,
            mult_bound_push: 1e-8,
            restore_end_displacement: true,
            coarse_tolerance: 1e-5,
            restart_after: 200,
            barrier: Some(DEFAULT_BARRIER),
        }
    }
}

impl WarmStart {
    /// Why these options are not usable, naming the field.
    pub fn validate(&self) -> Result<(), FieldError> {
        for (name, v) in [
            ("mu_init", self.mu_init),
            ("bound_push", self.bound_push),
            ("bound_frac", self.bound_frac),
            ("mult_bound_push", self.mult_bound_push),
        ] {
            require(v.is_finite() && v > 0.0 && v <= 0.5, name, || format!("must be a number in (0, 0.5], got {v}"))?;
        }
        let tol = self.coarse_tolerance;
        require(tol.is_finite() && tol > 0.0 && tol <= 1.0, "coarse_tolerance", || {
            format!("must be a number in (0, 1], got {tol}")
        })?;
        match self.barrier {
            Some(barrier) => barrier.validate().map_err(|e| e.under("barrier")),
            None => Ok(()),
        }
    }
}
