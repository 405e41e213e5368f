//! # spine-benchmarks: the evidence for speed and exactness
//!
//! The operations that `benches/derivatives.rs` times, written once here so that the tests in
//! `tests/agreement.rs` check the very same calls: the equilibrium residual (eq. (5)) and its
//! Jacobian three ways (forward AD, the paper's hand-derived eqs. (47)–(53), central differences),
//! one Newton step, the gradients of `J` and of the end position with respect to `(θ0, K)` four
//! ways (AD adjoint, hand adjoint of Appendices I–II, direct forward AD, central differences), and
//! the sparse Hessian of the Lagrangian of eq. (33) by second-order AD.
//!
//! Fixtures are families that grow with `N` without changing character:
//! * [`scaled_arch`]: an arch under transverse and axial load (equilibrium benchmarks);
//! * [`DesignFixture`]: the scaled family of `docs/PEERS.md` at the arch start (design
//!   benchmarks; at `N = 10` it is the paper's 10-link configuration).
//!
//! Modules:
//!
//! * `ad_peers`: CasADi's automatic differentiation beside the workspace's (`just bench-ad-peers`):
//!   the same residual Jacobian and Lagrangian Hessian of eq. (33), built as CasADi SX functions
//!   (`benchmarks/peers/casadi_ad.py`) and evaluated inside CasADi, its virtual machine and its
//!   generated C code compiled with `gcc -O3`, each over a batch so that Python's call overhead
//!   does not count; ours timed in the same run on the same point.
//! * `cli`: Command-line arguments of the benchmark programs: a bad argument is a usage error (the
//!   argument, what is allowed, exit code 2), never a panic.
//! * `kkt`: KKT matrices Ipopt factorised in real eq. (33) solves (recorded with `SPINE_KKT_DUMP`),
//!   for the factorisation benchmark and the agreement of the workspace's `LDLᵀ` with MUMPS on
//!   them.
//! * `peers`: The side-by-side comparison of eq. (33) with CasADi + IPOPT (`just bench-peers`): one
//!   row per N, both programs on the same case file from the same start point.
//! * `report`: `just bench` → `benchmarks/RESULTS.md` and `benchmarks/scaling.svg`: criterion's
//!   mean times read back from `target/criterion`, the fitted exponent `p` of `time ∝ N^p` per
//!   benchmark, the targets of the benchmark issue checked against them, and the CasADi comparison
//!   of `just bench-peers` when it has been run (`benchmarks/peers/results.json`).
//! * `report_merge`: `benchmarks/RESULTS.md` written by a run that measured part of it: `just
//!   bench-peers` has no criterion data unless `just bench` ran in the same tree, and a fresh clone
//!   has none.
//! * `targets`: The targets the benchmark issues set, checked against the measurements: criterion's
//!   (AD against the hand code, the Hessian, the fitted exponents, the KKT factorisation) and the
//!   peers run's (eq. (33) against CasADi).
#![forbid(unsafe_code)]

pub mod ad_peers;
pub mod cli;
pub mod kkt;
pub mod peers;
pub mod report;
pub mod report_merge;
pub mod targets;

use spine_design::adjoint::{self, ReducedGradients};
use spine_design::assembly::Assembled;
use spine_design::fixtures::{arch_start, scaled_family};
use spine_design::full_space::{self, Layout, StateForm};
use spine_design::DesignProblem;
use spine_model::finite_difference::{self, CENTRAL_STEP};
use spine_model::fixtures::{arch, uniform_loads};
use spine_model::rng::SplitMix64;
use spine_model::sparse::BorderedTridiagonal;
use spine_model::{hand, jacobian, residual, Design, LinkLoads, State, Structure};
use spine_solve::linalg::BorderedLu;
use spine_solve::{solve_static, ContinuationOptions, StaticProblem};

/// The equilibrium benchmark problem for `n` links: `s = N/10`, `K = 10³ s²` N·m/rad,
/// `P_X = −400 s` N at the end, `P_Y = −5` N per node, `L_x = 1` m, link mass `0.5/N` kg, on a
/// symmetric arch of amplitude 0.4 rad.
pub fn scaled_arch(n: usize) -> StaticProblem {
    let s = n as f64 / 10.0;
    let (mut chain, design) = arch(n, 1.0, 0.4, 1e3 * s * s);
    chain.masses = vec![0.5 / n as f64; n];
    let mut passive = uniform_loads(n, -5.0, 0.0);
    passive.p_x = vec![0.0; n + 1];
    StaticProblem { structure: Structure { chain, passive, actuation: uniform_loads(n, 0.0, -400.0 * s) }, design }
}

// The fixtures below panic, naming the property, where one of their own points lacks what they
// are built on (an equilibrium at full load, a regular Jacobian, Newton converging next to it):
// benchmarks/tests/agreement.rs builds every fixture at the sizes of its tests and checks those
// properties there.
/// The loaded equilibrium of [`scaled_arch`]: a point where every Jacobian entry is nonzero
/// (`λ ≠ 0`, bent links, self-weight on).
pub struct StateFixture {
    pub spans: Vec<f64>,
    pub design: Design,
    pub loads: LinkLoads,
    pub state: State,
}

impl StateFixture {
    pub fn new(n: usize) -> Self {
        let problem = scaled_arch(n);
        let solution = solve_static(&problem, &ContinuationOptions::default());
        let loaded = solution.loaded.expect("the scaled arch has a loaded equilibrium");
        assert_eq!(loaded.load_factor, 1.0, "N = {n}: the scaled arch reaches full load");
        StateFixture {
            loads: problem.total_loads(),
            spans: problem.structure.chain.spans,
            design: problem.design,
            state: loaded.state,
        }
    }

    /// The residual of eq. (5).
    pub fn residual(&self) -> Vec<f64> {
        residual::equilibrium_residual(&self.spans, &self.design, &self.loads, &self.state)
    }

    /// Residual and `∂r/∂(θ, λ)` by element-wise forward AD.
    pub fn jacobian_ad(&self) -> (Vec<f64>, BorderedTridiagonal) {
        jacobian::residual_and_state_jacobian(&self.spans, &self.design, &self.loads, &self.state)
    }

    /// Residual and `∂r/∂(θ, λ)` from the hand-derived entries (eqs. (46)–(49)).
    pub fn jacobian_hand(&self) -> (Vec<f64>, BorderedTridiagonal) {
        (self.residual(), hand::state_jacobian(&self.spans, &self.design, &self.loads, &self.state))
    }

    /// Residual and `∂r/∂(θ, λ)` by hand in one fused loop (one `sin_cos` and one `L_i` per
    /// joint): the best hand code.
    pub fn jacobian_hand_fused(&self) -> (Vec<f64>, BorderedTridiagonal) {
        hand::residual_and_state_jacobian(&self.spans, &self.design, &self.loads, &self.state)
    }

    /// Residual and `∂r/∂(θ, λ)` by element-wise central differences.
    pub fn jacobian_fd(&self) -> (Vec<f64>, BorderedTridiagonal) {
        finite_difference::residual_and_state_jacobian(
            &self.spans,
            &self.design,
            &self.loads,
            &self.state,
            CENTRAL_STEP,
        )
    }

    /// One Newton step on `(θ, λ)` from `start`: residual and AD Jacobian, the O(N) bordered
    /// factorisation, the solve. Returns the new state.
    pub fn newton_step(&self, start: &State) -> State {
        let (r, jac) = jacobian::residual_and_state_jacobian(&self.spans, &self.design, &self.loads, start);
        let step = BorderedLu::factor(&jac).expect("nonsingular at the fixture").solve(&r);
        let n = start.theta.len();
        State { theta: start.theta.iter().zip(&step).map(|(t, d)| t - d).collect(), lambda: start.lambda - step[n] }
    }

    /// The equilibrium with every angle moved by `size` rad (alternating signs): a Newton start.
    pub fn perturbed(&self, size: f64) -> State {
        let theta =
            self.state.theta.iter().enumerate().map(|(i, t)| t + if i % 2 == 0 { size } else { -size }).collect();
        State { theta, lambda: self.state.lambda }
    }
}

/// Eq. (33) on the scaled family at its arch start (`θ0` amplitude 0.3 rad, `K = 10³ s²`), with
/// both equilibria of the start design.
pub struct DesignFixture {
    pub problem: DesignProblem,
    pub design: Design,
    pub passive: State,
    pub loaded: State,
}

impl DesignFixture {
    pub fn new(n: usize) -> Self {
        let problem = scaled_family(n);
        let s = n as f64 / 10.0;
        let design = arch_start(n, 0.3, 1e3 * s * s);
        let opts = ContinuationOptions { residual_tolerance: 1e-12, ..ContinuationOptions::default() };
        let solution = solve_static(&problem.static_problem(&design), &opts);
        assert_eq!(solution.passive.load_factor, 1.0, "N = {n}: passive equilibrium of the start");
        let loaded = solution.loaded.expect("loaded equilibrium of the start");
        assert_eq!(loaded.load_factor, 1.0, "N = {n}: loaded equilibrium of the start");
        DesignFixture { problem, design, passive: solution.passive.state, loaded: loaded.state }
    }

    /// `dJ/d(θ0, K)` and `dX/d(θ0, K)` by the implicit-function-theorem adjoint with AD partials.
    pub fn gradients_ad(&self) -> ReducedGradients {
        adjoint::adjoint_ad(&self.problem, &self.design, &self.passive, &self.loaded).expect("nonsingular")
    }

    /// The same by the hand-derived adjoint of Appendices I and II.
    pub fn gradients_hand(&self) -> ReducedGradients {
        adjoint::adjoint_hand(&self.problem, &self.design, &self.passive, &self.loaded).expect("nonsingular")
    }

    /// The same by the direct method (one forward sensitivity per design variable), AD partials.
    pub fn gradients_forward(&self) -> ReducedGradients {
        adjoint::forward_ad(&self.problem, &self.design, &self.passive, &self.loaded).expect("nonsingular")
    }

    /// The same by central differences of re-solved equilibria.
    pub fn gradients_fd(&self) -> ReducedGradients {
        let opts = ContinuationOptions { residual_tolerance: 1e-13, ..ContinuationOptions::default() };
        adjoint::central_differences(&self.problem, &self.design, &self.passive, &self.loaded, 1e-5, &opts)
            .expect("Newton converges next to the fixture")
    }

    /// The full-space point of the fixture (design, both equilibria in `states`' form, node heights).
    pub fn full_space_point(&self, states: StateForm) -> Vec<f64> {
        let layout = Layout::of(&self.problem, states);
        let heights = self.problem.node_heights(&self.design.theta0);
        layout.pack(&self.design, self.problem.stiffness_scale, &self.passive, &self.loaded, &heights)
    }
}

/// The Hessian of the Lagrangian of eq. (33) in the full space at [`DesignFixture`]'s point, with
/// fixed multipliers drawn from `[−1, 1]` (seeded).
pub struct HessianFixture {
    pub assembled: Assembled,
    pub x: Vec<f64>,
    pub sigma: f64,
    pub lambda: Vec<f64>,
}

impl HessianFixture {
    /// With the states in `states`' form.
    pub fn new(design: &DesignFixture, states: StateForm) -> Self {
        let layout = Layout::of(&design.problem, states);
        let mut rng = SplitMix64::new(17);
        let lambda = (0..layout.num_constraints()).map(|_| rng.uniform(-1.0, 1.0)).collect();
        HessianFixture {
            assembled: full_space::assemble(&design.problem, states),
            x: design.full_space_point(states),
            sigma: 1.0,
            lambda,
        }
    }

    /// The lower-triangle values of `σ ∇²f + Σ λ_r ∇²g_r` (positions as in `patterns.hessian`).
    pub fn hessian(&self, values: &mut [f64]) {
        self.assembled.hessian(&self.x, self.sigma, &self.lambda, values);
    }

    /// `∇_x L = σ ∇f + Jᵀ λ` at `x` by first-order AD (the finite-difference reference of the
    /// Hessian differentiates this).
    pub fn lagrangian_gradient(&self, x: &[f64]) -> Vec<f64> {
        let mut gradient = vec![0.0; x.len()];
        let mut jacobian = vec![0.0; self.assembled.patterns.jacobian.len()];
        self.assembled.first_derivatives(x, &mut gradient, &mut jacobian);
        for g in gradient.iter_mut() {
            *g *= self.sigma;
        }
        for (&(r, c), v) in self.assembled.patterns.jacobian.iter().zip(&jacobian) {
            gradient[c] += self.lambda[r] * v;
        }
        gradient
    }
}

/// The heading of `benchmarks/DYNAMICS.md`'s section written by `just bench-gradients`; `just
/// bench-dynamics` rewrites the rest of the file and keeps it.
pub const GRADIENTS_SECTION: &str = "## Gradients of eq. (37): the discrete adjoint against forward sensitivities";

/// `text` followed by the section of `old` that starts at `heading` (if any).
pub fn keep_section(text: &str, old: &str, heading: &str) -> String {
    match old.find(heading) {
        Some(i) => format!("{}\n\n{}", text.trim_end(), &old[i..]),
        None => text.to_string(),
    }
}
