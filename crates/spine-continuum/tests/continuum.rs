//! The chain converges to the rod it discretises: its critical load to Euler's, its equilibria to
//! the elastica's, both as `O(1/N²)`; and the elastica solver itself against closed forms and a
//! solve at twice its degree.

use spine_continuum::{critical_load, loaded, on_branch, Elastica, Rod};
use std::f64::consts::PI;

use spine_continuum::convergence::{reference_states, study_rod as rod};

/// Post-buckled: 1.1 times Euler's load, no transverse load, buckled upward.
fn buckled() -> Elastica {
    reference_states(&rod()).unwrap().0
}

/// Transversely loaded, with self-weight and half Euler's load pushing the end.
fn transverse() -> Elastica {
    reference_states(&rod()).unwrap().1
}

#[test]
fn the_critical_load_converges_to_eulers_at_second_order() {
    let r = rod();
    let (c100, c1000) = (critical_load(&r, 100), critical_load(&r, 1000));
    // Below Euler's (the chain is softer), by (2π/N)²/12 to leading order.
    assert!(c100.relative_error < 0.0 && c1000.relative_error < 0.0, "{c100:?} {c1000:?}");
    let ratio = c100.relative_error / c1000.relative_error;
    assert!((ratio - 100.0).abs() < 1.0, "error ratio N = 100 → 1000: {ratio} (O(1/N²): 100)");
    let leading = -(2.0 * PI).powi(2) / 12.0;
    assert!((c1000.scaled_error - leading).abs() < 1e-3 * leading.abs(), "{} vs {leading}", c1000.scaled_error);
    // The fold is where the certificate's smallest eigenvalue crosses zero.
    let below = spine_continuum::straight_min_eigenvalue(&r, 100, 0.999 * c100.chain);
    let above = spine_continuum::straight_min_eigenvalue(&r, 100, 1.001 * c100.chain);
    assert!(below > 0.0 && above < 0.0, "{below} {above}");
}

#[test]
fn equilibria_converge_to_the_elastica_at_second_order() {
    for (name, elastica, compare) in [
        ("post-buckled", buckled(), on_branch as fn(&Elastica, usize) -> spine_continuum::NodeComparison),
        ("transverse", transverse(), loaded),
    ] {
        let (e100, e200, e1000) = (compare(&elastica, 100), compare(&elastica, 200), compare(&elastica, 1000));
        for e in [&e100, &e200, &e1000] {
            assert!(e.stable, "{name}: every compared state is stable: {e:?}");
        }
        // The order from N = 100 → 200, and N = 1000 within 2 % of what it predicts.
        let order = (e100.error / e200.error).log2();
        assert!((order - 2.0).abs() < 0.01, "{name}: order {order}");
        let predicted = e100.error * (100.0f64 / 1000.0).powf(order);
        assert!((e1000.error / predicted - 1.0).abs() < 0.02, "{name}: {:e} vs predicted {predicted:e}", e1000.error);
    }
}

#[test]
fn the_elastica_meets_closed_forms_and_its_own_refinement() {
    // Small uniform load, no axial force: the clamped–clamped beam, y(L/2) = qL⁴/(384 EI).
    let r = Rod { transverse_load: -1e-3, ..rod() };
    let e = Elastica::solve(&r, 32, |_| 0.0).unwrap();
    let exact = r.transverse_load / (384.0 * r.bending_stiffness);
    assert!((e.position_at(0.5).1 / exact - 1.0).abs() < 1e-9, "{} vs {exact}", e.position_at(0.5).1);
    // The reaction carries half the load (symmetry).
    assert!((e.reaction + 0.5 * r.transverse_load).abs() < 1e-12, "R = {}", e.reaction);
    // Degree 64 against 128: positions agree to 1e-12 (spectral convergence), the end stays on X.
    let b = buckled();
    let fine = Elastica::solve(&b.rod, 128, |s| b.theta_at(s)).unwrap();
    for s in [0.1, 0.25, 0.5, 0.8, 1.0] {
        let (p, q) = (b.position_at(s), fine.position_at(s));
        assert!((p.0 - q.0).abs() < 1e-12 && (p.1 - q.1).abs() < 1e-12, "s = {s}: {p:?} {q:?}");
    }
    assert!(b.position_at(1.0).1.abs() < 1e-13 && b.theta_at(0.25) > 0.5, "buckled upward: {}", b.theta_at(0.25));
    // Straight guess at 1.1 Euler's load stays straight (the unstable trivial branch).
    let straight = Elastica::solve(&b.rod, 64, |_| 0.0).unwrap();
    assert!(straight.theta.iter().all(|t| t.abs() < 1e-12));
}
