//! The stability certificate of an equilibrium.
//!
//! A stationary point of `U + V − λΦ` is a stable equilibrium when the Hessian `H` (the tridiagonal
//! block of the equilibrium Jacobian) is positive definite on the tangent space `{x : ∇Φᵀx = 0}`.
//! With `Z` an orthonormal basis of that space, the certificate is the smallest eigenvalue of
//! `ZᵀHZ`, in N·m/rad.
//!
//! It is found without forming `Z`: for a shift `μ`, the number of eigenvalues of `ZᵀHZ` below `μ`
//! is `neg(H − μI) + [bᵀ(H − μI)⁻¹b > 0] − 1` (inertia of the bordered matrix, Haynsworth), and both
//! terms come from one `LDLᵀ` sweep of the tridiagonal `H − μI` (a Sturm count). Bisection on `μ`
//! between Gershgorin bounds then brackets the smallest eigenvalue: `O(N)` per probe.

use serde::Serialize;
use spine_model::sparse::BorderedTridiagonal;

/// Stability of an equilibrium.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Stability {
    /// Smallest eigenvalue of the Hessian of `U + V − λΦ` on the tangent space of `Φ = 0`,
    /// N·m/rad. `None` when the tangent space is empty (one link: the chain cannot move).
    pub min_eigenvalue: Option<f64>,
    /// Number of negative eigenvalues (directions in which the energy decreases).
    pub negative_directions: usize,
    /// `true` when `min_eigenvalue` is positive beyond rounding (`> 1e-9 ‖H‖`).
    pub stable: bool,
}

/// Symmetric view of the tridiagonal block `H` and the constraint gradient `b`.
struct Pencil<'a> {
    diag: &'a [f64],
    off: Vec<f64>,
    grad: &'a [f64],
    pivot_floor: f64,
}

impl<'a> Pencil<'a> {
    fn new(jac: &'a BorderedTridiagonal) -> Self {
        let off: Vec<f64> = jac.lower.iter().zip(&jac.upper).map(|(l, u)| 0.5 * (l + u)).collect();
        let (lo, hi) = gershgorin(&jac.diag, &off);
        let norm = lo.abs().max(hi.abs());
        Self { diag: &jac.diag, off, grad: &jac.row, pivot_floor: f64::EPSILON * norm.max(f64::MIN_POSITIVE) }
    }

    /// Number of eigenvalues of `ZᵀHZ` strictly below `mu`.
    fn count_below(&self, mu: f64) -> usize {
        let n = self.diag.len();
        let (mut negatives, mut quad) = (0usize, 0.0f64);
        let (mut d_prev, mut y_prev) = (1.0, 0.0);
        for i in 0..n {
            let (mut d, mut y) = (self.diag[i] - mu, self.grad[i]);
            if i > 0 {
                let l = self.off[i - 1] / d_prev;
                d -= l * self.off[i - 1];
                y -= l * y_prev;
            }
            if d.abs() < self.pivot_floor {
                d = -self.pivot_floor;
            }
            if d < 0.0 {
                negatives += 1;
            }
            quad += y * y / d;
            d_prev = d;
            y_prev = y;
        }
        (negatives + usize::from(quad > 0.0)).saturating_sub(1)
    }
}

/// Gershgorin bounds `(lo, hi)` of a symmetric tridiagonal matrix.
fn gershgorin(diag: &[f64], off: &[f64]) -> (f64, f64) {
    let n = diag.len();
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for i in 0..n {
        let r = if i > 0 { off[i - 1].abs() } else { 0.0 } + if i + 1 < n { off[i].abs() } else { 0.0 };
        lo = lo.min(diag[i] - r);
        hi = hi.max(diag[i] + r);
    }
    (lo, hi)
}

/// Number of negative eigenvalues of the projected Hessian (one `O(N)` sweep).
pub fn negative_directions(jac: &BorderedTridiagonal) -> usize {
    Pencil::new(jac).count_below(0.0)
}

/// The stability certificate of the equilibrium whose Jacobian is `jac`.
pub fn certify(jac: &BorderedTridiagonal) -> Stability {
    let n = jac.block_size();
    let pencil = Pencil::new(jac);
    let negative_directions = pencil.count_below(0.0);
    if n < 2 {
        return Stability { min_eigenvalue: None, negative_directions: 0, stable: true };
    }
    let (mut lo, mut hi) = gershgorin(pencil.diag, &pencil.off);
    let norm = lo.abs().max(hi.abs()).max(f64::MIN_POSITIVE);
    // Invariant: count_below(lo) == 0 and count_below(hi) ≥ 1.
    lo -= 1e-12 * norm;
    hi += 1e-12 * norm;
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if hi - lo <= 4.0 * f64::EPSILON * norm || mid <= lo || mid >= hi {
            break;
        }
        if pencil.count_below(mid) >= 1 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let min_eigenvalue = 0.5 * (lo + hi);
    Stability { min_eigenvalue: Some(min_eigenvalue), negative_directions, stable: min_eigenvalue > 1e-9 * norm }
}
