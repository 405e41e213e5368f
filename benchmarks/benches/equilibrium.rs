//! Equilibrium solve times: the whole `θ0 → θ1 → θ2` continuation, and its parts (residual with
//! the AD Jacobian, the O(N) factorisation, the stability certificate), for N = 10 … 1000.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use spine_benchmarks::scaled_arch;
use spine_model::jacobian::residual_and_state_jacobian;
use spine_model::State;
use spine_solve::linalg::BorderedLu;
use spine_solve::{solve_static, stability, ContinuationOptions};
use std::hint::black_box;

const SIZES: [usize; 4] = [10, 100, 1000, 10_000];

fn equilibrium(c: &mut Criterion) {
    let opts = ContinuationOptions::default();
    let mut g = c.benchmark_group("equilibrium/solve_static");
    for n in SIZES {
        let p = scaled_arch(n);
        let check = solve_static(&p, &opts);
        assert!(check.passive.status.is_stable() && check.loaded.as_ref().unwrap().status.is_stable(), "N={n}");
        g.bench_with_input(BenchmarkId::from_parameter(n), &p, |b, p| b.iter(|| solve_static(black_box(p), &opts)));
    }
    g.finish();

    let mut g = c.benchmark_group("equilibrium/parts");
    for n in SIZES {
        let p = scaled_arch(n);
        let loads = p.total_loads();
        let state = State::unloaded(&p.design);
        g.bench_with_input(BenchmarkId::new("residual+AD jacobian", n), &n, |b, _| {
            b.iter(|| residual_and_state_jacobian(&p.chain.spans, &p.design, black_box(&loads), black_box(&state)))
        });
        let (r, jac) = residual_and_state_jacobian(&p.chain.spans, &p.design, &loads, &state);
        g.bench_with_input(BenchmarkId::new("factor+solve O(N)", n), &n, |b, _| {
            b.iter(|| BorderedLu::factor(black_box(&jac)).unwrap().solve(&r))
        });
        g.bench_with_input(BenchmarkId::new("stability certificate", n), &n, |b, _| {
            b.iter(|| stability::certify(black_box(&jac)))
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(2)).warm_up_time(std::time::Duration::from_millis(500));
    targets = equilibrium
}
criterion_main!(benches);
