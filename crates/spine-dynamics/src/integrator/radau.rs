//! Radau IIA of order 5 ([`super::Method::Radau5`]; Hairer & Wanner, *Solving ODEs II*, IV.8, the
//! method of RADAU5 and of scipy's `Radau`): the collocation stages, their simplified Newton
//! iterations, the error estimate, the forward sensitivities and the driver.
//!
//! **Stages.** `Z_i = h Σ_j a_ij f(t + c_j h, y + Z_j)` at the Radau points `c = ((4 − √6)/10,
//! (4 + √6)/10, 1)`; `y₁ = y + Z₃` (stiffly accurate, order 5 at the step's end, stage order 3).
//! With `A⁻¹ = T Λ T⁻¹` (one real eigenvalue `μ` and a complex pair `α ± iβ`), the simplified Newton
//! iteration in `W = T⁻¹ Z` needs one real matrix `μ/h I − J̃` and one complex `(α − iβ)/h I − J̃`,
//! each factored once per step size ([`super::linear`]); its rate is watched and the iteration given
//! up when the predicted error after the remaining iterations exceeds the tolerance.
//!
//! **Error.** `err = (μ/h I − J̃)⁻¹ (f(y) + Σ e_i Z_i / h)` (third-order embedded estimate, filtered so
//! that stiff components do not force tiny steps; refiltered through `f(y + err)` after a
//! rejection), on the weighted RMS norm; steps follow Gustafsson's predictive controller with
//! exponent 1/4, the safety factor shrinking with the Newton iterations.
//!
//! **Sensitivities.** `S = ∂y/∂p` by internal differentiation: the stage sensitivities solve the
//! linear collocation system `dZ_i = h Σ_j a_ij (J(Y_j) (S₀ + dZ_j) + ∂f/∂p(Y_j))` at the converged
//! stage points `Y_j` (exact `J v` products, [`OdeSystem::jacobian_times`]), by the same transformed
//! iteration to round-off; `S₁ = S₀ + dZ₃`, then the projection's derivative.

use super::dense::{Interval, Trajectory};
use super::options::{Options, Outcome, Stats};
use super::{sensitivity_rate, weighted_rms, Course, Extras};
use crate::linearization::{Complex64, Linearization, ShiftedSolve};
use crate::ode::OdeSystem;
use nalgebra::DMatrix;

/// `√6`.
const S6: f64 = 2.449_489_742_783_178;
/// Collocation points.
const C: [f64; 3] = [(4.0 - S6) / 10.0, (4.0 + S6) / 10.0, 1.0];
/// Error-estimate weights `e_i` (multiplying `Z_i / h`).
const E: [f64; 3] = [(-13.0 - 7.0 * S6) / 3.0, (-13.0 + 7.0 * S6) / 3.0, -1.0 / 3.0];
/// The real eigenvalue `μ = 3 + 3^{2/3} − 3^{1/3}` of `A⁻¹`.
const MU_REAL: f64 = 3.637_834_252_744_496;
/// The complex pair `α ± iβ` of `A⁻¹`: `α = 3 + (3^{1/3} − 3^{2/3})/2`, `β = (3^{5/6} + 3^{7/6})/2`.
const MU_ALPHA: f64 = 2.681_082_873_627_752_3;
const MU_BETA: f64 = 3.050_430_199_247_411;
/// `T` and `T⁻¹` with `T⁻¹ A⁻¹ T = [[μ, 0, 0], [0, α, β], [0, −β, α]]` (the test checks them against
/// the Butcher matrix).
#[allow(clippy::excessive_precision)]
const T: [[f64; 3]; 3] = [
    [0.094_438_762_488_975_24, -0.141_255_295_020_954_21, 0.030_029_194_105_147_42],
    [0.250_213_122_965_333_32, 0.204_129_352_293_799_94, -0.382_942_112_757_261_92],
    [1.0, 1.0, 0.0],
];
#[allow(clippy::excessive_precision)]
const TI: [[f64; 3]; 3] = [
    [4.178_718_591_551_904_28, 0.327_682_820_761_062_37, 0.523_376_445_499_449_51],
    [-4.178_718_591_551_904_28, -0.327_682_820_761_062_37, 0.476_623_554_500_550_44],
    [0.502_872_634_945_786_82, -2.571_926_949_855_605_22, 0.596_039_204_828_224_92],
];
/// The collocation polynomial `y(t₀ + x h) = y₀ + Σ_k (Σ_i Z_i P_ik) x^{k+1}`: the guess of the next
/// step's stages.
const P: [[f64; 3]; 3] = [
    [10.048_809_399_827_414, -25.629_591_447_076_64, 15.580_782_047_249_224],
    [-1.382_142_733_160_748, 10.296_258_113_743_303, -8.914_115_380_582_556],
    [1.0 / 3.0, -8.0 / 3.0, 10.0 / 3.0],
];
/// A stalled iteration with corrections below this weighted norm has converged to round-off.
const STALL_FLOOR: f64 = 3e-3;
/// Most simplified Newton iterations on the stages.
const NEWTON_MAXITER: usize = 6;

/// The two Newton matrices for one step size.
struct Factors {
    h: f64,
    real: Box<dyn ShiftedSolve<f64>>,
    complex: Box<dyn ShiftedSolve<Complex64>>,
}

fn factor(lin: &dyn Linearization, h: f64, stats: &mut Stats) -> Option<Factors> {
    stats.factorizations += 2;
    Some(Factors {
        h,
        real: lin.factor_real(MU_REAL / h)?,
        complex: lin.factor_complex(Complex64::new(MU_ALPHA, -MU_BETA) / h)?,
    })
}

type Stages = [Vec<f64>; 3];

/// Converged stages, with the iterations taken and the last contraction rate.
struct Collocation {
    z: Stages,
    iterations: usize,
    rate: Option<f64>,
}

/// Simplified Newton in `W = T⁻¹ Z` on `Z_i = h Σ_j a_ij F_j(Z_j)`, `F_i = stage(i, Z_i)`. `norm`
/// is the RMS norm of a correction over all stages; converged when the predicted remaining error
/// `rate/(1 − rate) ‖ΔW‖` is below `tol`. `None` when it diverges, stalls or `F` is not finite.
fn collocation(
    stage: &mut dyn FnMut(usize, &[f64]) -> Vec<f64>,
    z0: Stages,
    factors: &Factors,
    norm: &dyn Fn(&Stages) -> f64,
    tol: f64,
    max_iterations: usize,
) -> Option<Collocation> {
    let n = z0[0].len();
    let h = factors.h;
    let transform = |m: &[[f64; 3]; 3], x: &Stages| -> Stages {
        std::array::from_fn(|r| (0..n).map(|j| m[r][0] * x[0][j] + m[r][1] * x[1][j] + m[r][2] * x[2][j]).collect())
    };
    let mut w = transform(&TI, &z0);
    let mut z = z0;
    let mut previous: Option<f64> = None;
    let mut rate;
    let (mu, mu_c) = (MU_REAL / h, Complex64::new(MU_ALPHA, -MU_BETA) / h);
    for k in 0..max_iterations {
        let f: Stages = std::array::from_fn(|i| stage(i, &z[i]));
        if f.iter().flatten().any(|v| !v.is_finite()) {
            return None;
        }
        let tf = transform(&TI, &f);
        let mut real: Vec<f64> = (0..n).map(|j| tf[0][j] - mu * w[0][j]).collect();
        let mut complex: Vec<Complex64> =
            (0..n).map(|j| Complex64::new(tf[1][j], tf[2][j]) - mu_c * Complex64::new(w[1][j], w[2][j])).collect();
        factors.real.solve(&mut real);
        factors.complex.solve(&mut complex);
        let dw: Stages = [real, complex.iter().map(|c| c.re).collect(), complex.iter().map(|c| c.im).collect()];
        let dw_norm = norm(&dw);
        if !dw_norm.is_finite() {
            return None;
        }
        rate = previous.map(|p| dw_norm / p);
        // From the second iteration on, corrections below `STALL_FLOOR` that no longer shrink fast
        // enough are round-off: the right-hand side of a stiff chain carries errors of order
        // ε ‖K‖/‖M‖ (about 1e-12 relative in the accelerations at N = 100), above Hairer's
        // `10 ε / rtol` floor at tight tolerances. They are a few thousandths of the local error
        // tolerance: done.
        let noise = k >= 1 && dw_norm <= STALL_FLOOR;
        // Diverging, or not reaching `tol` in the iterations left.
        let slow = rate.is_some_and(|r| r >= 1.0 || r.powi((max_iterations - k) as i32) / (1.0 - r) * dw_norm > tol);
        if slow && !noise {
            return None;
        }
        for (wr, dr) in w.iter_mut().zip(&dw) {
            wr.iter_mut().zip(dr).for_each(|(a, b)| *a += b);
        }
        z = transform(&T, &w);
        // Stalled at round-off, a correction a tenth of the tolerance, or a predicted remaining
        // error below it: done.
        let stalled = slow && noise;
        if stalled || dw_norm <= 0.1 * tol || rate.is_some_and(|r| r < 1.0 && r / (1.0 - r) * dw_norm < tol) {
            return Some(Collocation { z, iterations: k + 1, rate });
        }
        previous = Some(dw_norm);
    }
    None
}

/// The collocation polynomial of an accepted step, for the next step's guess.
struct Polynomial {
    t0: f64,
    h: f64,
    y0: Vec<f64>,
    /// `Q_k = Σ_i Z_i P_ik`.
    q: Stages,
}

impl Polynomial {
    fn new(t0: f64, h: f64, y0: &[f64], z: &Stages) -> Self {
        let n = y0.len();
        let q = std::array::from_fn(|k| (0..n).map(|j| (0..3).map(|i| z[i][j] * P[i][k]).sum()).collect());
        Self { t0, h, y0: y0.to_vec(), q }
    }

    fn value(&self, t: f64) -> Vec<f64> {
        let x = (t - self.t0) / self.h;
        (0..self.y0.len()).map(|j| self.y0[j] + x * (self.q[0][j] + x * (self.q[1][j] + x * self.q[2][j]))).collect()
    }
}

/// Gustafsson's predictive factor `min(1, (h/h_old) (err_old/err)^{1/4}) err^{−1/4}`.
fn predict_factor(h: f64, old: Option<(f64, f64)>, err: f64) -> f64 {
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
fn newton_tol(opts: &Options) -> f64 {
    (10.0 * f64::EPSILON / opts.rtol).max(0.03f64.min(opts.rtol.sqrt())).min(opts.newton_tolerance)
}

/// The stage sensitivities of an accepted step: `S₁ = S₀ + dZ₃` (before the projection).
#[allow(clippy::too_many_arguments)]
fn step_sensitivities(
    sys: &dyn OdeSystem,
    t: f64,
    piece: f64,
    y: &[f64],
    z: &Stages,
    factors: &Factors,
    s0: &DMatrix<f64>,
    sd0: &DMatrix<f64>,
    stats: &mut Stats,
) -> DMatrix<f64> {
    let n = y.len();
    let h = factors.h;
    let points: Vec<(f64, Vec<f64>)> =
        (0..3).map(|i| (t + C[i] * h, (0..n).map(|j| y[j] + z[i][j]).collect())).collect();
    let params: Vec<DMatrix<f64>> = points.iter().map(|(ti, yi)| sys.rhs_params(*ti, piece, yi)).collect();
    let mut s1 = s0.clone();
    for k in 0..s0.ncols() {
        let s0k: Vec<f64> = s0.column(k).iter().copied().collect();
        let mut stage = |i: usize, dz: &[f64]| -> Vec<f64> {
            let v: Vec<f64> = (0..n).map(|j| s0k[j] + dz[j]).collect();
            let (ti, yi) = &points[i];
            stats.rhs_evaluations += 1;
            let mut jv = sys.jacobian_times(*ti, piece, yi, &v);
            jv.iter_mut().enumerate().for_each(|(j, x)| *x += params[i][(j, k)]);
            jv
        };
        // The linear iteration contracts like the stages' Newton iteration; it runs to round-off
        // relative to the size of the sensitivities.
        let scale =
            1.0 + s0k.iter().map(|v| v.abs()).chain(sd0.column(k).iter().map(|v| (v * h).abs())).fold(0.0, f64::max);
        let norm = |dw: &Stages| dw.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs())) / scale;
        let guess: Stages = std::array::from_fn(|i| (0..n).map(|j| C[i] * h * sd0[(j, k)]).collect());
        // When the linear iteration does not converge (not seen in the tests: the stages' own
        // iteration converged with the same matrices), the first-order guess `c_i h Ṡ₀` stands.
        let dz = collocation(&mut stage, guess.clone(), factors, &norm, 1e-13, 60).map_or(guess, |c| c.z);
        for j in 0..n {
            s1[(j, k)] += dz[2][j];
        }
    }
    s1
}

/// The Radau IIA driver.
pub(super) fn integrate(
    sys: &dyn OdeSystem,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    opts: &Options,
    extras: Extras<'_>,
) -> Trajectory {
    let Extras { sensitivities, steps, stop } = extras;
    let n = sys.dim();
    let mut stats = Stats::default();
    let mut intervals = Vec::new();
    let mut course = Course::new(sys, t0, t_end, steps, opts);
    let mut t = t0;
    let mut y = y0.to_vec();
    sys.project(&mut y);
    let y_start = y.clone();
    let mut s = sensitivities;
    let mut piece = course.piece(t);
    let tol = newton_tol(opts);
    let h_max = opts.max_step.unwrap_or(f64::INFINITY);

    let mut f = sys.rhs(t, piece, &y);
    stats.rhs_evaluations += 1;
    let mut lin = sys.linearize(t, piece, &y);
    stats.jacobian_evaluations += 1;
    let mut current = true;
    let mut s_dot = s.as_ref().map(|s| sensitivity_rate(sys, t, piece, &y, s));
    let mut factors: Option<Factors> = None;
    let mut polynomial: Option<Polynomial> = None;
    let mut h = course.initial_step(opts);
    // `(h, err)` of the last accepted step, for the predictive controller.
    let mut last: Option<(f64, f64)> = None;
    let mut outcome = Outcome::Completed;

    'steps: while t < t_end {
        if let Some(o) = course.must_stop(t, &stats) {
            outcome = o;
            break;
        }
        if h > h_max {
            h = h_max;
            last = None;
        }
        let mut rejected = false;
        // Try steps from t until one is accepted.
        let (t1, col, err, safety) = loop {
            let next = match course.next_step(t, h) {
                Ok(next) => next,
                Err(o) => {
                    outcome = o;
                    break 'steps;
                }
            };
            let (t1, fixed) = (next.t1, next.fixed);
            let h_step = t1 - t;
            if factors.as_ref().is_none_or(|fa| fa.h != h_step) {
                factors = factor(lin.as_ref(), h_step, &mut stats);
            }
            let solved = factors.as_ref().and_then(|fa| {
                let guess: Stages = match &polynomial {
                    Some(p) => std::array::from_fn(|i| {
                        let v = p.value(t + C[i] * h_step);
                        (0..n).map(|j| v[j] - y[j]).collect()
                    }),
                    None => std::array::from_fn(|_| vec![0.0; n]),
                };
                let scale: Vec<f64> = y.iter().map(|v| opts.atol + opts.rtol * v.abs()).collect();
                let norm = |dw: &Stages| {
                    let sum: f64 =
                        dw.iter().map(|d| d.iter().zip(&scale).map(|(a, s)| (a / s).powi(2)).sum::<f64>()).sum();
                    (sum / (3 * n.max(1)) as f64).sqrt()
                };
                let mut stage = |i: usize, zi: &[f64]| {
                    let yi: Vec<f64> = (0..n).map(|j| y[j] + zi[j]).collect();
                    stats.rhs_evaluations += 1;
                    stats.newton_iterations += usize::from(i == 0);
                    sys.rhs(t + C[i] * h_step, piece, &yi)
                };
                let col = collocation(&mut stage, guess, fa, &norm, tol, NEWTON_MAXITER);
                stats.newton_failures += usize::from(col.is_none());
                col
            });
            // A singular Newton matrix or a failed iteration: a fresh linearisation, then a
            // smaller step.
            let (Some(col), Some(fa)) = (solved, factors.as_ref()) else {
                factors = None;
                if !current {
                    lin = sys.linearize(t, piece, &y);
                    stats.jacobian_evaluations += 1;
                    current = true;
                } else if fixed {
                    outcome = Outcome::StepTooSmall { t };
                    break 'steps;
                } else {
                    h = 0.5 * h_step;
                }
                continue;
            };
            let y_new: Vec<f64> = (0..n).map(|j| y[j] + col.z[2][j]).collect();
            let ze: Vec<f64> = (0..n).map(|j| (0..3).map(|i| E[i] * col.z[i][j]).sum::<f64>() / h_step).collect();
            let mut error: Vec<f64> = (0..n).map(|j| f[j] + ze[j]).collect();
            fa.real.solve(&mut error);
            let mut err = weighted_rms(&error, &y, &y_new, opts);
            let safety = 0.9 * (2 * NEWTON_MAXITER + 1) as f64 / (2 * NEWTON_MAXITER + col.iterations) as f64;
            if rejected && err > 1.0 {
                let shifted: Vec<f64> = (0..n).map(|j| y[j] + error[j]).collect();
                let fs = sys.rhs(t, piece, &shifted);
                stats.rhs_evaluations += 1;
                error = (0..n).map(|j| fs[j] + ze[j]).collect();
                fa.real.solve(&mut error);
                err = weighted_rms(&error, &y, &y_new, opts);
            }
            let err = if err.is_finite() { err } else { f64::INFINITY };
            if !fixed && err > 1.0 {
                stats.rejected_steps += 1;
                rejected = true;
                h = h_step * (safety * predict_factor(h_step, last, err)).max(0.2);
                continue;
            }
            break (t1, col, err, safety);
        };

        // Accepted.
        let h_step = t1 - t;
        let fa = factors.as_ref().expect("an accepted step has its factors");
        let mut y1: Vec<f64> = (0..n).map(|j| y[j] + col.z[2][j]).collect();
        let start_sens = s.clone().zip(s_dot.clone());
        if let (Some(s0), Some(sd0)) = (s.as_mut(), s_dot.as_ref()) {
            *s0 = step_sensitivities(sys, t, piece, &y, &col.z, fa, s0, sd0, &mut stats);
        }
        polynomial = Some(Polynomial::new(t, h_step, &y, &col.z));
        course.project(&mut y1, s.as_mut(), &mut stats);
        let f1 = sys.rhs(t1, piece, &y1);
        stats.rhs_evaluations += 1;
        let s_dot1 = s.as_ref().map(|s| sensitivity_rate(sys, t1, piece, &y1, s));
        let end_sens = s.clone().zip(s_dot1.clone());
        let collocation = polynomial.as_ref().map(|p| p.q.clone());
        intervals.push(Interval::accepted((t, &y, &f), (t1, &y1, &f1), (start_sens, end_sens), collocation));
        stats.accepted_steps += 1;
        let refresh = col.iterations > 2 && col.rate.is_some_and(|r| r > 1e-3);
        let factor = (safety * predict_factor(h_step, last, err)).min(10.0);
        last = Some((h_step, err));
        if refresh || factor >= 1.2 {
            h = h_step * factor;
        } else {
            h = h_step;
        }
        t = t1;
        y = y1;
        f = f1;
        s_dot = s_dot1;
        current = false;
        if refresh {
            lin = sys.linearize(t, piece, &y);
            stats.jacobian_evaluations += 1;
            current = true;
            factors = None;
        }
        if stop.is_some_and(|g| g(t, &y)) {
            outcome = Outcome::Stopped { t };
            break;
        }
        if course.passed_break(t) {
            piece = course.piece(t);
            f = sys.rhs(t, piece, &y);
            stats.rhs_evaluations += 1;
            lin = sys.linearize(t, piece, &y);
            stats.jacobian_evaluations += 1;
            current = true;
            factors = None;
            polynomial = None;
            last = None;
            s_dot = s.as_ref().map(|s| sensitivity_rate(sys, t, piece, &y, s));
        }
    }
    Trajectory { start: (t0, y_start), intervals, outcome, stats }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Radau IIA Butcher matrix.
    fn butcher() -> nalgebra::Matrix3<f64> {
        nalgebra::Matrix3::new(
            (88.0 - 7.0 * S6) / 360.0,
            (296.0 - 169.0 * S6) / 1800.0,
            (-2.0 + 3.0 * S6) / 225.0,
            (296.0 + 169.0 * S6) / 1800.0,
            (88.0 + 7.0 * S6) / 360.0,
            (-2.0 - 3.0 * S6) / 225.0,
            (16.0 - S6) / 36.0,
            (16.0 + S6) / 36.0,
            1.0 / 9.0,
        )
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
            assert!((p.value(C[i])[0] - z[i][0]).abs() < 1e-12);
        }
    }
}
