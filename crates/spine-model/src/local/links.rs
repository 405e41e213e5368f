//! The link, height and spring elements of eq. (33): a link's rise and run, a step of the unloaded
//! node heights, a spring's strain energy, and the relative angle of two links.

use super::Element;
use crate::jet::Elementary;
use crate::kinematics::{link_length, link_rise};

/// A link's rise `L_i sin θ_i = a_i sin θ_i / cos θ0_i`, m; local variables `[θ_i, θ0_i]`, or
/// `[u_i, θ0_i]` with `θ_i = θ0_i + u_i` when `deflection`. Summed over the links it is `Φ(θ)`
/// (the end constraint).
#[derive(Clone, Copy, Debug)]
pub struct LinkRise {
    pub span: f64,
    pub deflection: bool,
}

/// `θ_i` from a link element's first local variable (`θ_i` itself, or `u_i` with `θ0_i` second).
pub(super) fn link_angle<D: Elementary>(x: &[D; 2], deflection: bool) -> D {
    if deflection {
        x[1] + x[0]
    } else {
        x[0]
    }
}

impl Element<2> for LinkRise {
    const HESSIAN_PAIRS: &'static [(usize, usize)] = &[(0, 0), (1, 0), (1, 1)];
    fn eval<D: Elementary>(&self, x: &[D; 2]) -> D {
        link_rise(self.span, x[1], link_angle(x, self.deflection))
    }
    fn eval_moving<D: Elementary>(&self, rates: &Self, lift: impl Fn(f64, f64) -> D, x: &[D; 2]) -> D {
        link_rise(lift(self.span, rates.span), x[1], link_angle(x, self.deflection))
    }
}

/// A link's run `L_i cos θ_i = a_i cos θ_i / cos θ0_i`, m; local variables as [`LinkRise`]'s.
/// Summed over the links it is `X_{N+1}(θ)`.
#[derive(Clone, Copy, Debug)]
pub struct LinkRun {
    pub span: f64,
    pub deflection: bool,
}

impl Element<2> for LinkRun {
    const HESSIAN_PAIRS: &'static [(usize, usize)] = &[(0, 0), (1, 0), (1, 1)];
    fn eval<D: Elementary>(&self, x: &[D; 2]) -> D {
        link_length(self.span, x[1]) * link_angle(x, self.deflection).cos()
    }
    fn eval_moving<D: Elementary>(&self, rates: &Self, lift: impl Fn(f64, f64) -> D, x: &[D; 2]) -> D {
        link_length(lift(self.span, rates.span), x[1]) * link_angle(x, self.deflection).cos()
    }
}

/// One step of the unloaded node heights, `Y0_{j+1} − Y0_j − a_j tan θ0_j` (m), local variables
/// `[Y0_{j+1}, Y0_j, θ0_j]`. Zero for every link is the lifted form of the node heights
/// `Y0_j = Σ_{k<j} a_k tan θ0_k`; with `Y0_1 = Y0_{N+1} = 0` it contains `Φ(θ0) = 0`.
#[derive(Clone, Copy, Debug)]
pub struct HeightStep {
    pub span: f64,
}

impl Element<3> for HeightStep {
    const HESSIAN_PAIRS: &'static [(usize, usize)] = &[(2, 2)];
    fn eval<D: Elementary>(&self, x: &[D; 3]) -> D {
        x[0] - x[1] - x[2].tan() * self.span
    }
    fn eval_moving<D: Elementary>(&self, rates: &Self, lift: impl Fn(f64, f64) -> D, x: &[D; 3]) -> D {
        x[0] - x[1] - x[2].tan() * lift(self.span, rates.span)
    }
}

/// Spring `j`'s strain energy `½ K_j (Δθ_j − Δθ_{j−1})²`, J, with `K_j = C_K k_j`; local
/// variables `[θ_{j−1}, θ0_{j−1}, θ_j, θ0_j, k_j]` (a missing neighbour holds zero).
#[derive(Clone, Copy, Debug)]
pub struct SpringEnergy {
    pub stiffness_scale: f64,
}

/// Every lower-triangle pair of the five spring slots `[θ_{j−1}, θ0_{j−1}, θ_j, θ0_j, k_j]`, row by
/// row; the last, `(4, 4)`, is `∂²/∂k²`.
pub(super) const SPRING_SLOT_PAIRS: [(usize, usize); 15] = [
    (0, 0),
    (1, 0),
    (1, 1),
    (2, 0),
    (2, 1),
    (2, 2),
    (3, 0),
    (3, 1),
    (3, 2),
    (3, 3),
    (4, 0),
    (4, 1),
    (4, 2),
    (4, 3),
    (4, 4),
];

impl Element<5> for SpringEnergy {
    // Linear in `k_j`: every pair but `(4, 4)`.
    const HESSIAN_PAIRS: &'static [(usize, usize)] = SPRING_SLOT_PAIRS.split_at(14).0;
    fn eval<D: Elementary>(&self, x: &[D; 5]) -> D {
        let rel = (x[2] - x[3]) - (x[0] - x[1]);
        x[4] * self.stiffness_scale * rel * rel * 0.5
    }
    fn eval_moving<D: Elementary>(&self, rates: &Self, lift: impl Fn(f64, f64) -> D, x: &[D; 5]) -> D {
        let rel = (x[2] - x[3]) - (x[0] - x[1]);
        x[4] * lift(self.stiffness_scale, rates.stiffness_scale) * rel * rel * 0.5
    }
}

/// [`SpringEnergy`] on deflections: `½ K_j (u_j − u_{j−1})²`, J, with `K_j = C_K k_j` and the
/// deflections `u = θ − θ0`; local variables `[u_{j−1}, u_j, k_j]` (a missing neighbour holds zero).
#[derive(Clone, Copy, Debug)]
pub struct DeflectionSpringEnergy {
    pub stiffness_scale: f64,
}

impl Element<3> for DeflectionSpringEnergy {
    const HESSIAN_PAIRS: &'static [(usize, usize)] = &[(0, 0), (1, 0), (1, 1), (2, 0), (2, 1)];
    fn eval<D: Elementary>(&self, x: &[D; 3]) -> D {
        let rel = x[1] - x[0];
        x[2] * self.stiffness_scale * rel * rel * 0.5
    }
    fn eval_moving<D: Elementary>(&self, rates: &Self, lift: impl Fn(f64, f64) -> D, x: &[D; 3]) -> D {
        let rel = x[1] - x[0];
        x[2] * lift(self.stiffness_scale, rates.stiffness_scale) * rel * rel * 0.5
    }
}

/// The difference of two variables `x_0 − x_1` (the relative angle `θ0_i − θ0_{i+1}`); linear.
#[derive(Clone, Copy, Debug)]
pub struct Difference;

impl Element<2> for Difference {
    const HESSIAN_PAIRS: &'static [(usize, usize)] = &[];
    fn eval<D: Elementary>(&self, x: &[D; 2]) -> D {
        x[0] - x[1]
    }
    fn eval_moving<D: Elementary>(&self, _: &Self, _: impl Fn(f64, f64) -> D, x: &[D; 2]) -> D {
        self.eval(x)
    }
}
