//! The chain coarsened and a coarse optimum prolonged (see the module docs of [`super`]).

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
pub(super) fn interpolate(at: &[f64], values: &[f64], to: &[f64]) -> Vec<f64> {
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
