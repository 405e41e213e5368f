//! The equilibrium solver: exactness at zero load, residual at the returned state, stability of a
//! compressed straight chain against an independent buckling load, a snap-through limit point, and
//! a large chain.

mod common;

use nalgebra::DMatrix;
use spine_model::fixtures::{arch, uniform_loads};
use spine_model::{Chain, Design, NodalLoads, Structure};
use spine_solve::{solve_static, ContinuationOptions, EquilibriumStatus, StaticProblem};

fn problem(chain: Chain, design: Design, p_y: f64, p_x: f64) -> StaticProblem {
    let n = chain.n_links();
    let mut passive = uniform_loads(n, p_y, 0.0);
    passive.p_x = vec![0.0; n + 1];
    StaticProblem { structure: Structure { chain, passive, actuation: uniform_loads(n, 0.0, p_x) }, design }
}

#[test]
fn zero_load_returns_the_design() {
    for n in [1, 2, 5, 30] {
        let (mut chain, design) = arch(n, 1.0, if n == 1 { 0.0 } else { 0.4 }, 800.0);
        chain.gravity = 0.0;
        let sol = solve_static(&problem(chain, design.clone(), 0.0, 0.0), &ContinuationOptions::default());
        assert_eq!(sol.passive.state.theta, design.theta0);
        assert_eq!(sol.passive.state.lambda, 0.0);
        assert!(sol.passive.status.is_stable());
        assert_eq!(sol.loaded.unwrap().state.theta, design.theta0);
    }
}

/// The scaled family of `PEERS.md` (one continuum problem discretised ever finer): `s = N/10`,
/// `K = 10³ s²` N·m/rad, `P_X = −400 s` N, `P_Y = −5` N per node; here with link masses too.
fn scaled_family(n: usize) -> StaticProblem {
    let s = n as f64 / 10.0;
    let (mut chain, design) = arch(n, 1.0, 0.4, 1e3 * s * s);
    chain.masses = vec![0.5 / n as f64; n];
    problem(chain, design, -5.0, -400.0 * s)
}

#[test]
fn loaded_arch_converges_with_small_residual_and_is_stable() {
    for n in [2, 3, 5, 10, 50] {
        let sol = solve_static(&scaled_family(n), &ContinuationOptions::default());
        for eq in [&sol.passive, sol.loaded.as_ref().unwrap()] {
            assert_eq!(eq.status, EquilibriumStatus::Stable, "N={n}");
            assert!(eq.residual_norm <= 1e-10, "N={n}: residual {}", eq.residual_norm);
            assert!(eq.constraint_violation <= 1e-10);
            assert!(eq.stability.stable && eq.stability.min_eigenvalue.unwrap() > 0.0);
        }
        assert!(sol.end_displacement.unwrap() < sol.passive_end_displacement, "compression shortens");
    }
}

/// Independent buckling load of a straight chain with equal links under end compression:
/// the smallest `p` with `Zᵀ(K_m − p L I)Z` singular, i.e. `λ_min(Zᵀ K_m Z) / L`.
fn buckling_load(design: &Design, link_length: f64) -> f64 {
    let n = design.theta0.len();
    let k = &design.stiffness;
    let km = DMatrix::from_fn(n, n, |i, j| {
        if i == j {
            k[i] + k[i + 1]
        } else if i == j + 1 {
            -k[i]
        } else if j == i + 1 {
            -k[j]
        } else {
            0.0
        }
    });
    let ones = vec![link_length; n];
    common::projected_eigenvalues(&km, &ones)[0] / link_length
}

#[test]
fn straight_chain_buckles_at_the_discrete_buckling_load() {
    let n = 6;
    let mut chain = Chain::uniform(n, 1.0);
    chain.gravity = 0.0;
    let design = Design { theta0: vec![0.0; n], stiffness: vec![1000.0; n + 1] };
    let p_cr = buckling_load(&design, 1.0 / n as f64);
    assert!(p_cr > 0.0);

    let small = solve_static(&problem(chain.clone(), design.clone(), 0.0, -0.5 * p_cr), &Default::default());
    let loaded = small.loaded.unwrap();
    assert_eq!(loaded.status, EquilibriumStatus::Stable);
    assert!(loaded.stability.min_eigenvalue.unwrap() > 0.0);

    let big = solve_static(&problem(chain, design, 0.0, -1.5 * p_cr), &Default::default());
    let loaded = big.loaded.unwrap();
    match loaded.status {
        EquilibriumStatus::Unstable { critical_load_factor } => {
            let expected = 1.0 / 1.5;
            assert!((critical_load_factor - expected).abs() < 1e-7, "{critical_load_factor} vs {expected}");
        }
        other => panic!("expected loss of stability, got {other:?}"),
    }
    assert!(!loaded.stability.stable);
    assert_eq!(loaded.stability.negative_directions, 1);
}

/// An arch pushed at its sliding end rises until it can carry no more compression: a fold of the
/// load path. The oracle is an independent displacement-controlled path: prescribe the end's X,
/// solve for `(θ, λ, s)` by dense Newton with a finite-difference Jacobian, and take the largest
/// load factor met along it.
#[test]
fn compressed_arch_reports_the_limit_point() {
    let n = 4;
    let (mut chain, design) = arch(n, 1.0, 0.4, 100.0);
    chain.gravity = 0.0;
    let p = problem(chain.clone(), design.clone(), 0.0, -400.0);
    let sol = solve_static(&p, &ContinuationOptions::default());
    let loaded = sol.loaded.unwrap();
    let s_limit = match loaded.status {
        EquilibriumStatus::LimitPoint { load_factor } => load_factor,
        other => panic!("expected a limit point, got {other:?}"),
    };
    assert!(loaded.stability.stable, "the returned state is the last stable one");
    assert!(loaded.residual_norm <= 1e-10);

    // Displacement control.
    let from = p.passive_loads();
    let to = p.total_loads();
    let equations = |x: &[f64], x_end: f64| -> Vec<f64> {
        let st = spine_model::State { theta: x[..n].to_vec(), lambda: x[n] };
        let loads = spine_model::LinkLoads::lerp(&from, &to, x[n + 1]);
        let mut r = spine_model::residual::equilibrium_residual(&chain.spans, &design, &loads, &st);
        r.push(spine_model::kinematics::end_x(&chain.spans, &design.theta0, &st.theta) - x_end);
        r
    };
    let mut x: Vec<f64> = design.theta0.clone();
    x.extend([0.0, 0.0]);
    let mut best: f64 = 0.0;
    for k in 1..=600 {
        let x_end = 1.0 - 1e-3 * k as f64;
        for _ in 0..50 {
            let r = equations(&x, x_end);
            if r.iter().fold(0.0f64, |m, v| m.max(v.abs())) < 1e-12 {
                break;
            }
            let m = x.len();
            let jac = DMatrix::from_fn(m, m, |i, j| {
                let (mut xp, mut xm) = (x.clone(), x.clone());
                xp[j] += 1e-7;
                xm[j] -= 1e-7;
                (equations(&xp, x_end)[i] - equations(&xm, x_end)[i]) / 2e-7
            });
            let dx = jac.lu().solve(&nalgebra::DVector::from_vec(r)).expect("regular under displacement control");
            for (xi, d) in x.iter_mut().zip(dx.iter()) {
                *xi -= d;
            }
        }
        best = best.max(x[n + 1]);
        if x[n + 1] < 0.9 * best {
            break;
        }
    }
    assert!(best > 0.1 && best < 1.0, "the oracle found a fold at {best}");
    assert!((s_limit - best).abs() < 2e-3, "load control {s_limit} vs displacement control {best}");
}

#[test]
fn thousand_links_come_back_stable() {
    let n = 1000;
    let s = n as f64 / 10.0;
    let (mut chain, design) = arch(n, 1.0, 0.4, 1e3 * s * s);
    chain.gravity = 0.0;
    let sol = solve_static(&problem(chain, design, -5.0, -400.0 * s), &ContinuationOptions::default());
    let loaded = sol.loaded.unwrap();
    assert_eq!(sol.passive.status, EquilibriumStatus::Stable);
    assert_eq!(loaded.status, EquilibriumStatus::Stable);
    // K = 10⁷ N·m/rad puts the residual's rounding floor near 1e-8 N·m: the solver says which
    // threshold it used, and meets it.
    assert!(loaded.residual_norm <= loaded.tolerance_used, "{} > {}", loaded.residual_norm, loaded.tolerance_used);
    assert!(loaded.tolerance_used < 1e-6);
    assert!(loaded.constraint_violation <= 1e-10);
}

#[test]
fn options_round_trip_through_json_and_reject_unknown_fields() {
    let opts = ContinuationOptions::default();
    let text = serde_json::to_string(&opts).unwrap();
    assert_eq!(serde_json::from_str::<ContinuationOptions>(&text).unwrap(), opts);
    assert!(serde_json::from_str::<ContinuationOptions>(r#"{"residual_tolerence": 1e-9}"#).is_err());
    let _ = NodalLoads::zero(1);
}

#[test]
fn options_validate_themselves_and_name_the_field() {
    assert_eq!(ContinuationOptions::default().validate(), Ok(()));
    let bad = |edit: &dyn Fn(&mut ContinuationOptions)| {
        let mut o = ContinuationOptions::default();
        edit(&mut o);
        o.validate().unwrap_err().field
    };
    assert_eq!(bad(&|o| o.residual_tolerance = f64::NAN), "residual_tolerance");
    assert_eq!(bad(&|o| o.max_angle_step = 0.0), "max_angle_step");
    assert_eq!(bad(&|o| o.initial_step = 1.5), "initial_step");
    assert_eq!(bad(&|o| o.min_step = 2.0 * o.initial_step), "min_step");
    assert_eq!(bad(&|o| o.max_newton_iterations = 0), "max_newton_iterations");
    assert_eq!(bad(&|o| o.max_steps = 0), "max_steps");
}
