//! `just bench-ad-peers`: the residual Jacobian and the Lagrangian Hessian of eq. (33) by this
//! workspace's AD and by CasADi's (`benchmarks/peers/casadi_ad.py`), on the same point of the
//! scaled family, one N at a time (see `spine_benchmarks::ad_peers`). Checks that both compute the
//! same values, prints the table and writes `benchmarks/peers/ad-results.json`.
//!
//! Usage: `bench_ad_peers PYTHON [N ...]` (default N: 10 100 1000). The case files and points go
//! to `target/bench-ad-peers/`.
#![forbid(unsafe_code)]

use spine_benchmarks::ad_peers::{table, AdPeerRow};
use spine_benchmarks::{cli, peers, DesignFixture, HessianFixture};
use spine_design::full_space::StateForm;
use spine_model::jacobian::residual_and_state_jacobian;
use std::collections::HashMap;
use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

/// Evaluations per timed batch: about 2·10⁵ joints, so that one batch takes milliseconds.
fn batch(n: usize) -> usize {
    (200_000 / n).clamp(20, 20_000)
}

/// Seconds per call of `f`: the best of 5 batches of `count` calls.
fn per_call(count: usize, mut f: impl FnMut()) -> f64 {
    f();
    (0..5)
        .map(|_| {
            let clock = Instant::now();
            for _ in 0..count {
                f();
            }
            clock.elapsed().as_secs_f64() / count as f64
        })
        .fold(f64::INFINITY, f64::min)
}

/// The largest difference between two sets of `(row, column, value)` entries (absent: zero), over
/// the largest entry.
fn difference(ours: &HashMap<(usize, usize), f64>, theirs: &[(usize, usize, f64)]) -> f64 {
    let mut theirs_map: HashMap<(usize, usize), f64> = HashMap::new();
    for &(r, c, v) in theirs {
        *theirs_map.entry((r, c)).or_default() += v;
    }
    let keys: std::collections::HashSet<_> = ours.keys().chain(theirs_map.keys()).copied().collect();
    let scale = ours.values().chain(theirs_map.values()).fold(0.0f64, |m, v| m.max(v.abs())).max(1e-300);
    keys.iter()
        .map(|k| (ours.get(k).copied().unwrap_or(0.0) - theirs_map.get(k).copied().unwrap_or(0.0)).abs())
        .fold(0.0, f64::max)
        / scale
}

fn triplets(value: &serde_json::Value) -> Vec<(usize, usize, f64)> {
    value
        .as_array()
        .map(|a| {
            a.iter().filter_map(|t| Some((t[0].as_u64()? as usize, t[1].as_u64()? as usize, t[2].as_f64()?))).collect()
        })
        .unwrap_or_default()
}

fn measure(python: &str, n: usize, dir: &Path) -> Result<AdPeerRow, String> {
    let design = DesignFixture::new(n);
    let hessian = HessianFixture::new(&design, StateForm::Absolute);
    let case = dir.join(format!("scaled-{n}.json"));
    let point = dir.join(format!("point-{n}.json"));
    let out = dir.join(format!("casadi-ad-{n}.json"));
    let count = batch(n);
    std::fs::write(&case, peers::scaled_family_case(n).to_string()).map_err(|e| e.to_string())?;
    let point_json =
        serde_json::json!({ "x": hessian.x, "lambda": hessian.lambda, "sigma": hessian.sigma, "batch": count });
    std::fs::write(&point, point_json.to_string()).map_err(|e| e.to_string())?;
    let v = peers::run_script(python, "casadi_ad.py", &[&case, &point, &out], &out)?;

    // Ours, on the same point: the passive rows at (θ1, λ1) of the fixture's start design.
    let (spans, loads) = (&design.problem.structure.chain.spans, design.problem.passive_loads());
    let jacobian = || residual_and_state_jacobian(spans, &design.design, &loads, &design.passive);
    let (residual, jac) = jacobian();
    let mut ours_jacobian: HashMap<(usize, usize), f64> = HashMap::new();
    for (r, c, value) in jac.to_sparse().entries {
        *ours_jacobian.entry((r, c)).or_default() += value;
    }
    // The residual counts as a column of its own (index n + 1) in the comparison.
    let mut theirs_jacobian = triplets(&v["jacobian"]);
    for (i, r) in v["residual"].as_array().into_iter().flatten().enumerate() {
        theirs_jacobian.push((i, n + 1, r.as_f64().unwrap_or(f64::NAN)));
    }
    for (i, r) in residual.iter().enumerate() {
        *ours_jacobian.entry((i, n + 1)).or_default() += r;
    }
    let mut values = vec![0.0; hessian.assembled.patterns.hessian.len()];
    hessian.hessian(&mut values);
    let mut ours_hessian: HashMap<(usize, usize), f64> = HashMap::new();
    for (&(r, c), &value) in hessian.assembled.patterns.hessian.iter().zip(&values) {
        *ours_hessian.entry((r, c)).or_default() += value;
    }
    let ours_jacobian_seconds = per_call(count, || {
        black_box(jacobian());
    });
    let ours_hessian_seconds = per_call(count, || hessian.hessian(black_box(&mut values)));
    let seconds = |k: &str| v[k].as_f64();
    Ok(AdPeerRow {
        n,
        ours_jacobian: ours_jacobian_seconds,
        casadi_vm_jacobian: seconds("jacobian_vm_seconds").unwrap_or(f64::NAN),
        casadi_c_jacobian: seconds("jacobian_c_seconds"),
        ours_hessian: ours_hessian_seconds,
        casadi_vm_hessian: seconds("hessian_vm_seconds").unwrap_or(f64::NAN),
        casadi_c_hessian: seconds("hessian_c_seconds"),
        jacobian_difference: difference(&ours_jacobian, &theirs_jacobian),
        hessian_difference: difference(&ours_hessian, &triplets(&v["hessian"])),
        compile_seconds: seconds("compile_seconds").unwrap_or(f64::NAN),
        casadi_version: v["casadi"].as_str().unwrap_or("unknown").into(),
    })
}

/// Our AD's Jacobian and Hessian of eq. (33) beside CasADi's, values compared and times measured.
#[derive(clap::Parser)]
struct Args {
    /// The Python interpreter with CasADi (benchmarks/peers/.venv/bin/python).
    python: String,
    /// Chain sizes (links, at least 2); 10, 100 and 1000 when none is given.
    #[arg(value_parser = cli::links)]
    sizes: Vec<usize>,
}

fn main() {
    let Args { python, sizes } = <Args as clap::Parser>::parse();
    let sizes = if sizes.is_empty() { vec![10, 100, 1000] } else { sizes };
    let dir = Path::new("target/bench-ad-peers");
    std::fs::create_dir_all(dir).expect("target/bench-ad-peers");
    let mut rows = Vec::new();
    for n in sizes {
        match measure(&python, n, dir) {
            Ok(row) => {
                eprintln!(
                    "N = {n}: values agree to {:.1e} (Jacobian), {:.1e} (Hessian)",
                    row.jacobian_difference, row.hessian_difference
                );
                if row.jacobian_difference > 1e-10 || row.hessian_difference > 1e-10 {
                    eprintln!("bench_ad_peers: N = {n}: the two programs computed different derivatives");
                    std::process::exit(1);
                }
                rows.push(row);
            }
            Err(e) => {
                eprintln!("bench_ad_peers: N = {n}: {e}");
                std::process::exit(1);
            }
        }
    }
    println!("{}", table(&rows));
    let path = Path::new("benchmarks/peers/ad-results.json");
    std::fs::write(path, serde_json::to_string_pretty(&rows).expect("JSON") + "\n").expect("ad-results.json");
    eprintln!("wrote {}", path.display());
}
