//! The chain coarsened and a coarse optimum prolonged (see the module docs of [`super`]).

use crate::objective::Objective;
use crate::problem::DesignProblem;
use spine_model::{Chain, Design, NodalLoads, State, Structure};

/// The fine node of each coarse node: `b_c = round(c N / M)`, `c = 0..=M` (strictly increasing
/// for `M ≤ N`).
pub fn coarse_nodes(n: usize, m: usize) -> Vec<usize> {
    assert!(m >= 1 && m <= n, "coarse chain of {m} links from {n}");
    (0..=m).map(|c| ((c * n) as f64 / m as f64).round() as usize).collect()
}

/// `X` of every node (`N + 1`), m.
pub(super) fn node_x(spans: &[f64]) -> Vec<f64> {
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
        objective: match &problem.objective {
            Objective::Compliance { load } => Objective::Compliance { load: lump(load) },
            other => other.clone(),
        },
        // `J` is a Riemann sum of the same energy: the budget carries over.
        strain_energy_max: problem.strain_energy_max,
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
pub fn interpolate(at: &[f64], values: &[f64], to: &[f64]) -> Vec<f64> {
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

pub(super) fn midpoints(spans: &[f64]) -> Vec<f64> {
    let x = node_x(spans);
    x.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect()
}

/// The stretch of chain whose flexibility the spring at each node stands for, `[from, to]` in m:
/// half a span on either side of the node (a whole span centred on an end node, as in
/// [`node_spans`], whose lengths these are).
fn node_intervals(spans: &[f64]) -> Vec<(f64, f64)> {
    let x = node_x(spans);
    let h = node_spans(spans);
    let n = spans.len();
    (0..=n)
        .map(|j| {
            let left = if j == 0 { 0.5 * h[0] } else { 0.5 * spans[j - 1] };
            let right = if j == n { 0.5 * h[n] } else { 0.5 * spans[j] };
            (x[j] - left, x[j] + right)
        })
        .collect()
}

/// Fine springs with the coarse chain's flexibility (N·m/rad): the coarse spring at node `c`
/// spreads the compliance `1/K_c` evenly over its interval ([`node_intervals`]), and each fine
/// spring gathers the compliance over its own interval, `1/K_j = Σ_c |I_j ∩ I_c| / (K_c |I_c|)`.
/// Total compliance is kept; aligned with a halving, a fine spring at a coarse node gets `2 K_c`
/// and one between coarse nodes `c`, `c + 1` twice their harmonic mean. A zero coarse spring (no
/// spring) makes every fine spring it covers zero.
///
/// Why compliance and not `k`: linear interpolation of `k` between a soft and a stiff coarse
/// spring (bounds 1e2 s² and 1e4 s² are both common at an optimum) gives a spring near the stiff
/// one, so the prolonged chain was stiffer than its coarse optimum; restoring `δ_d` by scaling
/// every spring then raised J by up to 70 % before Ipopt started (docs/design.md, "Warm levels").
fn prolong_compliance(coarse_spans: &[f64], coarse_stiffness: &[f64], fine_spans: &[f64]) -> Vec<f64> {
    let coarse = node_intervals(coarse_spans);
    let mut c = 0;
    node_intervals(fine_spans)
        .into_iter()
        .map(|(from, to)| {
            while c + 1 < coarse.len() && coarse[c].1 <= from {
                c += 1;
            }
            let mut compliance = 0.0;
            for (&(c_from, c_to), &k) in coarse[c..].iter().zip(&coarse_stiffness[c..]) {
                if c_from >= to {
                    break;
                }
                let overlap = to.min(c_to) - from.max(c_from);
                if overlap > 0.0 {
                    compliance += overlap / ((c_to - c_from) * k);
                }
            }
            1.0 / compliance
        })
        .collect()
}

/// A fine start from a coarse solution: the design (exactly feasible for the design constraints)
/// and interpolated states (not yet equilibria: see `warm_states`).
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
    let stiffness = prolong_compliance(&coarse.structure.chain.spans, &design.stiffness, &fine.structure.chain.spans)
        .into_iter()
        .enumerate()
        .map(|(j, k)| k.clamp(fine.bounds.stiffness_min[j], fine.bounds.stiffness_max[j]))
        .collect();
    let (coarse_mid, fine_mid) = (midpoints(&coarse.structure.chain.spans), midpoints(&fine.structure.chain.spans));
    let state = |s: &State| State { theta: interpolate(&coarse_mid, &s.theta, &fine_mid), lambda: s.lambda };
    (Design { theta0, stiffness }, (state(&states.0), state(&states.1)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs().max(1e-300)
    }

    /// A uniform bending stiffness `EI` (`K = EI / h` at every node, `h` its node span) is a
    /// uniform compliance density: every fine spring must get `EI / h_fine`, at any ratio of
    /// sizes and with unequal spans.
    #[test]
    fn a_uniform_bending_stiffness_is_kept_at_any_ratio() {
        let ei = 3.7;
        let fine_spans: Vec<f64> = (0..10).map(|i| 0.08 + 0.005 * i as f64).collect();
        for m in [1, 3, 5, 7, 9] {
            let nodes = coarse_nodes(10, m);
            let coarse_spans: Vec<f64> = nodes.windows(2).map(|w| fine_spans[w[0]..w[1]].iter().sum()).collect();
            let coarse_k: Vec<f64> = node_spans(&coarse_spans).iter().map(|h| ei / h).collect();
            let fine_k = prolong_compliance(&coarse_spans, &coarse_k, &fine_spans);
            for (j, (k, h)) in fine_k.iter().zip(node_spans(&fine_spans)).enumerate() {
                assert!(close(*k, ei / h), "M = {m}, node {j}: {k} against {}", ei / h);
            }
        }
    }

    /// Halving: a fine spring at a coarse node gets `2 K_c`, one between coarse nodes twice
    /// their harmonic mean (a soft and a stiff spring in series), not their mean.
    #[test]
    fn halving_puts_springs_in_series() {
        let coarse_spans = [0.5, 0.5];
        let coarse_k = [100.0, 1e4, 300.0];
        let fine_k = prolong_compliance(&coarse_spans, &coarse_k, &[0.25; 4]);
        let series = |a: f64, b: f64| 2.0 / (1.0 / a + 1.0 / b);
        let expected = [200.0, 2.0 * series(100.0, 1e4), 2e4, 2.0 * series(1e4, 300.0), 600.0];
        for (j, (k, e)) in fine_k.iter().zip(expected).enumerate() {
            assert!(close(*k, e), "node {j}: {k} against {e}");
        }
        // 2 × 198 N·m/rad where the mean of k would have given 2 × 5050.
        assert!(fine_k[1] < 400.0);
    }

    /// A coarse node without a spring (K = 0) leaves every fine node it covers without one;
    /// the others are untouched by it.
    #[test]
    fn no_spring_stays_no_spring() {
        let fine_k = prolong_compliance(&[0.5, 0.5], &[0.0, 50.0, 50.0], &[0.25; 4]);
        assert_eq!(fine_k[0], 0.0);
        assert_eq!(fine_k[1], 0.0);
        assert!(close(fine_k[2], 100.0) && close(fine_k[4], 100.0));
    }
}
