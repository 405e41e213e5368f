//! Forward sensitivities of an accepted Radau IIA step by internal differentiation: the stage
//! sensitivities solve the linear collocation system `dZ_i = h Σ_j a_ij (J(Y_j) (S₀ + dZ_j) +
//! ∂f/∂p(Y_j))` at the converged stage points `Y_j` by the stages' own transformed iteration.

use super::super::options::Stats;
use super::super::DENSE_AFTER;
use super::stages::{collocation, Factors, Orientation, Stages, Workspace, A, C};
use crate::ode::OdeSystem;
use nalgebra::DMatrix;

/// The stage sensitivities of an accepted step: `S₁ = S₀ + dZ₃` (before the projection).
#[allow(clippy::too_many_arguments)]
pub(super) fn step_sensitivities(
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
    // With few states per parameter, the dense Jacobians of the three stage points and one direct
    // solve for all columns ([`direct`]); otherwise `J(Y_i) v` by a directional pass for every
    // column and iteration of the linear iteration.
    let (dense, params): (Option<Vec<DMatrix<f64>>>, Vec<DMatrix<f64>>) = if n <= DENSE_AFTER * s0.ncols() {
        stats.jacobian_evaluations += 3;
        let (jac, params) = points.iter().map(|(ti, yi)| sys.jacobian_and_params(*ti, piece, yi)).unzip();
        (Some(jac), params)
    } else {
        (None, points.iter().map(|(ti, yi)| sys.rhs_params(*ti, piece, yi)).collect())
    };
    if let Some(s1) = dense.as_ref().and_then(|jac| direct(jac, &params, s0, h)) {
        return s1;
    }
    let mut s1 = s0.clone();
    let mut work = Workspace::default();
    for k in 0..s0.ncols() {
        let s0k: Vec<f64> = s0.column(k).iter().copied().collect();
        let mut stage = |i: usize, dz: &[f64], out: &mut [f64]| {
            let v: Vec<f64> = (0..n).map(|j| s0k[j] + dz[j]).collect();
            let jv: Vec<f64> = match &dense {
                Some(jac) => (&jac[i] * nalgebra::DVector::from_vec(v)).data.into(),
                None => {
                    let (ti, yi) = &points[i];
                    stats.rhs_evaluations += 1;
                    sys.jacobian_times(*ti, piece, yi, &v)
                }
            };
            for (j, (o, x)) in out.iter_mut().zip(jv).enumerate() {
                *o = x + params[i][(j, k)];
            }
        };
        // The linear iteration contracts like the stages' Newton iteration; it runs to round-off
        // relative to the size of the sensitivities.
        let scale =
            1.0 + s0k.iter().map(|v| v.abs()).chain(sd0.column(k).iter().map(|v| (v * h).abs())).fold(0.0, f64::max);
        let norm = |dw: &Stages| dw.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs())) / scale;
        let guess: Stages = std::array::from_fn(|i| (0..n).map(|j| C[i] * h * sd0[(j, k)]).collect());
        // When the linear iteration does not converge (not seen in the tests: the stages' own
        // iteration converged with the same matrices), the first-order guess `c_i h Ṡ₀` stands. No
        // contraction is carried in (∞): it runs at least two iterations, to round-off.
        let dz = collocation(
            Orientation::Stages,
            &mut stage,
            guess.clone(),
            factors,
            &norm,
            1e-13,
            f64::INFINITY,
            60,
            &mut work,
        )
        .map_or(guess, |c| c.z);
        for j in 0..n {
            s1[(j, k)] += dz[2][j];
        }
    }
    s1
}

/// With the stage Jacobians dense, the linear collocation system for all parameters at once:
/// `(I − h (A ⊗ I) diag(J₁, J₂, J₃)) dZ = h (A ⊗ I) (J_j S₀ + ∂f/∂p(Y_j))_j`, one LU of the
/// `3n × 3n` matrix and one solve with a right-hand side per parameter (instead of a linear
/// iteration per parameter). `S₁ = S₀ + dZ₃`; `None` where the matrix is singular (then the
/// iteration decides).
fn direct(jac: &[DMatrix<f64>], params: &[DMatrix<f64>], s0: &DMatrix<f64>, h: f64) -> Option<DMatrix<f64>> {
    use faer::linalg::solvers::Solve;
    let (n, p) = (s0.nrows(), s0.ncols());
    let forcing: Vec<DMatrix<f64>> = (0..3).map(|j| &jac[j] * s0 + &params[j]).collect();
    // Blocked LU (faer): about four times nalgebra's unblocked one at 3n = 60.
    let matrix = faer::Mat::<f64>::from_fn(3 * n, 3 * n, |r, c| {
        let (i, j) = (r / n, c / n);
        let identity = if r == c { 1.0 } else { 0.0 };
        identity - h * A[i][j] * jac[j][(r % n, c % n)]
    });
    let rhs = faer::Mat::<f64>::from_fn(3 * n, p, |r, k| {
        let i = r / n;
        (0..3).map(|j| h * A[i][j] * forcing[j][(r % n, k)]).sum()
    });
    let dz = matrix.partial_piv_lu().solve(&rhs);
    let s1 = DMatrix::from_fn(n, p, |r, k| s0[(r, k)] + dz[(2 * n + r, k)]);
    s1.iter().all(|v| v.is_finite()).then_some(s1)
}
