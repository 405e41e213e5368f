//! Sec. 3 completed: eq. (12) solved, the Lagrange conditions (18)–(20) and the angle derivatives
//! checked against central differences, and the small-deflection system (25), (26) against the
//! general solver (erratum E8: the printed sign of `P_X,3 L2 sin θ0,2`).

use spine_model::twolink::{SmallDeflection, TwoLink};
use spine_solve::twolink::{optimum, optimum_within, small_deflection_study, OptimumPlace};
use spine_solve::ContinuationOptions;

/// Sec. 3's loads on links of 0.5 m (the `twolink` paper case).
const TL: TwoLink = TwoLink { length: 0.5, p_y: -10.0, p_x: -400.0 };

/// The equilibrium angle of eq. (7)/(8) by Newton on the scalar equation.
fn angle(theta0: f64, stiffness: f64, axial: bool) -> f64 {
    let mut t = theta0;
    for _ in 0..60 {
        let g = TL.equilibrium(t, theta0, stiffness, axial);
        let h = 1e-7;
        let slope = (TL.equilibrium(t + h, theta0, stiffness, axial) - TL.equilibrium(t - h, theta0, stiffness, axial))
            / (2.0 * h);
        t -= g / slope;
    }
    t
}

#[test]
fn angle_derivatives_of_eqs_7_and_8_match_central_differences() {
    for axial in [false, true] {
        let (theta0, k) = (0.3, 1000.0);
        let theta = angle(theta0, k, axial);
        let (d_dk, d_dt0) = TL.angle_derivatives(theta, theta0, k, axial);
        let fd_k = (angle(theta0, k + 1e-2, axial) - angle(theta0, k - 1e-2, axial)) / 2e-2;
        let fd_t0 = (angle(theta0 + 1e-6, k, axial) - angle(theta0 - 1e-6, k, axial)) / 2e-6;
        assert!((d_dk - fd_k).abs() <= 1e-6 * fd_k.abs(), "axial {axial}: ∂θ/∂K {d_dk} vs {fd_k}");
        assert!((d_dt0 - fd_t0).abs() <= 1e-6 * fd_t0.abs(), "axial {axial}: ∂θ/∂θ0 {d_dt0} vs {fd_t0}");
    }
}

#[test]
fn eq_12_optimum_sits_on_the_upper_bound_and_eqs_19_20_give_its_kkt_multiplier() {
    let opts = ContinuationOptions::default();
    for upper in [1e4, 1e3] {
        let o = optimum(&TL, -0.001, (100.0, upper), &opts).expect("a design in the bounds");
        assert_eq!(o.place, OptimumPlace::UpperBound, "{o:?}");
        assert_eq!(o.stiffness, upper);
        // Eq. (19) with λ1 from eq. (20) is dJ/dK along the constraint: it matches the central
        // difference of J(K, θ0(K)) and is negative, so the bound's multiplier −dJ/dK is positive.
        let fd = o.dl_dk_central_difference.expect("both sides have designs");
        assert!((o.dl_dk - fd).abs() <= 1e-5 * fd.abs(), "eq. (19) {} vs central difference {fd}", o.dl_dk);
        assert!(o.dl_dk < 0.0);
        assert!((o.objective - TL.strain_energy(o.theta1, o.theta0, o.stiffness)).abs() < 1e-15);
        // The end displacement is met.
        assert!((TL.end_displacement(o.theta2, o.theta0) + 0.001).abs() < 1e-10);
    }
}

#[test]
fn eq_12_at_the_papers_delta_d_ends_at_the_stability_edge_below_the_upper_bound() {
    let opts = ContinuationOptions::default();
    let o = optimum(&TL, -0.02, (100.0, 1e4), &opts).expect("a design in the bounds");
    assert_eq!(o.place, OptimumPlace::StabilityEdge, "{o:?}");
    // The arch needed to meet δ stands almost upright before K reaches 10⁴, and J still falls.
    assert!(o.stiffness > 4000.0 && o.stiffness < 6000.0, "K at the edge {}", o.stiffness);
    assert!(o.theta0 > 1.5 && o.theta0 < std::f64::consts::FRAC_PI_2, "θ0 at the edge {}", o.theta0);
    assert!(o.dl_dk < 0.0 && o.dl_dk_central_difference.is_none(), "{o:?}");
    let capped = optimum(&TL, -0.02, (100.0, 1e3), &opts).unwrap();
    assert_eq!(capped.place, OptimumPlace::UpperBound);
    assert!(o.objective < capped.objective, "a stiffer edge design stores less energy");
}

#[test]
fn with_sec5s_angle_bound_eq_12_stops_on_the_bound_with_its_kkt_sign() {
    let opts = ContinuationOptions::default();
    let limit = std::f64::consts::FRAC_PI_6;
    let o = optimum_within(&TL, -0.02, (100.0, 1e4), Some(limit), &opts).expect("a design within the bounds");
    assert_eq!(o.place, OptimumPlace::AngleBound, "{o:?}");
    assert!((o.theta0 - limit).abs() < 1e-8, "θ0 on the bound: {}", o.theta0);
    // Between the text's bound (θ0 = 0.436 at K = 1000) and the stability edge (K ≈ 5000).
    assert!(o.stiffness > 1000.0 && o.stiffness < 5000.0, "K {}", o.stiffness);
    // J still falls there: eq. (19) with eq. (20)'s λ1 against a one-sided difference inside.
    let h = 1e-4 * o.stiffness;
    let inside = optimum_within(&TL, -0.02, (100.0, o.stiffness - h), Some(limit), &opts).unwrap();
    assert_eq!(inside.place, OptimumPlace::UpperBound);
    let slope = (o.objective - inside.objective) / h;
    assert!(o.dl_dk < 0.0 && (slope - o.dl_dk).abs() < 1e-3 * o.dl_dk.abs(), "{slope} against {}", o.dl_dk);
    // A limit the free optimum keeps changes nothing.
    let free = optimum(&TL, -0.02, (100.0, 1e3), &opts).unwrap();
    let kept = optimum_within(&TL, -0.02, (100.0, 1e3), Some(limit), &opts).unwrap();
    assert_eq!((kept.place, kept.stiffness, kept.theta0), (free.place, free.stiffness, free.theta0));
}

/// The small-deflection system of the `twolink` case: unequal links (0.5 m, 0.6 m) on the axis,
/// `θ0,1` = 0.3 rad, `K1` = 500 and `K2` = 1000 N·m/rad, so that no symmetry hides a sign.
fn unequal_system() -> SmallDeflection {
    let (l1, l2, t1) = (0.5, 0.6, 0.3);
    SmallDeflection {
        lengths: [l1, l2],
        theta0: [t1, -(l1 * f64::sin(t1) / l2).asin()],
        stiffness: [500.0, 1000.0],
        p_y2: -10.0,
        p_x3: -400.0,
    }
}

#[test]
fn eq_26_small_deflections_converge_to_the_exact_ones_only_with_the_corrected_sign() {
    let system = unequal_system();
    let study = small_deflection_study(&system, &[1e-1, 1e-2, 1e-3, 1e-4], &ContinuationOptions::default());
    let order = study.order.unwrap();
    assert!((order - 1.0).abs() < 0.15, "corrected eq. (26) is first order: {order}");
    let last = study.rows.last().unwrap();
    assert!(last.error.unwrap() < 1e-3, "{last:?}");
    // As printed, the error does not shrink with the loads: the model is wrong, not inexact.
    assert!(study.order_printed.unwrap().abs() < 0.1, "{:?}", study.order_printed);
    assert!(last.error_printed.unwrap() > 0.1, "{last:?}");
}

/// Eqs. (27)–(30) against the exact gradient of the same small-deflection Lagrangian (forward AD
/// through the corrected eq. (26), itself checked against central differences of `ℒ`): (29) and
/// (30) are the chain rule, to round-off; (27) and (28) leave out `Δθ1ᵀ K_m ∂θ1/∂K_i` (erratum
/// E10), which is not small — with it they are exact.
#[test]
fn eqs_27_to_30_are_the_exact_gradient_except_for_the_missing_stiffness_term_of_27_and_28() {
    let system = unequal_system();
    let (delta, multipliers) = (-0.001, [0.7, -2.5]);
    let exact = system.lagrangian_gradient(delta, multipliers).unwrap();
    // The exact gradient against central differences of ℒ.
    let moved = |k: usize, h: f64| {
        let mut s = system;
        match k {
            0 | 1 => s.stiffness[k] += h,
            _ => s.theta0[k - 2] += h,
        }
        s.lagrangian_value(delta, multipliers).unwrap()
    };
    for (k, &g) in exact.iter().enumerate() {
        let h = if k < 2 { 1e-3 } else { 1e-6 };
        let fd = (moved(k, h) - moved(k, -h)) / (2.0 * h);
        assert!((g - fd).abs() <= 1e-6 * g.abs().max(1e-9), "∂ℒ/∂x{k}: AD {g} vs {fd}");
    }
    let printed = system.gradient_eqs_27_30(multipliers).unwrap();
    let missing = system.missing_stiffness_terms().unwrap();
    for i in 2..4 {
        assert!(
            (printed[i] - exact[i]).abs() <= 1e-12 * exact[i].abs(),
            "eq. ({}) {} vs {}",
            27 + i,
            printed[i],
            exact[i]
        );
    }
    // On the feasible set (Φ1(θ0) = 0) the missing term is −Δθ1ᵀ (∂K_m/∂K_i) Δθ1, twice the
    // printed strain term with the opposite sign: ∂J/∂K_i = −½ Δθ1ᵀ (∂K_m/∂K_i) Δθ1 (a stiffer
    // spring stores less energy under the same load, as in erratum E4).
    let (d1, _) = SmallDeflection { p_x3: 0.0, ..system }.delta_theta(false).unwrap();
    let strain = [d1[0] * d1[0], (d1[0] - d1[1]).powi(2)];
    for i in 0..2 {
        assert!((missing[i] + strain[i]).abs() <= 1e-9 * strain[i], "K{}: {} vs {}", i + 1, missing[i], -strain[i]);
    }
    for i in 0..2 {
        assert!((printed[i] + missing[i] - exact[i]).abs() <= 1e-12 * exact[i].abs().max(1e-15), "eq. ({})", 27 + i);
        let share = missing[i].abs() / exact[i].abs();
        println!(
            "eq. ({}): printed {:.6e}, exact {:.6e}, missing term {:.6e} ({share:.3} of the exact)",
            27 + i,
            printed[i],
            exact[i],
            missing[i]
        );
        assert!(share > 0.1, "eq. ({}): the missing term is {share} of the gradient", 27 + i);
    }
}
