//! Local elements (value, AD gradient, AD Hessian, declared Hessian pattern) against central
//! differences, and the hand-written derivatives of Appendix I against the AD ones.

use spine_model::energy::strain_energy;
use spine_model::finite_difference::central_gradient;
use spine_model::fixtures::random_problem;
use spine_model::hand;
use spine_model::jacobian::{design_jacobian, residual_and_state_jacobian};
use spine_model::kinematics::end_x;
use spine_model::local::{
    self, joint_slot, DeflectionJointResidual, DeflectionSpringEnergy, Difference, Element, HeightStep, JointResidual,
    LinkRise, LinkRun, LinkWork, MomentPower, SpringEnergy, SpringStiffness,
};
use spine_model::residual::{equilibrium_residual, slot};
use spine_model::rng::SplitMix64;
use spine_model::State;

fn random_point<const M: usize>(rng: &mut SplitMix64) -> [f64; M] {
    std::array::from_fn(|_| rng.uniform(-0.8, 0.8))
}

/// Checks one element at random points: gradient and Hessian against central differences of the
/// value and of the gradient (relative 1e-6), the element's own Hessian method against the full
/// second-order pass (1e-13), and the full Hessian zero outside `HESSIAN_PAIRS`.
fn check_element<const M: usize, E: Element<M>>(element: &E, name: &str, scale: [f64; M]) {
    let mut rng = SplitMix64::new(7);
    for _ in 0..20 {
        let mut x: [f64; M] = random_point(&mut rng);
        for k in 0..M {
            x[k] *= scale[k];
        }
        let (v, g) = local::gradient(element, &x);
        let (v2, g2, h_full) = local::full_hessian(element, &x);
        let h = local::hessian(element, &x);
        // The branch-free jets against num-dual's duals: the same derivatives.
        let (_, g_nd) = local::gradient_num_dual(element, &x);
        let (_, _, h_nd) = local::full_hessian_num_dual(element, &x);
        for a in 0..M {
            assert!((g[a] - g_nd[a]).abs() <= 1e-13 * g_nd[a].abs().max(1.0), "{name} ∂/∂x{a}: jet vs num-dual");
            for b in 0..M {
                let (mine, theirs) = (h_full[a][b], h_nd[a][b]);
                assert!(
                    (mine - theirs).abs() <= 1e-13 * theirs.abs().max(1.0),
                    "{name} ({a}, {b}): {mine} vs {theirs}"
                );
            }
        }
        assert!((v - local::value(element, &x)).abs() <= 1e-14 * v.abs().max(1.0));
        assert!((v - v2).abs() <= 1e-14 * v.abs().max(1.0));
        let gmax = g.iter().fold(1e-12f64, |m, a| m.max(a.abs()));
        let hmax = h_full.iter().flatten().fold(1e-12f64, |m, a| m.max(a.abs()));
        // The constant pairs are constant (the assembly takes them once, at zero), and the
        // varying Hessian agrees with the full one everywhere else.
        let (at_zero, varying) = (local::hessian(element, &[0.0; M]), element.varying_hessian(&x));
        for &(a, b) in E::HESSIAN_PAIRS {
            if E::CONSTANT_PAIRS.contains(&(a, b)) {
                assert_eq!(h_full[a][b], at_zero[a][b], "{name} ({a}, {b}) is declared constant");
            } else {
                assert!((varying[a][b] - h_full[a][b]).abs() <= 1e-13 * hmax, "{name} ({a}, {b}): varying Hessian");
            }
        }
        assert!(E::CONSTANT_PAIRS.iter().all(|p| E::HESSIAN_PAIRS.contains(p)), "{name}: constant pairs declared");
        for &(a, b) in E::HESSIAN_PAIRS {
            assert!(
                (h[a][b] - h_full[a][b]).abs() <= 1e-13 * hmax,
                "{name} ({a}, {b}): own {} full {}",
                h[a][b],
                h_full[a][b]
            );
            assert_eq!(h[a][b], h[b][a], "{name}: own Hessian not symmetric at ({a}, {b})");
        }
        for k in 0..M {
            assert!((g[k] - g2[k]).abs() <= 1e-12 * gmax);
            let step = 1e-6 * x[k].abs().max(1.0);
            let (mut xp, mut xm) = (x, x);
            xp[k] += step;
            xm[k] -= step;
            let fd = (local::value(element, &xp) - local::value(element, &xm)) / (2.0 * step);
            assert!((g[k] - fd).abs() <= 1e-6 * gmax, "{name} ∂/∂x{k}: AD {} FD {fd}", g[k]);
            let (gp, gm) = (local::gradient(element, &xp).1, local::gradient(element, &xm).1);
            for a in 0..M {
                let fd = (gp[a] - gm[a]) / (2.0 * step);
                assert!((h_full[a][k] - fd).abs() <= 1e-6 * hmax, "{name} ∂²/∂x{a}∂x{k}: AD {} FD {fd}", h[a][k]);
            }
        }
        for a in 0..M {
            for b in 0..=a {
                assert_eq!(h_full[a][b], h_full[b][a]);
                let declared = E::HESSIAN_PAIRS.contains(&(a, b));
                if !declared {
                    assert_eq!(
                        h_full[a][b], 0.0,
                        "{name}: Hessian entry ({a}, {b}) is not declared but is {}",
                        h[a][b]
                    );
                }
            }
        }
        for &(a, b) in E::HESSIAN_PAIRS {
            assert!(a >= b && a < M, "{name}: pair ({a}, {b}) is not in the lower triangle");
        }
    }
}

#[test]
fn elements_match_central_differences_and_their_declared_hessian_pattern() {
    let joint = JointResidual { span: 0.1, vertical: -30.0, axial: 250.0, stiffness_scale: 10.0 };
    let mut scale = [1.0; slot::COUNT];
    scale[slot::LAMBDA] = 40.0;
    scale[slot::STIFFNESS_LEFT] = 100.0;
    scale[slot::STIFFNESS_RIGHT] = 100.0;
    check_element(&joint, "joint residual", scale);
    let deflection_joint = DeflectionJointResidual { span: 0.1, vertical: -30.0, axial: 250.0, stiffness_scale: 10.0 };
    let mut scale = [1.0; joint_slot::COUNT];
    scale[joint_slot::LAMBDA] = 40.0;
    scale[joint_slot::STIFFNESS_LEFT] = 100.0;
    scale[joint_slot::STIFFNESS_RIGHT] = 100.0;
    check_element(&deflection_joint, "joint residual on deflections", scale);
    for deflection in [false, true] {
        check_element(&LinkRise { span: 0.2, deflection }, "link rise", [1.0; 2]);
        check_element(&LinkRun { span: 0.2, deflection }, "link run", [1.0; 2]);
    }
    check_element(&HeightStep { span: 0.2 }, "height step", [0.1, 0.1, 1.0]);
    check_element(&SpringEnergy { stiffness_scale: 25.0 }, "spring energy", [1.0, 1.0, 1.0, 1.0, 40.0]);
    check_element(&DeflectionSpringEnergy { stiffness_scale: 25.0 }, "spring energy on deflections", [1.0, 1.0, 40.0]);
    check_element(&Difference, "difference", [1.0; 2]);
    check_element(&SpringStiffness { stiffness_scale: 25.0 }, "spring stiffness", [40.0]);
    for exponent in [2, 8] {
        let moment = MomentPower { stiffness_scale: 25.0, reference: 300.0, exponent };
        check_element(&moment, "moment power", [0.3, 0.3, 0.3, 0.3, 40.0]);
    }
    for deflection in [false, true] {
        check_element(&LinkWork { span: 0.2, vertical: -30.0, axial: 250.0, deflection }, "link work", [1.0; 2]);
    }
}

#[test]
fn every_declared_hessian_pair_is_nonzero_somewhere() {
    // The declared pattern is exact, not just a superset: each pair is nonzero at a random point.
    fn check<const M: usize, E: Element<M>>(e: &E, name: &str) {
        let x: [f64; M] = random_point(&mut SplitMix64::new(3));
        let h = local::hessian(e, &x);
        for &(a, b) in E::HESSIAN_PAIRS {
            assert!(h[a][b] != 0.0, "{name}: declared pair ({a}, {b}) is zero");
        }
    }
    check(&JointResidual { span: 0.1, vertical: -30.0, axial: 250.0, stiffness_scale: 10.0 }, "joint");
    check(&DeflectionJointResidual { span: 0.1, vertical: -30.0, axial: 250.0, stiffness_scale: 10.0 }, "joint (u)");
    for deflection in [false, true] {
        check(&LinkRise { span: 0.2, deflection }, "rise");
        check(&LinkRun { span: 0.2, deflection }, "run");
    }
    check(&DeflectionSpringEnergy { stiffness_scale: 2.0 }, "spring (u)");
    check(&HeightStep { span: 0.2 }, "height");
    check(&SpringEnergy { stiffness_scale: 2.0 }, "spring");
    check(&MomentPower { stiffness_scale: 2.0, reference: 3.0, exponent: 4 }, "moment power");
    for deflection in [false, true] {
        check(&LinkWork { span: 0.2, vertical: -30.0, axial: 250.0, deflection }, "link work");
    }
}

#[test]
fn joint_element_is_the_model_residual() {
    for n in [1, 2, 5, 12] {
        let (chain, design, loads, state) = random_problem(n, 11 + n as u64);
        let r = equilibrium_residual(&chain.spans, &design, &loads, &state);
        for i in 0..n {
            let mut x = [0.0; slot::COUNT];
            if i > 0 {
                x[slot::THETA_PREV] = state.theta[i - 1];
                x[slot::THETA0_PREV] = design.theta0[i - 1];
            }
            if i + 1 < n {
                x[slot::THETA_NEXT] = state.theta[i + 1];
                x[slot::THETA0_NEXT] = design.theta0[i + 1];
            }
            x[slot::THETA] = state.theta[i];
            x[slot::THETA0] = design.theta0[i];
            x[slot::LAMBDA] = state.lambda;
            x[slot::STIFFNESS_LEFT] = design.stiffness[i] / 4.0;
            x[slot::STIFFNESS_RIGHT] = design.stiffness[i + 1] / 4.0;
            let e = JointResidual {
                span: chain.spans[i],
                vertical: loads.vertical[i],
                axial: loads.axial[i],
                stiffness_scale: 4.0,
            };
            let v = local::value(&e, &x);
            assert!((v - r[i]).abs() <= 1e-12 * r[i].abs().max(1.0), "row {i}: {v} vs {}", r[i]);
            let u = |k: usize| state.theta[k] - design.theta0[k];
            let mut xu = [0.0; joint_slot::COUNT];
            xu[joint_slot::U_PREV] = if i > 0 { u(i - 1) } else { 0.0 };
            xu[joint_slot::U] = u(i);
            xu[joint_slot::U_NEXT] = if i + 1 < n { u(i + 1) } else { 0.0 };
            xu[joint_slot::LAMBDA] = state.lambda;
            xu[joint_slot::THETA0] = design.theta0[i];
            xu[joint_slot::STIFFNESS_LEFT] = x[slot::STIFFNESS_LEFT];
            xu[joint_slot::STIFFNESS_RIGHT] = x[slot::STIFFNESS_RIGHT];
            let e =
                DeflectionJointResidual { span: e.span, vertical: e.vertical, axial: e.axial, stiffness_scale: 4.0 };
            let vu = local::value(&e, &xu);
            assert!((vu - r[i]).abs() <= 1e-12 * r[i].abs().max(1.0), "row {i} on deflections: {vu} vs {}", r[i]);
        }
        let energy = (0..=n)
            .map(|j| {
                let get = |v: &[f64], i: isize| if i >= 0 && (i as usize) < n { v[i as usize] } else { 0.0 };
                let jj = j as isize;
                let x = [
                    get(&state.theta, jj - 1),
                    get(&design.theta0, jj - 1),
                    get(&state.theta, jj),
                    get(&design.theta0, jj),
                    design.stiffness[j],
                ];
                let absolute = local::value(&SpringEnergy { stiffness_scale: 1.0 }, &x);
                let u = [x[0] - x[1], x[2] - x[3], x[4]];
                let on_deflections = local::value(&DeflectionSpringEnergy { stiffness_scale: 1.0 }, &u);
                assert!((absolute - on_deflections).abs() <= 1e-12 * absolute.max(1e-300));
                absolute
            })
            .sum::<f64>();
        let expected = strain_energy(&state.theta, &design.theta0, &design.stiffness);
        assert!((energy - expected).abs() <= 1e-12 * expected.max(1.0));
        for deflection in [false, true] {
            let run: f64 = (0..n)
                .map(|i| {
                    let angle = if deflection { state.theta[i] - design.theta0[i] } else { state.theta[i] };
                    local::value(&LinkRun { span: chain.spans[i], deflection }, &[angle, design.theta0[i]])
                })
                .sum();
            assert!((run - end_x(&chain.spans, &design.theta0, &state.theta)).abs() < 1e-14);
        }
    }
}

#[test]
fn hand_state_jacobian_equals_the_ad_one() {
    for n in [1, 2, 3, 10, 50] {
        for seed in 0..3 {
            let (chain, design, loads, state) = random_problem(n, 500 + 10 * n as u64 + seed);
            let (_, ad) = residual_and_state_jacobian(&chain.spans, &design, &loads, &state);
            let hand = hand::state_jacobian(&chain.spans, &design, &loads, &state);
            let (a, h) = (ad.to_sparse().to_dense(), hand.to_sparse().to_dense());
            for (ra, rh) in a.iter().zip(&h) {
                for (x, y) in ra.iter().zip(rh) {
                    assert!((x - y).abs() <= 1e-10 * x.abs().max(1.0), "N={n}: AD {x} hand {y}");
                }
            }
        }
    }
}

#[test]
fn hand_design_products_equal_the_ad_design_jacobian() {
    for n in [1, 2, 3, 10, 50] {
        let (chain, design, loads, state) = random_problem(n, 900 + n as u64);
        let mut rng = SplitMix64::new(n as u64);
        let psi: Vec<f64> = (0..=n).map(|_| rng.uniform(-1.0, 1.0)).collect();
        let ad = design_jacobian(&chain.spans, &design, &loads, &state).transpose_mul_vec(&psi);
        let hand = hand::design_jacobian_transpose_mul(&chain.spans, &design, &loads, &state, &psi);
        let big = ad.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        for (k, (a, h)) in ad.iter().zip(&hand).enumerate() {
            assert!((a - h).abs() <= 1e-12 * big, "N={n} column {k}: AD {a} hand {h}");
        }
    }
}

#[test]
fn hand_energy_and_end_partials_match_central_differences() {
    for n in [1, 3, 10] {
        let (chain, design, _, state) = random_problem(n, 40 + n as u64);
        let (du_dtheta, du_ddesign) = hand::strain_energy_partials(&design, &state);
        let (dx_dtheta, dx_ddesign) = hand::end_x_partials(&chain.spans, &design, &state);
        let energy = |t: &[f64], t0: &[f64], k: &[f64]| strain_energy(t, t0, k);
        let endx = |t: &[f64], t0: &[f64]| end_x(&chain.spans, t0, t);
        let h = 1e-6;
        let fd_u_theta = central_gradient(&state.theta, h, |t| energy(t, &design.theta0, &design.stiffness));
        let fd_x_theta = central_gradient(&state.theta, h, |t| endx(t, &design.theta0));
        let fd_u_theta0 = central_gradient(&design.theta0, h, |t0| energy(&state.theta, t0, &design.stiffness));
        let fd_x_theta0 = central_gradient(&design.theta0, h, |t0| endx(&state.theta, t0));
        let fd_u_k = central_gradient(&design.stiffness, h, |k| energy(&state.theta, &design.theta0, k));
        for i in 0..n {
            assert!((fd_u_theta[i] - du_dtheta[i]).abs() < 1e-6 * du_dtheta[i].abs().max(1.0));
            assert!((fd_x_theta[i] - dx_dtheta[i]).abs() < 1e-8);
            assert!((fd_u_theta0[i] - du_ddesign[i]).abs() < 1e-6 * du_ddesign[i].abs().max(1.0));
            assert!((fd_x_theta0[i] - dx_ddesign[i]).abs() < 1e-8);
        }
        for j in 0..=n {
            let fd = fd_u_k[j];
            assert!((fd - du_ddesign[n + j]).abs() < 1e-6, "∂U/∂K{j}: FD {fd} hand {}", du_ddesign[n + j]);
            assert_eq!(dx_ddesign[n + j], 0.0);
        }
        let _ = State::unloaded(&design);
    }
}

/// The constraint row of the AD state Jacobian is taken as `−∂r_i/∂λ` (the residual is the
/// gradient of a Lagrangian); it equals the AD of `Φ = Σ L_i sin θ_i` term by term.
#[test]
fn constraint_row_of_the_state_jacobian_equals_the_ad_of_phi() {
    for seed in 0..5 {
        let (chain, design, loads, state) = random_problem(3 + seed as usize, seed);
        let (_, jac) = residual_and_state_jacobian(&chain.spans, &design, &loads, &state);
        for i in 0..chain.n_links() {
            let direct = spine_model::jacobian::rise_derivatives(chain.spans[i], design.theta0[i], state.theta[i]).0;
            assert!(
                (jac.row[i] - direct).abs() <= 1e-15 * direct.abs().max(1.0),
                "seed {seed} link {i}: {} vs {direct}",
                jac.row[i]
            );
        }
    }
}

#[test]
fn deflections_keep_stiff_spring_moments_to_round_off_of_themselves() {
    // Link i deflected by u from θ0 = 0.5 rad between two springs of K = 1e8 N·m/rad, no loads:
    // r_i = K u − K (0 − u) = 2 K u exactly in real arithmetic.
    let (k, theta0, u) = (1e8, 0.5, 1.234567e-9);
    let exact = 2.0 * k * u;
    let on_deflections = DeflectionJointResidual { span: 0.1, vertical: 0.0, axial: 0.0, stiffness_scale: 1.0 };
    let mut x = [0.0; joint_slot::COUNT];
    x[joint_slot::U] = u;
    x[joint_slot::THETA0] = theta0;
    x[joint_slot::STIFFNESS_LEFT] = k;
    x[joint_slot::STIFFNESS_RIGHT] = k;
    let r = local::value(&on_deflections, &x);
    assert!((r - exact).abs() <= 4.0 * f64::EPSILON * exact, "on deflections: {r} vs {exact}");
    // The same row on absolute angles: θ = θ0 + u is rounded to the spacing of doubles near 0.5
    // (1.1e-16 rad), and K turns that into about 1e-9 N·m, far above u's own round-off. This is the
    // floor that stopped eq. (33) at N = 1000 short of its tolerance (docs/design.md).
    let absolute = JointResidual { span: 0.1, vertical: 0.0, axial: 0.0, stiffness_scale: 1.0 };
    let mut x = [0.0; slot::COUNT];
    x[slot::THETA] = theta0 + u;
    x[slot::THETA0] = theta0;
    x[slot::STIFFNESS_LEFT] = k;
    x[slot::STIFFNESS_RIGHT] = k;
    let r = local::value(&absolute, &x);
    assert!((r - exact).abs() > 1e-10, "absolute angles lost nothing: {r} vs {exact}");
}

/// An element's rates along a direction in its constants ([`local::rates`], one tangent-jet pass)
/// against central differences of its value and AD gradient with the constants moved by `±h` along
/// the direction; the plain lift gives the element's value; a direction of zeros gives zero rates.
fn check_rates<const M: usize, E: Element<M>>(element: &E, rates: &E, still: &E, name: &str, scale: [f64; M]) {
    use spine_model::jet::Jet;
    let mut rng = SplitMix64::new(11);
    for _ in 0..20 {
        let mut x: [f64; M] = random_point(&mut rng);
        for k in 0..M {
            x[k] *= scale[k];
        }
        let (dv, dg) = local::rates(element, rates, &x);
        assert_eq!(element.eval_moving(rates, |c, _| c, &x), element.eval(&x), "{name}: the plain lift");
        assert_eq!(local::rates(element, still, &x), (0.0, [0.0; M]), "{name}: nothing moves");
        let h = 1e-6;
        let value = |t: f64| element.eval_moving(rates, |c, r| c + t * r, &x);
        let gradient = |t: f64| {
            let seeded: [Jet<M>; M] = std::array::from_fn(|k| Jet::variable(x[k], k));
            element.eval_moving(rates, |c, r| Jet::constant(c + t * r), &seeded).eps
        };
        let fd = (value(h) - value(-h)) / (2.0 * h);
        assert!((dv - fd).abs() <= 1e-7 * fd.abs().max(1.0), "{name}: ∂e/∂p {dv} vs {fd}");
        let (gp, gm) = (gradient(h), gradient(-h));
        for k in 0..M {
            let fd = (gp[k] - gm[k]) / (2.0 * h);
            assert!((dg[k] - fd).abs() <= 1e-7 * fd.abs().max(1.0), "{name}: ∂²e/∂x{k}∂p {} vs {fd}", dg[k]);
        }
    }
}

#[test]
fn element_rates_match_central_differences_in_their_constants() {
    let (joint, moving, still) = (
        JointResidual { span: 0.1, vertical: -30.0, axial: 250.0, stiffness_scale: 10.0 },
        JointResidual { span: 0.01, vertical: 3.0, axial: -20.0, stiffness_scale: 2.0 },
        JointResidual { span: 0.0, vertical: 0.0, axial: 0.0, stiffness_scale: 0.0 },
    );
    let mut scale = [1.0; slot::COUNT];
    scale[slot::LAMBDA] = 40.0;
    check_rates(&joint, &moving, &still, "joint residual", scale);
    let d = |j: JointResidual| DeflectionJointResidual {
        span: j.span,
        vertical: j.vertical,
        axial: j.axial,
        stiffness_scale: j.stiffness_scale,
    };
    let mut scale = [1.0; joint_slot::COUNT];
    scale[joint_slot::LAMBDA] = 40.0;
    check_rates(&d(joint), &d(moving), &d(still), "joint residual on deflections", scale);
    for deflection in [false, true] {
        let rise = |span| LinkRise { span, deflection };
        check_rates(&rise(0.2), &rise(-0.5), &rise(0.0), "link rise", [1.0; 2]);
        let run = |span| LinkRun { span, deflection };
        check_rates(&run(0.2), &run(0.7), &run(0.0), "link run", [1.0; 2]);
    }
    let step = |span| HeightStep { span };
    check_rates(&step(0.2), &step(1.5), &step(0.0), "height step", [0.1, 0.1, 1.0]);
    let spring = |stiffness_scale| SpringEnergy { stiffness_scale };
    check_rates(&spring(25.0), &spring(1.0), &spring(0.0), "spring energy", [1.0, 1.0, 1.0, 1.0, 40.0]);
    let spring = |stiffness_scale| DeflectionSpringEnergy { stiffness_scale };
    check_rates(&spring(25.0), &spring(-3.0), &spring(0.0), "spring energy on deflections", [1.0, 1.0, 40.0]);
    check_rates(&Difference, &Difference, &Difference, "difference", [1.0; 2]);
    let stiffness = |stiffness_scale| SpringStiffness { stiffness_scale };
    check_rates(&stiffness(25.0), &stiffness(-3.0), &stiffness(0.0), "spring stiffness", [40.0]);
    let moment = |stiffness_scale, reference| MomentPower { stiffness_scale, reference, exponent: 6 };
    let scale = [0.3, 0.3, 0.3, 0.3, 40.0];
    check_rates(&moment(25.0, 300.0), &moment(-3.0, 40.0), &moment(0.0, 0.0), "moment power", scale);
    for deflection in [false, true] {
        let work = |span, vertical, axial| LinkWork { span, vertical, axial, deflection };
        let (at, moving) = (work(0.2, -30.0, 250.0), work(0.7, 4.0, -20.0));
        check_rates(&at, &moving, &work(0.0, 0.0, 0.0), "link work", [1.0; 2]);
    }
}
