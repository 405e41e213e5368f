//! Multi-start: eq. (33) is non-convex ("there are many solutions", Sec. 5), so a run from one
//! start finds one local optimum. [`feasible_starts`] draws seeded starts that satisfy every bound
//! and `Φ(θ0) = 0`; [`cluster`] groups the converged results into distinct optima.

use crate::census::{estimate, CensusEstimate};
use crate::problem::DesignProblem;
use crate::result::DesignResult;
use crate::solve::ipopt::DesignError;
use crate::solve::Solver;
use crate::solver_run::SolverRun;
use serde::Serialize;
use spine_model::rng::SplitMix64;
use spine_model::Design;
use std::f64::consts::PI;

/// `count` deterministic starts from `seed`. Each start's unloaded shape is a random positive
/// combination of the first three arch modes `Y(x) = Σ c_m sin(m π x / L_x)`, scaled so that the
/// interior node heights lie in `[y_min, y_max]`; `θ0_i = atan((Y_{i+1} − Y_i)/a_i)` then satisfies
/// `Φ(θ0) = 0` exactly. Shapes breaking the angle bounds are redrawn (up to 1000 times, then
/// scaled toward the lowest admissible arch). Stiffnesses are log-uniform within their bounds.
pub fn feasible_starts(problem: &DesignProblem, count: usize, seed: u64) -> Vec<Design> {
    let mut rng = SplitMix64::new(seed);
    let n = problem.n_links();
    let b = &problem.bounds;
    let spans = &problem.structure.chain.spans;
    let floors = b.height_floors(spans);
    let lx = problem.structure.chain.length_x();
    let mut starts = Vec::with_capacity(count);
    while starts.len() < count {
        let mut theta0 = None;
        for _ in 0..1000 {
            let c = [rng.uniform(0.3, 1.0), rng.uniform(-0.3, 0.3), rng.uniform(-0.2, 0.2)];
            let mut x = 0.0;
            let mut y = vec![0.0];
            for a in spans {
                x += a;
                let s = x / lx;
                y.push(c.iter().enumerate().map(|(m, cm)| cm * ((m + 1) as f64 * PI * s).sin()).sum::<f64>());
            }
            y[n] = 0.0;
            let interior = &y[1..n];
            let (lo, hi) = interior.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| (l.min(*v), h.max(*v)));
            if n > 1 && lo <= 0.0 {
                continue;
            }
            let target = rng.uniform(b.height_min, b.height_max);
            let scale = if n > 1 { (target / hi).min(b.height_max / hi) } else { 0.0 };
            let heights: Vec<f64> = y.iter().map(|v| v * scale).collect();
            if n > 1 && heights[1..n].iter().zip(&floors).any(|(h, floor)| *h < *floor || *h > b.height_max) {
                continue;
            }
            let t: Vec<f64> = (0..n).map(|i| ((heights[i + 1] - heights[i]) / spans[i]).atan()).collect();
            let angles_ok = t.iter().all(|v| v.abs() <= b.theta0_max)
                && t.windows(2).all(|w| (w[0] - w[1]).abs() <= b.relative_angle_max);
            if angles_ok {
                theta0 = Some(t);
                break;
            }
        }
        let theta0 = theta0.unwrap_or_else(|| vec![0.0; n]);
        let stiffness = (0..=n)
            .map(|j| {
                let (lo, hi) = (b.stiffness_min[j], b.stiffness_max[j]);
                if lo > 0.0 && hi > lo {
                    (lo.ln() + rng.next_f64() * (hi.ln() - lo.ln())).exp()
                } else {
                    rng.uniform(lo, hi)
                }
            })
            .collect();
        starts.push(Design { theta0, stiffness });
    }
    starts
}

/// A distinct local optimum, the starts that reached it, and the full result of the first of
/// them (design, both equilibria with `λ`, violations, stability, Ipopt's report).
#[derive(Clone, Debug, Serialize)]
pub struct Optimum {
    /// How many starts converged here, and which (0-based; 0 is the case's own start).
    pub count: usize,
    pub starts: Vec<usize>,
    /// The run met every check ([`DesignResult::is_clean`]).
    pub clean: bool,
    /// The optimum (index into `optima`) this one is the mirror image of: `θ0` reversed and
    /// negated, `K` reversed, the same `J`. Symmetric loads make such pairs distinct optima of
    /// equal value.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mirror_of: Option<usize>,
    /// The run from `starts[0]`.
    #[serde(flatten)]
    pub result: DesignResult,
}

impl Optimum {
    /// `J`, J.
    pub fn objective(&self) -> f64 {
        self.result.objective
    }
}

/// Summary of a multi-start run.
#[derive(Clone, Debug, Serialize)]
pub struct MultiStartSummary {
    /// Runs in all: the case's own start (start 0) and the seeded ones.
    pub starts: usize,
    pub seed: u64,
    pub converged: usize,
    /// Distinct optima: the clean ones first, each group by increasing `J`. The first, when
    /// clean, is the best clean optimum found.
    pub optima: Vec<Optimum>,
    /// Starts that did not converge, with Ipopt's status.
    pub failed: Vec<(usize, spine_ipopt::Status)>,
    /// How complete the census of clean optima is ([`crate::census`]).
    pub census: CensusEstimate,
    /// A census run to a stated confidence: the target, whether it was reached, and the batches.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub confidence: Option<ConfidenceRun>,
}

/// How a census to a stated confidence ran.
#[derive(Clone, Debug, Serialize)]
pub struct ConfidenceRun {
    /// The target: P(a better optimum unseen) at most this.
    pub target: f64,
    /// Whether the estimate reached it (else the cap or a time limit ended the census).
    pub reached: bool,
    /// Batches of seeded starts run, their size, and the cap on seeded starts.
    pub batches: usize,
    pub batch: usize,
    pub cap: usize,
    /// Seeded starts solved and settled in all (the last batch is cut at the cap, or by a time
    /// limit): the count of the runs themselves.
    pub seeded: usize,
}

impl MultiStartSummary {
    /// The best clean optimum, if any start reached one.
    pub fn best_clean(&self) -> Option<&Optimum> {
        self.optima.first().filter(|o| o.clean)
    }
}

/// The left–right mirror image of a design: `θ0_i → −θ0_{N−1−i}`, `K_j → K_{N−j}`.
pub fn mirror(design: &Design) -> Design {
    Design {
        theta0: design.theta0.iter().rev().map(|t| -t).collect(),
        stiffness: design.stiffness.iter().rev().copied().collect(),
    }
}

/// Whether `b`, with angles `b_theta0` (its own, or those of its mirror image), is the optimum
/// `a`: both clean or both not, `J` within `1e-6` relative, `θ0` within `1e-4` rad.
fn same_optimum(a: &DesignResult, b: &DesignResult, b_theta0: &[f64]) -> bool {
    a.is_clean() == b.is_clean()
        && (a.objective - b.objective).abs() <= 1e-6 * a.objective.abs().max(1e-12)
        && a.design.theta0.iter().zip(b_theta0).all(|(x, y)| (x - y).abs() <= 1e-4)
}

/// The reported results of `runs` (in start order) by `solver` ([`Solver::report`]), as
/// [`Settled`] gives them.
pub fn settle_all(
    problem: &DesignProblem,
    runs: Vec<SolverRun>,
    solver: &Solver,
) -> Result<Vec<DesignResult>, DesignError> {
    let mut settled = Settled::new(problem, solver.clone());
    for run in runs {
        settled.add(run)?;
    }
    Ok(settled.results())
}

/// Runs checked, grouped as [`cluster`] groups them, and settled once per group, as they come
/// (start order): the first run of each group is settled ([`Solver::report`]: with the exact
/// preset certified, and left for a lower minimum where it is not one) and every run of the group
/// reports that settled result. One certificate per distinct point (at Ipopt's default tolerance
/// a point's weakly active bounds cannot be told apart, so each certificate costs a tight
/// re-solve), and the same results whatever order or process the runs came from.
pub struct Settled<'a> {
    problem: &'a DesignProblem,
    solver: Solver,
    /// Each group's first run, checked (what later runs are compared with), and settled.
    groups: Vec<(DesignResult, DesignResult)>,
    /// Each run's group, or its own result (a run that did not converge).
    runs: Vec<Member>,
}

enum Member {
    Group(usize),
    Alone(Box<DesignResult>),
}

impl<'a> Settled<'a> {
    pub fn new(problem: &'a DesignProblem, solver: Solver) -> Self {
        Self { problem, solver, groups: Vec::new(), runs: Vec::new() }
    }

    /// How many runs have been added.
    pub fn len(&self) -> usize {
        self.runs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.runs.is_empty()
    }

    /// Adds the next run.
    pub fn add(&mut self, run: SolverRun) -> Result<(), DesignError> {
        let checked = run.clone().check(self.problem, self.solver.settings());
        if !checked.solver.converged || !checked.objective.is_finite() {
            self.runs.push(Member::Alone(Box::new(self.solver.report(self.problem, run)?)));
            return Ok(());
        }
        let theta0 = checked.design.theta0.clone();
        match self.groups.iter().position(|(first, _)| same_optimum(first, &checked, &theta0)) {
            Some(g) => self.runs.push(Member::Group(g)),
            None => {
                let settled = self.solver.report(self.problem, run)?;
                self.groups.push((checked, settled));
                self.runs.push(Member::Group(self.groups.len() - 1));
            }
        }
        Ok(())
    }

    /// Every run's settled result, in the order added.
    pub fn results(&self) -> Vec<DesignResult> {
        self.runs
            .iter()
            .map(|m| match m {
                Member::Group(g) => self.groups[*g].1.clone(),
                Member::Alone(r) => (**r).clone(),
            })
            .collect()
    }

    /// The census estimate of the runs so far: the clean settled optima (groups whose settled
    /// results are one optimum merged), an optimum and its mirror image one class
    /// ([`mirror_classes`]), and how many runs reached each.
    pub fn estimate(&self) -> CensusEstimate {
        let mut optima: Vec<(usize, usize)> = Vec::new(); // (group, runs)
        let mut counts = vec![0usize; self.groups.len()];
        for m in &self.runs {
            if let Member::Group(g) = m {
                counts[*g] += 1;
            }
        }
        for (g, (_, settled)) in self.groups.iter().enumerate() {
            if !settled.is_clean() {
                continue;
            }
            let theta0 = &settled.design.theta0;
            match optima.iter_mut().find(|(o, _)| same_optimum(&self.groups[*o].1, settled, theta0)) {
                Some((_, c)) => *c += counts[g],
                None => optima.push((g, counts[g])),
            }
        }
        let results: Vec<&DesignResult> = optima.iter().map(|(g, _)| &self.groups[*g].1).collect();
        let mirror_of: Vec<Option<usize>> =
            (0..results.len()).map(|k| mirror_among(&results[..k], results[k])).collect();
        estimate(mirror_classes(&optima.iter().map(|(_, c)| *c).collect::<Vec<_>>(), &mirror_of))
    }
}

/// The earliest of `earlier` that `result` is the mirror image of ([`mirror`]).
fn mirror_among(earlier: &[&DesignResult], result: &DesignResult) -> Option<usize> {
    let mirrored = mirror(&result.design);
    earlier.iter().position(|e| same_optimum(e, result, &mirrored.theta0))
}

/// How many runs reached each class of optima, an optimum and its mirror image one class:
/// `counts[k]` runs reached optimum `k`, which is the mirror image of optimum `mirror_of[k]`
/// (an earlier one) or of none. The census estimate counts classes, not points: the question it
/// answers is whether a *better* design is unseen, and a mirror image has the same `J` as its
/// partner (it is the same design read from the other end), so seeing either settles the value
/// of both. Where the case is not mirror-symmetric no two optima are mirror images and every
/// optimum is its own class.
pub fn mirror_classes(counts: &[usize], mirror_of: &[Option<usize>]) -> Vec<usize> {
    let mut classes: Vec<usize> = Vec::new();
    let mut class_of = Vec::with_capacity(counts.len());
    for (k, &c) in counts.iter().enumerate() {
        match mirror_of[k].map(|m| class_of[m]) {
            Some(class) => {
                classes[class] += c;
                class_of.push(class);
            }
            None => {
                class_of.push(classes.len());
                classes.push(c);
            }
        }
    }
    classes
}

/// Groups converged results: two belong to the same optimum when both are clean or both are
/// not, `J` agrees to `1e-6` relative and `θ0` to `1e-4` rad. `K` is not compared: a spring whose
/// two links deflect alike stores no energy, so its stiffness can move along a flat valley of `J`
/// (bounded by the end-displacement constraint) without changing the optimum's value; such runs
/// are one optimum. `results[k]` is the run from start `k`.
pub fn cluster(results: Vec<DesignResult>, seed: u64) -> MultiStartSummary {
    let starts = results.len();
    let mut optima: Vec<Optimum> = Vec::new();
    let mut failed = Vec::new();
    let mut converged = 0;
    for (k, r) in results.into_iter().enumerate() {
        if !r.solver.converged || !r.objective.is_finite() {
            failed.push((k, r.solver.status));
            continue;
        }
        converged += 1;
        match optima.iter_mut().find(|o| same_optimum(&o.result, &r, &r.design.theta0)) {
            Some(o) => {
                o.count += 1;
                o.starts.push(k);
            }
            None => optima.push(Optimum { count: 1, starts: vec![k], clean: r.is_clean(), mirror_of: None, result: r }),
        }
    }
    optima.sort_by(|a, b| b.clean.cmp(&a.clean).then(a.objective().total_cmp(&b.objective())));
    for k in 1..optima.len() {
        let mirrored = mirror(&optima[k].result.design);
        optima[k].mirror_of = (0..k).find(|&m| same_optimum(&optima[m].result, &optima[k].result, &mirrored.theta0));
    }
    // A mirror pair's two `J` agree only to round-off, so which member comes first would depend on
    // rounding (the linear solver, its pivot order): the pair keeps the place of its lower `J`,
    // with the member reached from the earlier start first.
    for k in 1..optima.len() {
        if let Some(m) = optima[k].mirror_of {
            if optima[k].starts[0] < optima[m].starts[0] {
                optima.swap(m, k);
                (optima[m].mirror_of, optima[k].mirror_of) = (None, Some(m));
            }
        }
    }
    // The clean optima lead the list and a mirror image names an earlier optimum as clean as
    // itself, so the clean ones' `mirror_of` index among them.
    let (counts, mirror_of): (Vec<usize>, Vec<Option<usize>>) =
        optima.iter().filter(|o| o.clean).map(|o| (o.count, o.mirror_of)).unzip();
    let census = estimate(mirror_classes(&counts, &mirror_of));
    MultiStartSummary { starts, seed, converged, optima, failed, census, confidence: None }
}

#[cfg(test)]
mod tests {
    use super::mirror_classes;

    #[test]
    fn mirror_images_join_their_partners_class() {
        // Optima 0..5: 2 is the image of 0, 4 the image of 1, 3 and 5 stand alone.
        let counts = [5, 3, 2, 7, 1, 4];
        let mirror_of = [None, None, Some(0), None, Some(1), None];
        assert_eq!(mirror_classes(&counts, &mirror_of), vec![7, 4, 7, 4]);
        // No mirror images: every optimum is its own class.
        assert_eq!(mirror_classes(&counts, &[None; 6]), counts.to_vec());
    }
}
