//! The discrete adjoint of the Radau IIA steps against the forward sensitivities of the same run:
//! the same gradients to 1e-8 relative (both are exact derivatives of the computed solution), for
//! the springs under a pulse train over two periods (two runs, as the periodic response runs
//! them) and for the dampers under a step.

use nalgebra::DMatrix;
use spine_dynamics::fixtures::{arch_problem, periodic_problem};
use spine_dynamics::integrator::adjoint::{adjoint, Term};
use spine_dynamics::integrator::{integrate, Extras, Options, Outcome, Trajectory};
use spine_dynamics::{Dynamics, Forcing, Parameters, SpineOde};

/// A start sensitivity with every entry non-zero (any `S(t₀)` will do: the adjoint's `λ₀` meets
/// it at the end).
fn start_sensitivity(rows: usize, cols: usize) -> DMatrix<f64> {
    DMatrix::from_fn(rows, cols, |r, c| ((r * 7 + c * 3) as f64 * 0.37).sin() * 1e-4)
}

/// Runs `periods` of `span` s each as separate runs with forward sensitivities from `s0`.
fn forward(ode: &SpineOde<'_>, y0: &[f64], span: f64, periods: usize, s0: DMatrix<f64>) -> Vec<Trajectory> {
    let opts = Options { rtol: 1e-8, atol: 1e-10, ..Options::default() };
    let mut runs: Vec<Trajectory> = Vec::new();
    let (mut y, mut s) = (y0.to_vec(), Some(s0));
    for k in 0..periods {
        let t0 = k as f64 * span;
        let extras = Extras { sensitivities: s.take(), ..Extras::default() };
        let run = integrate(ode, t0, &y, t0 + span, &opts, extras);
        assert_eq!(run.outcome, Outcome::Completed);
        y = run.end().to_vec();
        s = run.end_sensitivity();
        runs.push(run);
    }
    runs
}

/// `cᵀ S(t)` on the forward runs (the run whose span reaches `t`).
fn forward_value(runs: &[Trajectory], terms: &[Term]) -> Vec<f64> {
    let mut total: Option<Vec<f64>> = None;
    for term in terms {
        let run = runs.iter().find(|r| r.span().1 >= term.t).unwrap();
        let s = run.sensitivity(term.t).unwrap();
        let row: Vec<f64> = (0..s.ncols()).map(|p| (0..s.nrows()).map(|i| term.weights[i] * s[(i, p)]).sum()).collect();
        total = Some(match total {
            None => row,
            Some(t) => t.iter().zip(&row).map(|(a, b)| a + b).collect(),
        });
    }
    total.unwrap()
}

fn end_x_gradient(d: &Dynamics, runs: &[Trajectory], t: f64) -> Term {
    let run = runs.iter().find(|r| r.span().1 >= t).unwrap();
    Term { t, weights: d.end_x_state_gradient(&run.value(t)) }
}

fn check(ode: &SpineOde<'_>, runs: &[Trajectory], s0: &DMatrix<f64>, outputs: &[Vec<Term>]) {
    let refs: Vec<&Trajectory> = runs.iter().collect();
    let (gradients, stats) = adjoint(ode, &refs, outputs).expect("Radau runs");
    assert!(stats.jacobian_evaluations > 0);
    for (output, gradient) in outputs.iter().zip(&gradients) {
        let want = forward_value(runs, output);
        let got = gradient.total(s0);
        let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(scale > 0.0);
        for (p, (a, b)) in got.iter().zip(&want).enumerate() {
            assert!((a - b).abs() <= 1e-8 * scale, "parameter {p}: adjoint {a:e} vs forward {b:e} (scale {scale:e})");
        }
    }
}

#[test]
fn the_adjoint_of_two_periods_equals_the_forward_spring_sensitivities() {
    let problem = periodic_problem(7);
    let ends = problem.static_ends(&Default::default()).unwrap();
    let d = problem.dynamics(Forcing::PulseTrain { period: 0.2, duty: 0.5, delay: 0.0 });
    let ode = SpineOde { dynamics: &d, parameters: Parameters::Springs };
    let s0 = start_sensitivity(14, 8);
    let runs = forward(&ode, &ends.rest_state(), 0.2, 2, s0.clone());
    let outputs = vec![
        // Inside the second period (a step's interior), at the end, and inside the first period
        // plus at the second's start, as one output.
        vec![end_x_gradient(&d, &runs, 0.2 + 0.0731)],
        vec![end_x_gradient(&d, &runs, 0.4)],
        vec![end_x_gradient(&d, &runs, 0.05), end_x_gradient(&d, &runs, 0.2)],
        // Every state at once, weights of both signs.
        vec![Term { t: 0.33, weights: (0..14).map(|i| if i % 2 == 0 { 1.0 } else { -0.5 }).collect() }],
    ];
    check(&ode, &runs, &s0, &outputs);
}

#[test]
fn the_adjoint_of_a_step_response_equals_the_forward_damper_sensitivities() {
    let problem = arch_problem(6, 30.0);
    let ends = problem.static_ends(&Default::default()).unwrap();
    let d = problem.dynamics(Forcing::Step);
    let ode = SpineOde { dynamics: &d, parameters: Parameters::Dampers };
    let s0 = DMatrix::zeros(12, 7);
    let runs = forward(&ode, &ends.rest_state(), 0.15, 1, s0.clone());
    check(&ode, &runs, &s0, &[vec![end_x_gradient(&d, &runs, 0.0412)], vec![end_x_gradient(&d, &runs, 0.15)]]);
}

/// Eq. (35)'s `dT_90/dC` (an event's sensitivity, `−(∇g · S)/ġ`) by the adjoint of the plain run
/// equals the forward sensitivities' to 1e-8 relative, with the run stopped at the rise as the
/// design runs it.
#[test]
fn the_rise_time_gradient_by_the_adjoint_equals_the_forward_one() {
    use spine_dynamics::integrator::adjoint::Sensitivities;
    use spine_dynamics::response::rise_time_by;
    for n in [3, 8] {
        let problem = arch_problem(n, 25.0);
        let ends = problem.static_ends(&Default::default()).unwrap();
        let d = problem.dynamics(Forcing::Step);
        let settings = spine_dynamics::StepSettings::default();
        let (t_a, g_a) = rise_time_by(&d, &ends, &settings, Some(Sensitivities::Adjoint));
        let (t_f, g_f) = rise_time_by(&d, &ends, &settings, Some(Sensitivities::Forward));
        assert_eq!(t_a, t_f, "the same run and event");
        let (g_a, g_f) = (g_a.unwrap(), g_f.unwrap());
        let scale = g_f.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(scale > 0.0);
        for (j, (a, f)) in g_a.iter().zip(&g_f).enumerate() {
            assert!((a - f).abs() <= 1e-8 * scale, "N = {n}, C_{j}: adjoint {a:e} vs forward {f:e}");
        }
    }
}
