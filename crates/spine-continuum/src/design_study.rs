//! Eq. (33) for one rod ([`RodDesign`]) at a ladder of `N`, each level warm-started from the
//! previous optimum: `J*(N)`, the optimal `θ0(x)` and `EI(x)`, the active-bound pattern of `EI`
//! and its number of switches, and a Richardson estimate of `J*∞`.
//!
//! Each level after the first is started from the previous optimum carried over
//! ([`RodDesign::prolong`]) with Ipopt's barrier started small and the point close to its bounds
//! (`bound_push`, `bound_frac` 1e-8), once for each `mu_init` of
//! [`StudySettings::warm_barriers`]: the two reach different points on some levels (a small `μ`
//! keeps the coarse active set and is fast at large `N`; a larger one frees springs a coarse
//! optimum put on the wrong bound). The level reports every attempt and keeps the lowest `J`
//! among the clean ones that are not certified `not_a_minimum`.
//!
//! Then every level below the finest clean one is solved again from its optimum carried back (the same
//! barrier starts), and keeps the lower clean optimum: the first pass inherits the coarsest
//! level's basin, which need not be the basin the fine levels settle in (the paper's rod: from
//! the arch, `N = 10` and 20 reach hinge designs with `J*` 6.54 and 6.43 mJ; carried back from
//! `N = 2000`, 4.87 and 4.85 mJ).

use crate::design::RodDesign;
use serde::{Deserialize, Serialize};
use spine_check::{require, FieldError};
use spine_design::certificate::MinimumStatus;
use spine_design::refine::{Refine, RefineMode};
use spine_design::result::DesignResult;
use spine_design::settings::ExtraOption;
use spine_design::settings::{Formulation, SolverPreset, SolverSettings};
use spine_design::solve::ipopt::DesignError;
use spine_design::solve::Solver;
use spine_model::Design;
use std::time::Instant;

/// How each level is solved (case field `solver` of `"kind": "continuum"`; every field optional).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct StudySettings {
    /// Ipopt's `tol` and the constraint tolerance (the equilibrium rows are moments, N·m, of the
    /// same size at every `N` in this formulation).
    pub tolerance: f64,
    /// Ipopt's iteration limit per attempt.
    pub max_iterations: usize,
    /// `mu_init` of the warm attempts of each level after the first.
    pub warm_barriers: Vec<f64>,
}

/// Most levels of one study, and the largest `N` of a level.
pub const MAX_LEVELS: usize = 20;
pub const MAX_LEVEL_LINKS: usize = 100_000;

impl StudySettings {
    /// Why these settings are not usable, naming the field.
    pub fn validate(&self) -> Result<(), FieldError> {
        require(self.tolerance.is_finite() && self.tolerance > 0.0 && self.tolerance < 1.0, "tolerance", || {
            format!("must be a number in (0, 1), got {}", self.tolerance)
        })?;
        require((1..=100_000).contains(&self.max_iterations), "max_iterations", || {
            format!("must be an integer in [1, 100000], got {}", self.max_iterations)
        })?;
        require(!self.warm_barriers.is_empty() && self.warm_barriers.len() <= 4, "warm_barriers", || {
            format!("must hold 1 to 4 values of mu_init, got {}", self.warm_barriers.len())
        })?;
        for (k, &mu) in self.warm_barriers.iter().enumerate() {
            require(mu.is_finite() && mu > 0.0 && mu <= 1.0, &format!("warm_barriers[{k}]"), || {
                format!("must be a barrier parameter in (0, 1], got {mu}")
            })?;
        }
        Ok(())
    }
}

/// Why `links` cannot be a study's ladder, naming the field (`[k]` of the list).
pub fn validate_links(links: &[usize]) -> Result<(), FieldError> {
    require(!links.is_empty() && links.len() <= MAX_LEVELS, "", || {
        format!("must hold 1 to {MAX_LEVELS} chain sizes, got {}", links.len())
    })?;
    for (k, &n) in links.iter().enumerate() {
        require((2..=MAX_LEVEL_LINKS).contains(&n), &format!("[{k}]"), || {
            format!("must be a number of links in [2, {MAX_LEVEL_LINKS}], got {n}")
        })?;
        require(k == 0 || n > links[k - 1], &format!("[{k}]"), || {
            format!("must be larger than the size before it ({}): the ladder increases", links[k - 1])
        })?;
    }
    Ok(())
}

impl Default for StudySettings {
    fn default() -> Self {
        StudySettings { tolerance: 1e-8, max_iterations: 1000, warm_barriers: vec![1e-8, 1e-6] }
    }
}

/// One solve of one level.
#[derive(Clone, Debug, Serialize)]
pub struct Attempt {
    pub from: StartedFrom,
    /// `mu_init` of a warm attempt (`None`: the cold first level).
    pub mu_init: Option<f64>,
    /// How Ipopt ended the attempt (written as its name, `solve_succeeded`).
    pub status: spine_ipopt::Status,
    /// Ipopt iterations of the attempt's first run and of the run it reports (the same run, or
    /// the tight re-solve that certified it).
    pub first_run_iterations: usize,
    pub iterations: usize,
    /// `J`, J.
    pub objective: f64,
    pub clean: bool,
    pub certificate: Option<MinimumStatus>,
    pub wall_seconds: f64,
}

/// Where a spring's `EI` sits: on its lower bound (`L`), its upper bound (`U`) or between (`f`).
pub fn bound_pattern(design: &RodDesign, n: usize, stiffness: &[f64]) -> String {
    (0..=n)
        .map(|j| {
            let e = design.bending_stiffness_of(n, j, stiffness[j]);
            if e <= design.bending_stiffness_min * (1.0 + 1e-4) {
                'L'
            } else if e >= design.bending_stiffness_max * (1.0 - 1e-4) {
                'U'
            } else {
                'f'
            }
        })
        .collect()
}

/// `pattern` run-length encoded: `U12 L3 f1 U5` (class and count of each run of joints).
pub fn runs(pattern: &str) -> String {
    let mut out: Vec<String> = Vec::new();
    let mut chars = pattern.chars().peekable();
    while let Some(c) = chars.next() {
        let mut count = 1;
        while chars.peek() == Some(&c) {
            chars.next();
            count += 1;
        }
        out.push(format!("{c}{count}"));
    }
    out.join(" ")
}

/// One level: the optimum kept and what it looks like.
#[derive(Clone, Debug, Serialize)]
pub struct RodOptimum {
    pub links: usize,
    pub attempts: Vec<Attempt>,
    /// The optimum kept (checked and certified).
    pub result: DesignResult,
    /// `x` of the links' middles (for `θ0`) and of the joints (for `EI`), m.
    pub x_links: Vec<f64>,
    pub x_joints: Vec<f64>,
    /// `EI_j`, N·m².
    pub bending_stiffness: Vec<f64>,
    /// [`bound_pattern`] of the optimum, its number of switches (neighbouring joints in different
    /// classes) and the share of the joints on the lower bound.
    pub pattern: String,
    pub switches: usize,
    pub soft_share: f64,
    /// The share of the links at `|θ0| = θ0_max` and of the joints whose curvature bound is active.
    pub theta0_at_bound_share: f64,
    pub curvature_at_bound_share: f64,
    pub wall_seconds: f64,
}

impl RodOptimum {
    /// The level kept a clean optimum that is not certified `not_a_minimum` (some attempt
    /// reached one, and the kept result is the best of those).
    pub fn is_clean(&self) -> bool {
        self.attempts.iter().any(|a| a.clean)
    }
}

/// A Richardson estimate from three levels `N1 < N2 < N3`: `J(N) = J∞ + C N^−p` through them.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Richardson {
    pub links: [usize; 3],
    /// `p`.
    pub order: f64,
    /// `J∞`, J.
    pub limit: f64,
    /// `|J(N3) − J∞| / J∞`.
    pub remaining: f64,
}

impl Richardson {
    /// The estimate through three `(N, J)`, where the changes have one sign and shrink (`None`
    /// otherwise: no limit is visible in them).
    pub fn through(points: [(usize, f64); 3]) -> Option<Self> {
        let [(n1, j1), (n2, j2), (n3, j3)] = points;
        let (d1, d2) = (j2 - j1, j3 - j2);
        if !(n1 < n2 && n2 < n3) || d1 * d2 <= 0.0 || d2.abs() >= d1.abs() {
            return None;
        }
        let (x1, x2, x3) = (n1 as f64, n2 as f64, n3 as f64);
        let ratio = |p: f64| (x1.powf(-p) - x2.powf(-p)) / (x2.powf(-p) - x3.powf(-p));
        let target = d1 / d2;
        // `ratio` grows with `p` for N1 < N2 < N3: bisection on [1e-3, 12].
        let (mut low, mut high) = (1e-3, 12.0);
        if !(ratio(low) <= target && target <= ratio(high)) {
            return None;
        }
        for _ in 0..200 {
            let mid = 0.5 * (low + high);
            if ratio(mid) < target {
                low = mid;
            } else {
                high = mid;
            }
        }
        let p = 0.5 * (low + high);
        let limit = j3 + d2 * x3.powf(-p) / (x2.powf(-p) - x3.powf(-p));
        Some(Richardson { links: [n1, n2, n3], order: p, limit, remaining: ((j3 - limit) / limit).abs() })
    }
}

/// The study: one [`RodOptimum`] per `N` and the Richardson estimate of the last three clean
/// levels.
#[derive(Clone, Debug, Serialize)]
pub struct RodStudy {
    pub levels: Vec<RodOptimum>,
    pub richardson: Option<Richardson>,
}

/// Where a level's attempt started.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StartedFrom {
    /// The coarsest level's arch ([`RodDesign::start`]).
    Arch,
    /// The next coarser level's optimum, carried over.
    Coarser,
    /// The finest level's optimum, carried back (the second pass).
    Finest,
}

fn usable(result: &DesignResult) -> bool {
    result.is_clean() && result.certificate.as_ref().is_none_or(|c| c.status != MinimumStatus::NotAMinimum)
}

/// Solves level `n` from `start` once for each barrier start, appending the attempts to
/// `attempts`; `kept` becomes the best result so far (a usable one before any other, then the
/// lowest `J`).
fn solve_level(
    design: &RodDesign,
    n: usize,
    (start, from): (&Design, StartedFrom),
    settings: &StudySettings,
    attempts: &mut Vec<Attempt>,
    kept: &mut Option<DesignResult>,
) -> Result<(), DesignError> {
    let problem = design.problem(n);
    let barriers: Vec<Option<f64>> = match from {
        StartedFrom::Arch => vec![None],
        _ => settings.warm_barriers.iter().map(|&m| Some(m)).collect(),
    };
    for mu_init in barriers {
        let clock = Instant::now();
        let mut first_run_iterations = 0;
        let solver = Solver::new(SolverPreset::Exact, Formulation::Full, &solver_settings(settings, mu_init));
        let result = solver.solve(&problem, start, &mut |_| {
            first_run_iterations += 1;
            true
        })?;
        let good = usable(&result);
        attempts.push(Attempt {
            from,
            mu_init,
            status: result.solver.status,
            first_run_iterations,
            iterations: result.solver.iterations,
            objective: result.objective,
            clean: good,
            certificate: result.certificate.as_ref().map(|c| c.status),
            wall_seconds: clock.elapsed().as_secs_f64(),
        });
        let better = kept.as_ref().is_none_or(|k| {
            let k_good = usable(k);
            (good && !k_good) || (good == k_good && result.objective < k.objective)
        });
        if better {
            *kept = Some(result);
        }
    }
    Ok(())
}

/// Solves `design` at each `N` of `links` (increasing), each level from the previous one, then
/// every level below the finest clean one again from its optimum carried back (module docs).
/// `progress` hears of each level's first pass as it ends: `N` and the result kept.
pub fn study(
    design: &RodDesign,
    links: &[usize],
    settings: &StudySettings,
    progress: &mut dyn FnMut(usize, &DesignResult),
) -> Result<RodStudy, DesignError> {
    let mut passes: Vec<(Vec<Attempt>, DesignResult, f64)> = Vec::new();
    for &n in links {
        let clock = Instant::now();
        let start = match passes.last() {
            Some((_, previous, _)) => (design.prolong(&previous.design, n), StartedFrom::Coarser),
            None => (design.start(n), StartedFrom::Arch),
        };
        let (mut attempts, mut kept) = (Vec::new(), None);
        solve_level(design, n, (&start.0, start.1), settings, &mut attempts, &mut kept)?;
        // Invariant: `solve_level` makes one attempt per barrier start (one from the arch, 1 to 4
        // warm ones: `StudySettings::validate` refuses an empty `warm_barriers`), and the first sets
        // `kept`.
        let result = kept.expect("every level makes at least one attempt");
        progress(n, &result);
        passes.push((attempts, result, clock.elapsed().as_secs_f64()));
    }
    // The finest level that kept a usable optimum (an unconverged finest level carries nothing
    // back), and the levels below it.
    let finest_clean = passes.iter().rposition(|(_, r, _)| usable(r));
    let finest = finest_clean.map(|k| passes[k].1.design.clone());
    let count = finest_clean.unwrap_or(0) + 1;
    let mut levels = Vec::with_capacity(links.len());
    for (k, ((mut attempts, result, seconds), &n)) in passes.into_iter().zip(links).enumerate() {
        let clock = Instant::now();
        let mut kept = Some(result);
        if let (Some(finest), true) = (&finest, k + 1 < count) {
            let start = design.prolong(finest, n);
            solve_level(design, n, (&start, StartedFrom::Finest), settings, &mut attempts, &mut kept)?;
        }
        // Invariant: the first pass set `kept` (previous comment), and later passes only replace it.
        let result = kept.expect("kept from the first pass");
        levels.push(describe(design, n, result, attempts, seconds + clock.elapsed().as_secs_f64()));
    }
    let clean: Vec<(usize, f64)> =
        levels.iter().filter(|l| l.is_clean()).map(|l| (l.links, l.result.objective)).collect();
    let richardson = (clean.len() >= 3)
        .then(|| Richardson::through([clean[clean.len() - 3], clean[clean.len() - 2], clean[clean.len() - 1]]))
        .flatten();
    Ok(RodStudy { levels, richardson })
}

/// The level's solver settings: the study's tolerances, no mesh sequencing of its own (the
/// study is the sequence), and the warm start where `mu_init` is given.
fn solver_settings(settings: &StudySettings, mu_init: Option<f64>) -> SolverSettings {
    let mut s = SolverSettings {
        tolerance: settings.tolerance,
        constraint_tolerance: settings.tolerance,
        max_iterations: settings.max_iterations,
        refine: Refine::Mode(RefineMode::Off),
        ..SolverSettings::default()
    };
    if let Some(mu) = mu_init {
        for (name, value) in [("mu_init", mu), ("bound_push", 1e-8), ("bound_frac", 1e-8)] {
            s.ipopt_options.insert(name.into(), ExtraOption::Num(value));
        }
    }
    s
}

fn describe(design: &RodDesign, n: usize, result: DesignResult, attempts: Vec<Attempt>, seconds: f64) -> RodOptimum {
    let d: &Design = &result.design;
    let pattern = bound_pattern(design, n, &d.stiffness);
    let switches = pattern.as_bytes().windows(2).filter(|w| w[0] != w[1]).count();
    let soft_share = pattern.chars().filter(|c| *c == 'L').count() as f64 / (n + 1) as f64;
    let at_theta = d.theta0.iter().filter(|t| t.abs() >= design.theta0_max * (1.0 - 1e-6)).count();
    let kappa = design.curvature_max * design.span(n);
    let at_curvature = d.theta0.windows(2).filter(|w| (w[0] - w[1]).abs() >= kappa * (1.0 - 1e-6)).count();
    RodOptimum {
        links: n,
        attempts,
        x_links: design.link_middles(n),
        x_joints: design.joints(n),
        bending_stiffness: (0..=n).map(|j| design.bending_stiffness_of(n, j, d.stiffness[j])).collect(),
        pattern,
        switches,
        soft_share,
        theta0_at_bound_share: at_theta as f64 / n as f64,
        curvature_at_bound_share: at_curvature as f64 / (n.max(2) - 1) as f64,
        result,
        wall_seconds: seconds,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn richardson_recovers_a_known_limit_and_order() {
        let j = |n: usize| 4.0 + 3.0 * (n as f64).powf(-1.5);
        let r = Richardson::through([(100, j(100)), (200, j(200)), (500, j(500))]).unwrap();
        assert!((r.order - 1.5).abs() < 1e-6, "{r:?}");
        assert!((r.limit - 4.0).abs() < 1e-9, "{r:?}");
        // Changes that do not shrink show no limit.
        assert!(Richardson::through([(10, 1.0), (20, 2.0), (50, 3.5)]).is_none());
        assert!(Richardson::through([(10, 1.0), (20, 2.0), (50, 1.5)]).is_none());
    }
}
