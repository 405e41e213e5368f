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
            assert!((critical_load_factor - expected).abs() <= 1e-9, "{critical_load_factor} vs {expected}");
        }
        other => panic!("expected loss of stability, got {other:?}"),
    }
    assert!(!loaded.stability.stable);
    assert_eq!(loaded.stability.negative_directions, 1);
}

/// The central-difference Jacobian of `f` at `x` as a dense matrix (the oracles' Newton matrix).
fn fd_jacobian(x: &[f64], f: impl Fn(&[f64]) -> Vec<f64>) -> DMatrix<f64> {
    let rows = spine_model::finite_difference::central_jacobian(x, 1e-7, f);
    DMatrix::from_fn(rows.len(), x.len(), |i, j| rows[i][j])
}

/// Independent oracle of a fold: displacement control. The end's X is prescribed and
/// `(θ, λ, s)` solved by dense Newton with a central-difference Jacobian, stepping X down from the
/// start of the loaded path (1 mm steps) until the load factor falls; the largest load factor is
/// then found by golden-section search on X (to 1e-9 m, where `s(X)` is flat to 1e-15).
fn fold_by_displacement_control(p: &StaticProblem, start: &spine_model::State) -> f64 {
    let spans = p.structure.chain.spans.clone();
    let n = spans.len();
    let (from, to) = (p.passive_loads(), p.total_loads());
    let design = &p.design;
    let equations = |x: &[f64], x_end: f64| -> Vec<f64> {
        let st = spine_model::State { theta: x[..n].to_vec(), lambda: x[n] };
        let loads = spine_model::LinkLoads::lerp(&from, &to, x[n + 1]);
        let mut r = spine_model::residual::equilibrium_residual(&spans, design, &loads, &st);
        r.push(spine_model::kinematics::end_x(&spans, &design.theta0, &st.theta) - x_end);
        r
    };
    let solve = |x: &mut Vec<f64>, x_end: f64| {
        for _ in 0..60 {
            let r = equations(x, x_end);
            if r.iter().fold(0.0f64, |m, v| m.max(v.abs())) < 1e-12 {
                return;
            }
            let jac = fd_jacobian(x, |y| equations(y, x_end));
            let dx = jac.lu().solve(&nalgebra::DVector::from_vec(r)).expect("regular under displacement control");
            x.iter_mut().zip(dx.iter()).for_each(|(xi, d)| *xi -= d);
        }
        panic!("displacement control did not converge at X = {x_end}");
    };
    let mut x: Vec<f64> = start.theta.clone();
    x.extend([start.lambda, 0.0]);
    let x0 = spine_model::kinematics::end_x(&spans, &design.theta0, &start.theta);
    let mut previous = x.clone();
    let mut k = 0;
    loop {
        k += 1;
        assert!(k < 5000, "no fold within 5 m of end travel");
        let x_end = x0 - 1e-3 * k as f64;
        solve(&mut x, x_end);
        if x[n + 1] < previous[n + 1] {
            break;
        }
        previous = x.clone();
    }
    // The largest s lies between X at step k − 2 and X at step k.
    let (mut a, mut b) = (x0 - 1e-3 * (k - 2) as f64, x0 - 1e-3 * k as f64);
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let mut best = previous[n + 1];
    let mut guess = previous;
    let at = |x_end: f64, guess: &mut Vec<f64>| {
        solve(guess, x_end);
        guess[n + 1]
    };
    while (a - b).abs() > 1e-9 {
        let (c, d) = (b + g * (a - b), a + g * (b - a));
        let (sc, sd) = (at(c, &mut guess), at(d, &mut guess));
        best = best.max(sc).max(sd);
        if sc > sd {
            b = d;
        } else {
            a = c;
        }
    }
    best
}

/// The fold's load factor by load control, checked against displacement control to 1e-9.
fn assert_fold_located(p: &StaticProblem, what: &str) -> f64 {
    let sol = solve_static(p, &ContinuationOptions::default());
    let loaded = sol.loaded.unwrap();
    let s_limit = match loaded.status {
        EquilibriumStatus::LimitPoint { load_factor } => load_factor,
        other => panic!("{what}: expected a limit point, got {other:?}"),
    };
    assert!(loaded.stability.stable, "{what}: the returned state is the last stable one");
    assert!(loaded.residual_norm <= 1e-10);
    assert!(loaded.load_factor <= s_limit);
    let tolerance = ContinuationOptions::default().critical_load_tolerance;
    let by_arc = fold_by_arclength(p, &sol.passive.state).expect("the arclength oracle finds the fold");
    let by_displacement = fold_by_displacement_control(p, &sol.passive.state);
    for (oracle, name) in [(by_arc, "arclength"), (by_displacement, "displacement control")] {
        assert!(oracle > 0.05 && oracle < 1.0, "{what}: {name} found a fold at {oracle}");
        assert!(
            (s_limit - oracle).abs() <= tolerance,
            "{what}: load control {s_limit} vs {name} {oracle} (difference {:e})",
            s_limit - oracle
        );
    }
    s_limit
}

/// An arch pushed at its sliding end rises until it can carry no more compression: a fold of the
/// load path, located to `critical_load_tolerance` (issue 18: it was located only to `min_step`).
#[test]
fn compressed_arch_reports_the_limit_point() {
    let (mut chain, design) = arch(4, 1.0, 0.4, 100.0);
    chain.gravity = 0.0;
    assert_fold_located(&problem(chain, design, 0.0, -400.0), "4-link arch");
}

/// A steep 10-link design whose loaded path folds at s ≈ 0.683. Found by comparing the default
/// continuation with one of 50 times smaller angle steps on 6000 random designs: load control with
/// the default steps used to jump past the fold onto a collapsed stable branch (the end moved by
/// −0.74 m) and report that as the stable equilibrium.
#[test]
fn steep_design_stops_at_its_fold_instead_of_jumping_to_a_collapsed_branch() {
    let steep = design10(
        -2.207153665131283,
        -1947.2495983354445,
        steep_theta0(),
        &[
            2299.657906492926,
            3535.600756691748,
            2137.5634007258313,
            610.7754483762466,
            9484.973373391398,
            662.5791126319525,
            109.59948758660417,
            662.3617398406554,
            4517.791862021018,
            1294.4006933307376,
            220.91116952974156,
        ],
    );
    let s = assert_fold_located(&steep, "steep 10-link design");
    assert!((s - 0.683322).abs() < 1e-5, "{s}");
}

/// A 10-link arch whose load-controlled path stalls at s ≈ 0.944 but does not fold: the old
/// continuation called the stall a limit point (its smallest eigenvalue had fallen below 1 % of
/// the start's). The arclength oracle traces the path rising to the full load; the continuation
/// now follows it there too, to the state the finely stepped continuation reaches.
#[test]
fn a_stall_of_load_control_is_not_reported_as_a_fold() {
    let arch = design10(
        -14.151877162347768,
        -1837.7600901176636,
        vec![
            0.25777953592700764,
            0.23254627889483487,
            0.1845497718392381,
            0.11848824728214755,
            0.04082826752491781,
            -0.04082826752491772,
            -0.11848824728214752,
            -0.18454977183923807,
            -0.23254627889483484,
            -0.2577795359270076,
        ],
        &[
            281.8086946264345,
            2471.0397678131676,
            1452.7054526248041,
            4454.797322803245,
            113.4303250156606,
            690.1553802222188,
            188.24756650287713,
            153.98346182387692,
            1285.0426729673595,
            3564.0929818641507,
            3463.3421845077055,
        ],
    );
    let default = solve_static(&arch, &ContinuationOptions::default());
    assert_eq!(fold_by_arclength(&arch, &default.passive.state), None, "the oracle found a fold");
    let fine = solve_static(&arch, &ContinuationOptions { max_angle_step: 0.002, ..ContinuationOptions::default() });
    let (a, b) = (default.loaded.unwrap(), fine.loaded.unwrap());
    assert_eq!(a.status, EquilibriumStatus::Stable, "{}", a.status);
    assert_eq!(b.status, EquilibriumStatus::Stable, "{}", b.status);
    let difference = a.state.theta.iter().zip(&b.state.theta).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(difference < 1e-9, "{difference}");
}

/// `θ0 = (π/6, 0, …, 0, −π/6)` for 10 links.
fn steep_theta0() -> Vec<f64> {
    let mut theta0 = vec![0.0; 10];
    theta0[0] = std::f64::consts::FRAC_PI_6;
    theta0[9] = -std::f64::consts::FRAC_PI_6;
    theta0
}

/// 10 links over 1 m, `p_y` per node (passive), `p_x` at the end (actuation), no self-weight.
fn design10(p_y: f64, p_x: f64, theta0: Vec<f64>, stiffness: &[f64]) -> StaticProblem {
    let mut chain = Chain::uniform(10, 1.0);
    chain.gravity = 0.0;
    problem(chain, Design { theta0, stiffness: stiffness.to_vec() }, p_y, p_x)
}

/// Issue 18: on a steep arch the continuation took a large step, landed on an unstable
/// equilibrium of another branch and reported "stability lost at 0.48 (buckling)", while the path
/// itself stays stable to the full load and ends collapsed (X − L_x = −0.633 m). Checked against
/// the same path traced with 50 times smaller angle steps and against the dense eigenvalues of the
/// final state.
#[test]
fn steep_arch_reaches_the_full_load_on_its_stable_path() {
    let p = design10(
        -17.44,
        -1930.1,
        steep_theta0(),
        &[1059.0, 1294.0, 149.0, 9369.0, 2316.0, 9814.0, 114.0, 530.0, 1307.0, 161.0, 477.0],
    );
    let default = solve_static(&p, &ContinuationOptions::default());
    let fine = solve_static(&p, &ContinuationOptions { max_angle_step: 0.002, ..ContinuationOptions::default() });
    let (a, b) = (default.loaded.unwrap(), fine.loaded.unwrap());
    assert_eq!(a.status, EquilibriumStatus::Stable, "{}", a.status);
    assert_eq!(b.status, EquilibriumStatus::Stable);
    let difference = a.state.theta.iter().zip(&b.state.theta).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(difference < 1e-9, "{difference}");
    let end = default.end_displacement.unwrap();
    assert!((end - (-0.6332)).abs() < 1e-3, "{end}");
    let (_, jac) = spine_model::jacobian::residual_and_state_jacobian(
        &p.structure.chain.spans,
        &p.design,
        &p.total_loads(),
        &a.state,
    );
    let n = p.design.theta0.len();
    let border: Vec<f64> = jac.row[..n].to_vec();
    let eigenvalues = common::projected_eigenvalues(&common::block(&jac), &border);
    assert!(eigenvalues[0] > 1.0, "dense oracle: smallest projected eigenvalue {}", eigenvalues[0]);
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

/// Independent oracle of a fold: pseudo-arclength continuation of `F(θ, λ, s) = 0` written out
/// densely, with a central-difference Jacobian, the tangent as the null vector of `∂F/∂(θ, λ, s)`
/// (normalised over θ and s), and a fixed small step of `1e-3` along it. Returns the largest load
/// factor before the path first turns back (refined by golden-section search along the arc), or
/// `None` when the path reaches the full load rising.
fn fold_by_arclength(p: &StaticProblem, start: &spine_model::State) -> Option<f64> {
    let spans = p.structure.chain.spans.clone();
    let n = spans.len();
    let (from, to) = (p.passive_loads(), p.total_loads());
    let design = &p.design;
    let f = |z: &[f64]| -> Vec<f64> {
        let st = spine_model::State { theta: z[..n].to_vec(), lambda: z[n] };
        let loads = spine_model::LinkLoads::lerp(&from, &to, z[n + 1]);
        spine_model::residual::equilibrium_residual(&spans, design, &loads, &st)
    };
    let jacobian = |z: &[f64]| fd_jacobian(z, f);
    // Weights of the arclength: θ and s count, λ (in N) is carried along.
    let weight = |j: usize| if j == n { 0.0 } else { 1.0 };
    let tangent = |z: &[f64], previous: &[f64]| -> Vec<f64> {
        let mut a = DMatrix::zeros(n + 2, n + 2);
        a.view_mut((0, 0), (n + 1, n + 2)).copy_from(&jacobian(z));
        for j in 0..n + 2 {
            a[(n + 1, j)] = previous[j] * weight(j);
        }
        let mut rhs = nalgebra::DVector::zeros(n + 2);
        rhs[n + 1] = 1.0;
        let t = a.lu().solve(&rhs).expect("regular bordered matrix");
        let norm = (0..n + 2).map(|j| weight(j) * t[j] * t[j]).sum::<f64>().sqrt();
        t.iter().map(|v| v / norm).collect()
    };
    let correct = |z0: &[f64], t: &[f64], h: f64| -> Vec<f64> {
        let predicted: Vec<f64> = z0.iter().zip(t).map(|(z, t)| z + h * t).collect();
        let mut z = predicted.clone();
        for _ in 0..60 {
            let mut r = f(&z);
            r.push((0..n + 2).map(|j| weight(j) * t[j] * (z[j] - predicted[j])).sum());
            if r.iter().fold(0.0f64, |m, v| m.max(v.abs())) < 1e-11 {
                return z;
            }
            let mut a = DMatrix::zeros(n + 2, n + 2);
            a.view_mut((0, 0), (n + 1, n + 2)).copy_from(&jacobian(&z));
            for j in 0..n + 2 {
                a[(n + 1, j)] = weight(j) * t[j];
            }
            let dz = a.lu().solve(&nalgebra::DVector::from_vec(r)).expect("regular corrector");
            z.iter_mut().zip(dz.iter()).for_each(|(zi, d)| *zi -= d);
        }
        panic!("arclength corrector did not converge");
    };
    let mut z: Vec<f64> = start.theta.clone();
    z.extend([start.lambda, 0.0]);
    let mut t = vec![0.0; n + 2];
    t[n + 1] = 1.0;
    t = tangent(&z, &t);
    let h = 1e-3;
    for _ in 0..200_000 {
        let next = correct(&z, &t, h);
        if next[n + 1] >= 1.0 {
            return None;
        }
        let t_next = tangent(&next, &t);
        if t_next[n + 1] < 0.0 {
            // s(σ) has its maximum within (0, h) of z: golden-section search on σ.
            let (mut a, mut b) = (0.0, h);
            let g = (5f64.sqrt() - 1.0) / 2.0;
            let mut best = z[n + 1].max(next[n + 1]);
            while b - a > 1e-10 {
                let (c, d) = (b - g * (b - a), a + g * (b - a));
                let (sc, sd) = (correct(&z, &t, c)[n + 1], correct(&z, &t, d)[n + 1]);
                best = best.max(sc).max(sd);
                if sc > sd {
                    b = d;
                } else {
                    a = c;
                }
            }
            return Some(best);
        }
        z = next;
        t = t_next;
    }
    panic!("the arclength oracle took too many steps");
}

/// A run's time limit (`spine_stop`) ends the continuation at its next step with status
/// `time_limit` at the load factor reached; a limit the solve stays within changes nothing.
#[test]
fn a_passed_time_limit_ends_the_continuation_with_its_own_status() {
    let p = scaled_family(20);
    let (sol, reached) =
        spine_stop::with_time_limit(Some(std::time::Duration::ZERO), || solve_static(&p, &Default::default()));
    assert!(reached);
    assert_eq!(sol.passive.status, EquilibriumStatus::TimeLimit { load_factor: 0.0 });
    assert!(!sol.passive.status.is_stable() && sol.loaded.is_none());
    let (sol, reached) = spine_stop::with_time_limit(Some(std::time::Duration::from_secs(3600)), || {
        solve_static(&p, &Default::default())
    });
    assert!(!reached);
    assert_eq!(sol.passive.status, EquilibriumStatus::Stable);
}
