//! How complete a multi-start's census of local optima is: a Bayesian estimate in the manner of
//! Boender and Rinnooy Kan ("Bayesian stopping rules for multistart global optimization
//! methods", Math. Programming 37, 1987).
//!
//! **Model.** The starts are independent draws; each local search ends at the optimum whose
//! region of attraction holds its start. There are `k` optima (prior: every `k ≥ 1` equally
//! likely, improper), and the relative sizes of their regions are uniform on the simplex
//! (Dirichlet(1, …, 1)). After `n` searches that found `w` distinct optima the posterior of `k` is
//!
//! `p(k | n, w) ∝ k! (k − 1)! / ((k − w)! (n + k − 1)!)`, `k ≥ w`,
//!
//! proper for `n ≥ w + 2`. Its mean is `w (n − 1) / (n − w − 2)` (for `n ≥ w + 3`), and the
//! expected total size of the regions not yet sampled is `w (w + 1) / (n (n − 1))`.
//!
//! **Probability that a better optimum is unseen.** If, in addition, the ranking of the optima by
//! objective is independent of the sizes of their regions (every optimum equally likely to be the
//! global one), the best optimum is unseen with probability `(k − w)/k` given `k`, so
//! `P(better unseen) = Σ_k p(k | n, w) (k − w) / k`. This assumption is the rule's weak point
//! here: deep optima of eq. (33) tend to have large regions, which makes the estimate cautious.
//!
//! Only runs that reached a clean optimum count as searches (`n`). The "optima" of the model are
//! classes: an optimum and its mirror image (the same design read from the other end, the same
//! `J`; [`crate::multistart::mirror_classes`]) are one class with the union of their regions,
//! because the question asked is whether a better *value* is unseen, and seeing either member
//! of a pair settles it. The census still lists both members, each with its own count. Counting
//! mirror images as distinct (as this workspace did until 2026-11-28) nearly doubles `w` for the
//! mirror-symmetric paper cases and with it the searches a stated confidence needs (the posterior
//! depends on `n` and `w` only: design10 needed 3599 runs for P ≤ 0.01 with 35 points, 20 classes).

use serde::Serialize;

/// The name of the rule, as reported.
pub const RULE: &str = "Boender-Rinnooy Kan (1987): uniform prior on the number of optima, uniform (Dirichlet) prior on the sizes of their regions of attraction";

/// The posterior summary of one census.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CensusEstimate {
    pub rule: &'static str,
    /// Searches that reached a clean optimum (`n`), distinct classes of optima among them (`w`:
    /// an optimum and its mirror image one class), and how many searches reached each class (in
    /// the order each class was first met in the census's list of optima).
    pub searches: usize,
    pub distinct: usize,
    pub reached: Vec<usize>,
    /// Posterior mean of the number of optima (`None` for `n < w + 3`: too few searches).
    pub estimated_optima: Option<f64>,
    /// Posterior probability that every optimum has been seen (`None` for `n < w + 2`).
    pub probability_all_seen: Option<f64>,
    /// Expected relative size of the regions of attraction not yet sampled.
    pub unseen_fraction: Option<f64>,
    /// Posterior probability that an optimum better than the best seen exists (assumption in the
    /// module docs).
    pub probability_better_unseen: Option<f64>,
}

/// Terms summed until they fall below this fraction of the sum (and a tail bound is added).
const RELATIVE_TAIL: f64 = 1e-15;
/// At most this many terms of the posterior are summed before the tail is bounded analytically.
const MAX_TERMS: usize = 2_000_000;

/// The estimate for `reached[i]` searches ending at optimum `i`.
pub fn estimate(reached: Vec<usize>) -> CensusEstimate {
    let (n, w) = (reached.iter().sum::<usize>(), reached.iter().filter(|&&c| c > 0).count());
    let mean = (w > 0 && n >= w + 3).then(|| (w * (n - 1)) as f64 / (n - w - 2) as f64);
    let unseen = (n >= 2).then(|| (w * (w + 1)) as f64 / (n * (n - 1)) as f64);
    let posterior = (w > 0 && n >= w + 2).then(|| posterior_sums(n, w));
    CensusEstimate {
        rule: RULE,
        searches: n,
        distinct: w,
        reached,
        estimated_optima: mean,
        probability_all_seen: posterior.map(|p| 1.0 / p.total),
        unseen_fraction: unseen.map(|u| u.min(1.0)),
        probability_better_unseen: posterior.map(|p| p.better_unseen / p.total),
    }
}

/// Sums of the posterior's unnormalised terms `t_k` (`t_w = 1`): `Σ t_k`, `Σ t_k (k − w)/k` and
/// `Σ t_k k` (the last only where the mean exists; used by the tests).
#[derive(Clone, Copy, Debug)]
pub(crate) struct PosteriorSums {
    pub total: f64,
    pub better_unseen: f64,
    pub mean_numerator: f64,
}

/// `t_{k+1}/t_k = (k + 1) k / ((k + 1 − w)(n + k))`. The terms decay like `k^(w−n)`; after
/// [`MAX_TERMS`] the tail `Σ_{j>m} t_j ≈ t_m m / (n − w − 1)` is added (and likewise for the
/// weighted sums).
pub(crate) fn posterior_sums(n: usize, w: usize) -> PosteriorSums {
    let (nf, wf) = (n as f64, w as f64);
    let mut t = 1.0;
    let mut sums = PosteriorSums { total: 1.0, better_unseen: 0.0, mean_numerator: wf };
    let mut k = wf;
    for _ in 0..MAX_TERMS {
        t *= (k + 1.0) * k / ((k + 1.0 - wf) * (nf + k));
        k += 1.0;
        sums.total += t;
        sums.better_unseen += t * (k - wf) / k;
        sums.mean_numerator += t * k;
        if t < RELATIVE_TAIL * sums.total && t * k < RELATIVE_TAIL * sums.mean_numerator {
            return sums;
        }
    }
    let decay = nf - wf;
    sums.total += t * k / (decay - 1.0);
    sums.better_unseen += t * k / (decay - 1.0);
    if decay > 2.0 {
        sums.mean_numerator += t * k * k / (decay - 2.0);
    }
    sums
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_series_mean_is_the_closed_form() {
        for (n, w) in [(10, 1), (20, 3), (21, 9), (50, 9), (200, 12)] {
            let s = posterior_sums(n, w);
            let closed = (w * (n - 1)) as f64 / (n - w - 2) as f64;
            let series = s.mean_numerator / s.total;
            assert!((series - closed).abs() <= 1e-6 * closed, "n {n}, w {w}: series {series}, closed form {closed}");
        }
    }

    #[test]
    fn one_optimum_reached_by_every_search_is_almost_surely_all() {
        let e = estimate(vec![40]);
        assert_eq!((e.searches, e.distinct), (40, 1));
        // p(k=1) ∝ 1/n!·0!… : t_2/t_1 = 2/(n+1); the series gives p(1) = 1 − O(1/n).
        let all = e.probability_all_seen.unwrap();
        assert!(all > 0.94 && all < 1.0, "{all}");
        assert!((e.estimated_optima.unwrap() - 39.0 / 37.0).abs() < 1e-12);
        assert!((e.unseen_fraction.unwrap() - 2.0 / (40.0 * 39.0)).abs() < 1e-15);
        assert!(e.probability_better_unseen.unwrap() < 0.05);
    }

    #[test]
    fn many_optima_seen_once_leave_the_census_open() {
        // Nine optima from 21 searches (design10's census): the estimate says more are likely.
        let e = estimate(vec![5, 3, 3, 2, 2, 2, 2, 1, 1]);
        assert!(e.estimated_optima.unwrap() > 9.0);
        assert!(e.probability_all_seen.unwrap() < 0.5);
        assert!(e.probability_better_unseen.unwrap() > 0.01);
        // More searches with no new optimum make the census more complete.
        let more = estimate(vec![50, 30, 30, 20, 20, 20, 20, 10, 10]);
        assert!(more.probability_better_unseen.unwrap() < e.probability_better_unseen.unwrap());
        assert!(more.probability_all_seen.unwrap() > e.probability_all_seen.unwrap());
    }

    #[test]
    fn too_few_searches_give_no_estimate() {
        let e = estimate(vec![1, 1]);
        assert_eq!((e.estimated_optima, e.probability_all_seen, e.probability_better_unseen), (None, None, None));
        let edge = estimate(vec![3, 1, 1]);
        assert!(edge.probability_all_seen.is_some() && edge.estimated_optima.is_none());
    }
}
