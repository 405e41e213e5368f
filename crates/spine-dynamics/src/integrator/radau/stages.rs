//! The Radau IIA stages: the method's constants, the two Newton matrices of a step size, the
//! simplified Newton iteration on the collocation system, the collocation polynomial and the
//! step-size prediction.

use super::super::options::{Options, Stats};
use crate::linearization::{Complex64, Linearization, ShiftedSolve};

/// `√6`.
pub(super) const S6: f64 = 2.449_489_742_783_178;
/// Collocation points.
pub(super) const C: [f64; 3] = [(4.0 - S6) / 10.0, (4.0 + S6) / 10.0, 1.0];
/// Error-estimate weights `e_i` (multiplying `Z_i / h`).
pub(super) const E: [f64; 3] = [(-13.0 - 7.0 * S6) / 3.0, (-13.0 + 7.0 * S6) / 3.0, -1.0 / 3.0];
/// The Radau IIA Butcher matrix `A` (order 5, stiffly accurate: its last row is `b`).
pub(super) const A: [[f64; 3]; 3] = [
    [(88.0 - 7.0 * S6) / 360.0, (296.0 - 169.0 * S6) / 1800.0, (-2.0 + 3.0 * S6) / 225.0],
    [(296.0 + 169.0 * S6) / 1800.0, (88.0 + 7.0 * S6) / 360.0, (-2.0 - 3.0 * S6) / 225.0],
    [(16.0 - S6) / 36.0, (16.0 + S6) / 36.0, 1.0 / 9.0],
];
/// The real eigenvalue `μ = 3 + 3^{2/3} − 3^{1/3}` of `A⁻¹`.
pub(super) const MU_REAL: f64 = 3.637_834_252_744_496;
/// The complex pair `α ± iβ` of `A⁻¹`: `α = 3 + (3^{1/3} − 3^{2/3})/2`, `β = (3^{5/6} + 3^{7/6})/2`.
pub(super) const MU_ALPHA: f64 = 2.681_082_873_627_752_3;
pub(super) const MU_BETA: f64 = 3.050_430_199_247_411;
/// `T` and `T⁻¹` with `T⁻¹ A⁻¹ T = [[μ, 0, 0], [0, α, β], [0, −β, α]]` (the test checks them against
/// the Butcher matrix).
#[allow(clippy::excessive_precision)]
pub(super) const T: [[f64; 3]; 3] = [
    [0.094_438_762_488_975_24, -0.141_255_295_020_954_21, 0.030_029_194_105_147_42],
    [0.250_213_122_965_333_32, 0.204_129_352_293_799_94, -0.382_942_112_757_261_92],
    [1.0, 1.0, 0.0],
];
#[allow(clippy::excessive_precision)]
pub(super) const TI: [[f64; 3]; 3] = [
    [4.178_718_591_551_904_28, 0.327_682_820_761_062_37, 0.523_376_445_499_449_51],
    [-4.178_718_591_551_904_28, -0.327_682_820_761_062_37, 0.476_623_554_500_550_44],
    [0.502_872_634_945_786_82, -2.571_926_949_855_605_22, 0.596_039_204_828_224_92],
];
/// Which collocation system [`collocation`] solves: a step's stages, `Z = h (A ⊗ I) F(Z)`, or
/// the adjoint of an accepted step, `V = h (Aᵀ ⊗ I) G(V)`. With `A⁻ᵀ = T⁻ᵀ Λᵀ Tᵀ` the adjoint
/// iterates on `Tᵀ V`, its complex pair has the shift `(α + iβ)/h` and its Newton matrices are the
/// transposes `(σ I − J̃)ᵀ` of the step's (for the real `J̃`, `((α + iβ)/h I − J̃ᵀ)⁻¹ r =
/// conj(((α − iβ)/h I − J̃)⁻ᵀ conj(r))`).
///
/// The stages' iteration runs with the Newton matrices of its own step size; the adjoint's carries
/// its step size `h` and may precondition with the matrices of a nearby one (the fixed point is
/// the same, the contraction a little slower), so that a backward sweep refactors only when the
/// step size moves by more than [`super::adjoint`]'s margin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Orientation {
    Stages,
    Adjoint(f64),
}

impl Orientation {
    /// The transform into the iteration's variables and back.
    fn transforms(self) -> ([[f64; 3]; 3], [[f64; 3]; 3]) {
        let transpose = |m: [[f64; 3]; 3]| std::array::from_fn(|r| std::array::from_fn(|c| m[c][r]));
        match self {
            Self::Stages => (TI, T),
            Self::Adjoint(_) => (transpose(T), transpose(TI)),
        }
    }
}

/// The collocation polynomial `y(t₀ + x h) = y₀ + Σ_k (Σ_i Z_i P_ik) x^{k+1}`: the guess of the next
/// step's stages.
pub(super) const P: [[f64; 3]; 3] = [
    [10.048_809_399_827_414, -25.629_591_447_076_64, 15.580_782_047_249_224],
    [-1.382_142_733_160_748, 10.296_258_113_743_303, -8.914_115_380_582_556],
    [1.0 / 3.0, -8.0 / 3.0, 10.0 / 3.0],
];
/// A stalled iteration with corrections below this weighted norm has converged to round-off.
pub(super) const STALL_FLOOR: f64 = 3e-3;
/// Most simplified Newton iterations on the stages.
pub(super) const NEWTON_MAXITER: usize = 6;

/// The two Newton matrices for one step size.
pub(super) struct Factors {
    pub(super) h: f64,
    pub(super) real: Box<dyn ShiftedSolve<f64>>,
    pub(super) complex: Box<dyn ShiftedSolve<Complex64>>,
}

pub(super) fn factor(lin: &dyn Linearization, h: f64, stats: &mut Stats) -> Option<Factors> {
    stats.factorizations += 2;
    Some(Factors {
        h,
        real: lin.factor_real(MU_REAL / h)?,
        complex: lin.factor_complex(Complex64::new(MU_ALPHA, -MU_BETA) / h)?,
    })
}

pub(super) type Stages = [Vec<f64>; 3];

/// `stage(i, Z_i, F_i)`: writes the right-hand side `F_i` of stage `i` at the stage value `Z_i`.
pub(super) type StageFunction<'a> = dyn FnMut(usize, &[f64], &mut [f64]) + 'a;

/// The vectors of [`collocation`]'s iteration, each overwritten before it is read: `W = T⁻¹ Z`,
/// the stages' `F`, `T⁻¹ F`, the correction `ΔW` and the right-hand sides of the real and the
/// complex Newton solve.
#[derive(Default)]
pub(super) struct Workspace {
    w: Stages,
    f: Stages,
    tf: Stages,
    dw: Stages,
    real: Vec<f64>,
    complex: Vec<Complex64>,
}

impl Workspace {
    /// Every vector at length `n`.
    fn fit(&mut self, n: usize) {
        for v in self.w.iter_mut().chain(&mut self.f).chain(&mut self.tf).chain(&mut self.dw) {
            v.resize(n, 0.0);
        }
        self.real.resize(n, 0.0);
        self.complex.resize(n, Complex64::new(0.0, 0.0));
    }
}

/// Converged stages, with the iterations taken and the last contraction rate.
pub(super) struct Collocation {
    pub(super) z: Stages,
    pub(super) iterations: usize,
    pub(super) rate: Option<f64>,
}

impl Collocation {
    /// The contraction factor `Θ/(1 − Θ)` to carry into the next step's first-iteration test
    /// ([`collocation`]'s `carried`): this step's measured one, or, after a single iteration, the
    /// one it was accepted with.
    pub(super) fn contraction(&self, carried: f64) -> f64 {
        match self.rate {
            Some(r) if r < 1.0 => r / (1.0 - r),
            _ => carried,
        }
    }
}

/// The contraction factor a step starts from: the last one carried, raised to the power 0.8
/// (RADAU5's `FACCON = max(FACCON, UROUND)^0.8`, which lets it drift towards 1 while steps converge in one
/// iteration and so no new rate is measured).
pub(super) fn carried_contraction(last: f64) -> f64 {
    last.max(f64::EPSILON).powf(0.8)
}

/// Simplified Newton in `W = T⁻¹ Z` on `Z_i = h Σ_j a_ij F_j(Z_j)`, `stage(i, Z_i, F_i)` writing
/// `F_i`. `norm`
/// is the RMS norm of a correction over all stages; converged when the predicted remaining error
/// `rate/(1 − rate) ‖ΔW‖` is below `tol`, or, after the first iteration where no rate is measured
/// yet, when `carried ‖ΔW‖` is (Hairer & Wanner's RADAU5: `carried` is the contraction factor of
/// the previous step, [`carried_contraction`]). `None` when it diverges, stalls or `F` is not
/// finite. `work` holds the iteration's vectors (kept from one call to the next, so that a step
/// allocates nothing for them).
#[allow(clippy::too_many_arguments)]
pub(super) fn collocation(
    orientation: Orientation,
    stage: &mut StageFunction<'_>,
    z0: Stages,
    factors: &Factors,
    norm: &dyn Fn(&Stages) -> f64,
    tol: f64,
    carried: f64,
    max_iterations: usize,
    work: &mut Workspace,
) -> Option<Collocation> {
    let n = z0[0].len();
    let (h, adjoint) = match orientation {
        Orientation::Stages => (factors.h, false),
        Orientation::Adjoint(h) => (h, true),
    };
    work.fit(n);
    let Workspace { w, f, tf, dw, real, complex } = work;
    // `out = m x` stage by stage, into storage kept across the iterations.
    let transform = |m: &[[f64; 3]; 3], x: &Stages, out: &mut Stages| {
        for (r, row) in out.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = m[r][0] * x[0][j] + m[r][1] * x[1][j] + m[r][2] * x[2][j];
            }
        }
    };
    let (into, back) = orientation.transforms();
    transform(&into, &z0, w);
    let mut z = z0;
    let mut previous: Option<f64> = None;
    let mut rate;
    let beta = if adjoint { MU_BETA } else { -MU_BETA };
    // The adjoint's linear iteration, on a norm relative to the size of its solution, may only
    // stall at round-off.
    let floor = if adjoint { 1e3 * tol } else { STALL_FLOOR };
    let (mu, mu_c) = (MU_REAL / h, Complex64::new(MU_ALPHA, beta) / h);
    for k in 0..max_iterations {
        for (i, (fi, zi)) in f.iter_mut().zip(&z).enumerate() {
            stage(i, zi, fi);
        }
        if f.iter().flatten().any(|v| !v.is_finite()) {
            return None;
        }
        transform(&into, f, tf);
        for (j, x) in real.iter_mut().enumerate() {
            *x = tf[0][j] - mu * w[0][j];
        }
        for (j, x) in complex.iter_mut().enumerate() {
            *x = Complex64::new(tf[1][j], tf[2][j]) - mu_c * Complex64::new(w[1][j], w[2][j]);
        }
        if adjoint {
            factors.real.solve_transpose(real);
            complex.iter_mut().for_each(|c| *c = c.conj());
            factors.complex.solve_transpose(complex);
            complex.iter_mut().for_each(|c| *c = c.conj());
        } else {
            factors.real.solve(real);
            factors.complex.solve(complex);
        }
        dw[0].copy_from_slice(real);
        for (j, c) in complex.iter().enumerate() {
            (dw[1][j], dw[2][j]) = (c.re, c.im);
        }
        let dw_norm = norm(dw);
        if !dw_norm.is_finite() {
            return None;
        }
        rate = previous.map(|p| dw_norm / p);
        // From the second iteration on, corrections below `STALL_FLOOR` that no longer shrink fast
        // enough are round-off: the right-hand side of a stiff chain carries errors of order
        // ε ‖K‖/‖M‖ (about 1e-12 relative in the accelerations at N = 100), above Hairer's
        // `10 ε / rtol` floor at tight tolerances. They are a few thousandths of the local error
        // tolerance: done.
        let noise = k >= 1 && dw_norm <= floor;
        // Diverging, or not reaching `tol` in the iterations left.
        let slow = rate.is_some_and(|r| r >= 1.0 || r.powi((max_iterations - k) as i32) / (1.0 - r) * dw_norm > tol);
        if slow && !noise {
            return None;
        }
        for (wr, dr) in w.iter_mut().zip(dw.iter()) {
            wr.iter_mut().zip(dr).for_each(|(a, b)| *a += b);
        }
        transform(&back, w, &mut z);
        // Stalled at round-off, a correction a tenth of the tolerance, or a predicted remaining
        // error below it: done.
        let stalled = slow && noise;
        let predicted = match rate {
            Some(r) => r < 1.0 && r / (1.0 - r) * dw_norm < tol,
            None => carried * dw_norm <= tol,
        };
        if stalled || dw_norm <= 0.1 * tol || predicted {
            return Some(Collocation { z, iterations: k + 1, rate });
        }
        previous = Some(dw_norm);
    }
    None
}

/// The collocation polynomial of an accepted step, for the next step's guess.
pub(super) struct Polynomial {
    t0: f64,
    h: f64,
    y0: Vec<f64>,
    /// `Q_k = Σ_i Z_i P_ik`.
    pub(super) q: Stages,
}

impl Polynomial {
    pub(super) fn new(t0: f64, h: f64, y0: &[f64], z: &Stages) -> Self {
        let n = y0.len();
        let q = std::array::from_fn(|k| (0..n).map(|j| (0..3).map(|i| z[i][j] * P[i][k]).sum()).collect());
        Self { t0, h, y0: y0.to_vec(), q }
    }

    /// `y(t) − y`.
    pub(super) fn value_minus(&self, t: f64, y: &[f64]) -> Vec<f64> {
        let x = (t - self.t0) / self.h;
        (0..self.y0.len())
            .map(|j| (self.y0[j] + x * (self.q[0][j] + x * (self.q[1][j] + x * self.q[2][j]))) - y[j])
            .collect()
    }
}

/// Gustafsson's predictive factor `min(1, (h/h_old) (err_old/err)^{1/4}) err^{−1/4}`.
pub(super) fn predict_factor(h: f64, old: Option<(f64, f64)>, err: f64) -> f64 {
    let multiplier = match old {
        Some((h_old, err_old)) if err > 0.0 => h / h_old * (err_old / err).powf(0.25),
        _ => 1.0,
    };
    if err == 0.0 {
        return f64::INFINITY;
    }
    multiplier.min(1.0) * err.powf(-0.25)
}

/// The Newton tolerance on the weighted norm: `max(10 ε / rtol, min(0.03, √rtol))` (Hairer's
/// choice), never above `newton_tolerance`.
pub(super) fn newton_tol(opts: &Options) -> f64 {
    (10.0 * f64::EPSILON / opts.rtol).max(0.03f64.min(opts.rtol.sqrt())).min(opts.newton_tolerance)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Radau IIA Butcher matrix.
    fn butcher() -> nalgebra::Matrix3<f64> {
        nalgebra::Matrix3::from_fn(|r, c| A[r][c])
    }

    #[test]
    fn the_constants_diagonalise_the_butcher_matrix() {
        let m = |a: [[f64; 3]; 3]| nalgebra::Matrix3::from_fn(|r, c| a[r][c]);
        let (t, ti) = (m(T), m(TI));
        assert!((t * ti - nalgebra::Matrix3::identity()).abs().max() < 1e-14);
        let a_inv = butcher().try_inverse().unwrap();
        let lambda = ti * a_inv * t;
        let expected = nalgebra::Matrix3::new(MU_REAL, 0.0, 0.0, 0.0, MU_ALPHA, MU_BETA, 0.0, -MU_BETA, MU_ALPHA);
        assert!((lambda - expected).abs().max() < 1e-12, "{lambda}");
        // Row sums of A are the collocation points; the last row is b (stiffly accurate).
        let a = butcher();
        for i in 0..3 {
            assert!((a.row(i).sum() - C[i]).abs() < 1e-15);
        }
        // The interpolant through (0, 0) and (c_i, Z_i) reproduces the stages.
        let z: Stages = [vec![1.0], vec![-2.0], vec![0.5]];
        let p = Polynomial::new(0.0, 1.0, &[0.0], &z);
        for i in 0..3 {
            assert!((p.value_minus(C[i], &[0.25])[0] + 0.25 - z[i][0]).abs() < 1e-12);
        }
    }
}
