//! Euler's elastica with the rod's loads, solved by Chebyshev collocation: the continuum reference
//! the chain converges to.
//!
//! With `θ(s)` the tangent's angle, `x' = cos θ`, `y' = sin θ`, stationarity of
//! `½∫EI θ'² ds − P_X x(L) − ∫ w y ds − R y(L)` (`R` the slider's vertical reaction, the
//! multiplier of `y(L) = 0`; `w = q − ρA g`) gives
//!
//! `EI θ'' = P_X sin θ − (R + w (L − s)) cos θ`,  `θ(0) = θ(L) = 0`,  `∫_0^L sin θ ds = 0`.
//!
//! The unknowns are `θ` at `M + 1` Chebyshev–Gauss–Lobatto nodes and `R`; the equation holds at
//! the `M − 1` interior nodes, the two boundary rows pin `θ`, and Clenshaw–Curtis quadrature gives
//! the end condition. Newton's method with a backtracking line search from the caller's guess
//! (which picks the branch: straight, or buckled one way or the other). For a smooth solution the
//! error falls spectrally with `M`; [`Elastica::solve`] reports the residual, and the tests check
//! the result against a solve at twice the degree.

use crate::chebyshev::{Grid, Series};
use crate::rod::Rod;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// The elastica's failure to converge from the guess given.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ElasticaError {
    #[error("Newton on the elastica's collocation equations did not converge in {iterations} iterations (residual {residual:.3e}, scaled)")]
    NotConverged { iterations: usize, residual: f64 },
    #[error("the collocation Jacobian is singular at iteration {iteration} (a bifurcation point, or a guess on it)")]
    Singular { iteration: usize },
    #[error("degree must be at least 4, got {0}")]
    Degree(usize),
}

/// A solved elastica.
#[derive(Clone, Debug, Serialize)]
pub struct Elastica {
    pub rod: Rod,
    #[serde(skip)]
    grid: Grid,
    /// `θ` at the collocation nodes, rad.
    pub theta: Vec<f64>,
    /// `R`, the slider's vertical reaction, N.
    pub reaction: f64,
    /// Newton iterations and the final residual (each row scaled by its natural size).
    pub iterations: usize,
    pub residual: f64,
    #[serde(skip)]
    theta_series: Series,
    #[serde(skip)]
    x_series: Series,
    #[serde(skip)]
    y_series: Series,
}

/// Newton stops when the scaled residual is at most this.
const TOLERANCE: f64 = 1e-13;
const MAX_ITERATIONS: usize = 100;
const STEP_TOLERANCE: f64 = 1e-13;

impl Elastica {
    /// Solves the rod's elastica on `degree + 1` nodes from the guess `guess(s)` for `θ` (rad).
    pub fn solve(rod: &Rod, degree: usize, guess: impl Fn(f64) -> f64) -> Result<Self, ElasticaError> {
        if degree < 4 {
            return Err(ElasticaError::Degree(degree));
        }
        let grid = Grid::new(degree, rod.length);
        let d = grid.differentiation();
        let d2 = &d * &d;
        let weights = grid.weights();
        let n = degree + 1;
        let mut theta: Vec<f64> = grid.nodes.iter().map(|&s| guess(s)).collect();
        theta[0] = 0.0;
        theta[degree] = 0.0;
        let mut reaction = 0.0;
        let w = rod.distributed_load();
        let ei = rod.bending_stiffness;
        // Row scales: the bending term's size on this grid, and the rod's length for ∫ sin θ.
        let force_scale = rod.end_force.abs() + (w * rod.length).abs() + ei / rod.length.powi(2);
        let residual_of = |theta: &[f64], reaction: f64| -> DVector<f64> {
            let th = DVector::from_column_slice(theta);
            let bend = &d2 * &th;
            let mut f = DVector::zeros(n + 1);
            f[0] = theta[0];
            f[degree] = theta[degree];
            for k in 1..degree {
                let s = grid.nodes[k];
                f[k] = (ei * bend[k] - rod.end_force * theta[k].sin()
                    + (reaction + w * (rod.length - s)) * theta[k].cos())
                    / force_scale;
            }
            f[n] = weights.iter().zip(theta).map(|(wk, t)| wk * t.sin()).sum::<f64>() / rod.length;
            f
        };
        let norm = |f: &DVector<f64>| f.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let mut f = residual_of(&theta, reaction);
        for iteration in 0..MAX_ITERATIONS {
            if norm(&f) <= TOLERANCE {
                return Ok(Self::finish(rod, grid, theta, reaction, iteration, norm(&f)));
            }
            let mut jac = DMatrix::zeros(n + 1, n + 1);
            jac[(0, 0)] = 1.0;
            jac[(degree, degree)] = 1.0;
            for k in 1..degree {
                let s = grid.nodes[k];
                for j in 0..n {
                    jac[(k, j)] = ei * d2[(k, j)] / force_scale;
                }
                jac[(k, k)] += (-rod.end_force * theta[k].cos() - (reaction + w * (rod.length - s)) * theta[k].sin())
                    / force_scale;
                jac[(k, n)] = theta[k].cos(); // the unknown is R / force_scale
            }
            for j in 0..n {
                jac[(n, j)] = weights[j] * theta[j].cos() / rod.length;
            }
            let step = jac.lu().solve(&(-&f)).ok_or(ElasticaError::Singular { iteration })?;
            // At high degree rounding in `D²` keeps the residual above the tolerance: a Newton step
            // below `STEP_TOLERANCE` rad near a root is convergence too.
            if norm(&f) <= 1e-8 && step.iter().take(n).fold(0.0f64, |m, v| m.max(v.abs())) <= STEP_TOLERANCE {
                let theta: Vec<f64> = theta.iter().enumerate().map(|(k, v)| v + step[k]).collect();
                let reaction = reaction + step[n] * force_scale;
                let residual = norm(&residual_of(&theta, reaction));
                return Ok(Self::finish(rod, grid, theta, reaction, iteration + 1, residual));
            }
            // Backtracking on the residual's norm.
            let mut t = 1.0;
            loop {
                let trial: Vec<f64> = theta.iter().enumerate().map(|(k, v)| v + t * step[k]).collect();
                let trial_reaction = reaction + t * step[n] * force_scale;
                let ft = residual_of(&trial, trial_reaction);
                if norm(&ft) < (1.0 - 1e-4 * t) * norm(&f) || t < 1e-6 {
                    (theta, reaction, f) = (trial, trial_reaction, ft);
                    break;
                }
                t *= 0.5;
            }
        }
        Err(ElasticaError::NotConverged { iterations: MAX_ITERATIONS, residual: norm(&f) })
    }

    fn finish(rod: &Rod, grid: Grid, theta: Vec<f64>, reaction: f64, iterations: usize, residual: f64) -> Self {
        let cos: Vec<f64> = theta.iter().map(|t| t.cos()).collect();
        let sin: Vec<f64> = theta.iter().map(|t| t.sin()).collect();
        Self {
            rod: rod.clone(),
            theta_series: Series::interpolate(&grid, &theta),
            x_series: Series::interpolate(&grid, &cos).integral(),
            y_series: Series::interpolate(&grid, &sin).integral(),
            grid,
            theta,
            reaction,
            iterations,
            residual,
        }
    }

    /// The collocation nodes, m.
    pub fn nodes(&self) -> &[f64] {
        &self.grid.nodes
    }

    /// `θ(s)`, rad.
    pub fn theta_at(&self, s: f64) -> f64 {
        self.theta_series.eval(s)
    }

    /// `(x(s), y(s))`, m.
    pub fn position_at(&self, s: f64) -> (f64, f64) {
        (self.x_series.eval(s), self.y_series.eval(s))
    }
}
