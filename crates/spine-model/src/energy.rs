//! Energies: strain energy of the springs (eq. (31)) and potential of the loads (eq. (3),
//! with the sign of gravity corrected: see `docs/errata.md`).

use crate::kinematics::{link_lengths, node_positions};
use crate::{Chain, NodalLoads, Scalar};

/// Strain energy, J: `U = ½ Σ_{i=0}^{N} K_i (Δθ_i − Δθ_{i−1})²` with `Δθ = θ − θ0` and
/// `Δθ_{−1} = Δθ_N = 0` (the base and the slider keep their orientation). Eqs. (21), (31).
pub fn strain_energy<D: Scalar>(theta: &[D], theta0: &[D], stiffness: &[D]) -> D {
    let n = theta.len();
    let delta = |i: isize| -> D {
        if i < 0 || i as usize >= n {
            D::zero()
        } else {
            theta[i as usize] - theta0[i as usize]
        }
    };
    (0..=n)
        .map(|i| {
            let rel = delta(i as isize) - delta(i as isize - 1);
            stiffness[i] * rel * rel * 0.5
        })
        .sum()
}

/// Potential of the loads, J:
/// `V = −Σ_j (P_X,j X_j + P_Y,j Y_j) + Σ_k m_k g (Y_k + ½ L_k sin θ_k)`.
/// Self-weight is included when `with_weight`. Node positions use the design's link lengths.
pub fn load_potential<D: Scalar>(chain: &Chain, loads: &NodalLoads, with_weight: bool, theta0: &[D], theta: &[D]) -> D {
    let lengths = link_lengths(&chain.spans, theta0);
    let nodes = node_positions(&lengths, theta);
    let mut v = D::zero();
    for (j, &(x, y)) in nodes.iter().enumerate() {
        v -= x * loads.p_x[j] + y * loads.p_y[j];
    }
    if with_weight {
        for k in 0..chain.n_links() {
            let centre_y = nodes[k].1 + lengths[k] * theta[k].sin() * 0.5;
            v += centre_y * (chain.masses[k] * chain.gravity);
        }
    }
    v
}
