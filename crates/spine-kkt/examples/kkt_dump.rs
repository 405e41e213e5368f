//! Factorises a matrix written by `SPINE_KKT_DUMP=FILE` (see `src/pardiso.rs`) and prints the
//! best time of REPEATS factorisations and solves, the inertia, the front statistics and the
//! result of one solve: `cargo run --release -p spine-kkt --example kkt_dump FILE [REPEATS]`
//! (REPEATS, 20 by default, also serves `perf record`). With `KKT_SEARCH` set, every factorisation
//! searches for its pivots instead of replaying those of the one before; with `KKT_FACTOR_ONLY`
//! set, it stops after the factorisations (for `perf record` of the factorisation alone); with
//! `KKT_TIMES` set, it prints every factorisation's time; with `KKT_COLD=MB`, it writes MB
//! megabytes between two factorisations (untimed), so that each starts with cold caches.
use spine_kkt::{Dump, SymmetricSolver};
fn best_of<T>(repeats: usize, mut run: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut out = run();
    let all = std::time::Instant::now();
    // `KKT_COLD=MB`: write MB megabytes between runs (untimed), as Ipopt's own work does between
    // two factorisations, so that each run starts with cold caches.
    let cold: usize = std::env::var("KKT_COLD").ok().and_then(|mb| mb.parse().ok()).unwrap_or(0);
    let mut flush = vec![0u8; cold << 20];
    let each = std::env::var_os("KKT_TIMES").is_some();
    for round in 0..repeats {
        for (i, byte) in flush.iter_mut().enumerate().step_by(64) {
            *byte = byte.wrapping_add((i + round) as u8);
        }
        std::hint::black_box(&flush);
        let clock = std::time::Instant::now();
        out = run();
        best = best.min(clock.elapsed().as_secs_f64());
        if each {
            eprintln!("time {:.3}", clock.elapsed().as_secs_f64() * 1e3);
        }
    }
    eprintln!("mean {:.3} ms", all.elapsed().as_secs_f64() * 1e3 / repeats as f64);
    (best, out)
}
fn main() {
    let path = std::env::args().nth(1).expect("usage: kkt_dump FILE [REPEATS]");
    let repeats: usize = std::env::args().nth(2).map_or(20, |r| r.parse().expect("REPEATS: a count"));
    let dump = Dump::parse(&std::fs::read_to_string(&path).expect("a readable file")).expect("a recorded system");
    let (n, a) = (dump.n, dump.a.clone());
    let mut solver = SymmetricSolver::new(dump.structure().expect("a valid structure"));
    let search = std::env::var_os("KKT_SEARCH").is_some();
    let (factor_time, inertia) = best_of(repeats, || {
        if search {
            solver.forget_pivot_sequence();
        }
        solver.factorize(&a).unwrap()
    });
    println!(
        "factorisation {:.3} ms, {:?} {:?} dense {} predicted {}",
        factor_time * 1e3,
        inertia,
        solver.stats(),
        solver.analysis().dense_rows(),
        solver.analysis().predicted_front()
    );
    if std::env::var_os("KKT_FACTOR_ONLY").is_some() {
        return;
    }
    let b: Vec<f64> = dump.rhs.clone().unwrap_or_else(|| (0..n).map(|i| (i as f64).sin()).collect());
    let (solve_time, report) = best_of(repeats, || {
        let mut x = b.clone();
        solver.solve(&mut x)
    });
    println!("solve {:.3} ms, {report:?}", solve_time * 1e3);
}
