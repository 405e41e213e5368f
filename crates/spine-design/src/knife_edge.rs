//! Knife edges: whether the optimum reached from one start is a fact about the problem or about
//! the last bit of rounding. A start that is its own mirror image, or one on the boundary between
//! two basins of attraction, sends the solver down one branch or the other as round-off (the
//! linear solver's pivots, the compiler's fused operations) decides, so two builds of the same
//! program can report different optima from the same case.
//!
//! [`moved_starts`] draws a few starts moved from the given one by a tiny seeded amount, in
//! antithetic pairs `start ± ε u`: where the edge passes through the start, the two members of a
//! pair fall on opposite sides of it whatever the rounding, so the pair shows the edge, and where
//! it does not, every moved start reaches the start's own optimum. [`KnifeEdge`] reports the
//! optima the start and its moved starts reached (grouped as [`crate::multistart::cluster`]
//! groups a census) and the spread of their iteration counts and end points.

use crate::multistart::{cluster, Optimum};
use crate::problem::DesignProblem;
use crate::result::DesignResult;
use serde::{Deserialize, Serialize};
use spine_check::{require, FieldError};
use spine_model::rng::SplitMix64;
use spine_model::Design;

/// How the moved starts are drawn (`knife_edge` in a design case).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct KnifeEdgeSettings {
    /// Antithetic pairs of moved starts (`start + ε u` and `start − ε u`), 0 to solve from the
    /// start alone. Default 2 (four moved starts).
    #[serde(default = "default_pairs")]
    pub pairs: usize,
    /// `ε`, the relative size of the move (default 1e-6): `θ0_i` moves by at most `ε θ0_max`
    /// (the angle bound, rad) and `K_j` by at most `ε K_j`.
    #[serde(default = "default_size")]
    pub size: f64,
    /// Seed of the directions `u` (each entry uniform in [−1, 1]).
    #[serde(default = "default_seed")]
    pub seed: u64,
}

fn default_pairs() -> usize {
    2
}
fn default_size() -> f64 {
    1e-6
}
fn default_seed() -> u64 {
    1
}

/// Most pairs of moved starts (each start is a full solve).
pub const MAX_PAIRS: usize = 50;

impl Default for KnifeEdgeSettings {
    fn default() -> Self {
        Self { pairs: default_pairs(), size: default_size(), seed: default_seed() }
    }
}

impl KnifeEdgeSettings {
    /// Errors name the field (`pairs`, `size`).
    pub fn validate(&self) -> Result<(), FieldError> {
        require(self.pairs <= MAX_PAIRS, "pairs", || format!("must be at most {MAX_PAIRS}, got {}", self.pairs))?;
        require(self.size.is_finite() && self.size > 0.0 && self.size <= 1e-2, "size", || {
            format!("must be a relative move > 0 and at most 1e-2 (e.g. 1e-6), got {}", self.size)
        })
    }
}

/// The `2 · pairs` moved starts of `start`: pair `k` is `start + ε u_k` then `start − ε u_k`,
/// `u_k` seeded, with `θ0_i` moved by `ε u_{k,i} θ0_max` and `K_j` by `ε u_{k,j} K_j`. Not
/// projected into the bounds: the solve projects every start as it projects the case's own.
pub fn moved_starts(problem: &DesignProblem, start: &Design, settings: &KnifeEdgeSettings) -> Vec<Design> {
    let mut rng = SplitMix64::new(settings.seed);
    let eps = settings.size;
    let angle_scale = problem.bounds.theta0_max;
    let mut starts = Vec::with_capacity(2 * settings.pairs);
    for _ in 0..settings.pairs {
        let u_theta: Vec<f64> = start.theta0.iter().map(|_| rng.uniform(-1.0, 1.0)).collect();
        let u_k: Vec<f64> = start.stiffness.iter().map(|_| rng.uniform(-1.0, 1.0)).collect();
        for sign in [1.0, -1.0] {
            starts.push(Design {
                theta0: start.theta0.iter().zip(&u_theta).map(|(t, u)| t + sign * eps * u * angle_scale).collect(),
                stiffness: start.stiffness.iter().zip(&u_k).map(|(k, u)| k * (1.0 + sign * eps * u)).collect(),
            });
        }
    }
    starts
}

/// One optimum reached from the start or its moved starts.
#[derive(Clone, Debug, Serialize)]
pub struct Branch {
    /// `J` at the optimum, J.
    pub objective: f64,
    /// Whether the run met every check ([`DesignResult::is_clean`]).
    pub clean: bool,
    /// The starts that reached it: 0 is the unmoved start, `1 ..= 2·pairs` the moved ones.
    pub starts: Vec<usize>,
    /// The branch (index into [`KnifeEdge::branches`]) this one is the mirror image of.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mirror_of: Option<usize>,
    /// Fewest and most solver iterations among its starts.
    pub iterations: (usize, usize),
    /// The optimum's design (from the first start that reached it).
    pub design: Design,
}

/// What the start and its moved starts reached.
#[derive(Clone, Debug, Serialize)]
pub struct KnifeEdge {
    /// The settings the moved starts were drawn with.
    pub settings: KnifeEdgeSettings,
    /// The moved starts reached more than one outcome (optima, or an optimum and a failure): the
    /// start sits on a knife edge, and which branch a single run from it takes is decided by
    /// rounding.
    pub split: bool,
    /// The optima some moved start reached, the clean ones first, each group by increasing `J`
    /// (as a census lists them); `starts` includes 0 where the unmoved start reached it too.
    pub branches: Vec<Branch>,
    /// The optimum the unmoved start reached where no moved start reached it: an edge finer than
    /// `ε`, so that optimum is a fact about this build's rounding, not about the problem.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unmoved_only: Option<Branch>,
    /// Starts that did not converge (0: the unmoved one), with the solver's status.
    pub failed: Vec<(usize, spine_ipopt::Status)>,
    /// Fewest and most solver iterations over every start.
    pub iterations: (usize, usize),
    /// The largest distance of a moved start's end point from the unmoved start's,
    /// `max_k ‖θ0_k − θ0_0‖∞`, rad.
    pub end_spread_theta0: f64,
    /// The largest relative distance of a moved start's stiffnesses from the unmoved start's,
    /// `max_k max_j |K_kj − K_0j| / K_0j`.
    pub end_spread_stiffness: f64,
}

impl KnifeEdge {
    /// The knife edge of `results`: the settled result of the unmoved start first, then those of
    /// the moved starts in the order [`moved_starts`] drew them. The optima are the census's
    /// ([`cluster`]): `J` within 1e-6 relative and `θ0` within 1e-4 rad.
    pub fn of(settings: &KnifeEdgeSettings, results: &[DesignResult]) -> Self {
        let iterations = span(results.iter().map(|r| r.solver.iterations));
        let (mut end_spread_theta0, mut end_spread_stiffness) = (0.0f64, 0.0f64);
        if let Some((first, moved)) = results.split_first() {
            for r in moved {
                for (a, b) in r.design.theta0.iter().zip(&first.design.theta0) {
                    end_spread_theta0 = end_spread_theta0.max((a - b).abs());
                }
                for (a, b) in r.design.stiffness.iter().zip(&first.design.stiffness) {
                    end_spread_stiffness = end_spread_stiffness.max((a - b).abs() / b.abs().max(f64::MIN_POSITIVE));
                }
            }
        }
        let summary = cluster(results.to_vec(), settings.seed);
        let (mut branches, mut unmoved_only) = (Vec::new(), None);
        for o in &summary.optima {
            if o.starts == [0] {
                unmoved_only = Some(branch(o, results));
            } else {
                branches.push(branch(o, results));
            }
        }
        // `mirror_of` indexes the census's optima; here it indexes `branches` (None for the image
        // of the unmoved start's own optimum).
        let listed: Vec<&Optimum> = summary.optima.iter().filter(|o| o.starts != [0]).collect();
        for (b, o) in branches.iter_mut().zip(&listed) {
            b.mirror_of = o.mirror_of.and_then(|m| listed.iter().position(|l| l.starts == summary.optima[m].starts));
        }
        let moved_failed = summary.failed.iter().any(|(k, _)| *k > 0);
        let split = branches.len() + usize::from(moved_failed) > 1;
        Self {
            settings: settings.clone(),
            split,
            branches,
            unmoved_only,
            failed: summary.failed,
            iterations,
            end_spread_theta0,
            end_spread_stiffness,
        }
    }

    /// The index of the branch start `k` reached (`None`: that start did not converge, or for
    /// the unmoved start, reached an optimum no moved start did).
    pub fn branch_of(&self, k: usize) -> Option<usize> {
        self.branches.iter().position(|b| b.starts.contains(&k))
    }
}

fn branch(o: &Optimum, results: &[DesignResult]) -> Branch {
    Branch {
        objective: o.objective(),
        clean: o.clean,
        starts: o.starts.clone(),
        mirror_of: o.mirror_of,
        iterations: span(o.starts.iter().map(|&k| results[k].solver.iterations)),
        design: o.result.design.clone(),
    }
}

/// `(min, max)` of `values` (`(0, 0)` when empty).
fn span(values: impl Iterator<Item = usize>) -> (usize, usize) {
    values
        .fold(None, |acc: Option<(usize, usize)>, v| Some(acc.map_or((v, v), |(lo, hi)| (lo.min(v), hi.max(v)))))
        .unwrap_or((0, 0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::{arch_start, paper_problem};

    #[test]
    fn moved_starts_come_in_antithetic_pairs_of_the_stated_size() {
        let problem = paper_problem(10, -5.0, -400.0, -0.02, 1.0);
        let start = arch_start(10, 0.3, 1000.0);
        let settings = KnifeEdgeSettings { pairs: 3, size: 1e-6, seed: 7 };
        let moved = moved_starts(&problem, &start, &settings);
        assert_eq!(moved.len(), 6);
        let angle = problem.bounds.theta0_max;
        for pair in moved.chunks(2) {
            for i in 0..10 {
                let (plus, minus) = (pair[0].theta0[i] - start.theta0[i], pair[1].theta0[i] - start.theta0[i]);
                assert!((plus + minus).abs() <= 1e-15, "θ0[{i}]: {plus} and {minus}");
                assert!(plus.abs() <= 1e-6 * angle && plus != 0.0);
            }
            for j in 0..11 {
                let rel = pair[0].stiffness[j] / start.stiffness[j] - 1.0;
                let rel_minus = pair[1].stiffness[j] / start.stiffness[j] - 1.0;
                assert!((rel + rel_minus).abs() <= 1e-12 && rel.abs() <= 1e-6 && rel != 0.0);
            }
        }
        assert_ne!(moved[0], moved[2], "two pairs share a direction");
        assert_eq!(moved, moved_starts(&problem, &start, &settings), "not seeded");
        assert_ne!(moved, moved_starts(&problem, &start, &KnifeEdgeSettings { seed: 8, ..settings }));
    }

    #[test]
    fn bad_settings_name_their_field() {
        let e = KnifeEdgeSettings { pairs: MAX_PAIRS + 1, ..Default::default() }.validate().unwrap_err();
        assert_eq!(e.field, "pairs", "{e}");
        for size in [0.0, -1e-6, f64::NAN, 0.1] {
            let e = KnifeEdgeSettings { size, ..Default::default() }.validate().unwrap_err();
            assert_eq!(e.field, "size", "{e}");
        }
        assert!(KnifeEdgeSettings { pairs: 0, ..Default::default() }.validate().is_ok());
    }
}
