//! The chain (fixed geometry and masses), the design `(θ0, K)` and a state `(θ, λ)`.

use serde::{Deserialize, Serialize};

/// The parts of the structure that the static design does not change.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Chain {
    /// Horizontal span `a_i` of each link in the unloaded design, m (length `N`).
    pub spans: Vec<f64>,
    /// Mass `m_i` of each link, kg (length `N`); a uniform rod, centre of mass at its middle.
    pub masses: Vec<f64>,
    /// Gravitational acceleration along −Y, m/s² (0 switches self-weight off).
    pub gravity: f64,
}

impl Chain {
    /// `N` equal spans `L_x / N`, massless links.
    pub fn uniform(n_links: usize, length_x: f64) -> Self {
        Self {
            spans: vec![length_x / n_links as f64; n_links],
            masses: vec![0.0; n_links],
            gravity: crate::STANDARD_GRAVITY,
        }
    }

    /// Number of links `N`.
    pub fn n_links(&self) -> usize {
        self.spans.len()
    }

    /// Total horizontal length `L_x = Σ a_i`, m: the end's X in the unloaded design.
    pub fn length_x(&self) -> f64 {
        self.spans.iter().sum()
    }
}

/// The links that spring `j` (`0..=N`) joins, `(j − 1, j)`: `None` for the ground side of the
/// base spring (`j = 0`) and the slider side of the end spring (`j = N`).
pub fn spring_links(n_links: usize, j: usize) -> (Option<usize>, Option<usize>) {
    (j.checked_sub(1), (j < n_links).then_some(j))
}

/// A design: unloaded link angles `θ0` (rad, length `N`) and spring stiffnesses `K`
/// (N·m/rad, length `N+1`, `K[0]` at the base, `K[N]` at the slider).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Design {
    pub theta0: Vec<f64>,
    pub stiffness: Vec<f64>,
}

/// A configuration of the chain: link angles `θ` (rad) and the slider's vertical reaction `λ` (N),
/// the Lagrange multiplier of the end constraint `Φ(θ) = 0`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct State {
    pub theta: Vec<f64>,
    pub lambda: f64,
}

impl State {
    /// The unloaded state of a design: `θ = θ0`, `λ = 0` (an exact equilibrium at zero load).
    pub fn unloaded(design: &Design) -> Self {
        Self { theta: design.theta0.clone(), lambda: 0.0 }
    }
}
