//! The periodic-load design of eq. (37): the searches, the exact gradients, two minima.

use spine_dynamic_design::periodic_gradient::{eq37_point, Eq37Point};
use spine_dynamic_design::{design_periodic, PeriodicDesignSettings, SearchMethod};
use spine_dynamics::periodic::EndValue;
use spine_dynamics::{periodic_response, DynamicProblem, Forcing};
use spine_search::{GaSettings, PatternSettings};

fn problem(n: usize) -> DynamicProblem {
    spine_dynamics::fixtures::periodic_problem(n)
}

#[test]
fn eq37_searches_lower_the_strain_energy_and_keep_the_displacement() {
    let p = problem(3);
    let forcing = Forcing::PulseTrain { period: 0.6, duty: 0.5, delay: 0.0 };
    let mut settings = PeriodicDesignSettings::default();
    settings.response.max_periods = 3;
    settings.response.samples_per_period = 60;
    // δ_d: the start's own minimum, so the start is feasible and any improvement is real.
    let start = periodic_response(&p, forcing.clone(), None, &settings.response).unwrap();
    let delta_d = start.min_end_displacement * 1.2;
    settings.pattern =
        PatternSettings { initial_mesh: 0.1, mesh_tolerance: 0.01, max_evaluations: 60, ..Default::default() };
    settings.ga = GaSettings { population: 8, generations: 4, stall_generations: 4, seed: 5, ..Default::default() };
    for method in [SearchMethod::Pattern, SearchMethod::Ga] {
        let a = design_periodic(&p, forcing.clone(), delta_d, method, &settings, &mut |_| {}).unwrap();
        assert!(
            !a.start.better_than(&a.search.as_ref().unwrap().best),
            "{method:?}: the search never returns worse than its start"
        );
        if method == SearchMethod::Pattern {
            // The start is 20 % short of δ_d; softer springs reach it, and the search then trades
            // stiffness along the band for a lower strain energy.
            assert!(a.feasible, "{method:?}: min {} vs δ_d {delta_d}", a.min_end_displacement);
            assert!(a.relative_error <= settings.tolerance + 1e-12);
        }
        assert!(a.stiffness.iter().all(|k| (1e2..=1e4).contains(k)));
        let b = design_periodic(&p, forcing.clone(), delta_d, method, &settings, &mut |_| {}).unwrap();
        assert_eq!(a.stiffness, b.stiffness, "deterministic");
    }
    // The gradient method from the GA's best: the GA runs first and its result is kept beside
    // Ipopt's report.
    settings.gradient.start = spine_dynamic_design::periodic_settings::GradientStart::Ga;
    let g = design_periodic(&p, forcing.clone(), delta_d, SearchMethod::Gradient, &settings, &mut |_| {}).unwrap();
    let report = g.gradient.as_ref().unwrap();
    assert_eq!(report.start, spine_dynamic_design::periodic_settings::GradientStart::Ga);
    let ga = g.search.as_ref().expect("the GA's result");
    assert!(g.finished() && g.feasible && g.relative_error <= 1e-6, "{} {}", g.status(), g.relative_error);
    assert_eq!(g.simulations, 1 + ga.evaluations + report.root_search_simulations + report.gradient_simulations);
}

/// A 3-link chain under short pulses (period 0.1 s, dampers 9 N·m·s/rad, springs
/// `0.8 × [1500, 2500, 1800, 900]` N·m/rad) whose last period has two local minima of the end
/// displacement within 0.5 % of each other: an overshoot early in the on-phase and the lowest point
/// before the release.
fn two_minima() -> (DynamicProblem, Forcing, PeriodicDesignSettings, Vec<f64>) {
    let mut p = problem(3);
    p.damping = vec![9.0; 4];
    let forcing = Forcing::PulseTrain { period: PERIOD, duty: 0.5, delay: 0.0 };
    let mut settings = PeriodicDesignSettings::default();
    settings.response.max_periods = PERIODS;
    settings.response.samples_per_period = 60;
    settings.response.integrator.rtol = 1e-10;
    settings.response.integrator.atol = 1e-12;
    let k = [1500.0, 2500.0, 1800.0, 900.0].iter().map(|k| k * 0.8).collect();
    (p, forcing, settings, k)
}
const PERIOD: f64 = 0.1;
const PERIODS: usize = 4;

/// The overshoot and the minimum near the release (by their phase within the last period), when
/// both are local minima: `(overshoot, release)`.
fn overshoot_and_release(point: &Eq37Point) -> Option<(&EndValue, &EndValue)> {
    let phase = |m: &EndValue| (m.t - (PERIODS - 1) as f64 * PERIOD) / PERIOD;
    let early = point.minima.iter().find(|m| (0.05..0.35).contains(&phase(m)))?;
    let release = point.minima.iter().find(|m| (0.35..0.55).contains(&phase(m)))?;
    Some((early, release))
}

/// Central differences of `f` in each spring against `gradient` (relative to its largest entry).
fn check_gradient(what: &str, k: &[f64], gradient: &[f64], f: &dyn Fn(&[f64]) -> f64, tolerance: f64) {
    let scale = gradient.iter().fold(0.0f64, |m, g| m.max(g.abs()));
    assert!(scale > 0.0, "{what}: a gradient that is not zero");
    for j in 0..k.len() {
        let h = 1e-4 * k[j];
        let at = |sign: f64| {
            let mut kk = k.to_vec();
            kk[j] += sign * h;
            f(&kk)
        };
        let fd = (at(1.0) - at(-1.0)) / (2.0 * h);
        eprintln!("{what}, K_{j}: exact {:.10e}, differences {fd:.10e}", gradient[j]);
        assert!(
            (fd - gradient[j]).abs() <= tolerance * scale,
            "{what}, K_{j}: exact {} vs differences {fd}",
            gradient[j]
        );
    }
}

/// Eq. (37)'s gradients (module `periodic_gradient`) against central differences of the whole
/// periodic simulation from re-solved equilibria: the strain energy, and both local minima of
/// the last period. The two minima are within 0.5 % of each other, so both enter eq. (37): the
/// lowest as the equality, the other as `≥ δ_d`, each with its own gradient.
#[test]
fn eq37_gradients_match_central_differences_of_the_whole_periodic_simulation() {
    let (p, forcing, settings, k) = two_minima();
    let point = eq37_point(&p, &forcing, &k, -0.01, &settings, PERIODS).unwrap();
    let (early, release) = overshoot_and_release(&point).expect("two local minima");
    let [first, second] = &point.minima;
    assert_eq!((first, second), (early, release), "the overshoot is the lowest, the release minimum the second");
    let gap = (second.value - first.value) / first.value.abs();
    assert!(gap > 0.0 && gap < 5e-3, "within the band of each other: {gap:.2e}");
    let distinct: f64 = early.gradient.iter().zip(&release.gradient).map(|(a, b)| (a - b).abs()).sum();
    let size: f64 = release.gradient.iter().map(|g| g.abs()).sum();
    assert!(distinct > 0.03 * size, "two different gradients: {early:?} {release:?}");
    let at = |kk: &[f64]| eq37_point(&p, &forcing, kk, -0.01, &settings, PERIODS).unwrap();
    check_gradient("U(θ1)", &k, &point.energy_gradient, &|kk| at(kk).energy, 1e-6);
    let value = |overshoot: bool| {
        move |kk: &[f64]| {
            let point = at(kk);
            let (e, r) = overshoot_and_release(&point).expect("both minima");
            if overshoot {
                e.value
            } else {
                r.value
            }
        }
    };
    check_gradient("overshoot minimum", &k, &early.gradient, &value(true), 1e-5);
    check_gradient("release minimum", &k, &release.gradient, &value(false), 1e-5);
}

/// The constraint gradients by the discrete adjoint (the default) equal those by forward
/// sensitivities to 1e-8 relative, for both minima of the two-minima design and for a 7-link
/// chain under the periodic fixture's pulses; the adjoint's values come from a plain run.
#[test]
fn adjoint_constraint_gradients_equal_the_forward_ones() {
    use spine_dynamic_design::periodic_gradient::eq37_values;
    use spine_dynamic_design::periodic_settings::Sensitivities;
    let (p3, forcing3, settings3, k3) = two_minima();
    let p7 = problem(7);
    let forcing7 = Forcing::PulseTrain { period: 0.4, duty: 0.5, delay: 0.0 };
    let k7: Vec<f64> = (0..8).map(|j| 1500.0 + 150.0 * j as f64).collect();
    for (p, forcing, settings, k, periods) in
        [(p3, forcing3, settings3, k3, PERIODS), (p7, forcing7, PeriodicDesignSettings::default(), k7, 3)]
    {
        let mut adjoint = eq37_values(&p, &forcing, &k, -0.01, &settings, periods).unwrap();
        assert!(adjoint.pending() && adjoint.minima[0].gradient.is_empty(), "values first, gradients on demand");
        assert!(adjoint.constraint_gradients() && !adjoint.pending());
        let mut forward_settings = settings.clone();
        forward_settings.gradient.sensitivities = Sensitivities::Forward;
        let forward = eq37_point(&p, &forcing, &k, -0.01, &forward_settings, periods).unwrap();
        for (a, f) in adjoint.minima.iter().zip(&forward.minima) {
            assert_eq!((a.t, a.value), (f.t, f.value), "the same run");
            let scale = f.gradient.iter().fold(0.0f64, |m, g| m.max(g.abs()));
            for (j, (x, y)) in a.gradient.iter().zip(&f.gradient).enumerate() {
                assert!((x - y).abs() <= 1e-8 * scale, "N = {}, K_{j}: adjoint {x:e} vs forward {y:e}", k.len() - 1);
            }
        }
    }
}

/// The gradient method from the two-minima design, asked for 5 % more displacement: Ipopt
/// converges with the lowest minimum on δ_d, the other one not below it, and the result's
/// numbers agree with a plain re-simulation of the final springs.
#[test]
fn eq37_by_gradient_meets_delta_d_with_two_minima_in_play() {
    use spine_dynamic_design::periodic_settings::GradientStart;
    let (mut p, forcing, mut settings, k) = two_minima();
    let start = eq37_point(&p, &forcing, &k, -0.01, &settings, PERIODS).unwrap();
    let delta_d = 1.05 * start.minima[0].value;
    p.design.stiffness = k;
    settings.gradient.start = GradientStart::Case;
    // The horizon of the other tests (the start would settle to 1e-3 in 2 periods, and the
    // horizon would be 3).
    settings.response.settle_tolerance = 1e-12;
    settings.response.integrator.rtol = 1e-8;
    settings.response.integrator.atol = 1e-10;
    let d = design_periodic(&p, forcing.clone(), delta_d, SearchMethod::Gradient, &settings, &mut |_| {}).unwrap();
    let g = d.gradient.as_ref().unwrap();
    eprintln!("{g:?}\nK = {:?}, U = {} (start {})", d.stiffness, d.objective, start.energy);
    assert!(g.converged, "{}", g.status);
    assert!(g.constraints[0].abs() <= 1e-6 && g.constraints[1] >= -1e-6, "{:?}", g.constraints);
    assert!(
        d.feasible && d.relative_error <= 1e-6,
        "min {} vs δ_d {delta_d}, feasible {}, error {}",
        d.min_end_displacement,
        d.feasible,
        d.relative_error
    );
    assert_eq!(
        d.simulations,
        1 + g.root_search_simulations + g.gradient_simulations,
        "the start, the settling and Ipopt"
    );
    let replay = eq37_point(&p_with(&p, &d.stiffness), &forcing, &d.stiffness, delta_d, &settings, g.periods).unwrap();
    assert_eq!(replay.minima[0].value, d.min_end_displacement);
    // Bounds became active on the way (the start is inside): one spring at 10⁴ and one at 10².
    // Which ones depends on the path: the design has local optima with the roles of the outer
    // and inner springs swapped (K ≈ (10⁴, 3282, 10², 757) and (752, 10², 3447, 10⁴) both satisfy
    // the tests below).
    assert_eq!((g.at_lower_bound.len(), g.at_upper_bound.len()), (1, 1), "{g:?}");
    let (lower, upper) = (g.at_lower_bound[0], g.at_upper_bound[0]);
    assert!((d.stiffness[lower] / 1e2 - 1.0).abs() <= 1e-4 && (d.stiffness[upper] / 1e4 - 1.0).abs() <= 1e-4);
    // First-order conditions from our own gradients (in K; the scaling to log10 K cancels): the
    // free springs share one ratio μ = (dU/dK_j)/(dx/dK_j); at the upper bound U would still fall
    // along the constraint (dU − μ dx < 0), at the lower bound it would rise.
    let (du, dx) = (&replay.energy_gradient, &replay.minima[0].gradient);
    let reduced = |j: usize, mu: f64| (du[j] - mu * dx[j]) * d.stiffness[j];
    let free: Vec<usize> = (0..4).filter(|j| ![lower, upper].contains(j)).collect();
    let mu = du[free[0]] / dx[free[0]];
    for &j in &free {
        assert!(reduced(j, mu).abs() <= 1e-4 * (du[j] * d.stiffness[j]).abs(), "K_{j} stationary: {}", reduced(j, mu));
    }
    assert!(reduced(upper, mu) < 0.0 && reduced(lower, mu) > 0.0, "bound multipliers of the right sign");
}

fn p_with(p: &DynamicProblem, stiffness: &[f64]) -> DynamicProblem {
    let mut q = p.clone();
    q.design.stiffness = stiffness.to_vec();
    q
}

/// `dU/dK` of eq. (37) (the direct method through the passive equilibrium) against the hand adjoint
/// of the static design (`spine_design::adjoint::adjoint_hand`, Appendix II): two formulations of
/// the same derivative.
#[test]
fn the_strain_energy_gradient_equals_the_static_designs_hand_adjoint() {
    let (p, forcing, settings, k) = two_minima();
    let q = p_with(&p, &k);
    let ends = q.static_ends(&settings.response.continuation).unwrap();
    let point = eq37_point(&p, &forcing, &k, -0.01, &settings, PERIODS).unwrap();
    let n = q.structure.n_links();
    let bounds = spine_design::DesignBounds {
        theta0_max: 1.0,
        relative_angle_max: 1.0,
        stiffness_min: vec![1e2; n + 1],
        stiffness_max: vec![1e4; n + 1],
        height_min: 0.0,
        height_max: 1.0,
        height_ramp: 0.0,
    };
    let problem = spine_design::DesignProblem {
        structure: q.structure.clone(),
        delta_d: -0.01,
        bounds,
        stiffness_scale: 1.0,
        objective: Default::default(),
        strain_energy_max: None,
    };
    let passive = spine_model::State { theta: ends.theta1.clone(), lambda: ends.lambda1 };
    let loaded = spine_model::State { theta: ends.theta2.clone(), lambda: ends.lambda2 };
    let adjoint = spine_design::adjoint::adjoint_hand(&problem, &q.design, &passive, &loaded).unwrap();
    assert!((adjoint.energy - point.energy).abs() <= 1e-14 * point.energy);
    for j in 0..=n {
        let (ours, theirs) = (point.energy_gradient[j], adjoint.energy_gradient[n + j]);
        eprintln!("dU/dK_{j}: direct {ours:.15e}, hand adjoint {theirs:.15e}");
        assert!((ours - theirs).abs() <= 1e-10 * theirs.abs(), "dU/dK_{j}: {ours} vs {theirs}");
    }
}
