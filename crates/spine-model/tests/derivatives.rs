//! Every derivative of the model against central finite differences, and the residual against the
//! gradient of the energy `U + V − λΦ` (two formulations of the same physics).

use num_dual::Dual64;
use spine_model::energy::{load_potential, strain_energy};
use spine_model::fixtures::random_problem;
use spine_model::jacobian::{design_jacobian, residual_and_state_jacobian};
use spine_model::kinematics::end_constraint;
use spine_model::residual::equilibrium_residual;
use spine_model::rng::SplitMix64;
use spine_model::{Design, NodalLoads, State};

const SIZES: [usize; 5] = [1, 2, 3, 10, 50];

/// Entry-wise check `|a − f| ≤ tol · max(|f|, floor)`, with `floor = 1e-6 · max |f|` over the matrix
/// so that entries that are zero up to rounding do not demand impossible relative accuracy.
fn assert_matrix_close(ad: &[Vec<f64>], fd: &[Vec<f64>], tol: f64, what: &str) {
    let big = fd.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let floor = 1e-6 * big;
    for (i, (ra, rf)) in ad.iter().zip(fd).enumerate() {
        for (j, (a, f)) in ra.iter().zip(rf).enumerate() {
            let err = (a - f).abs() / f.abs().max(floor).max(1e-300);
            assert!(err <= tol, "{what}[{i}][{j}]: AD {a:e} vs FD {f:e} (relative error {err:e})");
        }
    }
}

/// Central differences of `f` (vector valued) in each of `x`'s entries, as a dense matrix, with the
/// step `ε^{1/3}` that balances truncation and rounding.
fn central_differences(x: &[f64], f: impl Fn(&[f64]) -> Vec<f64>) -> Vec<Vec<f64>> {
    spine_model::finite_difference::central_jacobian(x, spine_model::finite_difference::CENTRAL_STEP, f)
}

/// Relative tolerance of the AD–FD comparison. AD is exact; what remains is the rounding of the
/// central difference, `ε · (size of the row's terms) / h`. With springs up to 10⁴ N·m/rad and
/// `|λ|` up to 100 N, that reaches 1.2e-6 of an entry of 0.06 N·m (the property test found two such
/// draws at N = 33 and 38), so the check allows 1e-5: ten times the worst rounding seen, while a
/// wrong derivative is off by O(1).
const FD_TOLERANCE: f64 = 1e-5;

fn check_state_jacobian(n: usize, seed: u64) {
    let (chain, design, loads, state) = random_problem(n, seed);
    let (r, jac) = residual_and_state_jacobian(&chain.spans, &design, &loads, &state);
    assert_eq!(r, equilibrium_residual(&chain.spans, &design, &loads, &state));
    let mut x = state.theta.clone();
    x.push(state.lambda);
    let fd = central_differences(&x, |x| {
        let s = State { theta: x[..n].to_vec(), lambda: x[n] };
        equilibrium_residual(&chain.spans, &design, &loads, &s)
    });
    assert_matrix_close(&jac.to_sparse().to_dense(), &fd, FD_TOLERANCE, &format!("dr/d(θ,λ) N={n} seed={seed}"));
}

fn check_design_jacobian(n: usize, seed: u64) {
    let (chain, design, loads, state) = random_problem(n, seed);
    let jac = design_jacobian(&chain.spans, &design, &loads, &state);
    assert_eq!((jac.nrows, jac.ncols), (n + 1, 2 * n + 1));
    assert!(jac.entries.len() <= 6 * n, "design Jacobian must stay sparse");
    let mut p = design.theta0.clone();
    p.extend(&design.stiffness);
    let fd = central_differences(&p, |p| {
        let d = Design { theta0: p[..n].to_vec(), stiffness: p[n..].to_vec() };
        equilibrium_residual(&chain.spans, &d, &loads, &state)
    });
    assert_matrix_close(&jac.to_dense(), &fd, FD_TOLERANCE, &format!("dr/d(θ0,K) N={n} seed={seed}"));
}

#[test]
fn jacobians_match_central_differences_at_the_listed_sizes() {
    for &n in &SIZES {
        for seed in 0..3 {
            check_state_jacobian(n, 100 * n as u64 + seed);
            check_design_jacobian(n, 200 * n as u64 + seed);
        }
    }
    // Draws the property test found where rounding exceeded 1e-6 (see FD_TOLERANCE).
    check_state_jacobian(38, 13025324799438442098);
    check_state_jacobian(33, 2050937072542431855);
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 64, rng_seed: proptest::test_runner::RngSeed::Fixed(64), ..Default::default() })]
    /// Over chain sizes, seeds and states (the fixture draws spans, masses, design, loads and a
    /// state that is not an equilibrium from the seed).
    #[test]
    fn jacobians_match_central_differences_for_any_chain(n in 1usize..40, seed in proptest::prelude::any::<u64>()) {
        check_state_jacobian(n, seed);
        check_design_jacobian(n, seed);
    }
}

/// The residual's joint rows are the gradient of `U + V − λΦ` (energy written separately, eq. (3)
/// and (31)); the gradient is taken by AD one direction at a time.
#[test]
fn residual_is_the_gradient_of_the_total_potential() {
    for &n in &SIZES {
        let (chain, design, _, state) = random_problem(n, 300 + n as u64);
        let mut rng = SplitMix64::new(7 + n as u64);
        let nodal = NodalLoads {
            p_x: (0..=n).map(|_| rng.uniform(-50.0, 50.0)).collect(),
            p_y: (0..=n).map(|_| rng.uniform(-50.0, 50.0)).collect(),
        };
        let loads = spine_model::LinkLoads::from_nodal(&chain, &nodal, true);
        let r = equilibrium_residual(&chain.spans, &design, &loads, &state);
        let lift = |v: &[f64]| v.iter().map(|&x| Dual64::from(x)).collect::<Vec<_>>();
        let theta0 = lift(&design.theta0);
        let stiffness = lift(&design.stiffness);
        for k in 0..n {
            let mut theta = lift(&state.theta);
            theta[k] = Dual64::from(state.theta[k]).derivative();
            let total = strain_energy(&theta, &theta0, &stiffness)
                + load_potential(&chain, &nodal, true, &theta0, &theta)
                - end_constraint(&chain.spans, &theta0, &theta) * state.lambda;
            let scale = r.iter().fold(1.0f64, |m, v| m.max(v.abs()));
            assert!(
                (total.eps - r[k]).abs() <= 1e-12 * scale,
                "N={n} row {k}: energy gradient {} vs residual {}",
                total.eps,
                r[k]
            );
        }
    }
}

#[test]
fn unloaded_design_is_an_exact_equilibrium() {
    let (chain, design) = spine_model::fixtures::arch(10, 1.0, 0.4, 500.0);
    let zero = spine_model::LinkLoads::zero(10);
    let r = equilibrium_residual(&chain.spans, &design, &zero, &State::unloaded(&design));
    assert!(r.iter().all(|v| v.abs() < 1e-15), "{r:?}");
}

/// Erratum E9: eq. (49)'s load derivative sums the nodal forces from `j = i` (and from an undefined
/// `k` in its first line). A force at the base node of link `i` does not move with `θ_i`, so the
/// sum runs over the nodes beyond the link, `j = i + 1 … N + 1` (paper numbering; the model's
/// `V_i`, `A_i` of docs/model.md). Central second differences of the load potential, which knows
/// nothing of either formula, show it: with one force at node 2 (0-based), `∂²V/∂θ_i²` vanishes for
/// link 2 (whose base node it is) and equals the model's `L_i (sin θ_i V_i + cos θ_i A_i)` for the
/// links before it, where the printed index would give link 2 a nonzero term.
#[test]
fn eq_49_sums_the_forces_beyond_the_link_not_from_its_base_node() {
    let chain = spine_model::Chain { spans: vec![0.25; 4], masses: vec![0.0; 4], gravity: 0.0 };
    let (p_y, p_x) = (-7.0, -30.0);
    let mut loads = NodalLoads { p_x: vec![0.0; 5], p_y: vec![0.0; 5] };
    (loads.p_y[2], loads.p_x[2]) = (p_y, p_x);
    let theta0 = [0.3, 0.1, -0.1, -0.3];
    let theta = [0.35, 0.05, -0.2, -0.25];
    let lengths = spine_model::kinematics::link_lengths(&chain.spans, &theta0);
    let v = |t: &[f64]| load_potential(&chain, &loads, false, &theta0, t);
    let h = 1e-4;
    for i in 0..4 {
        let at = |d: f64| {
            let mut t = theta;
            t[i] += d;
            v(&t)
        };
        let second = (at(h) - 2.0 * at(0.0) + at(-h)) / (h * h);
        let (s, c) = theta[i].sin_cos();
        // The model: forces beyond link i (nodes > i) only.
        let beyond = if i < 2 { lengths[i] * (s * p_y + c * p_x) } else { 0.0 };
        // As printed: forces from node i on, so link 2 also feels node 2's force.
        let printed = if i <= 2 { lengths[i] * (s * p_y + c * p_x) } else { 0.0 };
        assert!((second - beyond).abs() < 1e-6, "link {i}: ∂²V/∂θ² {second} vs {beyond}");
        if i == 2 {
            assert!((second - printed).abs() > 1.0, "the printed index would give link 2 {printed}");
        }
    }
}
