//! The full-space derivatives against central differences, their sparsity patterns against what
//! Ipopt is told, and the reduced-space gradients: hand adjoint = AD adjoint = forward AD = central differences
//! through the equilibrium solver.

use spine_design::adjoint::{adjoint_ad, adjoint_hand, forward_ad};
use spine_design::fixtures::{arch_start, paper_problem, scaled_family};
use spine_design::full_space::{FullSpaceNlp, Layout, StateForm};
use spine_design::objective::Equilibria;
use spine_design::{DesignProblem, Objective};
use spine_ipopt::Problem;
use spine_model::rng::SplitMix64;
use spine_model::{Design, State};
use spine_solve::{solve_static, ContinuationOptions};

/// A random point near a design and its (non-equilibrium) states, with masses so that self-weight
/// is exercised.
fn random_point(problem: &DesignProblem, seed: u64) -> Vec<f64> {
    let n = problem.n_links();
    let layout = Layout::of(problem, StateForm::Absolute);
    let mut rng = SplitMix64::new(seed);
    let mut x = vec![0.0; layout.num_variables()];
    for (k, v) in x.iter_mut().enumerate() {
        *v = rng.uniform(-0.5, 0.5);
        if (n..2 * n + 1).contains(&k) {
            *v = rng.uniform(1.0, 100.0);
        }
    }
    x[layout.lambda(spine_design::full_space::LoadState::Passive)] = rng.uniform(-50.0, 50.0);
    x[layout.lambda(spine_design::full_space::LoadState::Loaded)] = rng.uniform(-50.0, 50.0);
    if layout.probe {
        x[layout.lambda(spine_design::full_space::LoadState::Probe)] = rng.uniform(-50.0, 50.0);
    }
    x
}

/// Every criterion of [`Objective`] for `n` links (the compliance's load: −3 N at every node,
/// 20 N axial at the end).
fn objectives(n: usize) -> Vec<Objective> {
    let mut load = spine_model::NodalLoads::zero(n);
    load.p_y.fill(-3.0);
    load.p_x[n] = 20.0;
    vec![
        Objective::StrainEnergy,
        Objective::TotalStiffness,
        // M_ref of the random points' moments (K up to 700 N·m/rad, deflections up to 1 rad).
        Objective::PeakMoment { exponent: 8, reference: 1000.0 },
        Objective::Compliance { load },
    ]
}

/// Sizes, state forms and criteria the derivative tests go over: `(N, form, name, problem)`.
fn cases() -> impl Iterator<Item = (usize, StateForm, String, DesignProblem)> {
    [1, 2, 3, 6, 15].into_iter().flat_map(|n| {
        [StateForm::Absolute, StateForm::Deflection]
            .into_iter()
            .flat_map(move |form| objectives(n).into_iter().map(move |o| (n, form, o, None)))
            // The strain-energy budget row, with the least-material criterion it is made for.
            .chain([(n, StateForm::Absolute, Objective::TotalStiffness, Some(0.05))])
            .chain([(n, StateForm::Deflection, Objective::TotalStiffness, Some(0.05))])
            .map(|(n, form, objective, budget)| {
                let name = format!("{}{}", objective.name(), if budget.is_some() { " with a budget" } else { "" });
                (n, form, name, problem_with_mass(n, objective, budget))
            })
    })
}

/// The full space of `problem` started at the arch `θ0_i = 0.3 cos(…)`, `K = 500 N·m/rad`, with
/// its unloaded shape as every state.
fn arch_nlp(problem: &DesignProblem, form: StateForm) -> FullSpaceNlp<'_> {
    let start = arch_start(problem.n_links(), 0.3, 500.0);
    let unloaded = State::unloaded(&start);
    FullSpaceNlp::new(problem, form, &start, &unloaded, &unloaded)
}

fn problem_with_mass(n: usize, objective: Objective, strain_energy_max: Option<f64>) -> DesignProblem {
    let mut p = paper_problem(n, -5.0, -400.0, -0.02, 7.0);
    p.structure.chain.masses = (0..n).map(|i| 0.1 + 0.01 * i as f64).collect();
    p.objective = objective;
    p.strain_energy_max = strain_energy_max;
    p
}

fn nlp_parts(nlp: &mut FullSpaceNlp<'_>, x: &[f64]) -> (f64, Vec<f64>, Vec<f64>) {
    let mut g = vec![0.0; nlp.num_constraints()];
    let f = nlp.objective(x, true).unwrap();
    assert!(nlp.constraints(x, false, &mut g));
    let mut grad = vec![0.0; x.len()];
    assert!(nlp.objective_gradient(x, false, &mut grad));
    (f, g, grad)
}

#[test]
fn full_space_jacobian_and_gradient_match_central_differences_and_the_pattern_is_exact() {
    for (n, form, name, problem) in cases() {
        let mut nlp = arch_nlp(&problem, form);
        let structure = nlp.jacobian_structure();
        let mut seen = std::collections::HashSet::new();
        for &entry in &structure {
            assert!(seen.insert(entry), "duplicate Jacobian entry {entry:?}");
        }
        for seed in 0..3 {
            let x = random_point(&problem, 100 * n as u64 + seed);
            let (_, _, grad) = nlp_parts(&mut nlp, &x);
            let mut values = vec![0.0; structure.len()];
            assert!(nlp.jacobian_values(&x, false, &mut values));
            let m = nlp.num_constraints();
            let mut dense = vec![vec![0.0; x.len()]; m];
            for (&(r, c), v) in structure.iter().zip(&values) {
                dense[r][c] = *v;
            }
            for k in 0..x.len() {
                let h = 1e-6 * x[k].abs().max(1.0);
                let (mut xp, mut xm) = (x.clone(), x.clone());
                xp[k] += h;
                xm[k] -= h;
                let (fp, gp, _) = nlp_parts(&mut nlp, &xp);
                let (fm, gm, _) = nlp_parts(&mut nlp, &xm);
                let fd = (fp - fm) / (2.0 * h);
                assert!(
                    (fd - grad[k]).abs() <= 1e-6 * grad[k].abs().max(1.0),
                    "N={n} {form:?} {name} ∂f/∂x{k}: AD {} FD {fd}",
                    grad[k]
                );
                for r in 0..m {
                    let fd = (gp[r] - gm[r]) / (2.0 * h);
                    let ad = dense[r][k];
                    assert!(
                        (fd - ad).abs() <= 1e-6 * ad.abs().max(1.0),
                        "N={n} {form:?} {name} ∂g{r}/∂x{k}: AD {ad} FD {fd}"
                    );
                }
            }
            // Every declared entry is nonzero at a random point: the pattern is exact.
            for (&(r, c), v) in structure.iter().zip(&values) {
                assert!(*v != 0.0, "N={n} {name}: declared Jacobian entry ({r}, {c}) is zero");
            }
        }
    }
}

#[test]
fn assembled_objective_is_each_criterion_evaluated_directly() {
    // The elements' sum against `Objective::value` from the design and states (node positions for
    // the compliance, joint moments for the peak moment): two formulations of each criterion.
    for (n, form, name, problem) in cases() {
        let mut nlp = arch_nlp(&problem, form);
        let layout = nlp.layout;
        for seed in 0..3 {
            let mut x = random_point(&problem, 31 * n as u64 + seed);
            if form == StateForm::Deflection {
                // The same absolute angles in deflections (random_point draws absolute ones).
                let absolute = Layout::of(&problem, StateForm::Absolute);
                for &s in layout.load_states() {
                    for i in 0..n {
                        x[layout.state_angle(s, i)] = x[absolute.state_angle(s, i)] - x[layout.theta0(i)];
                    }
                }
            }
            let design = layout.design(&x, problem.stiffness_scale);
            use spine_design::full_space::LoadState;
            let (passive, loaded) = (layout.state(&x, LoadState::Passive), layout.state(&x, LoadState::Loaded));
            let probe = layout.probe.then(|| layout.state(&x, LoadState::Probe));
            let states = Equilibria { passive: &passive, loaded: &loaded, probe: probe.as_ref() };
            let direct = problem.objective.value(&problem.structure.chain.spans, &design, &states);
            let assembled = nlp.objective(&x, true).unwrap();
            assert!(
                (assembled - direct).abs() <= 1e-12 * direct.abs().max(1.0),
                "N={n} {form:?} {name}: assembled {assembled} direct {direct}"
            );
        }
    }
}

#[test]
fn full_space_hessian_matches_central_differences_of_the_lagrangian_gradient() {
    for (n, form, name, problem) in cases() {
        let mut nlp = arch_nlp(&problem, form);
        let structure = nlp.hessian_structure().unwrap();
        let jac_structure = nlp.jacobian_structure();
        let m = nlp.num_constraints();
        let mut rng = SplitMix64::new(n as u64);
        let lambda: Vec<f64> = (0..m).map(|_| rng.uniform(-2.0, 2.0)).collect();
        let sigma = 1.7;
        let x = random_point(&problem, 7 + n as u64);
        let mut values = vec![0.0; structure.len()];
        assert!(nlp.hessian_values(&x, true, sigma, &lambda, true, &mut values));
        let mut dense = vec![vec![0.0; x.len()]; x.len()];
        let mut seen = std::collections::HashSet::new();
        for (&(r, c), v) in structure.iter().zip(&values) {
            assert!(r >= c, "upper-triangle entry ({r}, {c})");
            assert!(seen.insert((r, c)), "duplicate Hessian entry ({r}, {c})");
            dense[r][c] = *v;
            dense[c][r] = *v;
            assert!(*v != 0.0, "N={n} {name}: declared Hessian entry ({r}, {c}) is zero");
        }
        // ∇_x L = σ∇f + Jᵀλ, by the AD first derivatives.
        let mut lagrangian_gradient = |x: &[f64]| -> Vec<f64> {
            let mut grad = vec![0.0; x.len()];
            assert!(nlp.objective_gradient(x, true, &mut grad));
            let mut jac = vec![0.0; jac_structure.len()];
            assert!(nlp.jacobian_values(x, false, &mut jac));
            let mut out: Vec<f64> = grad.iter().map(|g| sigma * g).collect();
            for (&(r, c), v) in jac_structure.iter().zip(&jac) {
                out[c] += lambda[r] * v;
            }
            out
        };
        for k in 0..x.len() {
            let h = 1e-6 * x[k].abs().max(1.0);
            let (mut xp, mut xm) = (x.clone(), x.clone());
            xp[k] += h;
            xm[k] -= h;
            let (gp, gm) = (lagrangian_gradient(&xp), lagrangian_gradient(&xm));
            for r in 0..x.len() {
                let fd = (gp[r] - gm[r]) / (2.0 * h);
                let ad = dense[r][k];
                assert!(
                    (fd - ad).abs() <= 1e-6 * ad.abs().max(1.0),
                    "N={n} {form:?} {name} ∂²L/∂x{r}∂x{k}: AD {ad} FD {fd}"
                );
            }
        }
    }
}

#[test]
fn full_space_derivative_counts_are_linear_in_n() {
    for (n, form) in [10, 100, 1000].into_iter().flat_map(|n| [(n, StateForm::Absolute), (n, StateForm::Deflection)]) {
        let problem = scaled_family(n);
        let start = arch_start(n, 0.3, 1e3);
        let unloaded = State::unloaded(&start);
        let nlp = FullSpaceNlp::new(&problem, form, &start, &unloaded, &unloaded);
        let (jac, hess) = (nlp.jacobian_structure().len(), nlp.hessian_structure().unwrap().len());
        // Per link: two joint rows of 9, two rises and a run of 2, a height step of ≤ 3, a
        // relative angle of 2 → at most 30 Jacobian entries; Hessian entries per link are bounded too.
        assert!(jac <= 30 * n, "N={n}: {jac} Jacobian entries");
        assert!(hess <= 40 * n, "N={n}: {hess} Hessian entries");
    }
}

/// Solves both equilibria of `design` to rounding precision.
fn equilibria(problem: &DesignProblem, design: &Design) -> (State, State) {
    let opts = ContinuationOptions { residual_tolerance: 1e-15, ..ContinuationOptions::default() };
    let s = solve_static(&problem.static_problem(design), &opts);
    assert_eq!(s.passive.load_factor, 1.0);
    let loaded = s.loaded.unwrap();
    assert_eq!(loaded.load_factor, 1.0);
    (s.passive.state, loaded.state)
}

#[test]
fn adjoint_gradients_equal_forward_ad_and_central_differences_through_the_solver() {
    for (n, seed) in [(2, 1), (5, 2), (10, 3), (20, 4)] {
        let mut problem = problem_with_mass(n, Objective::StrainEnergy, None);
        problem.structure.actuation.p_x[n] = -200.0;
        let mut rng = SplitMix64::new(seed);
        let mut design = arch_start(n, 0.25, 1500.0);
        for k in design.stiffness.iter_mut() {
            *k *= rng.uniform(0.8, 1.2);
        }
        for t in design.theta0.iter_mut() {
            *t += rng.uniform(-0.02, 0.02);
        }
        let (s1, s2) = equilibria(&problem, &design);
        let hand = adjoint_hand(&problem, &design, &s1, &s2).unwrap();
        let ad = forward_ad(&problem, &design, &s1, &s2).unwrap();
        let ad_adjoint = adjoint_ad(&problem, &design, &s1, &s2).unwrap();
        let scale_j = hand.energy_gradient.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let scale_x = hand.end_x_gradient.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for k in 0..2 * n + 1 {
            assert!((hand.energy_gradient[k] - ad.energy_gradient[k]).abs() <= 1e-10 * scale_j, "N={n} dJ/dd{k}");
            assert!((hand.end_x_gradient[k] - ad.end_x_gradient[k]).abs() <= 1e-10 * scale_x, "N={n} dX/dd{k}");
            assert!(
                (hand.energy_gradient[k] - ad_adjoint.energy_gradient[k]).abs() <= 1e-10 * scale_j,
                "N={n} dJ/dd{k} (AD adjoint)"
            );
            assert!(
                (hand.end_x_gradient[k] - ad_adjoint.end_x_gradient[k]).abs() <= 1e-10 * scale_x,
                "N={n} dX/dd{k} (AD adjoint)"
            );
            // Fourth-order central differences through the continuation solver (truncation
            // O(h⁴): about 1e-12 for θ0 with h = 1e-3 rad, 1e-8 for K with h = 1e-2 K; rounding of
            // the solves about 1e-15 m in X divided by 12h). Each entry is compared
            // relative to its own size, with a floor of 1e-7 of the gradient's largest entry
            // (entries below that are zero up to the solver's rounding).
            let h = if k < n { 1e-3 } else { 1e-2 * design.stiffness[k - n] };
            let at = |sign: f64| {
                let mut d = design.clone();
                if k < n {
                    d.theta0[k] += sign * h;
                } else {
                    d.stiffness[k - n] += sign * h;
                }
                let (a, b) = equilibria(&problem, &d);
                let g = adjoint_hand(&problem, &d, &a, &b).unwrap();
                (g.energy, g.end_x)
            };
            let ((jp, xp), (jm, xm)) = (at(1.0), at(-1.0));
            let ((jp2, xp2), (jm2, xm2)) = (at(2.0), at(-2.0));
            let fd_j = (8.0 * (jp - jm) - (jp2 - jm2)) / (12.0 * h);
            let fd_x = (8.0 * (xp - xm) - (xp2 - xm2)) / (12.0 * h);
            let err_j = (fd_j - hand.energy_gradient[k]).abs() / hand.energy_gradient[k].abs().max(1e-7 * scale_j);
            let err_x = (fd_x - hand.end_x_gradient[k]).abs() / hand.end_x_gradient[k].abs().max(1e-7 * scale_x);
            assert!(
                err_j <= 1e-7,
                "N={n} dJ/dd{k}: adjoint {} FD {fd_j} (relative {err_j:e})",
                hand.energy_gradient[k]
            );
            assert!(err_x <= 1e-7, "N={n} dX/dd{k}: adjoint {} FD {fd_x} (relative {err_x:e})", hand.end_x_gradient[k]);
        }
    }
}
