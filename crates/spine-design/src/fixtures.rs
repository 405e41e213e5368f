//! Ready-made design problems for tests, examples and benchmarks (the case files are the
//! user-facing way to state a problem).

use crate::problem::{DesignBounds, DesignProblem};
use spine_model::fixtures::{arch, uniform_loads};
use spine_model::{Chain, Design, NodalLoads, Structure};
use std::f64::consts::{FRAC_PI_6, PI};

/// The paper's bounds (Sec. 5) for `n` links over `L_x`: `|θ0| ≤ π/6`, relative angles `≤ π/6`,
/// `K ∈ [k_min, k_max]`, interior node heights in `[y_min, 0.25 L_x]`.
pub fn paper_bounds(n: usize, length_x: f64, k_min: f64, k_max: f64, y_min: f64) -> DesignBounds {
    DesignBounds {
        theta0_max: FRAC_PI_6,
        relative_angle_max: FRAC_PI_6,
        stiffness_min: vec![k_min; n + 1],
        stiffness_max: vec![k_max; n + 1],
        height_min: y_min,
        height_max: 0.25 * length_x,
        height_ramp: 0.0,
    }
}

/// The paper's static configurations (Sec. 5.1): `n` links over `L_x = 1 m`, `p_y` N at every node,
/// `p_x` N at the end, no link mass, `K ∈ [10², 10⁴]`, `y_min = 0.01 m`, with `δ_d` and `C_K` given.
pub fn paper_problem(n: usize, p_y: f64, p_x: f64, delta_d: f64, stiffness_scale: f64) -> DesignProblem {
    let loads = uniform_loads(n, p_y, p_x);
    DesignProblem {
        structure: Structure {
            chain: Chain::uniform(n, 1.0),
            passive: NodalLoads { p_x: vec![0.0; n + 1], p_y: loads.p_y },
            actuation: NodalLoads { p_x: loads.p_x, p_y: vec![0.0; n + 1] },
        },
        delta_d,
        bounds: paper_bounds(n, 1.0, 1e2, 1e4, 0.01),
        stiffness_scale,
        objective: crate::objective::Objective::StrainEnergy,
        strain_energy_max: None,
    }
}

/// The scaled family of `docs/PEERS.md`: `s = N/10`, `P_Y = −5 N` per node,
/// `P_X = −400 s N`, `K ∈ [10² s², 10⁴ s²]`, `y_min = 0.01 min(1, 10/N)`, `δ_d = −0.02 m`,
/// `C_K = s²`. At `N = 10` it is the paper's 10-link configuration.
pub fn scaled_family(n: usize) -> DesignProblem {
    let s = n as f64 / 10.0;
    let mut problem = paper_problem(n, -5.0, -400.0 * s, -0.02, s * s);
    problem.bounds = paper_bounds(n, 1.0, 1e2 * s * s, 1e4 * s * s, 0.01 * (10.0 / n as f64).min(1.0));
    problem
}

/// A start design for `n` links: the symmetric arch `θ0_i = amplitude cos(π (i + ½)/N)` with
/// every `K` equal to `stiffness` (the end spring included).
pub fn arch_start(n: usize, amplitude: f64, stiffness: f64) -> Design {
    let (_, mut design) = arch(n, 1.0, amplitude, stiffness);
    design.stiffness[n] = stiffness;
    design
}

/// The paper's 5-link start `{π/5, 0, 0, 0, −π/5, 10000, 250, 250, 250, 250, 0}` (outside its own
/// bounds; [`DesignProblem::project_start`] projects it).
pub fn paper_five_link_start() -> Design {
    Design { theta0: vec![PI / 5.0, 0.0, 0.0, 0.0, -PI / 5.0], stiffness: vec![1e4, 250.0, 250.0, 250.0, 250.0, 0.0] }
}
