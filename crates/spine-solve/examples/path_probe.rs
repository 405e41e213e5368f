//! Probe: follow a loaded arch and print the stability certificate along the load path.
//! `cargo run --release -p spine-solve --example path_probe -- N K PY PX`
use spine_model::fixtures::{arch, uniform_loads};
use spine_model::{LinkLoads, State};
use spine_solve::{solve_path, stability, ContinuationOptions, LoadPath};

fn main() {
    let a: Vec<f64> = std::env::args().skip(1).map(|s| s.parse().unwrap()).collect();
    let (n, k, p_y, p_x) = (a[0] as usize, a[1], a[2], a[3]);
    let (mut chain, design) = arch(n, 1.0, 0.4, k);
    chain.gravity = 0.0;
    let passive = LinkLoads::from_nodal(&chain, &uniform_loads(n, p_y, 0.0), true);
    let total = LinkLoads::from_nodal(&chain, &uniform_loads(n, p_y, p_x), true);
    let opts = ContinuationOptions::default();
    let p1 = solve_path(
        &LoadPath {
            spans: &chain.spans,
            design: &design,
            from: LinkLoads::zero(n),
            to: passive.clone(),
            start: State::unloaded(&design),
        },
        &opts,
    );
    println!("passive: {:?} {:?} stats {:?}", p1.status, p1.stability, p1.stats);
    for f in [0.2, 0.4, 0.6, 0.7, 0.75, 0.8, 0.81, 0.815, 0.817, 0.818, 0.819, 0.82, 0.9, 1.0] {
        let to = LinkLoads::lerp(&passive, &total, f);
        let p2 = solve_path(
            &LoadPath { spans: &chain.spans, design: &design, from: passive.clone(), to, start: p1.state.clone() },
            &opts,
        );
        let (_, jac) = spine_model::jacobian::residual_and_state_jacobian(
            &chain.spans,
            &design,
            &LinkLoads::lerp(&passive, &total, f * p2.load_factor),
            &p2.state,
        );
        println!(
            "f={f}: {:?} s={} min_eig={:?} neg={} max|θ|={:.3} steps={:?}",
            p2.status,
            p2.load_factor,
            p2.stability.min_eigenvalue,
            stability::negative_directions(&jac),
            p2.state.theta.iter().fold(0.0f64, |m, t| m.max(t.abs())),
            p2.stats
        );
    }
}
