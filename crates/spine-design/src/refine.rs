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
//! angle, `Φ(θ0) = 0` holds and no bound or relative angle is exceeded; `k` is interpolated
//! linearly between coarse nodes; states are interpolated at link midpoints and then made exact
//! equilibria of the fine design by Newton's method at full load (falling back to load
//! continuation from `θ0`). Each warm level starts Ipopt close to the boundary
//! (`mu_init`, `bound_push`, `bound_frac`: [`WarmStart`]).

use crate::full_space::{FullSpaceNlp, Layout, LoadState};
use crate::problem::DesignProblem;
use serde::{Deserialize, Serialize};
use spine_model::{Chain, Design, NodalLoads, State, Structure};

/// The ladder of chain sizes: start at `from` links, multiply by `factor` until the next size
/// would reach the chain's own `N`, then solve `N` itself.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
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
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Refine {
    Mode(RefineMode),
    Ladder(Ladder),
}

/// The named refinement choices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
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
    pub fn check(&self) -> Result<(), (&'static str, String)> {
        if self.from < 2 {
            return Err(("from", format!("must be at least 2 links, got {}", self.from)));
        }
        if !(self.factor.is_finite() && self.factor > 1.0 && self.factor <= 16.0) {
            return Err(("factor", format!("must be a number in (1, 16], got {}", self.factor)));
        }
        Ok(())
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

impl std::str::FromStr for Refine {
    type Err = String;
    /// The command-line form: `off`, `auto`, `FROM` or `FROM:FACTOR` (e.g. `50:2`).
    fn from_str(text: &str) -> Result<Self, String> {
        let refine = match text {
            "off" => Refine::Mode(RefineMode::Off),
            "auto" => Refine::Mode(RefineMode::Auto),
            _ => {
                let (from, factor) = text.split_once(':').unwrap_or((text, "2"));
                let bad = || format!("expected off, auto, FROM or FROM:FACTOR (e.g. 50:2), got {text:?}");
                let ladder =
                    Ladder { from: from.parse().map_err(|_| bad())?, factor: factor.parse().map_err(|_| bad())? };
                ladder.check().map_err(|(field, why)| format!("{field} {why}"))?;
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
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
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
}

impl Default for WarmStart {
    fn default() -> Self {
        WarmStart { mu_init: 1e-6, bound_push: 1e-8, bound_frac: 1e-8, multipliers: false, mult_bound_push: 1e-8 }
    }
}

impl WarmStart {
    /// Why these options are not usable, naming the field.
    pub fn check(&self) -> Result<(), (&'static str, String)> {
        for (name, v) in [
            ("mu_init", self.mu_init),
            ("bound_push", self.bound_push),
            ("bound_frac", self.bound_frac),
            ("mult_bound_push", self.mult_bound_push),
        ] {
            if !(v.is_finite() && v > 0.0 && v <= 0.5) {
                return Err((name, format!("must be a number in (0, 0.5], got {v}")));
            }
        }
        Ok(())
    }
}

/// The fine node of each coarse node: `b_c = round(c N / M)`, `c = 0..=M` (strictly increasing
/// for `M ≤ N`).
pub fn coarse_nodes(n: usize, m: usize) -> Vec<usize> {
    assert!(m >= 1 && m <= n, "coarse chain of {m} links from {n}");
    (0..=m).map(|c| ((c * n) as f64 / m as f64).round() as usize).collect()
}

/// `X` of every node (`N + 1`), m.
fn node_x(spans: &[f64]) -> Vec<f64> {
    let mut x = Vec::with_capacity(spans.len() + 1);
    let mut sum = 0.0;
    x.push(0.0);
    for a in spans {
        sum += a;
        x.push(sum);
    }
    x
}

/// Mean span at each node (the one span at either end), m.
fn node_spans(spans: &[f64]) -> Vec<f64> {
    let n = spans.len();
    (0..=n)
        .map(|j| match (j.checked_sub(1).map(|i| spans[i]), spans.get(j).copied()) {
            (Some(a), Some(b)) => 0.5 * (a + b),
            (Some(a), None) | (None, Some(a)) => a,
            (None, None) => 0.0,
        })
        .collect()
}

/// The coarse problem of `m` links and the fine node of each coarse node (see the module docs).
pub fn coarsen(problem: &DesignProblem, m: usize) -> (DesignProblem, Vec<usize>) {
    let fine = &problem.structure.chain;
    let n = fine.n_links();
    let nodes = coarse_nodes(n, m);
    let spans: Vec<f64> = nodes.windows(2).map(|w| fine.spans[w[0]..w[1]].iter().sum()).collect();
    let masses: Vec<f64> = nodes.windows(2).map(|w| fine.masses[w[0]..w[1]].iter().sum()).collect();
    let chain = Chain { spans, masses, gravity: fine.gravity };

    let fine_x = node_x(&fine.spans);
    let lump = |loads: &NodalLoads| {
        let mut out = NodalLoads::zero(m);
        for c in 0..m {
            let (left, right) = (nodes[c], nodes[c + 1]);
            let width = fine_x[right] - fine_x[left];
            // Node `left` belongs to this coarse link only for c = 0 (else to the previous one).
            let first = if c == 0 { left } else { left + 1 };
            for j in first..=right {
                let w = if width > 0.0 { (fine_x[right] - fine_x[j]) / width } else { 0.0 };
                out.p_x[c] += w * loads.p_x[j];
                out.p_y[c] += w * loads.p_y[j];
                out.p_x[c + 1] += (1.0 - w) * loads.p_x[j];
                out.p_y[c + 1] += (1.0 - w) * loads.p_y[j];
            }
        }
        out
    };

    let fine_h = node_spans(&fine.spans);
    let coarse_h = node_spans(&chain.spans);
    let ratio: Vec<f64> = (0..=m).map(|c| fine_h[nodes[c]] / coarse_h[c]).collect();
    let b = &problem.bounds;
    let mut bounds = b.clone();
    bounds.stiffness_min = (0..=m).map(|c| b.stiffness_min[nodes[c]] * ratio[c]).collect();
    bounds.stiffness_max = (0..=m).map(|c| b.stiffness_max[nodes[c]] * ratio[c]).collect();
    let coarse = DesignProblem {
        structure: Structure {
            passive: lump(&problem.structure.passive),
            actuation: lump(&problem.structure.actuation),
            chain,
        },
        delta_d: problem.delta_d,
        bounds,
        stiffness_scale: problem.stiffness_scale * m as f64 / n as f64,
    };
    (coarse, nodes)
}

/// The fine start design restricted to the coarse chain: each coarse link is the chord of its
/// fine links (same node heights at the coarse nodes), each coarse `k` the fine `k` at its node,
/// projected into the coarse bounds.
pub fn restrict(fine: &DesignProblem, coarse: &DesignProblem, nodes: &[usize], design: &Design) -> Design {
    let heights = fine.node_heights(&design.theta0);
    let theta0 = nodes
        .windows(2)
        .zip(&coarse.structure.chain.spans)
        .map(|(w, a)| ((heights[w[1]] - heights[w[0]]) / a).atan())
        .collect();
    let stiffness = nodes
        .iter()
        .enumerate()
        .map(|(c, &j)| {
            let k = design.stiffness[j] / fine.stiffness_scale * coarse.stiffness_scale;
            k.clamp(coarse.bounds.stiffness_min[c], coarse.bounds.stiffness_max[c])
        })
        .collect();
    Design { theta0, stiffness }
}

/// Linear interpolation of `values` given at increasing `at` onto `to` (constant beyond the ends).
fn interpolate(at: &[f64], values: &[f64], to: &[f64]) -> Vec<f64> {
    let mut k = 0;
    to.iter()
        .map(|&x| {
            while k + 2 < at.len() && at[k + 1] < x {
                k += 1;
            }
            if at.len() == 1 || x <= at[0] {
                return values[0];
            }
            if x >= at[at.len() - 1] {
                return values[at.len() - 1];
            }
            let t = (x - at[k]) / (at[k + 1] - at[k]);
            values[k] + t * (values[k + 1] - values[k])
        })
        .collect()
}

fn midpoints(spans: &[f64]) -> Vec<f64> {
    let x = node_x(spans);
    x.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect()
}

/// A fine start from a coarse solution: the design (exactly feasible for the design constraints)
/// and interpolated states (not yet equilibria: see [`warm_states`]).
pub fn prolong(
    coarse: &DesignProblem,
    fine: &DesignProblem,
    design: &Design,
    states: &(State, State),
) -> (Design, (State, State)) {
    let coarse_x = node_x(&coarse.structure.chain.spans);
    let fine_x = node_x(&fine.structure.chain.spans);
    let heights = interpolate(&coarse_x, &coarse.node_heights(&design.theta0), &fine_x);
    let theta0 = fine_x
        .windows(2)
        .enumerate()
        .map(|(i, w)| ((heights[i + 1] - heights[i]) / (w[1] - w[0])).atan())
        .map(|t| t.clamp(-fine.bounds.theta0_max, fine.bounds.theta0_max))
        .collect();
    let k: Vec<f64> = design.stiffness.iter().map(|s| s / coarse.stiffness_scale).collect();
    let stiffness = interpolate(&coarse_x, &k, &fine_x)
        .into_iter()
        .enumerate()
        .map(|(j, k)| (k * fine.stiffness_scale).clamp(fine.bounds.stiffness_min[j], fine.bounds.stiffness_max[j]))
        .collect();
    let (coarse_mid, fine_mid) = (midpoints(&coarse.structure.chain.spans), midpoints(&fine.structure.chain.spans));
    let state = |s: &State| State { theta: interpolate(&coarse_mid, &s.theta, &fine_mid), lambda: s.lambda };
    (Design { theta0, stiffness }, (state(&states.0), state(&states.1)))
}

/// How a level of the ladder started.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LevelStart {
    /// From the case's start design (restricted to the level), states by load continuation,
    /// Ipopt's default start options.
    Cold,
    /// Warm: prolonged coarser optimum,
    /// states by Newton at full load from the interpolated states.
    Newton,
    /// Warm, states by load continuation from the unloaded shape (Newton failed).
    Continuation,
    /// Warm, neither converged: the interpolated states themselves.
    Interpolated,
}

/// Exact equilibria of the prolonged design near the interpolated states, or the best fallback.
pub fn warm_states(
    problem: &DesignProblem,
    design: &Design,
    interpolated: (State, State),
    continuation: &spine_solve::ContinuationOptions,
) -> ((State, State), LevelStart) {
    if let Some(states) = problem.equilibria_near(design, &interpolated.0, &interpolated.1, continuation) {
        return (states, LevelStart::Newton);
    }
    let mut notes = Vec::new();
    let states = crate::problem::start_states(problem, design, continuation, &mut notes);
    if notes.is_empty() {
        (states, LevelStart::Continuation)
    } else {
        (interpolated, LevelStart::Interpolated)
    }
}

/// One level of the ladder, ready for Ipopt: its chain (coarse, or the problem itself), how it
/// started, the start design and the start states.
pub struct LevelSetup {
    /// The coarse problem and the fine node of each coarse node; `None` at the problem's own `N`.
    pub coarse: Option<(DesignProblem, Vec<usize>)>,
    pub start: LevelStart,
    pub design: Design,
    pub states: (State, State),
}

impl LevelSetup {
    /// The level's problem: the coarse one, or `fine` itself.
    pub fn problem<'a>(&'a self, fine: &'a DesignProblem) -> &'a DesignProblem {
        self.coarse.as_ref().map_or(fine, |(c, _)| c)
    }
}

/// Prepares the level of `m` links of `problem`: cold from `start` restricted to it (states by
/// continuation, their notes added to `notes` with the level named) when there is no `previous`
/// level, else warm from the prolonged `previous` optimum (problem, design, states).
pub fn prepare_level(
    problem: &DesignProblem,
    m: usize,
    previous: Option<(&DesignProblem, &Design, &(State, State))>,
    start: &Design,
    continuation: &spine_solve::ContinuationOptions,
    notes: &mut Vec<String>,
) -> LevelSetup {
    let n = problem.n_links();
    let coarse = (m < n).then(|| coarsen(problem, m));
    let level = coarse.as_ref().map_or(problem, |(c, _)| c);
    let (how, design, states) = match previous {
        None => {
            let design = coarse.as_ref().map_or_else(|| start.clone(), |(c, nodes)| restrict(problem, c, nodes, start));
            let mut level_notes = Vec::new();
            let states = crate::problem::start_states(level, &design, continuation, &mut level_notes);
            notes.extend(level_notes.into_iter().map(|s| {
                if m < n {
                    format!("refinement level {m} links: {s}")
                } else {
                    s
                }
            }));
            (LevelStart::Cold, design, states)
        }
        Some((coarser, d, s)) => {
            let (design, interpolated) = prolong(coarser, level, d, s);
            let (states, how) = warm_states(level, &design, interpolated, continuation);
            (how, design, states)
        }
    };
    LevelSetup { coarse, start: how, design, states }
}

/// Design and states of a full-space solution vector.
pub fn solution_parts(nlp: &FullSpaceNlp<'_>, x: &[f64]) -> (Design, (State, State)) {
    let layout = nlp.layout;
    (
        layout.design(x, nlp.problem.stiffness_scale),
        (layout.state(x, LoadState::Passive), layout.state(x, LoadState::Loaded)),
    )
}

/// Multipliers of a full-space solution (Ipopt's sign convention), in the layout's order.
#[derive(Clone, Debug, PartialEq)]
pub struct Multipliers {
    pub constraints: Vec<f64>,
    pub z_lower: Vec<f64>,
    pub z_upper: Vec<f64>,
}

/// The multipliers of a coarse solution carried to the fine chain, for Ipopt's warm start.
///
/// From the stationarity conditions of eq. (33) with a consistent coarsening (`K ∝ 1/h`, `J` a
/// Riemann sum): the multipliers of the equilibrium, height and end rows are fields of order one,
/// interpolated at the links (or copied for the single `Φ` and end rows); the multipliers of the
/// relative-angle rows and of the bounds on `θ0`, `k` and the heights scale like the span,
/// interpolated and multiplied by `h_fine / h_coarse`. A bound multiplier is kept only where the
/// fine variable sits on that bound (`x_fine` within `1e-7` of it), else it is zero and Ipopt's
/// `warm_start_mult_bound_push` sets it.
pub fn prolong_multipliers(
    coarse: &DesignProblem,
    fine: &DesignProblem,
    m: &Multipliers,
    x_fine: &[f64],
    lower: &[f64],
    upper: &[f64],
) -> Multipliers {
    let (mc, nf) = (coarse.n_links(), fine.n_links());
    let (cl, fl) = (Layout { n: mc }, Layout { n: nf });
    let ratio = mc as f64 / nf as f64;
    let (cmid, fmid) = (midpoints(&coarse.structure.chain.spans), midpoints(&fine.structure.chain.spans));
    let (cx, fx) = (node_x(&coarse.structure.chain.spans), node_x(&fine.structure.chain.spans));
    let field = |values: Vec<f64>, at: &[f64], to: &[f64], scale: f64| -> Vec<f64> {
        interpolate(at, &values, to).into_iter().map(|v| v * scale).collect()
    };

    let mut constraints = vec![0.0; fl.num_constraints()];
    for s in [LoadState::Passive, LoadState::Loaded] {
        let joints = field((0..mc).map(|i| m.constraints[cl.equilibrium_row(s, i)]).collect(), &cmid, &fmid, 1.0);
        for (i, v) in joints.into_iter().enumerate() {
            constraints[fl.equilibrium_row(s, i)] = v;
        }
        constraints[fl.constraint_row(s)] = m.constraints[cl.constraint_row(s)];
    }
    for (j, v) in
        field((0..mc).map(|j| m.constraints[cl.height_row(j)]).collect(), &cmid, &fmid, 1.0).into_iter().enumerate()
    {
        constraints[fl.height_row(j)] = v;
    }
    constraints[fl.end_row()] = m.constraints[cl.end_row()];
    if mc >= 2 && nf >= 2 {
        let relative =
            field((0..mc - 1).map(|i| m.constraints[cl.relative_row(i)]).collect(), &cx[1..mc], &fx[1..nf], ratio);
        for (i, v) in relative.into_iter().enumerate() {
            constraints[fl.relative_row(i)] = v;
        }
    }

    let bound = |z: &[f64]| {
        let mut out = vec![0.0; fl.num_variables()];
        for (i, v) in field((0..mc).map(|i| z[cl.theta0(i)]).collect(), &cmid, &fmid, ratio).into_iter().enumerate() {
            out[fl.theta0(i)] = v;
        }
        for (j, v) in field((0..=mc).map(|j| z[cl.stiffness(j)]).collect(), &cx, &fx, ratio).into_iter().enumerate() {
            out[fl.stiffness(j)] = v;
        }
        if mc >= 2 && nf >= 2 {
            let heights =
                field((1..mc).map(|j| z[cl.height(j).expect("interior")]).collect(), &cx[1..mc], &fx[1..nf], ratio);
            for (j, v) in heights.into_iter().enumerate() {
                out[fl.height(j + 1).expect("interior")] = v;
            }
        }
        out
    };
    let near = |a: f64, b: f64| (a - b).abs() <= 1e-7 * (1.0 + b.abs());
    let mut z_lower = bound(&m.z_lower);
    let mut z_upper = bound(&m.z_upper);
    for k in 0..x_fine.len() {
        if !near(x_fine[k], lower[k]) {
            z_lower[k] = 0.0;
        }
        if !near(x_fine[k], upper[k]) {
            z_upper[k] = 0.0;
        }
    }
    Multipliers { constraints, z_lower, z_upper }
}
