//! The critical axial load of the straight chain, where its stability certificate's smallest
//! eigenvalue crosses zero, against Euler's.

use crate::rod::Rod;
use spine_model::jacobian::residual_and_state_jacobian;
use spine_model::{LinkLoads, State};
use spine_solve::stability::certify;

/// The straight chain of `n` links for `rod` under the compressive end force `p` (N, > 0 pushes):
/// the smallest eigenvalue of its certificate (the Hessian of `U + V − λΦ` on the tangent space of
/// `Φ = 0`), N·m/rad. The straight state is an equilibrium at every `p` (no transverse load).
pub fn straight_min_eigenvalue(rod: &Rod, n: usize, p: f64) -> f64 {
    let (structure, design) = rod.chain(n);
    let loads = LinkLoads { vertical: vec![0.0; n], axial: vec![-p; n] };
    let state = State { theta: vec![0.0; n], lambda: 0.0 };
    let (_, jac) = residual_and_state_jacobian(&structure.chain.spans, &design, &loads, &state);
    certify(&jac).min_eigenvalue.unwrap_or(f64::NAN)
}

/// The chain's critical load: the root of [`straight_min_eigenvalue`] in `p`, N, by the secant
/// method from `0` and Euler's load (the eigenvalue is affine in `p` on the straight state, so the
/// first secant step lands on it; the loop stops when a step changes `p` by under `1e-14 p`).
pub fn chain_critical_load(rod: &Rod, n: usize) -> f64 {
    let f = |p: f64| straight_min_eigenvalue(rod, n, p);
    let (mut p0, mut p1) = (0.0, rod.euler_critical_load());
    let (mut f0, mut f1) = (f(p0), f(p1));
    for _ in 0..50 {
        if f1 == f0 {
            break;
        }
        let p2 = p1 - f1 * (p1 - p0) / (f1 - f0);
        let done = (p2 - p1).abs() <= 1e-14 * p2.abs();
        (p0, f0, p1) = (p1, f1, p2);
        f1 = f(p1);
        if done {
            break;
        }
    }
    p1
}
