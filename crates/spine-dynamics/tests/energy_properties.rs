//! Property test of the dynamics: on random chains (links, masses, springs, dampers, loads and
//! shape drawn at random), the response to a step of the axial force keeps the energy balance
//! `E(0) − E(T) = ∫₀ᵀ θ̇ᵀ C θ̇ dt` (the dampers' dissipation) and never gains energy.

use proptest::prelude::*;
use spine_dynamics::integrator::{integrate, Extras, Options, Outcome};
use spine_dynamics::{Dynamics, Forcing, Parameters, SpineOde};
use spine_model::fixtures::{arch, uniform_loads};

fn total_energy(d: &Dynamics, t: f64, y: &[f64]) -> f64 {
    let (kinetic, strain, potential) = d.energies(t, t, y);
    kinetic + strain + potential
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, rng_seed: proptest::test_runner::RngSeed::Fixed(12), ..ProptestConfig::default() })]
    #[test]
    fn a_step_response_dissipates_exactly_what_its_dampers_take(
        n in 2usize..7,
        amplitude in 0.1f64..0.45,
        stiffness in 400.0f64..2000.0,
        mass in 0.1f64..1.0,
        damping in prop::collection::vec(0.5f64..10.0, 7),
        p_y in -8.0f64..-1.0,
        p_x in -250.0f64..-50.0,
    ) {
        let (mut chain, mut design) = arch(n, 1.0, amplitude, stiffness);
        design.stiffness[n] = 0.5 * stiffness;
        chain.masses = vec![mass; n];
        let passive = uniform_loads(n, p_y, 0.0);
        let actuation = uniform_loads(n, 0.0, p_x);
        let structure =
            spine_model::Structure { chain: chain.clone(), passive: passive.clone(), actuation: actuation.clone() };
        let problem = spine_solve::StaticProblem { structure, design: design.clone() };
        let start = spine_solve::solve_static(&problem, &Default::default()).passive;
        prop_assume!(start.status == spine_solve::EquilibriumStatus::Stable);
        let dampers = damping[..=n].to_vec();
        let d = Dynamics::new(&chain, &design, dampers, &passive, &actuation, Forcing::Step);
        let mut y0 = start.state.theta;
        y0.extend(vec![0.0; n]);
        let ode = SpineOde { dynamics: &d, parameters: Parameters::None };
        let t_end = 0.3;
        let traj = integrate(&ode, 0.0, &y0, t_end, &Options { rtol: 1e-10, atol: 1e-12, ..Default::default() }, Extras::default());
        prop_assert_eq!(&traj.outcome, &Outcome::Completed);
        let points: Vec<(f64, Vec<f64>)> = traj.points().map(|(t, y)| (t, y.to_vec())).collect();
        let e: Vec<f64> = points.iter().map(|(t, y)| total_energy(&d, *t, y)).collect();
        let lost = e[0] - e[e.len() - 1];
        prop_assume!(lost > 1e-9);
        for k in 1..e.len() {
            prop_assert!(e[k] <= e[k - 1] + 1e-6 * lost, "energy rose at t = {}: {} -> {}", points[k].0, e[k - 1], e[k]);
        }
        // ∫ θ̇ᵀ C θ̇ dt by the trapezoidal rule on the dense output.
        let m = 20_000;
        let power = |t: f64| d.dissipation(&traj.value(t)[n..]);
        let h = t_end / m as f64;
        let dissipated: f64 = (0..m).map(|k| 0.5 * h * (power(k as f64 * h) + power((k + 1) as f64 * h))).sum();
        prop_assert!((lost - dissipated).abs() < 1e-4 * dissipated, "lost {lost:.6e} J, dissipated {dissipated:.6e} J");
    }
}
