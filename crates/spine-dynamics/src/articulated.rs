//! `M(θ) x = b` in `O(N)`: the articulated-body recursion of the chain (Featherstone's ABA with the
//! velocities set to zero), generic over the number type so that Jacobians and sensitivities of the
//! accelerations still come from forward-mode AD.
//!
//! The chain's mass matrix in absolute angles ([`crate::Dynamics::mass_matrix`],
//! `M_ij = L_i L_j cos(θ_i − θ_j) (½ m_j + Σ_{k>j} m_k)`) is that of uniform rods pinned end to end.
//! With the relative angles `α_k = θ_k − θ_{k−1}` (`θ = T α`, `T` the prefix sum), the system
//! `M θ̈ = b` is `(Tᵀ M T) α̈ = Tᵀ b`: the joint-space equations of a serial chain of revolute
//! joints, which the articulated-body algorithm solves in two sweeps:
//!
//! * from the tip to the base, each link's articulated inertia `I^A_k` (3 × 3, planar: moment and
//!   force at the link's inboard joint) is its own rigid inertia plus its outboard neighbour's,
//!   reduced by that neighbour's free joint and moved to this joint;
//! * the joint moments `Tᵀ b` (suffix sums of `b`) are carried the same way, and from the base to
//!   the tip each joint's acceleration follows from its inboard neighbour's.
//!
//! The absolute angular accelerations `θ̈_k` are the links' own angular accelerations, read off
//! the second sweep. The factorisation ([`ArticulatedChain::new`]) is shared by every right-hand
//! side ([`ArticulatedChain::solve`]). The dense Cholesky path ([`crate::Dynamics::acceleration_dense`])
//! stays as the test oracle.

use spine_model::Scalar;

/// A planar spatial vector or the columns of a planar spatial inertia: `(angular, x, y)`.
type V3<D> = [D; 3];
type M3<D> = [[D; 3]; 3];

/// The articulated-body factorisation of `M(θ)` for one configuration `θ`.
pub struct ArticulatedChain<D> {
    /// `U_k = I^A_k S` (the first column of the articulated inertia; `S = (1, 0, 0)`: a revolute
    /// joint at the reference point).
    u: Vec<V3<D>>,
    /// `D_k = Sᵀ I^A_k S`, kg·m² (> 0 for links with mass).
    d: Vec<D>,
    /// `r_k^⊥ = L_k (−sin θ_k, cos θ_k)`, m: moves motion from joint `k` to joint `k + 1`
    /// (`a_{k+1} = a_k + α r_k^⊥` at rest).
    shift: Vec<[D; 2]>,
}

/// `Xᵀ A X` for the shift `X = [[1, 0, 0], [p_x, 1, 0], [p_y, 0, 1]]` (motion at the outboard joint
/// from motion at the inboard one): an inertia at the outboard joint seen from the inboard joint.
fn shift_inertia<D: Scalar>(a: &M3<D>, p: &[D; 2]) -> M3<D> {
    // A X: column 0 gains p_x · column 1 + p_y · column 2.
    let mut ax = *a;
    for row in ax.iter_mut() {
        row[0] = row[0] + row[1] * p[0] + row[2] * p[1];
    }
    // Xᵀ (A X): row 0 gains p_x · row 1 + p_y · row 2.
    let mut out = ax;
    for c in 0..3 {
        out[0][c] = ax[0][c] + ax[1][c] * p[0] + ax[2][c] * p[1];
    }
    out
}

/// `Xᵀ f`: a force at the outboard joint seen at the inboard joint.
fn shift_force<D: Scalar>(f: &V3<D>, p: &[D; 2]) -> V3<D> {
    [f[0] + f[1] * p[0] + f[2] * p[1], f[1], f[2]]
}

/// `X a`: motion at the inboard joint seen at the outboard joint.
fn shift_motion<D: Scalar>(a: &V3<D>, p: &[D; 2]) -> V3<D> {
    [a[0], a[1] + a[0] * p[0], a[2] + a[0] * p[1]]
}

impl<D: Scalar> ArticulatedChain<D> {
    /// Factorises `M(θ)` for links of lengths `lengths` (m) and masses `masses` (kg, uniform rods).
    /// `None` when a pivot `D_k` is not positive (a massless tip, or a non-finite `θ`).
    pub fn new(lengths: &[f64], masses: &[f64], theta: &[D]) -> Option<Self> {
        let n = theta.len();
        let zero = D::zero();
        let mut u = vec![[zero; 3]; n];
        let mut d = vec![zero; n];
        let mut shift = vec![[zero; 2]; n];
        // The reduced articulated inertia the outboard link hands inboard, at its own joint.
        let mut outboard: Option<M3<D>> = None;
        for k in (0..n).rev() {
            let (s, c) = theta[k].sin_cos();
            let (l, m) = (lengths[k], masses[k]);
            let p = [-s * l, c * l];
            shift[k] = p;
            // Rigid inertia at the inboard joint: centre of mass at c = (L/2) e_k, c^⊥ = (L/2) e_k^⊥,
            // I_c = m L² / 12: [[I_c + m|c|², m c^⊥ᵀ], [m c^⊥, m 1]].
            let half = [p[0] * (0.5 * m), p[1] * (0.5 * m)];
            let mut inertia: M3<D> = [
                [D::from(m * l * l / 3.0), half[0], half[1]],
                [half[0], D::from(m), zero],
                [half[1], zero, D::from(m)],
            ];
            if let Some(a) = &outboard {
                let seen = shift_inertia(a, &p);
                for (row, add) in inertia.iter_mut().zip(seen) {
                    for (x, y) in row.iter_mut().zip(add) {
                        *x += y;
                    }
                }
            }
            let dk = inertia[0][0];
            if dk.re().partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                return None;
            }
            let uk = [inertia[0][0], inertia[1][0], inertia[2][0]];
            // I^a = I^A − U Uᵀ / D: what the free joint passes on.
            let mut reduced = inertia;
            for (i, row) in reduced.iter_mut().enumerate() {
                for (j, x) in row.iter_mut().enumerate() {
                    *x -= uk[i] * uk[j] / dk;
                }
            }
            u[k] = uk;
            d[k] = dk;
            outboard = Some(reduced);
        }
        Some(Self { u, d, shift })
    }

    /// `x = M(θ)⁻¹ b` (`b` in N·m per absolute angle, `x` in rad/s²).
    pub fn solve(&self, b: &[D]) -> Vec<D> {
        let n = b.len();
        let zero = D::zero();
        // Joint moments τ = Tᵀ b: the moment at joint k carries every link from k outward.
        let mut tau = vec![zero; n];
        let mut sum = zero;
        for k in (0..n).rev() {
            sum += b[k];
            tau[k] = sum;
        }
        // Tip to base: the bias force p^A at each joint and u_k = τ_k − Sᵀ p^A_k.
        let mut free = vec![zero; n];
        let mut bias: V3<D> = [zero; 3];
        for k in (0..n).rev() {
            let uk = tau[k] - bias[0];
            free[k] = uk;
            let scale = uk / self.d[k];
            let passed =
                [bias[0] + self.u[k][0] * scale, bias[1] + self.u[k][1] * scale, bias[2] + self.u[k][2] * scale];
            if k > 0 {
                bias = shift_force(&passed, &self.shift[k - 1]);
            }
        }
        // Base to tip: the base joint is fixed (zero acceleration of its point).
        let mut x = vec![zero; n];
        let mut motion: V3<D> = [zero; 3];
        for k in 0..n {
            let seen = if k > 0 { shift_motion(&motion, &self.shift[k - 1]) } else { [zero; 3] };
            let dot = self.u[k][0] * seen[0] + self.u[k][1] * seen[1] + self.u[k][2] * seen[2];
            let joint = (free[k] - dot) / self.d[k];
            motion = [seen[0] + joint, seen[1], seen[2]];
            x[k] = motion[0];
        }
        x
    }
}
