//! One TR-BDF2 step: the two implicit stages by simplified Newton, the embedded error estimate and
//! the forward sensitivities through the same discrete scheme.

use super::options::{Options, Stats};
use crate::ode::OdeSystem;
use nalgebra::{DMatrix, DVector};

const SQRT2: f64 = std::f64::consts::SQRT_2;
/// `γ = 2 − √2`: the trapezoidal stage ends at `t + γ h`.
const GAMMA: f64 = 2.0 - SQRT2;
/// Diagonal coefficient `d = γ / 2`.
pub(super) const D: f64 = GAMMA / 2.0;
/// BDF2 stage weights of `f(y)` and `f(z₂)`.
const W: f64 = SQRT2 / 4.0;
/// `b − b̂` for the error estimate (third-order companion `b̂ = ((1 − w)/3, (3w + 1)/3, d/3)`).
const E1: f64 = (4.0 * W - 1.0) / 3.0;
const E2: f64 = -1.0 / 3.0;
const E3: f64 = 2.0 * D / 3.0;

fn weighted_rms(v: &[f64], y0: &[f64], y1: &[f64], o: &Options) -> f64 {
    let n = v.len().max(1);
    let s: f64 = (0..v.len())
        .map(|i| {
            let scale = o.atol + o.rtol * y0[i].abs().max(y1[i].abs());
            (v[i] / scale).powi(2)
        })
        .sum();
    (s / n as f64).sqrt()
}

/// A tried step: the new point, the stage, and the weighted error estimate.
pub(super) struct Attempt {
    /// The trapezoidal stage at `t + γh`.
    pub z2: Vec<f64>,
    /// The new point (before projection).
    pub y1: Vec<f64>,
    /// The weighted RMS error estimate (accept when ≤ 1).
    pub err: f64,
}

/// Simplified Newton on `z = base + c f(t, z)` with the factored `I − c J`; `None` when it diverges
/// or does not converge in `MAX_NEWTON` iterations.
#[allow(clippy::too_many_arguments)]
fn newton(
    sys: &dyn OdeSystem,
    t: f64,
    piece: f64,
    base: &[f64],
    c: f64,
    mut z: Vec<f64>,
    solve: &dyn Fn(Vec<f64>) -> Vec<f64>,
    y_ref: &[f64],
    opts: &Options,
    stats: &mut Stats,
) -> Option<(Vec<f64>, Vec<f64>)> {
    const MAX_NEWTON: usize = 12;
    let mut previous = f64::INFINITY;
    for _ in 0..MAX_NEWTON {
        let fz = sys.rhs(t, piece, &z);
        stats.rhs_evaluations += 1;
        stats.newton_iterations += 1;
        let residual: Vec<f64> = (0..z.len()).map(|i| base[i] + c * fz[i] - z[i]).collect();
        let dz = solve(residual);
        if dz.iter().any(|v| !v.is_finite()) {
            return None;
        }
        for (zi, di) in z.iter_mut().zip(&dz) {
            *zi += di;
        }
        let norm = weighted_rms(&dz, y_ref, &z, opts);
        if norm <= opts.newton_tolerance {
            let fz = sys.rhs(t, piece, &z);
            stats.rhs_evaluations += 1;
            return Some((z, fz));
        }
        if norm > previous {
            return None;
        }
        previous = norm;
    }
    None
}

#[allow(clippy::too_many_arguments)]
pub(super) fn attempt(
    sys: &dyn OdeSystem,
    t: f64,
    piece: f64,
    h: f64,
    y: &[f64],
    f: &[f64],
    lu: &nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>,
    opts: &Options,
    stats: &mut Stats,
) -> Option<Attempt> {
    let n = y.len();
    let solve = |rhs: Vec<f64>| -> Vec<f64> {
        lu.solve(&DVector::from_vec(rhs)).map(|v| v.as_slice().to_vec()).unwrap_or_else(|| vec![f64::NAN; n])
    };
    // Stage 2: trapezoidal rule to t + γh.
    let guess: Vec<f64> = (0..n).map(|i| y[i] + GAMMA * h * f[i]).collect();
    let base2: Vec<f64> = (0..n).map(|i| y[i] + h * D * f[i]).collect();
    let (z2, f2) = newton(sys, t + GAMMA * h, piece, &base2, h * D, guess, &solve, y, opts, stats)?;
    // Stage 3: BDF2 to t + h; guess from the line through y and z2.
    let guess: Vec<f64> = (0..n).map(|i| y[i] + (z2[i] - y[i]) / GAMMA).collect();
    let base3: Vec<f64> = (0..n).map(|i| y[i] + h * W * (f[i] + f2[i])).collect();
    let (y1, f3) = newton(sys, t + h, piece, &base3, h * D, guess, &solve, y, opts, stats)?;
    let est = solve((0..n).map(|i| h * (E1 * f[i] + E2 * f2[i] + E3 * f3[i])).collect());
    let err = weighted_rms(&est, y, &y1, opts);
    Some(Attempt { z2, y1, err: if err.is_finite() { err } else { f64::INFINITY } })
}

/// `S₁ = ∂y₁/∂p` of an accepted step from `S₀` and `Ṡ₀ = J S₀ + ∂f/∂p` at its start: the exact
/// derivative of the two stages (the same discrete scheme), then of the projection at the
/// unprojected `y₁`.
#[allow(clippy::too_many_arguments)]
pub(super) fn step_sensitivities(
    sys: &dyn OdeSystem,
    (t, t1): (f64, f64),
    piece: f64,
    step: &Attempt,
    y1: &[f64],
    s0: &DMatrix<f64>,
    sd0: &DMatrix<f64>,
    stats: &mut Stats,
) -> DMatrix<f64> {
    let n = y1.len();
    let h_step = t1 - t;
    let t2 = t + GAMMA * h_step;
    let j2 = sys.jacobian(t2, piece, &step.z2);
    let p2 = sys.rhs_params(t2, piece, &step.z2);
    let w2 = (DMatrix::<f64>::identity(n, n) - &j2 * (h_step * D)).lu();
    let s2 = w2.solve(&(s0 + (sd0 + &p2) * (h_step * D))).expect("stage matrix is regular");
    let j3 = sys.jacobian(t1, piece, y1);
    let p3 = sys.rhs_params(t1, piece, y1);
    let w3 = (DMatrix::<f64>::identity(n, n) - &j3 * (h_step * D)).lu();
    let rhs = s0 + (sd0 * W + (&j2 * &s2 + &p2) * W + &p3 * D) * h_step;
    let mut s1 = w3.solve(&rhs).expect("stage matrix is regular");
    stats.jacobian_evaluations += 2;
    stats.factorizations += 2;
    sys.project_sensitivities(y1, &mut s1);
    s1
}
