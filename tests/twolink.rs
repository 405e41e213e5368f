//! Sec. 3, the two-link structure: the general N-link code reproduces eqs. (7)–(9), and the closed
//! forms (10), (11), (16), (17) are checked against the exact solution, with their error orders
//! measured. The slips found here are the errata E2–E5 of `docs/errata.md`.

use num_dual::Dual64;
use spine_model::twolink::TwoLink;
use spine_solve::twolink::{exact_theta0, general_solution};
use spine_solve::{ContinuationOptions, EquilibriumStatus};

/// The paper's loads with links of 0.5 m (the paper's Sec. 3 gives no numbers; these are the
/// 5-link case's −10 N transverse and −400 N axial forces).
const PAPER: TwoLink = TwoLink { length: 0.5, p_y: -10.0, p_x: -400.0 };
/// A case where `θ*` is large enough for the small-δ expansion to be asymptotic early.
const STEEP: TwoLink = TwoLink { length: 0.5, p_y: -100.0, p_x: -100.0 };

fn opts() -> ContinuationOptions {
    ContinuationOptions::default()
}

/// Least-squares slope of `log err` against `log |δ|`.
fn order(deltas: &[f64], errors: &[f64]) -> f64 {
    let xs: Vec<f64> = deltas.iter().map(|d| d.abs().ln()).collect();
    let ys: Vec<f64> = errors.iter().map(|e| e.ln()).collect();
    let (mx, my) = (xs.iter().sum::<f64>() / xs.len() as f64, ys.iter().sum::<f64>() / ys.len() as f64);
    let num: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let den: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    num / den
}

#[test]
fn general_solver_reproduces_eqs_7_to_9() {
    for (tl, k, theta0) in [(PAPER, 1000.0, 0.1), (PAPER, 200.0, 0.3), (STEEP, 100.0, 0.5), (STEEP, 50.0, -0.2)] {
        let sol = general_solution(&tl, k, theta0, &opts());
        let loaded = sol.loaded.as_ref().unwrap();
        assert!(sol.passive.status.is_stable() && loaded.status.is_stable(), "{:?}", loaded.status);
        let (t1, t2) = (&sol.passive.state.theta, &loaded.state.theta);
        // Symmetry θ_{·,1} = −θ_{·,2}.
        assert!((t1[0] + t1[1]).abs() < 1e-12 && (t2[0] + t2[1]).abs() < 1e-12);
        // Eq. (7) at θ1, eq. (8) at θ2, with the spring moment 4K(θ − θ0) as scale.
        let scale = 4.0 * k;
        assert!(tl.equilibrium(t1[0], theta0, k, false).abs() <= 1e-12 * scale, "eq. (7)");
        assert!(tl.equilibrium(t2[0], theta0, k, true).abs() <= 1e-12 * scale, "eq. (8)");
        // Eq. (9): the end displacement.
        let delta = sol.end_displacement.unwrap();
        assert!((delta - tl.end_displacement(t2[0], theta0)).abs() <= 1e-12 * tl.length);
    }
}

#[test]
fn printed_eq10_is_on_the_wrong_branch() {
    // E2: with P_Y < 0, atan(2P_X/P_Y) differs from the angle of (P_Y, 2P_X) by π, so the printed
    // formula is off by π/2 for every δ.
    for delta in [-1e-4, -1e-5, -1e-6] {
        let exact = exact_theta0(&STEEP, 100.0, delta, &opts()).unwrap();
        let printed = STEEP.theta0_eq10_printed(100.0, delta);
        assert!((exact - printed - std::f64::consts::FRAC_PI_2).abs() < 1e-2, "{exact} vs {printed}");
        assert!((STEEP.theta0_eq10(100.0, delta) - exact).abs() < 1e-3);
    }
}

#[test]
fn closed_form_error_orders() {
    let k = 100.0;
    let deltas: Vec<f64> = (0..6).map(|i| -1e-4 * 0.5f64.powi(i)).collect();
    let mut err10 = Vec::new();
    let mut err_first = Vec::new();
    let mut err11 = Vec::new();
    for &d in &deltas {
        let exact = exact_theta0(&STEEP, k, d, &opts()).unwrap();
        err10.push((STEEP.theta0_eq10(k, d) - exact).abs());
        err_first.push((STEEP.theta0_first_order(k, d) - exact).abs());
        err11.push((STEEP.stiffness_eq11(exact, d) - k).abs() / k);
    }
    let (p10, p_first, p11) = (order(&deltas, &err10), order(&deltas, &err_first), order(&deltas, &err11));
    // E3: eq. (10) drops a term of the same order as the one it keeps; its θ0 error is O(δ), the same
    // order as θ0 − θ* itself. Keeping it (effective stiffness) gives O(δ²). Eq. (11) keeps it: O(δ).
    assert!((p10 - 1.0).abs() < 0.05, "eq. (10) order {p10}");
    assert!((p_first - 2.0).abs() < 0.05, "first-order-consistent eq. (10) order {p_first}");
    assert!((p11 - 1.0).abs() < 0.05, "eq. (11) relative error order {p11}");
    let theta_star = STEEP.zero_moment_angle();
    let exact = exact_theta0(&STEEP, k, deltas[5], &opts()).unwrap();
    assert!(err10[5] > 0.2 * (exact - theta_star).abs(), "eq. (10) misses a fixed fraction of θ0 − θ*");
}

/// `θ1` of eq. (7) for the paper's fixed-length links, by Newton (generic, so AD passes through).
fn theta1<D: spine_model::Scalar>(tl: &TwoLink, theta0: D, k: D) -> D {
    let mut t = theta0;
    for _ in 0..60 {
        let g = tl.equilibrium(t, theta0, k, false);
        let dg = k * 4.0 + t.sin() * (tl.p_y * tl.length);
        t -= g / dg;
    }
    t
}

#[test]
fn sensitivities_16_and_ratio_17() {
    let tl = TwoLink { length: 0.5, p_y: -10.0, p_x: 0.0 };
    for (theta0, k) in [(0.3, 100.0), (0.5, 20.0), (0.2, 1000.0)] {
        // Exact gradients of J = 2K(θ1 − θ0)² by AD through the Newton solve of eq. (7).
        let j_of = |t0: Dual64, kk: Dual64| {
            let t1 = theta1(&tl, t0, kk);
            tl.strain_energy(t1, t0, kk)
        };
        let dj_dk = j_of(Dual64::from(theta0), Dual64::from(k).derivative()).eps;
        let dj_dt0 = j_of(Dual64::from(theta0).derivative(), Dual64::from(k)).eps;
        let t1 = theta1(&tl, theta0, k);
        // The general solver gives the same θ1.
        let sol = general_solution(&tl, k, theta0, &opts());
        assert_eq!(sol.passive.status, EquilibriumStatus::Stable);
        assert!((sol.passive.state.theta[0] - t1).abs() < 1e-13);

        let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
        assert!(rel(tl.dj_dk(t1, theta0, k), dj_dk) < 1e-10, "corrected ∂J/∂K");
        assert!(rel(tl.dj_dtheta0(t1, theta0, k), dj_dt0) < 1e-10, "∂J/∂θ0 as printed");
        // E4: the printed ∂J/∂K has the opposite sign.
        assert!(rel(tl.dj_dk_eq16_printed(t1, theta0, k), -dj_dk) < 1e-10);
        assert!(dj_dk < 0.0, "a stiffer spring stores less energy");
        // E5: R = (∂J/∂θ0)/(∂J/∂K) = 2K / (cot θ1 − (θ1 − θ0)); the printed "+2(θ1 − θ0)" is off at
        // first order in θ1 − θ0.
        let r_exact = dj_dt0 / dj_dk;
        assert!(rel(TwoLink::ratio(t1, theta0, k), r_exact) < 1e-10);
        let printed = TwoLink::ratio_eq17_printed(t1, theta0, k);
        assert!(rel(printed, r_exact) > 1e-4 && rel(printed, r_exact) < 0.1, "printed R {printed} vs {r_exact}");
        assert!(r_exact > 1.0, "shape is preferred to stiffness (R > 1)");
    }
}
