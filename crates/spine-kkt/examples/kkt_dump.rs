//! Factorises a matrix written by `SPINE_KKT_DUMP=FILE` (see `src/pardiso.rs`) and prints the
//! time, inertia, front statistics and the result of one solve: `cargo run --release -p spine-kkt
//! --example kkt_dump FILE`.
use spine_kkt::{Structure, SymmetricSolver};
fn list<T: std::str::FromStr>(line: &str) -> Vec<T> {
    line.trim()
        .trim_start_matches('[')
        .trim_end_matches(']')
        .split(',')
        .filter(|s| !s.trim().is_empty())
        .map(|s| s.trim().parse().ok().unwrap())
        .collect()
}
fn main() {
    let text = std::fs::read_to_string(std::env::args().nth(1).unwrap()).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let n: usize = lines[0].trim().parse().unwrap();
    let ia: Vec<i32> = list(lines[1]);
    let ja: Vec<i32> = list(lines[2]);
    let a: Vec<f64> = list(lines[3]);
    let s = Structure::from_one_based(n, &ia, &ja).unwrap();
    let mut solver = SymmetricSolver::new(s);
    let t = std::time::Instant::now();
    let inertia = solver.factorize(&a).unwrap();
    println!(
        "{:?} {:?} {:?} dense {} predicted {}",
        t.elapsed(),
        inertia,
        solver.stats(),
        solver.analysis().dense_rows(),
        solver.analysis().predicted_front()
    );
    let lines4 = lines.get(4).map(|l| list::<f64>(l));
    let mut b: Vec<f64> = lines4.unwrap_or_else(|| (0..n).map(|i| (i as f64).sin()).collect());
    println!("{:?}", solver.solve(&mut b));
}
