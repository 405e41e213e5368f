//! The equations of motion against independent computations: the mass matrix and centrifugal terms
//! from the kinetic energy by AD, the two-link chain by hand, and the static equilibrium.

use num_dual::{Dual64, HyperDual64};
use spine_dynamics::articulated::ArticulatedChain;
use spine_dynamics::{Dynamics, Forcing};
use spine_model::fixtures::{arch, random_problem, uniform_loads};
use spine_model::rng::SplitMix64;
use spine_model::{Chain, Design, NodalLoads};

fn random_dynamics(n: usize, seed: u64) -> (Dynamics, Vec<f64>, Vec<f64>) {
    let (mut chain, design, _, state) = random_problem(n, seed);
    let mut rng = SplitMix64::new(seed + 100);
    chain.masses = (0..n).map(|_| rng.uniform(0.1, 1.0)).collect();
    let damping = (0..=n).map(|_| rng.uniform(1.0, 100.0)).collect();
    let passive = uniform_loads(n, -5.0, 0.0);
    let actuation = uniform_loads(n, 0.0, -100.0);
    let dynamics = Dynamics::new(&chain, &design, damping, &passive, &actuation, Forcing::Step);
    let omega = (0..n).map(|_| rng.uniform(-3.0, 3.0)).collect();
    (dynamics, state.theta, omega)
}

#[test]
fn mass_matrix_is_the_hessian_of_the_kinetic_energy_and_positive_definite() {
    for (n, seed) in [(1, 1), (2, 2), (5, 3), (9, 4)] {
        let (dynamics, theta, omega) = random_dynamics(n, seed);
        let m = dynamics.mass_matrix(&theta);
        for i in 0..n {
            for j in 0..n {
                assert_eq!(m[i][j], m[j][i], "symmetric");
                let w: Vec<HyperDual64> = omega
                    .iter()
                    .enumerate()
                    .map(|(k, &v)| {
                        let e1 = if k == i { 1.0 } else { 0.0 };
                        let e2 = if k == j { 1.0 } else { 0.0 };
                        HyperDual64::new(v, e1, e2, 0.0)
                    })
                    .collect();
                let th: Vec<HyperDual64> = theta.iter().map(|&t| HyperDual64::from(t)).collect();
                let t = dynamics.kinetic_energy(&th, &w);
                assert!((t.eps1eps2 - m[i][j]).abs() <= 1e-12 * m[i][i].abs().max(1e-12), "M[{i}][{j}] (n = {n})");
            }
        }
        // T = ½ ωᵀ M ω, and every Rayleigh quotient is positive.
        let t: f64 = 0.5 * (0..n).map(|i| (0..n).map(|j| omega[i] * m[i][j] * omega[j]).sum::<f64>()).sum::<f64>();
        assert!((t - dynamics.kinetic_energy(&theta, &omega)).abs() < 1e-12 * t.abs().max(1.0));
        let mut rng = SplitMix64::new(seed);
        for _ in 0..20 {
            let v: Vec<f64> = (0..n).map(|_| rng.uniform(-1.0, 1.0)).collect();
            let q: f64 = (0..n).map(|i| (0..n).map(|j| v[i] * m[i][j] * v[j]).sum::<f64>()).sum();
            assert!(q > 0.0);
        }
    }
}

#[test]
fn centrifugal_terms_follow_from_the_kinetic_energy() {
    // Lagrange: h = Ṁ θ̇ − ∂T/∂θ, with Ṁ θ̇ = Σ_k ∂(M θ̇)/∂θ_k θ̇_k, both by AD of independent code.
    for (n, seed) in [(2, 5), (4, 6), (8, 7)] {
        let (dynamics, theta, omega) = random_dynamics(n, seed);
        let h = dynamics.velocity_terms(&theta, &omega);
        let th: Vec<Dual64> = theta.iter().zip(&omega).map(|(&t, &w)| Dual64::new(t, w)).collect();
        let m = dynamics.mass_matrix(&th);
        let w: Vec<Dual64> = omega.iter().map(|&v| Dual64::from(v)).collect();
        for i in 0..n {
            let m_dot_omega: f64 = (0..n).map(|j| (m[i][j] * w[j]).eps).sum();
            let th_i: Vec<Dual64> = theta
                .iter()
                .enumerate()
                .map(|(k, &t)| if k == i { Dual64::from(t).derivative() } else { Dual64::from(t) })
                .collect();
            let dt_dtheta = dynamics.kinetic_energy(&th_i, &w).eps;
            let expected = m_dot_omega - dt_dtheta;
            assert!(
                (h[i] - expected).abs() < 1e-11 * (1.0 + expected.abs()),
                "h[{i}] = {} vs {expected} (n = {n})",
                h[i]
            );
        }
    }
}

#[test]
fn one_and_two_link_mass_matrices_by_hand() {
    let chain = Chain { spans: vec![0.3], masses: vec![2.0], gravity: 9.81 };
    let design = Design { theta0: vec![0.0], stiffness: vec![10.0, 0.0] };
    let d = Dynamics::new(&chain, &design, vec![0.0; 2], &NodalLoads::zero(1), &NodalLoads::zero(1), Forcing::Off);
    assert!((d.mass_matrix(&[0.7f64])[0][0] - 2.0 * 0.09 / 3.0).abs() < 1e-15, "m L² / 3 about the base");
    assert_eq!(d.velocity_terms(&[0.7f64], &[3.0])[0], 0.0);

    let (l1, l2, m1, m2) = (0.4, 0.25, 1.5, 0.8);
    let chain = Chain { spans: vec![l1, l2], masses: vec![m1, m2], gravity: 9.81 };
    let design = Design { theta0: vec![0.0, 0.0], stiffness: vec![0.0, 10.0, 0.0] };
    let d = Dynamics::new(&chain, &design, vec![0.0; 3], &NodalLoads::zero(2), &NodalLoads::zero(2), Forcing::Off);
    let (t1, t2, w1, w2): (f64, f64, f64, f64) = (0.3, -0.5, 1.2, -2.0);
    let m = d.mass_matrix(&[t1, t2]);
    let h = d.velocity_terms(&[t1, t2], &[w1, w2]);
    let c = m2 * l1 * l2 / 2.0;
    assert!((m[0][0] - l1 * l1 * (m1 / 3.0 + m2)).abs() < 1e-14);
    assert!((m[0][1] - c * (t1 - t2).cos()).abs() < 1e-14);
    assert!((m[1][1] - m2 * l2 * l2 / 3.0).abs() < 1e-14);
    assert!((h[0] - c * (t1 - t2).sin() * w2 * w2).abs() < 1e-13);
    assert!((h[1] + c * (t1 - t2).sin() * w1 * w1).abs() < 1e-13);
}

#[test]
fn symmetric_two_link_motion_matches_the_hand_derived_equation() {
    // Equal links, middle spring K and damper C only, P_Y at node 2, P_X at node 3, self-weight.
    // With θ1 = −θ2 = θ the Lagrangian reduces to one degree of freedom:
    // m L² (5/3 − cos 2θ) θ̈ + m L² sin 2θ θ̇² + 4C θ̇ + 4K (θ − θ0) − (P_Y − m g) L cos θ + 2 P_X L sin θ = 0.
    let (a, m, k, c, p_y, p_x, g, theta0) = (0.5, 0.7, 300.0, 4.0, -20.0, -150.0, 9.81, 0.25);
    let chain = Chain { spans: vec![a, a], masses: vec![m, m], gravity: g };
    let design = Design { theta0: vec![theta0, -theta0], stiffness: vec![0.0, k, 0.0] };
    let l = a / theta0.cos();
    let passive = NodalLoads { p_x: vec![0.0; 3], p_y: vec![0.0, p_y, 0.0] };
    let actuation = NodalLoads { p_x: vec![0.0, 0.0, p_x], p_y: vec![0.0; 3] };
    let d = Dynamics::new(&chain, &design, vec![0.0, c, 0.0], &passive, &actuation, Forcing::Step);
    for (theta, omega) in [(0.2, 0.0), (0.31, 1.7), (0.1, -3.0)] {
        let rhs = d.rhs(0.0, 0.0, &[theta, -theta, omega, -omega], &d.damping);
        let expected =
            -(m * l * l * (2.0 * theta).sin() * omega * omega + 4.0 * c * omega + 4.0 * k * (theta - theta0)
                - (p_y - m * g) * l * theta.cos()
                + 2.0 * p_x * l * theta.sin())
                / (m * l * l * (5.0 / 3.0 - (2.0 * theta).cos()));
        assert!((rhs[2] - expected).abs() < 1e-10 * expected.abs().max(1.0), "θ̈ = {} vs {expected}", rhs[2]);
        assert!((rhs[3] + expected).abs() < 1e-10 * expected.abs().max(1.0), "symmetric");
    }
}

#[test]
fn a_static_equilibrium_is_a_rest_point_and_the_load_potential_generates_the_load() {
    let (mut chain, design) = arch(6, 1.0, 0.4, 800.0);
    chain.masses = vec![0.3; 6];
    let passive = uniform_loads(6, -5.0, 0.0);
    let actuation = uniform_loads(6, 0.0, -300.0);
    let structure =
        spine_model::Structure { chain: chain.clone(), passive: passive.clone(), actuation: actuation.clone() };
    let problem = spine_solve::StaticProblem { structure, design: design.clone() };
    let sol = spine_solve::solve_static(&problem, &Default::default());
    let d = Dynamics::new(&chain, &design, vec![10.0; 7], &passive, &actuation, Forcing::Off);
    let mut y = sol.passive.state.theta.clone();
    y.extend(vec![0.0; 6]);
    let f = d.rhs(0.0, 0.0, &y, &d.damping);
    let (_, lambda) = d.acceleration(&d.passive, &sol.passive.state.theta, &[0.0; 6], &d.damping);
    assert!(f.iter().all(|v| v.abs() < 1e-7), "accelerations at θ1: {f:?}");
    assert!(
        (lambda - sol.passive.state.lambda).abs() < 1e-7 * (1.0 + lambda.abs()),
        "the reaction is the static multiplier"
    );

    // P = −∂V/∂θ, and V differs from the nodal potential of spine-model by a constant.
    let theta = sol.passive.state.theta.clone();
    let p = d.generalised_load(&d.loaded, &theta);
    let all = passive.plus(&actuation);
    let v_model = |t: &[f64]| spine_model::energy::load_potential(&chain, &all, true, &design.theta0, t);
    for i in 0..6 {
        let th: Vec<Dual64> = theta
            .iter()
            .enumerate()
            .map(|(k, &t)| if k == i { Dual64::from(t).derivative() } else { Dual64::from(t) })
            .collect();
        assert!((d.load_potential(&d.loaded, &th).eps + p[i]).abs() < 1e-10);
    }
    let shifted: Vec<f64> = theta.iter().map(|t| t + 0.05).collect();
    let diff = |t: &[f64]| d.load_potential(&d.loaded, t) - v_model(t);
    assert!((diff(&theta) - diff(&shifted)).abs() < 1e-10);
}

/// `M⁻¹ x` by a dense LU of [`Dynamics::mass_matrix`] (nalgebra), the reference of the recursion.
fn dense_solve(dynamics: &Dynamics, theta: &[f64], x: &[f64]) -> Vec<f64> {
    let n = theta.len();
    let m = dynamics.mass_matrix(theta);
    let m = nalgebra::DMatrix::from_fn(n, n, |i, j| m[i][j]);
    m.lu().solve(&nalgebra::DVector::from_column_slice(x)).unwrap().as_slice().to_vec()
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// Issue 15: `M(θ) x = b` by the articulated-body recursion agrees with a dense LU of the mass
/// matrix to 1e-12 on random states and right-hand sides, in values and in dual parts.
#[test]
fn articulated_body_solve_agrees_with_the_dense_mass_matrix() {
    for (n, seed) in [(1, 21), (2, 22), (3, 23), (10, 24), (50, 25)] {
        let (dynamics, theta, omega) = random_dynamics(n, seed);
        let chain = ArticulatedChain::new(&dynamics.lengths, &dynamics.masses, &theta).unwrap();
        let x = chain.solve(&omega);
        let x_dense = dense_solve(&dynamics, &theta, &omega);
        for i in 0..n {
            assert!((x[i] - x_dense[i]).abs() <= 1e-12 * max_abs(&x_dense), "x[{i}] (n = {n})");
        }
        // All columns at once: each column as its own solve, bit for bit (the same operations).
        let columns = nalgebra::DMatrix::from_fn(n, 3, |i, c| omega[i] * (c as f64 + 1.0) + theta[(i + c) % n]);
        let mut together = columns.clone();
        chain.solve_columns(&mut together);
        for c in 0..3 {
            let alone = chain.solve(&columns.column(c).iter().copied().collect::<Vec<_>>());
            assert_eq!(together.column(c).as_slice(), &alone[..], "column {c} (n = {n})");
        }
        // d/dθ_k of M⁻¹ b = −M⁻¹ (∂M/∂θ_k) M⁻¹ b, against central differences of the dense solve.
        let k = n / 2;
        let th: Vec<Dual64> =
            theta.iter().enumerate().map(|(j, &t)| Dual64::new(t, if j == k { 1.0 } else { 0.0 })).collect();
        let b: Vec<Dual64> = omega.iter().map(|&v| Dual64::from(v)).collect();
        let dx = ArticulatedChain::new(&dynamics.lengths, &dynamics.masses, &th).unwrap().solve(&b);
        let h = 1e-6;
        let shifted = |d: f64| {
            let mut t = theta.clone();
            t[k] += d;
            dense_solve(&dynamics, &t, &omega)
        };
        let (plus, minus) = (shifted(h), shifted(-h));
        let fd: Vec<f64> = (0..n).map(|i| (plus[i] - minus[i]) / (2.0 * h)).collect();
        for i in 0..n {
            assert!((dx[i].eps - fd[i]).abs() <= 1e-6 * max_abs(&fd).max(1e-9), "∂x[{i}]/∂θ[{k}] (n = {n})");
        }
    }
}

/// Issue 15: the `O(N)` accelerations (articulated-body recursion, prefix/suffix centrifugal sums)
/// agree with the dense path (mass matrix, Cholesky, double sum) to 1e-12 on random states, in
/// values and in dual parts (the Jacobian columns and the damping sensitivities come from them).
/// The scale of the comparison is that of the terms the bordered solve adds, `|M⁻¹Q|` and
/// `|λ M⁻¹∇Φ|` (they cancel when the constraint fixes the motion, e.g. one link).
#[test]
fn recursive_accelerations_agree_with_the_dense_path() {
    for (n, seed) in [(1, 21), (2, 22), (3, 23), (10, 24), (50, 25)] {
        let (dynamics, theta, omega) = random_dynamics(n, seed);
        let loads = dynamics.loads_at(0.3, 0.3);
        let damping = dynamics.damping.clone();
        let h = dynamics.velocity_terms(&theta, &omega);
        let h_dense = dynamics.velocity_terms_dense(&theta, &omega);
        for i in 0..n {
            assert!((h[i] - h_dense[i]).abs() <= 1e-12 * max_abs(&h_dense).max(1.0), "h[{i}] (n = {n})");
        }
        let (acc, lambda) = dynamics.acceleration(&loads, &theta, &omega, &damping);
        let (acc_dense, lambda_dense) = dynamics.acceleration_dense(&loads, &theta, &omega, &damping);
        let mg = dense_solve(&dynamics, &theta, &dynamics.constraint_gradient(&theta));
        let scale = max_abs(&acc_dense) + lambda_dense.abs() * max_abs(&mg);
        for i in 0..n {
            assert!((acc[i] - acc_dense[i]).abs() <= 1e-12 * scale, "θ̈[{i}] (n = {n}): {} vs {}", acc[i], acc_dense[i]);
        }
        assert!((lambda - lambda_dense).abs() <= 1e-12 * lambda_dense.abs().max(1.0), "λ (n = {n})");
        // Dual parts: one direction in θ, one in θ̇ and one in a damper.
        for direction in [0, n - 1] {
            let th: Vec<Dual64> = theta
                .iter()
                .enumerate()
                .map(|(k, &t)| Dual64::new(t, if k == direction { 1.0 } else { 0.0 }))
                .collect();
            let w: Vec<Dual64> = omega
                .iter()
                .enumerate()
                .map(|(k, &t)| Dual64::new(t, if k == n - 1 - direction { 1.0 } else { 0.0 }))
                .collect();
            let c: Vec<Dual64> = damping
                .iter()
                .enumerate()
                .map(|(k, &t)| Dual64::new(t, if k == direction + 1 { 1.0 } else { 0.0 }))
                .collect();
            let (a, l) = dynamics.acceleration(&loads, &th, &w, &c);
            let (a_dense, l_dense) = dynamics.acceleration_dense(&loads, &th, &w, &c);
            let eps: Vec<f64> = a_dense.iter().map(|v| v.eps).collect();
            for i in 0..n {
                assert!(
                    (a[i].eps - a_dense[i].eps).abs() <= 1e-10 * (max_abs(&eps) + scale),
                    "∂θ̈[{i}] (n = {n}): {} vs {}",
                    a[i].eps,
                    a_dense[i].eps
                );
            }
            assert!((l.eps - l_dense.eps).abs() <= 1e-10 * l_dense.eps.abs().max(1.0), "∂λ (n = {n})");
        }
    }
}

/// The recursion refuses what the dense path refuses: a non-finite state gives NaN, not a panic.
#[test]
fn a_non_finite_state_gives_nan_accelerations_on_both_paths() {
    let (dynamics, mut theta, omega) = random_dynamics(6, 31);
    theta[2] = f64::NAN;
    let loads = dynamics.loads_at(0.0, 0.0);
    for (acc, lambda) in [
        dynamics.acceleration(&loads, &theta, &omega, &dynamics.damping),
        dynamics.acceleration_dense(&loads, &theta, &omega, &dynamics.damping),
    ] {
        assert!(acc.iter().all(|a| a.is_nan()) && lambda.is_nan());
    }
}

/// The fast `∂f/∂y` and `∂f/∂C` of the integrator ([`Dynamics::rates_at`]) against the
/// reference path (a dual pass of the whole right-hand side per
/// column) and against central differences of the right-hand side.
#[test]
fn acceleration_rates_match_dual_passes_and_central_differences() {
    use spine_dynamics::integrator::OdeSystem;
    use spine_dynamics::system::reference;
    use spine_dynamics::{Parameters, SpineOde};
    for (n, seed) in [(1, 11), (2, 12), (5, 13), (10, 14), (24, 15)] {
        let (dynamics, theta, omega) = random_dynamics(n, seed);
        let ode = SpineOde { dynamics: &dynamics, parameters: Parameters::Dampers };
        let y: Vec<f64> = theta.iter().chain(&omega).copied().collect();
        let (t, piece) = (0.3, 0.3);
        let fast = (ode.jacobian(t, piece, &y), ode.rhs_params(t, piece, &y));
        let slow = (reference::jacobian(&ode, t, piece, &y), reference::rhs_params(&ode, t, piece, &y));
        for (a, b, what) in [(&fast.0, &slow.0, "∂f/∂y"), (&fast.1, &slow.1, "∂f/∂C")] {
            let scale = b.amax().max(1.0);
            eprintln!("N = {n}, {what}: {:.1e} of {scale:.1e}", (a - b).amax());
            assert!((a - b).amax() <= 1e-10 * scale, "N = {n}, {what}: {:.1e} of {scale:.1e}", (a - b).amax());
        }
        // Central differences in each θ, θ̇ and damper: `f` is quadratic in `θ̇` and affine in the
        // dampers, so the differences are exact but for round-off, and the steps can be large.
        // (A single link is held by the slider alone: its accelerations come from dividing by
        // `∇Φᵀ M⁻¹ ∇Φ` with heavy cancellation, and differences lose 8 digits; it is checked against
        // the dual passes only.)
        if n == 1 {
            continue;
        }
        let f = |y: &[f64], d: &Dynamics| d.rhs(t, piece, y, &d.damping);
        for k in 0..n {
            let h = 1e-3;
            let (mut plus, mut minus) = (y.clone(), y.clone());
            plus[n + k] += h;
            minus[n + k] -= h;
            let (fp, fm) = (f(&plus, &dynamics), f(&minus, &dynamics));
            // The differences' round-off: 1e-13 of the largest |f| (a single link's constraint
            // makes it 1e5) over the step.
            let noise = 1e-13 * fp.iter().chain(&fm).fold(0.0f64, |m, v| m.max(v.abs())) / h;
            for i in 0..2 * n {
                let fd = (fp[i] - fm[i]) / (2.0 * h);
                let exact = fast.0[(i, n + k)];
                let tol = 1e-8 * fast.0.amax().max(1.0) + noise;
                assert!((fd - exact).abs() <= tol, "N = {n}: ∂f_{i}/∂θ̇_{k}: {fd} vs {exact}");
            }
        }
        // In each angle `f` is not polynomial: a small step, a looser tolerance.
        for k in 0..n {
            let h = 1e-6;
            let (mut plus, mut minus) = (y.clone(), y.clone());
            plus[k] += h;
            minus[k] -= h;
            let (fp, fm) = (f(&plus, &dynamics), f(&minus, &dynamics));
            let noise = 1e-13 * fp.iter().chain(&fm).fold(0.0f64, |m, v| m.max(v.abs())) / h;
            for i in 0..2 * n {
                let fd = (fp[i] - fm[i]) / (2.0 * h);
                let exact = fast.0[(i, k)];
                let tol = 1e-6 * fast.0.amax().max(1.0) + noise;
                assert!((fd - exact).abs() <= tol, "N = {n}: ∂f_{i}/∂θ_{k}: {fd} vs {exact}");
            }
        }
        for k in 0..=n {
            let h = 1e-2 * dynamics.damping[k];
            let (mut plus, mut minus) = (dynamics.clone(), dynamics.clone());
            plus.damping[k] += h;
            minus.damping[k] -= h;
            let (fp, fm) = (f(&y, &plus), f(&y, &minus));
            let noise = 1e-13 * fp.iter().chain(&fm).fold(0.0f64, |m, v| m.max(v.abs())) / h;
            for i in 0..2 * n {
                let fd = (fp[i] - fm[i]) / (2.0 * h);
                let exact = fast.1[(i, k)];
                let tol = 1e-8 * fast.1.amax().max(1e-3) + noise;
                assert!((fd - exact).abs() <= tol, "N = {n}: ∂f_{i}/∂C_{k}: {fd} vs {exact}");
            }
        }
    }
}

/// The projection's tangent map for all sensitivity columns at once ([`Dynamics::project_tangent`])
/// against a dual pass of the projection per column, from states off the constraint.
#[test]
fn projection_tangent_matches_dual_passes() {
    use spine_dynamics::system::reference;
    use spine_dynamics::{Parameters, SpineOde};
    for (n, seed) in [(2, 21), (5, 22), (10, 23), (30, 24)] {
        let (dynamics, theta, omega) = random_dynamics(n, seed);
        let mut rng = SplitMix64::new(seed);
        // Off the manifold, as after an integration step.
        let y: Vec<f64> = theta.iter().map(|t| t + rng.uniform(-1e-3, 1e-3)).chain(omega).collect();
        let s = nalgebra::DMatrix::from_fn(2 * n, n + 1, |_, _| rng.uniform(-2.0, 2.0));
        let (mut fast, mut slow) = (s.clone(), s);
        dynamics.project_tangent(&y, &mut fast);
        reference::project_sensitivities(
            &SpineOde { dynamics: &dynamics, parameters: Parameters::Dampers },
            &y,
            &mut slow,
        );
        let error = (&fast - &slow).amax() / slow.amax();
        assert!(error <= 1e-13, "N = {n}: {error:.1e}");
    }
}

/// `∂θ̈/∂K` ([`RatesIn::Springs`](spine_dynamics::rates::RatesIn)) against central differences of
/// the right-hand side in each spring (the reference path; `f` is affine in `K`, so the differences
/// are exact to round-off), and the angle block unchanged by asking for the springs.
#[test]
fn spring_rates_match_central_differences() {
    use spine_dynamics::integrator::OdeSystem;
    use spine_dynamics::system::reference;
    use spine_dynamics::{Parameters, SpineOde};
    for (n, seed) in [(2, 21), (5, 22), (10, 23), (24, 24)] {
        let (dynamics, theta, omega) = random_dynamics(n, seed);
        let ode = SpineOde { dynamics: &dynamics, parameters: Parameters::Springs };
        assert_eq!(ode.n_params(), n + 1);
        let y: Vec<f64> = theta.iter().chain(&omega).copied().collect();
        let (t, piece) = (0.3, 0.3);
        let (fast, slow) = (ode.rhs_params(t, piece, &y), reference::rhs_params(&ode, t, piece, &y));
        let scale = slow.amax();
        assert!(scale > 0.0, "N = {n}: the springs move the accelerations");
        eprintln!("N = {n}, ∂f/∂K: {:.1e} of {scale:.1e}", (&fast - &slow).amax());
        assert!((&fast - &slow).amax() <= 1e-8 * scale, "N = {n}: {:.1e} of {scale:.1e}", (&fast - &slow).amax());
        assert!(fast.rows(0, n).iter().all(|v| *v == 0.0), "N = {n}: θ does not depend on K directly");
        let (jac, params) = ode.jacobian_and_params(t, piece, &y);
        assert_eq!(jac, ode.jacobian(t, piece, &y));
        assert_eq!(params, fast);
    }
}
