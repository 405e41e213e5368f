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
use std::ops::{Add, AddAssign, Div, Mul, Sub, SubAssign};

/// The arithmetic the recursion needs: real and dual numbers for the accelerations and their
/// derivatives, complex numbers for the shifted Newton matrices of the implicit integrator
/// ([`crate::newton`]).
pub trait ChainNumber:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + AddAssign
    + SubAssign
    + From<f64>
{
}
impl<T> ChainNumber for T where
    T: Copy + Add<Output = T> + Sub<Output = T> + Mul<Output = T> + Div<Output = T> + AddAssign + SubAssign + From<f64>
{
}

/// A planar spatial vector or the columns of a planar spatial inertia: `(angular, x, y)`.
type V3<D> = [D; 3];
type M3<D> = [[D; 3]; 3];

/// The articulated-body factorisation of `M(θ)` for one configuration `θ`: one record per link.
/// The default is the factorisation of no links, storage for [`ArticulatedChain::refactor_from_trig`].
pub struct ArticulatedChain<D> {
    links: Vec<Link<D>>,
}

impl<D> Default for ArticulatedChain<D> {
    fn default() -> Self {
        Self { links: Vec::new() }
    }
}

/// One link's part of [`ArticulatedChain`].
#[derive(Clone, Copy)]
struct Link<D> {
    /// `U_k = I^A_k S` (the first column of the articulated inertia; `S = (1, 0, 0)`: a revolute
    /// joint at the reference point).
    u: V3<D>,
    /// `D_k = Sᵀ I^A_k S`, kg·m² (> 0 for links with mass).
    d: D,
    /// `r_k^⊥ = L_k (−sin θ_k, cos θ_k)`, m: moves motion from joint `k` to joint `k + 1`
    /// (`a_{k+1} = a_k + α r_k^⊥` at rest).
    shift: [D; 2],
}

/// `Xᵀ A X` for the shift `X = [[1, 0, 0], [p_x, 1, 0], [p_y, 0, 1]]` (motion at the outboard joint
/// from motion at the inboard one): an inertia at the outboard joint seen from the inboard joint.
fn shift_inertia<D: ChainNumber>(a: &M3<D>, p: &[D; 2]) -> M3<D> {
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
fn shift_force<D: ChainNumber>(f: &V3<D>, p: &[D; 2]) -> V3<D> {
    [f[0] + f[1] * p[0] + f[2] * p[1], f[1], f[2]]
}

/// `X a`: motion at the inboard joint seen at the outboard joint.
fn shift_motion<D: ChainNumber>(a: &V3<D>, p: &[D; 2]) -> V3<D> {
    [a[0], a[1] + a[0] * p[0], a[2] + a[0] * p[1]]
}

impl<D: Scalar> ArticulatedChain<D> {
    /// Factorises `M(θ)` for links of lengths `lengths` (m) and masses `masses` (kg, uniform rods).
    /// `None` when a pivot `D_k` is not positive (a massless tip, or a non-finite `θ`).
    pub fn new(lengths: &[f64], masses: &[f64], theta: &[D]) -> Option<Self> {
        let trig: Vec<(D, D)> = theta.iter().map(|t| t.sin_cos()).collect();
        Self::from_trig(lengths, masses, &trig)
    }

    /// [`Self::new`] from `(sin θ_k, cos θ_k)`.
    pub fn from_trig(lengths: &[f64], masses: &[f64], trig: &[(D, D)]) -> Option<Self> {
        let mut chain = Self::default();
        chain.refactor_from_trig(lengths, masses, trig).then_some(chain)
    }

    /// [`Self::from_trig`] into this factorisation's storage (no allocation once it has held as
    /// many links); `false`, leaving it unusable, where `from_trig` gives `None`.
    pub fn refactor_from_trig(&mut self, lengths: &[f64], masses: &[f64], trig: &[(D, D)]) -> bool {
        let shifts = trig.iter().zip(lengths).map(|(&(s, c), &l)| [-s * l, c * l]);
        let positive = |d: &D| d.re().partial_cmp(&0.0) == Some(std::cmp::Ordering::Greater);
        Self::factor_into(&mut self.links, lengths, masses, shifts, None, &positive)
    }
}

impl<T: ChainNumber> ArticulatedChain<T> {
    /// Factorises `M(θ) + T⁻ᵀ diag(joint) T⁻¹ + diag(body)` at a real configuration `θ` (given as
    /// `(sin θ_k, cos θ_k)`): the mass
    /// matrix plus a term on each joint's relative angle `α_k = θ_k − θ_{k−1}` (`joint_k`, added to
    /// the joint's pivot `D_k`) and a term on each link's absolute angle (`body_k`, added to the
    /// link's rotational inertia). With `joint = (σ C_k + K_k)/σ²` this is the Newton matrix of the
    /// springs and dampers ([`crate::newton`]). `None` when a pivot fails `pivot_ok`.
    pub fn with_additions(
        lengths: &[f64],
        masses: &[f64],
        trig: &[(f64, f64)],
        joint: &[T],
        body: &[T],
        pivot_ok: &dyn Fn(&T) -> bool,
    ) -> Option<Self> {
        let shifts = trig.iter().zip(lengths).map(|(&(s, c), &l)| [T::from(-s * l), T::from(c * l)]);
        let mut links = Vec::new();
        Self::factor_into(&mut links, lengths, masses, shifts, Some((joint, body)), pivot_ok).then_some(Self { links })
    }

    /// The tip-to-base sweep from the links' shifts `r_k^⊥`, into `links` (overwritten); `false`
    /// when a pivot fails `pivot_ok`.
    fn factor_into(
        links: &mut Vec<Link<T>>,
        lengths: &[f64],
        masses: &[f64],
        shifts: impl Iterator<Item = [T; 2]>,
        additions: Option<(&[T], &[T])>,
        pivot_ok: &dyn Fn(&T) -> bool,
    ) -> bool {
        let zero = T::from(0.0);
        links.clear();
        links.extend(shifts.map(|shift| Link { u: [zero; 3], d: zero, shift }));
        let n = links.len();
        // The reduced articulated inertia the outboard link hands inboard, at its own joint.
        let mut outboard: Option<M3<T>> = None;
        for k in (0..n).rev() {
            let (l, m) = (lengths[k], masses[k]);
            let p = links[k].shift;
            // Rigid inertia at the inboard joint: centre of mass at c = (L/2) e_k, c^⊥ = (L/2) e_k^⊥,
            // I_c = m L² / 12: [[I_c + m|c|², m c^⊥ᵀ], [m c^⊥, m 1]].
            let half = [p[0] * T::from(0.5 * m), p[1] * T::from(0.5 * m)];
            let mut inertia: M3<T> = [
                [T::from(m * l * l / 3.0), half[0], half[1]],
                [half[0], T::from(m), zero],
                [half[1], zero, T::from(m)],
            ];
            if let Some((_, body)) = additions {
                inertia[0][0] += body[k];
            }
            if let Some(a) = &outboard {
                let seen = shift_inertia(a, &p);
                for (row, add) in inertia.iter_mut().zip(seen) {
                    for (x, y) in row.iter_mut().zip(add) {
                        *x += y;
                    }
                }
            }
            let uk = [inertia[0][0], inertia[1][0], inertia[2][0]];
            let dk = match additions {
                Some((joint, _)) => uk[0] + joint[k],
                None => uk[0],
            };
            if !pivot_ok(&dk) {
                return false;
            }
            // I^a = I^A − U Uᵀ / D: what the free joint passes on.
            let mut reduced = inertia;
            for (i, row) in reduced.iter_mut().enumerate() {
                for (j, x) in row.iter_mut().enumerate() {
                    *x -= uk[i] * uk[j] / dk;
                }
            }
            (links[k].u, links[k].d) = (uk, dk);
            outboard = Some(reduced);
        }
        true
    }

    /// `x = M(θ)⁻¹ b` (`b` in N·m per absolute angle, `x` in rad/s²).
    pub fn solve(&self, b: &[T]) -> Vec<T> {
        let mut x = b.to_vec();
        self.solve_in_place([&mut x]);
        x
    }

    /// `x_c = M(θ)⁻¹ x_c` for each of the `C` columns, in place. The columns go through the
    /// sweeps side by side: each link's factors are read once, and the columns' chains of
    /// dependent divisions overlap. Each column's arithmetic is that of a solve on its own.
    pub fn solve_in_place<const C: usize>(&self, mut columns: [&mut [T]; C]) {
        let n = self.links.len();
        let zero = T::from(0.0);
        // Each column is overwritten in turn by the joint moments τ, then the free parts u_k,
        // then x (each entry is read once before it is overwritten).
        // Joint moments τ = Tᵀ b: the moment at joint k carries every link from k outward.
        for x in columns.iter_mut() {
            let mut sum = zero;
            for k in (0..n).rev() {
                sum += x[k];
                x[k] = sum;
            }
        }
        // Tip to base: the bias force p^A at each joint and u_k = τ_k − Sᵀ p^A_k.
        let mut bias: [V3<T>; C] = [[zero; 3]; C];
        for k in (0..n).rev() {
            let Link { u, d, .. } = self.links[k];
            for (x, bias) in columns.iter_mut().zip(bias.iter_mut()) {
                let uk = x[k] - bias[0];
                x[k] = uk;
                let scale = uk / d;
                let passed = [bias[0] + u[0] * scale, bias[1] + u[1] * scale, bias[2] + u[2] * scale];
                if k > 0 {
                    *bias = shift_force(&passed, &self.links[k - 1].shift);
                }
            }
        }
        // Base to tip: the base joint is fixed (zero acceleration of its point).
        let mut motion: [V3<T>; C] = [[zero; 3]; C];
        for k in 0..n {
            let Link { u, d, .. } = self.links[k];
            for (x, motion) in columns.iter_mut().zip(motion.iter_mut()) {
                let seen = if k > 0 { shift_motion(motion, &self.links[k - 1].shift) } else { [zero; 3] };
                let dot = u[0] * seen[0] + u[1] * seen[1] + u[2] * seen[2];
                let joint = (x[k] - dot) / d;
                *motion = [seen[0] + joint, seen[1], seen[2]];
                x[k] = motion[0];
            }
        }
    }
}

impl ArticulatedChain<f64> {
    /// `X = M(θ)⁻¹ B` for all columns of `B` at once (overwritten with `X`): the sweeps of
    /// [`Self::solve`] with each link's factors read once for every column.
    pub fn solve_columns(&self, b: &mut nalgebra::DMatrix<f64>) {
        let (n, m) = b.shape();
        // τ = Tᵀ b per column (suffix sums), in place.
        for mut column in b.column_iter_mut() {
            let mut sum = 0.0;
            for k in (0..n).rev() {
                sum += column[k];
                column[k] = sum;
            }
        }
        let mut bias = vec![[0.0f64; 3]; m];
        for k in (0..n).rev() {
            let Link { u, d, .. } = self.links[k];
            for (c, bias) in bias.iter_mut().enumerate() {
                let uk = b[(k, c)] - bias[0];
                b[(k, c)] = uk;
                let scale = uk / d;
                let passed = [bias[0] + u[0] * scale, bias[1] + u[1] * scale, bias[2] + u[2] * scale];
                if k > 0 {
                    *bias = shift_force(&passed, &self.links[k - 1].shift);
                }
            }
        }
        let mut motion = vec![[0.0f64; 3]; m];
        for k in 0..n {
            let Link { u, d, .. } = self.links[k];
            for (c, motion) in motion.iter_mut().enumerate() {
                let seen = if k > 0 { shift_motion(motion, &self.links[k - 1].shift) } else { [0.0; 3] };
                let dot = u[0] * seen[0] + u[1] * seen[1] + u[2] * seen[2];
                let joint = (b[(k, c)] - dot) / d;
                *motion = [seen[0] + joint, seen[1], seen[2]];
                b[(k, c)] = motion[0];
            }
        }
    }
}
