//! `just bench`: every benchmark of `spine-benchmarks` for N = 5 … 10 000 (criterion). Groups:
//!
//! * `residual`: the equilibrium residual of eq. (5);
//! * `jacobian/{ad,hand,hand_fused,fd}`: residual and `∂r/∂(θ, λ)` by element-wise forward AD, by
//!   the paper's hand-derived entries (residual and Jacobian in two loops, and fused in one), by
//!   element-wise central differences;
//! * `newton_step`: residual, AD Jacobian, O(N) bordered factorisation and solve;
//! * `equilibrium_solve`: the whole `θ0 → θ1 → θ2` continuation with its stability certificates;
//! * `gradients/{ad,hand,forward_ad,fd}`: `dJ/d(θ0, K)` and `dX/d(θ0, K)` by the AD adjoint, the
//!   hand adjoint, the direct method and central differences (the last two are O(N²): N ≤ 1000);
//! * `hessian`: the sparse Hessian of the Lagrangian of eq. (33) by second-order AD;
//! * `design_solve/{full,reduced}`: a whole eq. (33) solve from the arch start (N ≤ 100 and
//!   N ≤ 10; larger N are timed once by `just bench-peers`).
//!
//! * `optimum_parameters/{sweep_fig5_40,polish,polish_and_sensitivities}` (N = 10 only): a followed
//!   sweep of Fig. 5's load from −1 to −20 N per node over 40 points (from the optimum at −1 N,
//!   events included), the tight re-solve of design10's optimum, and that re-solve plus the
//!   sensitivities to every default parameter (the difference is the sensitivities' cost).
//!
//! `tests/agreement.rs` checks that the compared derivatives agree, so no benchmark times a wrong
//! answer. `SPINE_BENCH_MAX_N` caps the sizes (for a quick run).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use spine_benchmarks::{scaled_arch, DesignFixture, HessianFixture, StateFixture};
use spine_design::full_space::StateForm;
use spine_design::settings::SolverPreset;
use spine_design::solve::Solver;
use spine_design::{Formulation, SolverSettings};
use spine_solve::{solve_static, ContinuationOptions};
use std::hint::black_box;
use std::time::Duration;

const SIZES: [usize; 6] = [5, 10, 50, 100, 1000, 10_000];
/// Largest N for the O(N²) gradients (direct method, central differences).
const QUADRATIC_MAX_N: usize = 1000;
const FULL_SOLVE_MAX_N: usize = 100;
const REDUCED_SOLVE_MAX_N: usize = 10;

fn sizes(limit: usize) -> impl Iterator<Item = usize> {
    let cap = std::env::var("SPINE_BENCH_MAX_N").ok().and_then(|v| v.parse().ok()).unwrap_or(usize::MAX);
    SIZES.into_iter().filter(move |&n| n <= limit.min(cap))
}

fn equilibrium(c: &mut Criterion) {
    let mut g = c.benchmark_group("residual");
    for n in sizes(usize::MAX) {
        let f = StateFixture::new(n);
        g.bench_with_input(BenchmarkId::from_parameter(n), &f, |b, f| b.iter(|| black_box(f).residual()));
    }
    g.finish();

    let mut g = c.benchmark_group("jacobian");
    for n in sizes(usize::MAX) {
        let f = StateFixture::new(n);
        g.bench_with_input(BenchmarkId::new("ad", n), &f, |b, f| b.iter(|| black_box(f).jacobian_ad()));
        g.bench_with_input(BenchmarkId::new("hand", n), &f, |b, f| b.iter(|| black_box(f).jacobian_hand()));
        g.bench_with_input(BenchmarkId::new("hand_fused", n), &f, |b, f| b.iter(|| black_box(f).jacobian_hand_fused()));
        g.bench_with_input(BenchmarkId::new("fd", n), &f, |b, f| b.iter(|| black_box(f).jacobian_fd()));
    }
    g.finish();

    let mut g = c.benchmark_group("newton_step");
    for n in sizes(usize::MAX) {
        let f = StateFixture::new(n);
        let start = f.perturbed(1e-3);
        g.bench_with_input(BenchmarkId::from_parameter(n), &f, |b, f| b.iter(|| f.newton_step(black_box(&start))));
    }
    g.finish();

    let mut g = c.benchmark_group("equilibrium_solve");
    let opts = ContinuationOptions::default();
    for n in sizes(usize::MAX) {
        let p = scaled_arch(n);
        g.bench_with_input(BenchmarkId::from_parameter(n), &p, |b, p| b.iter(|| solve_static(black_box(p), &opts)));
    }
    g.finish();
}

fn design(c: &mut Criterion) {
    let mut g = c.benchmark_group("gradients");
    for n in sizes(usize::MAX) {
        let f = DesignFixture::new(n);
        g.bench_with_input(BenchmarkId::new("ad", n), &f, |b, f| b.iter(|| black_box(f).gradients_ad()));
        g.bench_with_input(BenchmarkId::new("hand", n), &f, |b, f| b.iter(|| black_box(f).gradients_hand()));
        if n <= QUADRATIC_MAX_N {
            g.bench_with_input(BenchmarkId::new("forward_ad", n), &f, |b, f| {
                b.iter(|| black_box(f).gradients_forward())
            });
            g.bench_with_input(BenchmarkId::new("fd", n), &f, |b, f| b.iter(|| black_box(f).gradients_fd()));
        }
    }
    g.finish();

    let mut g = c.benchmark_group("hessian");
    for n in sizes(usize::MAX) {
        let f = HessianFixture::new(&DesignFixture::new(n), StateForm::Absolute);
        let mut values = vec![0.0; f.assembled.patterns.hessian.len()];
        g.bench_with_input(BenchmarkId::from_parameter(n), &f, |b, f| b.iter(|| black_box(f).hessian(&mut values)));
    }
    g.finish();

    let mut g = c.benchmark_group("design_solve");
    g.sample_size(10).measurement_time(Duration::from_secs(5));
    let settings = SolverSettings::default();
    for n in sizes(FULL_SOLVE_MAX_N) {
        let f = DesignFixture::new(n);
        for formulation in [Formulation::Full, Formulation::Reduced] {
            if formulation == Formulation::Reduced && n > REDUCED_SOLVE_MAX_N {
                continue;
            }
            let check = Solver::new(SolverPreset::Exact, formulation, &settings)
                .solve(&f.problem, &f.design, &mut |_| true)
                .expect("valid problem");
            assert!(check.is_clean(), "N = {n} {}: {}", formulation.name(), check.solver.status);
            g.bench_with_input(BenchmarkId::new(formulation.name(), n), &f, |b, f| {
                b.iter(|| {
                    Solver::new(SolverPreset::Exact, formulation, &settings).solve(&f.problem, &f.design, &mut |_| true)
                })
            });
        }
    }
    g.finish();
}

/// One factorisation of a recorded eq. (33) KKT matrix by the workspace's `LDLᵀ` (spine-kkt, the
/// default linear solver) and by MUMPS 5.5 (Debian's, with Ipopt's controls), same values.
/// `spine` replays the pivots of the factorisation before (as in Ipopt's solves, where about 97 %
/// of the pivots are replayed), `spine_search` searches for every pivot.
fn kkt(c: &mut Criterion) {
    let mut g = c.benchmark_group("kkt_factorization");
    for links in spine_benchmarks::kkt::RECORDED_LINKS {
        let dump = spine_benchmarks::kkt::recorded(links).expect("recorded matrix");
        let mut spine = spine_kkt::SymmetricSolver::new(dump.structure().expect("valid structure"));
        let coordinates = spine_benchmarks::kkt::coordinates(&dump).expect("valid structure");
        let mut mumps = spine_mumps::Mumps::analyse(dump.n, &coordinates, &dump.a).expect("MUMPS analysis");
        let negative = spine.factorize(&dump.a).expect("nonsingular").negative;
        assert_eq!(mumps.factorize(&dump.a).expect("MUMPS factorisation"), negative, "N = {links}: inertia");
        g.bench_with_input(BenchmarkId::new("spine", links), &dump.a, |b, a| b.iter(|| spine.factorize(a)));
        g.bench_with_input(BenchmarkId::new("spine_search", links), &dump.a, |b, a| {
            b.iter(|| {
                spine.forget_pivot_sequence();
                spine.factorize(a)
            })
        });
        g.bench_with_input(BenchmarkId::new("mumps", links), &dump.a, |b, a| b.iter(|| mumps.factorize(a)));
    }
    g.finish();
}

/// A design case of `paper-cases/`.
fn paper_case(name: &str) -> spine_case::DesignCase {
    let path = format!("{}/../paper-cases/{name}.json", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("paper case");
    let spine_case::Case::Design(c) = spine_case::Case::from_json(&text).expect("valid case") else {
        panic!("{name} is a design case")
    };
    c
}

/// Followed sweeps and sensitivities of the optimum at N = 10 (issue targets: a 40-point sweep
/// under 1 s; the sensitivities to all parameters about one extra factorisation).
fn optimum_parameters(c: &mut Criterion) {
    use spine_design::sweep::settings::SweepSettings;
    use spine_design::sweep::Sweep;
    let mut g = c.benchmark_group("optimum_parameters");
    g.sample_size(10).measurement_time(Duration::from_secs(5));
    let fig5 = paper_case("fig5-base");
    let valid = fig5.validate().expect("valid case");
    let start = Solver::new(SolverPreset::Exact, Formulation::Full, &valid.settings)
        .solve(&valid.problem, &valid.start, &mut |_| true)
        .unwrap();
    assert!(start.is_clean());
    let problem_at = |v: f64| -> Result<spine_design::DesignProblem, spine_case::FieldError> {
        Ok(fig5.with_parameter("loads.p_y", v).and_then(|c| c.validate())?.problem)
    };
    let tangent_at = |v: f64| -> Result<spine_design::ProblemTangent, spine_case::FieldError> {
        Ok(fig5.parameter_tangent("loads.p_y", &problem_at(v)?)?)
    };
    let sweep = Sweep::new("loads.p_y", &problem_at, &tangent_at, &valid.settings, SweepSettings::new(-1.0, -20.0, 40))
        .unwrap();
    let followed = sweep.follow(&start.design).expect("the sweep runs");
    assert_eq!(followed.points.len(), 40);
    g.bench_function(BenchmarkId::new("sweep_fig5_40", 10), |b| b.iter(|| sweep.follow(black_box(&start.design))));

    let design10 = paper_case("design10");
    let valid = design10.validate().expect("valid case");
    let first = Solver::new(SolverPreset::Exact, Formulation::Full, &valid.settings)
        .solve(&valid.problem, &valid.start, &mut |_| true)
        .unwrap();
    let names = design10.default_parameters();
    let differentiate = || spine_run::sensitivity::differentiate(&design10, &valid, &names, &first);
    let (report, _) = differentiate().expect("sensitivities");
    assert_eq!(report.expect("a differentiable optimum").parameters.len(), names.len());
    g.bench_function(BenchmarkId::new("polish", 10), |b| {
        b.iter(|| spine_design::solve::polish::polish(&valid.problem, black_box(&first.design), &valid.settings))
    });
    g.bench_function(BenchmarkId::new("polish_and_sensitivities", 10), |b| b.iter(differentiate));

    // The sensitivity step alone at the polished optimum (issue 51: at most twice its reduced KKT
    // factorisation and one solve per parameter), with the parameters' tangents built beforehand.
    use spine_design::sensitivity::{sensitivities, KktBaseline, Optimum, Parameter};
    let problem = &valid.problem;
    let run = spine_design::solve::polish::polish(problem, &first.design, &valid.settings).unwrap();
    let multipliers = run.multipliers.clone().expect("polished multipliers");
    let (layout, x) = run.point(problem).expect("polished states");
    let optimum = Optimum { problem, layout, x: &x, multipliers: &multipliers };
    let tangents = || -> Vec<Parameter> {
        let parameter = |name: &String| Parameter {
            name: name.clone(),
            value: design10.parameter_value(name).unwrap(),
            tangent: design10.parameter_tangent(name, problem).unwrap(),
        };
        names.iter().map(parameter).collect()
    };
    let parameters = tangents();
    let report = sensitivities(&optimum, &parameters).unwrap();
    assert!(report.conditions.hold && report.parameters.iter().all(|p| p.derivative.is_some()));
    let baseline = KktBaseline::new(&optimum, &parameters).unwrap();
    assert!(baseline.factorise_and_solve().is_some());
    g.bench_function(BenchmarkId::new("sensitivity_step", 10), |b| b.iter(|| sensitivities(&optimum, &parameters)));
    g.bench_function(BenchmarkId::new("factorisation_and_solves", 10), |b| {
        b.iter(|| black_box(&baseline).factorise_and_solve())
    });
    g.bench_function(BenchmarkId::new("parameter_tangents", 10), |b| b.iter(tangents));
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10).measurement_time(Duration::from_secs(1)).warm_up_time(Duration::from_millis(300));
    targets = equilibrium, design, kkt, optimum_parameters
}
criterion_main!(benches);
