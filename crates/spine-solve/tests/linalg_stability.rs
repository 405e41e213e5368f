//! The O(N) bordered solve against faer's sparse LU, and the Sturm-count stability certificate
//! against dense eigenvalues of the projected Hessian.

mod common;

use spine_model::fixtures::random_problem;
use spine_model::jacobian::residual_and_state_jacobian;
use spine_solve::linalg::BorderedLu;
use spine_solve::stability;

fn rel_err(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs())) / scale
}

#[test]
fn block_elimination_agrees_with_sparse_lu() {
    let mut used_block = 0;
    for n in [1, 2, 3, 10, 50, 400] {
        for seed in 0..4 {
            let (chain, design, loads, state) = random_problem(n, 1000 + 10 * n as u64 + seed);
            let (_, jac) = residual_and_state_jacobian(&chain.spans, &design, &loads, &state);
            let rhs: Vec<f64> = (0..=n).map(|i| ((i * 7 + 3) % 11) as f64 - 5.0).collect();
            let fast = BorderedLu::factor(&jac).expect("nonsingular");
            let oracle = BorderedLu::factor_general(&jac).expect("nonsingular");
            used_block += usize::from(fast.is_block());
            for transpose in [false, true] {
                let (x, y) = if transpose {
                    (fast.solve_transpose(&rhs), oracle.solve_transpose(&rhs))
                } else {
                    (fast.solve(&rhs), oracle.solve(&rhs))
                };
                assert!(rel_err(&x, &y) < 1e-9, "N={n} seed={seed} transpose={transpose}: {}", rel_err(&x, &y));
            }
            // And the solution really solves the system.
            let x = fast.solve(&rhs);
            assert!(rel_err(&jac.mul_vec(&x), &rhs) < 1e-9);
        }
    }
    assert!(used_block > 15, "the O(N) path should serve most random systems, served {used_block}");
}

#[test]
fn singular_block_falls_back_to_general_lu() {
    // Two links with only the middle spring, at zero load: the tridiagonal block K[[1,-1],[-1,1]]
    // is singular, the bordered system is not.
    let tl = spine_model::twolink::TwoLink { length: 0.5, p_y: 0.0, p_x: 0.0 };
    let p = spine_solve::twolink::general_problem(&tl, 100.0, 0.3);
    let zero = spine_model::LinkLoads::zero(2);
    let state = spine_model::State::unloaded(&p.design);
    let (_, jac) = residual_and_state_jacobian(&p.structure.chain.spans, &p.design, &zero, &state);
    let lu = BorderedLu::factor(&jac).expect("bordered system is nonsingular");
    assert!(!lu.is_block());
    let x = lu.solve(&[1.0, 2.0, 0.5]);
    assert!(rel_err(&jac.mul_vec(&x), &[1.0, 2.0, 0.5]) < 1e-12);
}

#[test]
fn certificate_matches_dense_projected_eigenvalues() {
    for n in [2, 3, 5, 10, 40] {
        for seed in 0..5 {
            let (chain, design, loads, state) = random_problem(n, 5000 + 10 * n as u64 + seed);
            let (_, jac) = residual_and_state_jacobian(&chain.spans, &design, &loads, &state);
            let eig = common::projected_eigenvalues(&common::block(&jac), &jac.row);
            let cert = stability::certify(&jac);
            let scale = eig.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let min = cert.min_eigenvalue.unwrap();
            assert!((min - eig[0]).abs() <= 1e-9 * scale, "N={n} seed={seed}: {min} vs {}", eig[0]);
            let negatives = eig.iter().filter(|&&e| e < 0.0).count();
            assert_eq!(cert.negative_directions, negatives, "N={n} seed={seed}: {eig:?}");
            assert_eq!(cert.stable, eig[0] > 0.0);
        }
    }
}

#[test]
fn one_link_has_no_free_direction() {
    let (chain, design, loads, state) = random_problem(1, 3);
    let (_, jac) = residual_and_state_jacobian(&chain.spans, &design, &loads, &state);
    let cert = stability::certify(&jac);
    assert_eq!(cert.min_eigenvalue, None);
    assert!(cert.stable);
}
