//! The rod the chain discretises, and the chain of `N` links that discretises it.
//!
//! A uniform planar rod of length `L` and bending stiffness `EI`, clamped at the base (`θ(0) = 0`,
//! at the origin), its end sliding on the X axis with its orientation held (`y(L) = 0`,
//! `θ(L) = 0`): the boundary conditions of the chain, whose end spring joins the last link to a
//! slider of fixed orientation. Loads: an axial end force `P_X`, a transverse load `q` per unit
//! length and self-weight `ρA g`.
//!
//! The chain of `N` links (span `a = L/N`, straight: `θ0 = 0`) whose energy is the rod's
//! `½∫ EI θ'² ds` by the midpoint rule with `θ_i` the angle at the link's middle `s = (i − ½) a`:
//! - an interior joint between two links carries `K = EI/a` (`θ'` over one span `a`);
//! - the base and end springs carry `K_1 = K_{N+1} = 2EI/a`: the clamp sits half a span from the
//!   first (last) link's middle, `½ EI (θ_1/(a/2))² (a/2) = ½ (2EI/a) θ_1²`;
//! - the transverse load is lumped on the nodes by the trapezoidal rule (`q a` on each interior
//!   node, `q a/2` on the slider node, whose force only the slider's reaction `λ` takes, and which
//!   makes every link's resultant `q (L − s)` at its middle, as the rod's);
//! - each link carries the mass `ρA a` at its middle.
//!
//! Every approximation is of second order in `a`: the chain's equilibria converge to the rod's as
//! `O(1/N²)`.

use serde::Serialize;
use spine_model::{Chain, Design, NodalLoads, Structure};

/// A uniform rod clamped at the base, its end sliding on X with its orientation held.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Rod {
    /// `L`, m.
    pub length: f64,
    /// `EI`, N·m².
    pub bending_stiffness: f64,
    /// `P_X` at the end, N (negative pushes the end toward the base).
    pub end_force: f64,
    /// `q`, N/m along +Y (negative: down).
    pub transverse_load: f64,
    /// `ρA`, kg/m, with gravity `g` (m/s²) along −Y.
    pub mass_per_length: f64,
    pub gravity: f64,
}

impl Rod {
    /// The transverse load per unit length with self-weight, `w = q − ρA g`, N/m.
    pub fn distributed_load(&self) -> f64 {
        self.transverse_load - self.mass_per_length * self.gravity
    }

    /// Euler's critical axial load of this rod's straight state, `P_cr = 4π² EI / L²`, N: both
    /// ends clamped in rotation, one free to slide axially (the first mode, `θ = sin(2πs/L)`,
    /// satisfies `θ(0) = θ(L) = 0` and `∫θ = 0`).
    pub fn euler_critical_load(&self) -> f64 {
        4.0 * std::f64::consts::PI.powi(2) * self.bending_stiffness / self.length.powi(2)
    }

    /// The chain of `n` links that discretises this rod (module docs): its structure (the passive
    /// load the transverse load and self-weight, the actuation the end force) and its straight
    /// design.
    pub fn chain(&self, n: usize) -> (Structure, Design) {
        let a = self.length / n as f64;
        let k = self.bending_stiffness / a;
        let mut stiffness = vec![k; n + 1];
        stiffness[0] = 2.0 * k;
        stiffness[n] = 2.0 * k;
        let mut passive = NodalLoads::zero(n);
        for j in 1..=n {
            passive.p_y[j] = self.transverse_load * a * if j == n { 0.5 } else { 1.0 };
        }
        let mut actuation = NodalLoads::zero(n);
        actuation.p_x[n] = self.end_force;
        let chain = Chain { spans: vec![a; n], masses: vec![self.mass_per_length * a; n], gravity: self.gravity };
        (Structure { chain, passive, actuation }, Design { theta0: vec![0.0; n], stiffness })
    }
}
