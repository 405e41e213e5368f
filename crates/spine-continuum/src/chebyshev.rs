//! Chebyshev–Gauss–Lobatto collocation on an interval `[0, L]`: the nodes, the differentiation
//! matrix, Clenshaw–Curtis weights, and a function's Chebyshev series with its integral, evaluated
//! anywhere (Trefethen, *Spectral Methods in MATLAB*, ch. 6 and 12).

use nalgebra::DMatrix;
use std::f64::consts::PI;

/// `M + 1` Chebyshev–Gauss–Lobatto nodes mapped to `[0, length]`, in increasing order.
#[derive(Clone, Debug)]
pub struct Grid {
    pub length: f64,
    /// `s_k = L (1 − cos(kπ/M)) / 2`, m.
    pub nodes: Vec<f64>,
}

impl Grid {
    /// The grid of degree `degree` (`M ≥ 2`) on `[0, length]`.
    pub fn new(degree: usize, length: f64) -> Self {
        let m = degree as f64;
        let nodes = (0..=degree).map(|k| 0.5 * length * (1.0 - (k as f64 * PI / m).cos())).collect();
        Self { length, nodes }
    }

    pub fn degree(&self) -> usize {
        self.nodes.len() - 1
    }

    /// `D` with `(D f)_k = f'(s_k)` for the interpolant of `f` (1/m).
    pub fn differentiation(&self) -> DMatrix<f64> {
        let n = self.nodes.len();
        let m = self.degree();
        // On x = −cos(kπ/M) ∈ [−1, 1] (increasing with k), then scaled by dx/ds = 2/L.
        let x: Vec<f64> = (0..n).map(|k| -(k as f64 * PI / m as f64).cos()).collect();
        let c = |k: usize| if k == 0 || k == m { 2.0 } else { 1.0 };
        let sign = |k: usize| if k.is_multiple_of(2) { 1.0 } else { -1.0 };
        let mut d = DMatrix::zeros(n, n);
        for i in 0..n {
            for j in 0..n {
                if i != j {
                    // The barycentric weights of −cos nodes: (−1)^k / c_k up to a common sign.
                    d[(i, j)] = (c(i) / c(j)) * sign(i) * sign(j) / (x[i] - x[j]);
                }
            }
            // Negative sum trick: rows of D annihilate constants exactly.
            let row: f64 = (0..n).filter(|&j| j != i).map(|j| d[(i, j)]).sum();
            d[(i, i)] = -row;
        }
        d * (2.0 / self.length)
    }

    /// Clenshaw–Curtis weights: `∫_0^L f ds ≈ Σ w_k f(s_k)`, exact for polynomials of degree `M`.
    pub fn weights(&self) -> Vec<f64> {
        let m = self.degree();
        let theta = |k: usize| k as f64 * PI / m as f64;
        let mut w = vec![0.0; m + 1];
        for (k, wk) in w.iter_mut().enumerate() {
            let mut sum = 0.0;
            for j in 1..=m / 2 {
                let b = if 2 * j == m { 1.0 } else { 2.0 };
                sum += b / (4.0 * (j * j) as f64 - 1.0) * (2.0 * j as f64 * theta(k)).cos();
            }
            let c = if k == 0 || k == m { 1.0 } else { 2.0 };
            *wk = c / m as f64 * (1.0 - sum) * 0.5 * self.length;
        }
        w
    }
}

/// A function given by its values at a [`Grid`]'s nodes, as a Chebyshev series `Σ a_j T_j(x)`,
/// `x = 2s/L − 1`.
#[derive(Clone, Debug)]
pub struct Series {
    length: f64,
    coefficients: Vec<f64>,
}

impl Series {
    /// The interpolant of `values` (at the grid's nodes, in increasing `s`).
    pub fn interpolate(grid: &Grid, values: &[f64]) -> Self {
        let m = grid.degree();
        let mf = m as f64;
        // Node k sits at x_k = −cos(kπ/M) = cos((M − k)π/M); the discrete cosine transform.
        let coefficients = (0..=m)
            .map(|j| {
                let mut a = 0.0;
                for (k, v) in values.iter().enumerate() {
                    let c = if k == 0 || k == m { 0.5 } else { 1.0 };
                    a += c * v * (j as f64 * (m - k) as f64 * PI / mf).cos();
                }
                let scale = if j == 0 || j == m { 1.0 / mf } else { 2.0 / mf };
                a * scale
            })
            .collect();
        Self { length: grid.length, coefficients }
    }

    /// The value at `s` (Clenshaw's recurrence).
    pub fn eval(&self, s: f64) -> f64 {
        let x = 2.0 * s / self.length - 1.0;
        let (mut b1, mut b2) = (0.0, 0.0);
        for &a in self.coefficients.iter().skip(1).rev() {
            (b1, b2) = (2.0 * x * b1 - b2 + a, b1);
        }
        x * b1 - b2 + self.coefficients[0]
    }

    /// The antiderivative vanishing at `s = 0` (`∫T_j = T_{j+1}/(2(j+1)) − T_{j−1}/(2(j−1))`).
    pub fn integral(&self) -> Self {
        let a = &self.coefficients;
        let m = a.len();
        let mut b = vec![0.0; m + 1];
        let at = |j: usize| a.get(j).copied().unwrap_or(0.0);
        for (j, bj) in b.iter_mut().enumerate().skip(1) {
            let lower = if j == 1 { 2.0 * at(0) } else { at(j - 1) };
            *bj = (lower - at(j + 1)) / (2.0 * j as f64);
        }
        // d/ds = (2/L) d/dx, so ∫ ds = (L/2) ∫ dx.
        for v in b.iter_mut() {
            *v *= 0.5 * self.length;
        }
        let mut out = Self { length: self.length, coefficients: b };
        out.coefficients[0] -= out.eval(0.0);
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivative_weights_and_integral_are_spectral() {
        let g = Grid::new(24, 2.0);
        let f: Vec<f64> = g.nodes.iter().map(|s| (1.3 * s).sin()).collect();
        let d = g.differentiation();
        let df = &d * nalgebra::DVector::from_vec(f.clone());
        for (k, s) in g.nodes.iter().enumerate() {
            assert!((df[k] - 1.3 * (1.3 * s).cos()).abs() < 1e-11, "D at {s}: {}", df[k]);
        }
        let w = g.weights();
        let quad: f64 = w.iter().zip(&f).map(|(w, f)| w * f).sum();
        let exact = (1.0 - (2.6f64).cos()) / 1.3;
        assert!((quad - exact).abs() < 1e-14, "{quad} vs {exact}");
        let series = Series::interpolate(&g, &f);
        let int = series.integral();
        for s in [0.0, 0.37, 1.0, 1.91, 2.0] {
            assert!((series.eval(s) - (1.3 * s).sin()).abs() < 1e-13);
            assert!((int.eval(s) - (1.0 - (1.3 * s).cos()) / 1.3).abs() < 1e-13, "∫ at {s}");
        }
    }
}
