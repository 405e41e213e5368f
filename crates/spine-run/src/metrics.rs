//! Measures of a static design that the paper's claims are about, each a plain function of the
//! design and its start.

use serde::Serialize;
use spine_model::Design;

fn norm(v: impl Iterator<Item = f64>) -> f64 {
    v.map(|x| x * x).sum::<f64>().sqrt()
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

/// How a design moved from its start and how its stiffness is spread.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DesignChange {
    /// `‖θ0 − θ0_start‖₂ / ‖θ0_start‖₂` (relative change of the shape).
    pub theta0_relative_change: f64,
    /// `‖K − K_start‖₂ / ‖K_start‖₂` (relative change of the stiffness).
    pub stiffness_relative_change: f64,
    /// `‖θ0 − θ0_start‖₂`, rad.
    pub theta0_change: f64,
    /// Mean `|θ0_i − θ0_start,i|` over the links nearer the end (`i > N/2`) and nearer the base, rad.
    pub end_half_change: f64,
    pub base_half_change: f64,
    /// The same with the halves split symmetrically: for odd `N` the middle link is in neither
    /// (the split above puts it in the end half), rad.
    pub end_half_change_symmetric: f64,
    pub base_half_change_symmetric: f64,
    /// `max K / min K` and the coefficient of variation (std / mean) of `K_1..K_{N+1}` (springs of
    /// zero stiffness are left out of the ratio).
    pub stiffness_max_over_min: f64,
    pub stiffness_variation: f64,
}

impl DesignChange {
    pub fn new(design: &Design, start: &Design) -> Self {
        let n = design.theta0.len();
        let dtheta: Vec<f64> = design.theta0.iter().zip(&start.theta0).map(|(a, b)| (a - b).abs()).collect();
        let k = &design.stiffness;
        let positive: Vec<f64> = k.iter().copied().filter(|v| *v > 0.0).collect();
        let (kmax, kmin) = positive.iter().fold((0.0f64, f64::INFINITY), |(hi, lo), v| (hi.max(*v), lo.min(*v)));
        let km = mean(k);
        let sd = (k.iter().map(|v| (v - km).powi(2)).sum::<f64>() / k.len() as f64).sqrt();
        DesignChange {
            theta0_relative_change: norm(dtheta.iter().copied()) / norm(start.theta0.iter().copied()),
            stiffness_relative_change: norm(k.iter().zip(&start.stiffness).map(|(a, b)| a - b))
                / norm(start.stiffness.iter().copied()),
            theta0_change: norm(dtheta.iter().copied()),
            end_half_change: mean(&dtheta[n / 2..]),
            base_half_change: mean(&dtheta[..n / 2]),
            end_half_change_symmetric: mean(&dtheta[n.div_ceil(2)..]),
            base_half_change_symmetric: mean(&dtheta[..n / 2]),
            stiffness_max_over_min: if positive.is_empty() { f64::NAN } else { kmax / kmin },
            stiffness_variation: sd / km,
        }
    }
}

/// Eq. (17) for N links: `R = ‖∂J/∂θ0‖₂ / ‖∂J/∂K‖₂` from the reduced gradient `dJ/d(θ0, K)`
/// (`N` angle entries, then `N + 1` stiffness entries). For two links it is the paper's ratio of
/// the two sensitivities (errata E5); `R > 1` is the paper's "the objective function is more
/// sensitive to change in θ0 in comparison to change in K".
pub fn sensitivity_ratio(energy_gradient: &[f64], n_links: usize) -> f64 {
    let (theta, k) = energy_gradient.split_at(n_links);
    norm(theta.iter().copied()) / norm(k.iter().copied())
}

/// Eq. (17) read as the paper derives it, a ratio of percentage changes: `R_rel =
/// ‖θ0 ∘ ∂J/∂θ0‖₂ / ‖K ∘ ∂J/∂K‖₂` (each partial times its variable: the change of `J` per relative
/// change of the variable, J). Dimensionless, unlike [`sensitivity_ratio`] (N·m/rad²), so `R > 1`
/// cannot hold by units alone.
pub fn relative_sensitivity_ratio(energy_gradient: &[f64], design: &Design) -> f64 {
    let n = design.theta0.len();
    let (theta, k) = energy_gradient.split_at(n);
    norm(theta.iter().zip(&design.theta0).map(|(g, t)| g * t))
        / norm(k.iter().zip(&design.stiffness).map(|(g, v)| g * v))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn change_measures() {
        let start = Design { theta0: vec![0.2, 0.0, -0.2, 0.0], stiffness: vec![100.0; 5] };
        let design = Design { theta0: vec![0.2, 0.0, -0.1, 0.1], stiffness: vec![100.0, 100.0, 300.0, 100.0, 100.0] };
        let c = DesignChange::new(&design, &start);
        assert!((c.theta0_change - 0.02f64.sqrt()).abs() < 1e-15);
        assert!((c.theta0_relative_change - 0.02f64.sqrt() / 0.08f64.sqrt()).abs() < 1e-15);
        assert!((c.stiffness_relative_change - 200.0 / (5.0f64.sqrt() * 100.0)).abs() < 1e-15);
        assert!((c.end_half_change - 0.1).abs() < 1e-15 && c.base_half_change == 0.0);
        // N = 4: the symmetric split is the same.
        assert_eq!(
            (c.end_half_change_symmetric, c.base_half_change_symmetric),
            (c.end_half_change, c.base_half_change)
        );
        // N = 5: the middle link (index 2) counts in the end half, in neither symmetrically.
        let start5 = Design { theta0: vec![0.0; 5], stiffness: vec![100.0; 6] };
        let moved5 = Design { theta0: vec![0.0, 0.0, 0.3, 0.0, 0.0], stiffness: vec![100.0; 6] };
        let c5 = DesignChange::new(&moved5, &start5);
        assert!((c5.end_half_change - 0.1).abs() < 1e-15 && c5.end_half_change_symmetric == 0.0);
        let g = [1.0, 2.0, 0.5, 0.0, 4.0];
        let d = Design { theta0: vec![0.5, -0.5], stiffness: vec![10.0, 20.0, 30.0] };
        // θ0 ∘ ∂J/∂θ0 = (0.5, −1), K ∘ ∂J/∂K = (5, 0, 120).
        assert!((relative_sensitivity_ratio(&g, &d) - 1.25f64.sqrt() / 14425f64.sqrt()).abs() < 1e-15);
        assert_eq!(c.stiffness_max_over_min, 3.0);
        let sd = (4.0 * 40.0f64.powi(2) + 160.0f64.powi(2)) / 5.0;
        assert!((c.stiffness_variation - sd.sqrt() / 140.0).abs() < 1e-15);
        assert_eq!(sensitivity_ratio(&[3.0, 4.0, 0.0, 1.0, 0.0], 2), 5.0);
    }
}
