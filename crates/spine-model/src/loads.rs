//! Loads: nodal forces and their per-link resultants (eq. (48) of the paper).

use crate::Chain;
use serde::{Deserialize, Serialize};

/// Constant nodal forces, N, positive along +X / +Y, one entry per node (`N+1`, node 0 the base).
///
/// A force at the base does nothing. A vertical force at the slider (node `N`) only changes the
/// reaction `λ`. Transverse loads pointing down are negative; the paper's axial `−400 N` at the
/// slider pushes the end towards the base.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NodalLoads {
    pub p_x: Vec<f64>,
    pub p_y: Vec<f64>,
}

impl NodalLoads {
    /// No force at any of the `n_links + 1` nodes.
    pub fn zero(n_links: usize) -> Self {
        Self { p_x: vec![0.0; n_links + 1], p_y: vec![0.0; n_links + 1] }
    }

    /// The node-by-node sum of two loads on the same chain (passive plus actuation).
    pub fn plus(&self, other: &NodalLoads) -> NodalLoads {
        let add = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x + y).collect();
        NodalLoads { p_x: add(&self.p_x, &other.p_x), p_y: add(&self.p_y, &other.p_y) }
    }
}

/// The resultants `(vertical, axial)` of [`LinkLoads`] (eq. (48)) from the nodal forces `p_y`,
/// `p_x` (N, `N + 1` each), the link masses (kg, `N`) and gravity `g` (m/s²), in any number type
/// (plain numbers, or duals carrying their rates along a parameter of the problem).
pub fn resultants<T: crate::Scalar>(p_y: &[T], p_x: &[T], masses: &[T], gravity: T) -> (Vec<T>, Vec<T>) {
    let n = masses.len();
    let mut vertical = vec![T::zero(); n];
    let mut axial = vec![T::zero(); n];
    let (mut sum_y, mut sum_x, mut mass_beyond) = (T::zero(), T::zero(), T::zero());
    for i in (0..n).rev() {
        sum_y += p_y[i + 1];
        sum_x += p_x[i + 1];
        vertical[i] = sum_y - gravity * (masses[i] * 0.5 + mass_beyond);
        axial[i] = sum_x;
        mass_beyond += masses[i];
    }
    (vertical, axial)
}

/// Per-link load resultants that the generalised load needs (paper eq. (48), `A P_Y` and `A P_X`):
///
/// * `vertical[i] = Σ_{j>i} P_Y,j − g (½ m_i + Σ_{k>i} m_k)`, N: everything hanging beyond the
///   start of link `i`, self-weight included;
/// * `axial[i] = Σ_{j>i} P_X,j`, N.
///
/// The generalised load on link `i` is then `P_i = L_i (cos θ_i · vertical_i − sin θ_i · axial_i)`.
/// Resultants are linear in the forces, so load continuation interpolates them ([`LinkLoads::lerp`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LinkLoads {
    pub vertical: Vec<f64>,
    pub axial: Vec<f64>,
}

impl LinkLoads {
    /// No load on a chain of `n_links` links (self-weight off too).
    pub fn zero(n_links: usize) -> Self {
        Self { vertical: vec![0.0; n_links], axial: vec![0.0; n_links] }
    }

    /// Resultants of the nodal forces, plus the chain's self-weight when `with_weight`.
    pub fn from_nodal(chain: &Chain, nodal: &NodalLoads, with_weight: bool) -> Self {
        let n = chain.n_links();
        assert_eq!(nodal.p_x.len(), n + 1, "p_x needs one entry per node");
        assert_eq!(nodal.p_y.len(), n + 1, "p_y needs one entry per node");
        let g = if with_weight { chain.gravity } else { 0.0 };
        let (vertical, axial) = resultants(&nodal.p_y, &nodal.p_x, &chain.masses, g);
        Self { vertical, axial }
    }

    /// `(1 − s) · from + s · to`: the load at continuation parameter `s`.
    pub fn lerp(from: &Self, to: &Self, s: f64) -> Self {
        let (vertical, axial) = (0..from.vertical.len()).map(|i| Self::lerp_at(from, to, s, i)).unzip();
        Self { vertical, axial }
    }

    /// `(vertical_i, axial_i)` of [`Self::lerp`], N, without writing the blend out.
    pub fn lerp_at(from: &Self, to: &Self, s: f64, i: usize) -> (f64, f64) {
        let mix = |x: f64, y: f64| x + s * (y - x);
        (mix(from.vertical[i], to.vertical[i]), mix(from.axial[i], to.axial[i]))
    }

    /// Largest resultant magnitude, N: a scale for tolerances.
    pub fn magnitude(&self) -> f64 {
        self.vertical.iter().chain(&self.axial).fold(0.0, |m, v| m.max(v.abs()))
    }
}
