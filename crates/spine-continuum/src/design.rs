//! Eq. (33) posed for one physical rod, so that the chain of any `N` discretises the same design
//! problem and its optima can be followed as `N → ∞`.
//!
//! The rod spans `L_x` horizontally (nodes at `x_j = (j − 1) a`, `a = L_x/N`, as in the paper).
//! Every number of eq. (33) is given per unit length or as a function of `x`, never per node:
//! - loads: the transverse load `q` (N/m) lumped by the trapezoidal rule ([`Rod::chain`]: `q a`
//!   on the interior nodes, `q a/2` on the slider), the end force `P_X` (N) as the actuation;
//! - stiffness: bounds on the bending stiffness `EI = K a` (N·m²), so `K ∈ [EI_min/a, EI_max/a]`
//!   inside and twice that at the base and end springs (the clamps sit half a span from the
//!   first and last links' middles, [`crate::rod`]); `C_K = EI_max/a`, so the optimiser's
//!   `k = K/C_K` lies in `[EI_min/EI_max, 1]` at every `N`;
//! - shape: `|θ0| ≤ θ0_max`, the relative-angle bound as a curvature bound
//!   `|θ0_i − θ0_{i+1}| ≤ κ_max a`, and node heights `Y0 ∈ [h_min·ramp(x), h_max]` with the
//!   ramp of [`spine_design::DesignBounds::height_ramp`] (a per-node bound makes the problem
//!   infeasible once `a tan θ0_max < h_min`).
//!
//! At `N = 10` with `L_x = 1 m`, `q = −50 N/m`, `P_X = −400 N`, `EI ∈ [10, 1000] N·m²`,
//! `κ_max = (π/6)/0.1 m` and a ramp of 0.1 m this is the paper's 10-link problem (Sec. 5.1)
//! but for the base and end springs' doubled bounds and the slider's half load.

use crate::rod::Rod;
use serde::{Deserialize, Serialize};
use spine_check::{require, FieldError};
use spine_design::refine::interpolate;
use spine_design::{DesignBounds, DesignProblem, Objective};
use spine_model::Design;
use std::f64::consts::PI;

/// Eq. (33) for one rod (module docs). Lengths in m, loads in N and N/m, `EI` in N·m². In a case
/// file (`"kind": "continuum"`) every field is given.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RodDesign {
    /// `L_x`, m.
    pub length: f64,
    /// `q`, N/m along +Y (the passive load).
    pub transverse_load: f64,
    /// `P_X` at the end, N (the actuation).
    pub end_force: f64,
    /// `δ_d`, m.
    pub delta_d: f64,
    /// Bounds on `EI = K a`, N·m².
    pub bending_stiffness_min: f64,
    pub bending_stiffness_max: f64,
    /// `θ0_max`, rad.
    pub theta0_max: f64,
    /// `κ_max`, rad/m: the relative-angle bound is `κ_max a`.
    pub curvature_max: f64,
    /// `h_min`, `h_max` and the ramp length of the lower bound, m.
    pub height_min: f64,
    pub height_max: f64,
    pub height_ramp: f64,
    /// The start: the arch `Y0(x) = h_0 sin(π x/L_x)` (m) with `EI = EI_0` everywhere (N·m²).
    pub start_height: f64,
    pub start_bending_stiffness: f64,
}

impl RodDesign {
    /// Why this rod's problem cannot be posed, naming the field.
    pub fn validate(&self) -> Result<(), FieldError> {
        let positive = |field: &str, v: f64, unit: &str| {
            require(v.is_finite() && v > 0.0, field, || format!("must be a positive number ({unit}), got {v}"))
        };
        let finite = |field: &str, v: f64, unit: &str| {
            require(v.is_finite(), field, || format!("must be a finite number ({unit}), got {v}"))
        };
        positive("length", self.length, "m")?;
        finite("transverse_load", self.transverse_load, "N/m")?;
        finite("end_force", self.end_force, "N")?;
        require(self.delta_d.is_finite() && self.delta_d.abs() < self.length, "delta_d", || {
            format!("must be a displacement (m) smaller than the length {} in size, got {}", self.length, self.delta_d)
        })?;
        positive("bending_stiffness_min", self.bending_stiffness_min, "N·m²")?;
        require(
            self.bending_stiffness_max.is_finite() && self.bending_stiffness_max > self.bending_stiffness_min,
            "bending_stiffness_max",
            || format!("must be a finite number (N·m²) > bending_stiffness_min, got {}", self.bending_stiffness_max),
        )?;
        require(self.theta0_max > 0.0 && self.theta0_max < 0.5 * PI, "theta0_max", || {
            format!("must be in (0, π/2) rad, got {}", self.theta0_max)
        })?;
        positive("curvature_max", self.curvature_max, "rad/m")?;
        finite("height_min", self.height_min, "m")?;
        require(self.height_max.is_finite() && self.height_max > self.height_min, "height_max", || {
            format!("must be a finite height (m) > height_min, got {}", self.height_max)
        })?;
        require(
            self.height_ramp.is_finite() && (0.0..=0.5 * self.length).contains(&self.height_ramp),
            "height_ramp",
            || format!("must be a length (m) in [0, length / 2], got {}", self.height_ramp),
        )?;
        require(self.start_height.is_finite() && self.start_height.abs() < self.length, "start_height", || {
            format!("must be a height (m) smaller than the length in size, got {}", self.start_height)
        })?;
        positive("start_bending_stiffness", self.start_bending_stiffness, "N·m²")
    }

    /// The span `a = L_x/N`, m.
    pub fn span(&self, n: usize) -> f64 {
        self.length / n as f64
    }

    /// `x` of the middles of the `n` links, m (where `θ0_i` is drawn and interpolated).
    pub fn link_middles(&self, n: usize) -> Vec<f64> {
        (0..n).map(|i| (i as f64 + 0.5) * self.span(n)).collect()
    }

    /// `x` of the `n + 1` joints, m (where `EI_j` is drawn and interpolated).
    pub fn joints(&self, n: usize) -> Vec<f64> {
        (0..=n).map(|j| j as f64 * self.span(n)).collect()
    }

    /// `K_j = EI / a` for `EI`, with the base and end springs' factor 2 (`j = 0` and `j = N`).
    pub fn stiffness_of(&self, n: usize, j: usize, bending_stiffness: f64) -> f64 {
        let end = if j == 0 || j == n { 2.0 } else { 1.0 };
        end * bending_stiffness / self.span(n)
    }

    /// `EI_j` of the spring `K_j`, N·m² (the inverse of [`RodDesign::stiffness_of`]).
    pub fn bending_stiffness_of(&self, n: usize, j: usize, stiffness: f64) -> f64 {
        stiffness / self.stiffness_of(n, j, 1.0)
    }

    /// Eq. (33) for the chain of `n` links.
    pub fn problem(&self, n: usize) -> DesignProblem {
        let rod = Rod {
            length: self.length,
            bending_stiffness: self.bending_stiffness_max,
            end_force: self.end_force,
            transverse_load: self.transverse_load,
            mass_per_length: 0.0,
            gravity: spine_model::STANDARD_GRAVITY,
        };
        let (structure, _) = rod.chain(n);
        let bound = |ei: f64| (0..=n).map(|j| self.stiffness_of(n, j, ei)).collect::<Vec<_>>();
        DesignProblem {
            structure,
            delta_d: self.delta_d,
            bounds: DesignBounds {
                theta0_max: self.theta0_max,
                relative_angle_max: self.curvature_max * self.span(n),
                stiffness_min: bound(self.bending_stiffness_min),
                stiffness_max: bound(self.bending_stiffness_max),
                height_min: self.height_min,
                height_max: self.height_max,
                height_ramp: self.height_ramp,
            },
            stiffness_scale: self.bending_stiffness_max / self.span(n),
            objective: Objective::StrainEnergy,
            strain_energy_max: None,
        }
    }

    /// The start design of `n` links (the arch and `EI_0`, module docs).
    pub fn start(&self, n: usize) -> Design {
        let a = self.span(n);
        let y = |j: usize| self.start_height * (PI * j as f64 / n as f64).sin();
        Design {
            theta0: (0..n).map(|i| ((y(i + 1) - y(i)) / a).atan()).collect(),
            stiffness: (0..=n).map(|j| self.stiffness_of(n, j, self.start_bending_stiffness)).collect(),
        }
    }

    /// `coarse` (an optimum of `m` links) carried to `n` links: `θ0(x)` interpolated linearly
    /// between the coarse links' middles (so that the fine relative angles stay within the
    /// curvature bound `κ_max a`), then shifted by one constant so that the end meets the X axis
    /// again (`Φ(θ0) = 0`); `EI(x)` interpolated at the new joints. Both clamped into the bounds.
    pub fn prolong(&self, coarse: &Design, n: usize) -> Design {
        let m = coarse.theta0.len();
        let a_n = self.span(n);
        let theta = interpolate(&self.link_middles(m), &coarse.theta0, &self.link_middles(n));
        let limit = self.theta0_max;
        let shifted = |c: f64| theta.iter().map(|t| (t + c).clamp(-limit, limit)).collect::<Vec<f64>>();
        let end_height = |c: f64| shifted(c).iter().map(|t| a_n * t.tan()).sum::<f64>();
        // The end height rises with the shift: bisection for its zero within ±θ0_max.
        let (mut low, mut high) = (-2.0 * limit, 2.0 * limit);
        for _ in 0..100 {
            let mid = 0.5 * (low + high);
            if end_height(mid) > 0.0 {
                high = mid;
            } else {
                low = mid;
            }
        }
        let ei: Vec<f64> = (0..=m).map(|j| self.bending_stiffness_of(m, j, coarse.stiffness[j])).collect();
        let ei = interpolate(&self.joints(m), &ei, &self.joints(n));
        let (low_ei, high_ei) = (self.bending_stiffness_min, self.bending_stiffness_max);
        Design {
            theta0: shifted(0.5 * (low + high)),
            stiffness: (0..=n).map(|j| self.stiffness_of(n, j, ei[j].clamp(low_ei, high_ei))).collect(),
        }
    }
}

/// The paper's 10-link problem as a rod (module docs): `L_x = 1 m`, `q = −50 N/m`, `P_X = −400 N`,
/// `δ_d = −0.02 m`, `EI ∈ [10, 1000] N·m²`, `θ0_max = π/6`, `κ_max = (π/6)/0.1 m`, heights in
/// `[0.01·ramp(x), 0.25] m` with a 0.1 m ramp, from the arch of height 0.1 m with `EI = 100`.
pub fn paper_rod() -> RodDesign {
    RodDesign {
        length: 1.0,
        transverse_load: -50.0,
        end_force: -400.0,
        delta_d: -0.02,
        bending_stiffness_min: 10.0,
        bending_stiffness_max: 1000.0,
        theta0_max: PI / 6.0,
        curvature_max: (PI / 6.0) / 0.1,
        height_min: 0.01,
        height_max: 0.25,
        height_ramp: 0.1,
        start_height: 0.1,
        start_bending_stiffness: 100.0,
    }
}
