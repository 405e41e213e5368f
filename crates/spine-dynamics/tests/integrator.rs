//! Radau IIA (the default) and TR-BDF2 on problems with known solutions, and on the spine: energy
//! conservation without damping, dissipation with damping, constraint drift, sensitivities against
//! finite differences, and the two methods against each other.

use nalgebra::DMatrix;
use spine_dynamics::integrator::{integrate, EventFunction, Extras, Method, OdeSystem, Options, Outcome};
use spine_dynamics::{Dynamics, Forcing, Parameters, SpineOde};
use spine_model::fixtures::{arch, uniform_loads};

/// Prothero–Robinson: `y' = λ (y − cos t) − sin t`, exact solution `cos t`, stiff for λ ≪ 0.
struct ProtheroRobinson(f64);

impl OdeSystem for ProtheroRobinson {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, t: f64, _: f64, y: &[f64]) -> Vec<f64> {
        vec![self.0 * (y[0] - t.cos()) - t.sin()]
    }
    fn jacobian(&self, _: f64, _: f64, _: &[f64]) -> DMatrix<f64> {
        DMatrix::from_element(1, 1, self.0)
    }
}

/// A run's time limit (`spine_stop`) ends the integration at its next step; a run stopped before
/// its first step is a valid trajectory holding the start alone (its dense output, span, points
/// and event search all work on it).
#[test]
fn a_passed_time_limit_ends_the_run_and_leaves_a_usable_trajectory() {
    let opts = Options { rtol: 1e-6, atol: 1e-8, ..Default::default() };
    let (traj, reached) = spine_stop::with_time_limit(Some(std::time::Duration::ZERO), || {
        integrate(&ProtheroRobinson(-1e6), 0.0, &[1.0], 10.0, &opts, Extras::default())
    });
    assert!(reached);
    assert_eq!(traj.outcome, Outcome::TimeLimit { t: 0.0 });
    assert_eq!(traj.span(), (0.0, 0.0));
    assert_eq!(traj.value(5.0), vec![1.0]);
    assert_eq!(traj.end(), &[1.0]);
    assert_eq!(traj.points().count(), 1);
    assert!(traj.first_root(0.0, &EventFunction::new(&|y| y[0] - 0.5, &|_| vec![1.0])).is_none());
}

#[test]
fn stiff_problem_is_solved_to_tolerance_in_few_steps() {
    for (method, most_steps) in [(Method::Radau5, 300), (Method::TrBdf2, 3000)] {
        let opts = Options { method, rtol: 1e-6, atol: 1e-8, max_step: Some(0.05), ..Default::default() };
        let traj = integrate(&ProtheroRobinson(-1e6), 0.0, &[1.0], 10.0, &opts, Extras::default());
        assert_eq!(traj.outcome, Outcome::Completed);
        let err = traj.points().map(|(t, y)| (y[0] - t.cos()).abs()).fold(0.0, f64::max);
        assert!(err < 1e-5, "{method:?}: max error {err}");
        assert!(
            traj.stats.accepted_steps < most_steps,
            "{method:?}: {} steps: the stiff mode must not limit the step",
            traj.stats.accepted_steps
        );
        // Dense output between the steps is accurate too.
        let dense = (0..1000).map(|k| k as f64 * 0.01).map(|t| (traj.value(t)[0] - t.cos()).abs()).fold(0.0, f64::max);
        assert!(dense < 1e-5, "{method:?}: dense output error {dense}");
    }
}

/// `y'' = −y` as a system: exact `(cos t, −sin t)`.
struct Oscillator;

impl OdeSystem for Oscillator {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _: f64, _: f64, y: &[f64]) -> Vec<f64> {
        vec![y[1], -y[0]]
    }
    fn jacobian(&self, _: f64, _: f64, _: &[f64]) -> DMatrix<f64> {
        DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -1.0, 0.0])
    }
}

/// An event's Lipschitz bound (`|y₀(s) − y₀(t)|` bounds `|g|`'s change for `g = y₀ − level`) skips
/// the scan of steps far from a root and finds every root the full scan finds, to the bit: single
/// crossings, a crossing and return inside one step near the oscillator's minimum, and none.
#[test]
fn the_lipschitz_bound_skips_steps_without_changing_the_roots() {
    let opts = Options { rtol: 1e-6, atol: 1e-8, ..Default::default() };
    let traj = integrate(&Oscillator, 0.0, &[1.0, 0.0], 20.0, &opts, Extras::default());
    assert_eq!(traj.outcome, Outcome::Completed);
    // A level the minimum passes by less than the scan's spacing: a double crossing inside a step.
    let longest = traj.intervals.iter().map(|iv| iv.t1 - iv.t0).fold(0.0, f64::max);
    let shallow = -1.0 + 0.05 * (longest / 8.0).powi(2);
    let weights = [1.0, 0.0];
    let (mut scanned, mut bounded) = (0, 0);
    for level in [0.5, 0.0, -0.9, shallow, -1.5] {
        for after in [0.0, 0.3, 3.0, 11.0] {
            let calls = std::cell::Cell::new(0usize);
            let g = |y: &[f64]| {
                calls.set(calls.get() + 1);
                y[0] - level
            };
            let grad = |_: &[f64]| vec![1.0, 0.0];
            let full = traj.first_root(after, &EventFunction::new(&g, &grad));
            scanned += calls.replace(0);
            let skipping = traj.first_root(after, &EventFunction::new(&g, &grad).with_lipschitz(&weights));
            bounded += calls.get();
            assert_eq!(full.as_ref().map(|e| e.t), skipping.as_ref().map(|e| e.t), "level {level}, after {after}");
            assert_eq!(full.is_none(), level < -1.0, "level {level}, after {after}");
        }
    }
    assert!(bounded * 2 < scanned, "{bounded} evaluations with the bound, {scanned} without");
}

/// With an exact Jacobian the simplified Newton iteration of a linear system contracts to
/// round-off in one iteration. The contraction measured on a step is carried to the next (RADAU5's
/// rule), raised to the power 0.8 at each step, so a step takes one iteration until the carried
/// factor has grown enough to ask for a second one that measures it again: here about one step
/// in six. Without the rule every step took two.
#[test]
fn a_linear_system_takes_about_one_newton_iteration_per_step() {
    let opts = Options { rtol: 1e-6, atol: 1e-8, ..Default::default() };
    let traj = integrate(&Oscillator, 0.0, &[1.0, 0.0], 20.0, &opts, Extras::default());
    let s = &traj.stats;
    assert_eq!(traj.outcome, Outcome::Completed);
    let attempts = s.accepted_steps + s.rejected_steps;
    assert!(attempts > 50, "{s:?}");
    assert!(4 * s.newton_iterations <= 5 * attempts, "{} iterations for {attempts} steps", s.newton_iterations);
    let y = traj.value(20.0);
    assert!((y[0] - 20f64.cos()).abs() < 1e-5, "{} vs {}", y[0], 20f64.cos());
}

/// Error at t = 1 of the oscillator on `n` equal steps.
fn oscillator_error(method: Method, n: usize) -> f64 {
    let steps: Vec<f64> = (1..=n).map(|k| k as f64 / n as f64).collect();
    let opts = Options { method, newton_tolerance: 1e-10, ..Default::default() };
    let traj =
        integrate(&Oscillator, 0.0, &[1.0, 0.0], 1.0, &opts, Extras { steps: Some(&steps), ..Default::default() });
    let y = traj.value(1.0);
    (y[0] - 1f64.cos()).abs().max((y[1] + 1f64.sin()).abs())
}

/// Observed orders on halving a fixed step: 5 for Radau IIA (error ratio 32), 2 for TR-BDF2 (4).
#[test]
fn observed_orders_on_fixed_steps_are_five_and_two() {
    for (method, sizes, order) in [(Method::Radau5, [5, 10, 20], 5), (Method::TrBdf2, [40, 80, 160], 2)] {
        let e: Vec<f64> = sizes.iter().map(|&n| oscillator_error(method, n)).collect();
        for w in e.windows(2) {
            let observed = (w[0] / w[1]).log2();
            assert!((observed - order as f64).abs() < 0.1, "{method:?}: observed order {observed} ({e:?})");
        }
    }
}

/// `y' = s(t)` with a pulse train `s`: the integral is exact at every step point only if steps land on
/// the switching instants.
struct Pulses(Forcing);

impl OdeSystem for Pulses {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, t: f64, piece: f64, _: &[f64]) -> Vec<f64> {
        vec![self.0.factor(t, piece)]
    }
    fn jacobian(&self, _: f64, _: f64, _: &[f64]) -> DMatrix<f64> {
        DMatrix::zeros(1, 1)
    }
    fn breakpoints(&self, t0: f64, t1: f64) -> Vec<f64> {
        self.0.breakpoints(t0, t1)
    }
}

#[test]
fn steps_land_on_forcing_switches() {
    let forcing = Forcing::PulseTrain { period: 0.3, duty: 0.4, delay: 0.05 };
    let traj = integrate(&Pulses(forcing.clone()), 0.0, &[0.0], 2.0, &Options::default(), Extras::default());
    let exact = |t: f64| {
        // ∫₀ᵗ s: whole periods plus the part of the current one.
        let k = ((t - 0.05) / 0.3).floor().max(0.0);
        let phase = (t - 0.05 - k * 0.3).max(0.0);
        if t < 0.05 {
            0.0
        } else {
            k * 0.12 + phase.min(0.12)
        }
    };
    for (t, y) in traj.points() {
        assert!((y[0] - exact(t)).abs() < 1e-12, "t = {t}: {} vs {}", y[0], exact(t));
    }
    for b in forcing.breakpoints(0.0, 2.0) {
        assert!(traj.points().any(|(t, _)| t == b), "a step ends at the switch {b}");
    }
}

fn spine(n: usize, damping: f64, forcing: Forcing) -> (Dynamics, Vec<f64>) {
    let (mut chain, mut design) = arch(n, 1.0, 0.4, 600.0);
    design.stiffness[n] = 300.0;
    chain.masses = vec![0.5; n];
    let passive = uniform_loads(n, -5.0, 0.0);
    let actuation = uniform_loads(n, 0.0, -200.0);
    let structure =
        spine_model::Structure { chain: chain.clone(), passive: passive.clone(), actuation: actuation.clone() };
    let problem = spine_solve::StaticProblem { structure, design: design.clone() };
    let theta1 = spine_solve::solve_static(&problem, &Default::default()).passive.state.theta;
    let dynamics = Dynamics::new(&chain, &design, vec![damping; n + 1], &passive, &actuation, forcing);
    let mut y0 = theta1;
    y0.extend(vec![0.0; n]);
    (dynamics, y0)
}

fn total_energy(d: &Dynamics, t: f64, y: &[f64]) -> f64 {
    let (kinetic, strain, potential) = d.energies(t, t, y);
    kinetic + strain + potential
}

#[test]
fn without_damping_energy_is_conserved_over_many_oscillations() {
    let (d, y0) = spine(4, 0.0, Forcing::Step);
    let ode = SpineOde { dynamics: &d, parameters: Parameters::None };
    let opts = Options { rtol: 1e-8, atol: 1e-10, ..Default::default() };
    let traj = integrate(&ode, 0.0, &y0, 1.0, &opts, Extras::default());
    assert_eq!(traj.outcome, Outcome::Completed);
    let e0 = total_energy(&d, 0.0, &y0);
    let kinetic_max = traj.points().map(|(_, y)| d.energies(0.0, 0.0, y).0).fold(0.0, f64::max);
    // Count oscillations: sign changes of the first link's angular velocity.
    let crossings = traj.points().collect::<Vec<_>>().windows(2).filter(|w| w[0].1[4] * w[1].1[4] < 0.0).count();
    assert!(crossings >= 20, "only {crossings} half-oscillations in 1 s");
    let drift = traj.points().map(|(t, y)| (total_energy(&d, t, y) - e0).abs()).fold(0.0, f64::max);
    assert!(drift < 1e-6 * kinetic_max, "energy drift {drift:.3e} J against a kinetic energy of {kinetic_max:.3e} J");
    assert!(traj.points().all(|(_, y)| d.constraint(&y[..4]).abs() < 1e-12), "|Φ| stays at round-off");
}

#[test]
fn with_damping_energy_never_increases_and_the_dissipation_balances() {
    let (d, y0) = spine(5, 2.0, Forcing::Step);
    let ode = SpineOde { dynamics: &d, parameters: Parameters::None };
    let opts = Options { rtol: 1e-9, atol: 1e-11, ..Default::default() };
    let traj = integrate(&ode, 0.0, &y0, 1.0, &opts, Extras::default());
    let pts: Vec<(f64, Vec<f64>)> = traj.points().map(|(t, y)| (t, y.to_vec())).collect();
    let e: Vec<f64> = pts.iter().map(|(t, y)| total_energy(&d, *t, y)).collect();
    let scale = (e[0] - e[e.len() - 1]).abs();
    for k in 1..e.len() {
        assert!(e[k] <= e[k - 1] + 1e-7 * scale, "energy rose at t = {}: {} → {}", pts[k].0, e[k - 1], e[k]);
    }
    // E(T) − E(0) = −∫ θ̇ᵀ C_m θ̇ dt (trapezoidal rule on the dense output).
    let m = 20_000;
    let power = |t: f64| d.dissipation(&traj.value(t)[5..]);
    let dissipated: f64 =
        (0..m).map(|k| 0.5 * (power(k as f64 / m as f64) + power((k + 1) as f64 / m as f64)) / m as f64).sum();
    assert!(
        ((e[0] - e[e.len() - 1]) - dissipated).abs() < 1e-4 * dissipated,
        "{} vs {dissipated}",
        e[0] - e[e.len() - 1]
    );
}

#[test]
fn damper_sensitivities_equal_finite_differences_of_the_discrete_solution() {
    let (d, y0) = spine(3, 3.0, Forcing::Step);
    for method in [Method::Radau5, Method::TrBdf2] {
        let opts = Options { method, rtol: 1e-7, atol: 1e-9, newton_tolerance: 1e-6, ..Default::default() };
        let ode = SpineOde { dynamics: &d, parameters: Parameters::Dampers };
        let traj = integrate(
            &ode,
            0.0,
            &y0,
            0.3,
            &opts,
            Extras { sensitivities: Some(DMatrix::zeros(6, 4)), ..Default::default() },
        );
        let steps: Vec<f64> = traj.points().map(|(t, _)| t).collect();
        let t_probe = 0.137;
        let s = traj.intervals.iter().find(|iv| iv.t1 >= t_probe).unwrap().sensitivity(t_probe).unwrap();
        for k in 0..4 {
            let eps = 1e-4 * d.damping[k];
            let run = |c: f64| {
                let mut dk = d.clone();
                dk.damping[k] = c;
                let ode = SpineOde { dynamics: &dk, parameters: Parameters::None };
                integrate(&ode, 0.0, &y0, 0.3, &opts, Extras { steps: Some(&steps), ..Default::default() })
                    .value(t_probe)
            };
            let (plus, minus) = (run(d.damping[k] + eps), run(d.damping[k] - eps));
            for i in 0..6 {
                let fd = (plus[i] - minus[i]) / (2.0 * eps);
                assert!(
                    (fd - s[(i, k)]).abs() < 1e-6 * (1.0 + fd.abs()),
                    "{method:?} ∂y{i}/∂C{k}: AD {} vs FD {fd}",
                    s[(i, k)]
                );
            }
        }
    }
}

/// `y' = −(A + q₀ B) y` with `A` a stiff tridiagonal chain and `B` diagonal, and `params`
/// parameters of which only `q₀` enters `f` (the rest are dummies).
struct StiffChain {
    q0: f64,
    params: usize,
}

impl StiffChain {
    const N: usize = 6;
    fn a(i: usize, j: usize) -> f64 {
        match i.abs_diff(j) {
            0 => 200.0 * (i + 1) as f64,
            1 => -50.0,
            _ => 0.0,
        }
    }
    fn b(i: usize) -> f64 {
        1.0 + i as f64
    }
}

impl OdeSystem for StiffChain {
    fn dim(&self) -> usize {
        Self::N
    }
    fn rhs(&self, _: f64, _: f64, y: &[f64]) -> Vec<f64> {
        (0..Self::N)
            .map(|i| -(0..Self::N).map(|j| Self::a(i, j) * y[j]).sum::<f64>() - self.q0 * Self::b(i) * y[i])
            .collect()
    }
    fn jacobian(&self, _: f64, _: f64, _: &[f64]) -> DMatrix<f64> {
        DMatrix::from_fn(Self::N, Self::N, |i, j| -Self::a(i, j) - if i == j { self.q0 * Self::b(i) } else { 0.0 })
    }
    fn n_params(&self) -> usize {
        self.params
    }
    fn rhs_params(&self, _: f64, _: f64, y: &[f64]) -> DMatrix<f64> {
        DMatrix::from_fn(Self::N, self.params, |i, k| if k == 0 { -Self::b(i) * y[i] } else { 0.0 })
    }
}

/// Radau IIA's step sensitivities take `J(Y_i) v` from directional products (one parameter:
/// `n > 4 p`) or from the dense stage Jacobians (two: `n ≤ 4 p`); both give the same `∂y/∂q₀`, equal
/// to central differences of the discrete solution.
#[test]
fn dense_and_directional_stage_products_give_the_same_sensitivities() {
    let opts = Options { rtol: 1e-8, atol: 1e-10, ..Default::default() };
    let y0: Vec<f64> = (0..StiffChain::N).map(|i| 1.0 - 0.1 * i as f64).collect();
    let run = |params: usize, q0: f64, steps: Option<&[f64]>| {
        let sys = StiffChain { q0, params };
        let extras = Extras {
            sensitivities: (params > 0).then(|| DMatrix::zeros(StiffChain::N, params)),
            steps,
            ..Default::default()
        };
        integrate(&sys, 0.0, &y0, 0.05, &opts, extras)
    };
    let (one, two) = (run(1, 3.0, None), run(2, 3.0, None));
    let steps: Vec<f64> = one.points().map(|(t, _)| t).collect();
    let t_probe = 0.031;
    let s1 = one.intervals.iter().find(|iv| iv.t1 >= t_probe).unwrap().sensitivity(t_probe).unwrap();
    let s2 = two.intervals.iter().find(|iv| iv.t1 >= t_probe).unwrap().sensitivity(t_probe).unwrap();
    let eps = 1e-5;
    let (plus, minus) =
        (run(0, 3.0 + eps, Some(&steps)).value(t_probe), run(0, 3.0 - eps, Some(&steps)).value(t_probe));
    for i in 0..StiffChain::N {
        let fd = (plus[i] - minus[i]) / (2.0 * eps);
        assert!(
            (s1[(i, 0)] - s2[(i, 0)]).abs() <= 1e-12 * (1.0 + s1[(i, 0)].abs()),
            "{} vs {}",
            s1[(i, 0)],
            s2[(i, 0)]
        );
        assert!((fd - s1[(i, 0)]).abs() < 1e-7 * (1.0 + fd.abs()), "∂y{i}/∂q0: AD {} vs FD {fd}", s1[(i, 0)]);
        assert_eq!(s2[(i, 1)], 0.0);
    }
}

/// The two methods cross-check each other on the spine: the same step response to 1e-8 s in `T_90`
/// (TR-BDF2 at a tight tolerance, Radau IIA at its default), through 10 links and a pulse train's
/// switches.
#[test]
fn radau_and_trbdf2_give_the_same_response() {
    let (d, y0) = spine(10, 20.0, Forcing::PulseTrain { period: 0.2, duty: 0.5, delay: 0.01 });
    let ode = SpineOde { dynamics: &d, parameters: Parameters::None };
    let run = |opts: Options| integrate(&ode, 0.0, &y0, 0.5, &opts, Extras::default());
    let radau = run(Options::default());
    let trbdf2 = run(Options { method: Method::TrBdf2, rtol: 1e-11, atol: 1e-13, ..Default::default() });
    assert_eq!(radau.outcome, Outcome::Completed);
    assert!(
        radau.stats.accepted_steps * 10 < trbdf2.stats.accepted_steps,
        "Radau {} steps, TR-BDF2 {}",
        radau.stats.accepted_steps,
        trbdf2.stats.accepted_steps
    );
    let gap = (0..=500).map(|k| k as f64 * 1e-3).fold(0.0f64, |m, t| {
        let (a, b) = (radau.value(t), trbdf2.value(t));
        m.max(a[..10].iter().zip(&b[..10]).fold(0.0f64, |m, (x, y)| m.max((x - y).abs())))
    });
    assert!(gap < 1e-7, "largest angle difference {gap:.2e} rad");
}
