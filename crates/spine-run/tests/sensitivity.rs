//! The sensitivities of an eq. (33) optimum against central differences of tight re-solves at
//! `p ± h` started from the optimum (`spine_design::solve::polish::polish`), on the paper's 5-link
//! case (stiffnesses and angles at their bounds, dependent active rows), and the one-sided
//! derivatives of a case where a stiffness bound is made weakly active.

use spine_case::{Case, DesignCase};
use spine_design::sensitivity::Derivative;
use spine_design::solve::polish::polish;
use spine_run::{run_sensitivity, KindResult, Overrides};

fn design5() -> DesignCase {
    let Case::Design(c) = Case::from_json(include_str!("../../../paper-cases/design5.json")).unwrap() else {
        panic!("design5 is a design case")
    };
    c
}

/// `θ0*`, `K*` and `J*` of the tight re-solve of `case` with `name` at `value`, from `start`.
fn resolve(case: &DesignCase, name: &str, value: f64, start: &spine_model::Design) -> (Vec<f64>, Vec<f64>, f64) {
    let valid = case.with_parameter(name, value).unwrap().validate().unwrap();
    let run = polish(&valid.problem, start, &valid.settings).unwrap();
    let result = run.check(&valid.problem, &valid.settings);
    assert!(result.is_clean(), "{name} = {value}: {}", result.solver.status);
    (result.design.theta0, result.design.stiffness, result.objective)
}

/// `spine sensitivity` on the case from its own start only (no multi-start).
fn report(case: &DesignCase, names: &[&str]) -> spine_run::sensitivity::SensitivityResult {
    let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
    let mut overrides = Overrides::default();
    overrides.design.starts = Some(0);
    let result = run_sensitivity(&Case::Design(case.clone()), &overrides, &names, &mut spine_run::quiet).unwrap();
    let KindResult::Sensitivity(r) = result.result else { panic!("a sensitivity result") };
    r
}

/// The largest difference between `a` and `b` relative to `max(‖b‖∞, floor)`.
fn relative(a: &[f64], b: &[f64], floor: f64) -> f64 {
    let scale = b.iter().fold(floor, |m, v| m.max(v.abs()));
    a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs())) / scale
}

fn central(plus: &[f64], minus: &[f64], h: f64) -> Vec<f64> {
    plus.iter().zip(minus).map(|(a, b)| (a - b) / (2.0 * h)).collect()
}

#[test]
fn derivatives_match_central_differences_of_re_solves_on_design5() {
    let case = design5();
    let names = ["delta_d", "loads.p_x", "loads.p_y[3]", "loads.scale", "chain.length_x", "bounds.stiffness_max"];
    let r = report(&case, &names);
    let s = r.sensitivity.as_ref().expect("a clean optimum");
    assert!(s.conditions.second_order_sufficient, "{:?}", s.conditions);
    assert!(!s.conditions.dependent_rows.is_empty(), "the angle vertex makes the active rows dependent");
    check_against_re_solves(&case, &r);
}

/// The 10-link case, where every condition holds (LICQ with σ_min 3e-4), including the angle
/// bounds, which move the optimum's vertex.
#[test]
fn derivatives_match_central_differences_of_re_solves_on_design10() {
    let Case::Design(case) = Case::from_json(include_str!("../../../paper-cases/design10.json")).unwrap() else {
        panic!("design10 is a design case")
    };
    let r = report(&case, &["delta_d", "loads.p_y[5]", "bounds.theta0_max", "bounds.relative_angle_max"]);
    let s = r.sensitivity.as_ref().expect("a clean optimum");
    assert!(s.conditions.hold, "{:?}", s.conditions);
    // LICQ's measure, not lost to rounding (through the Gram matrix it came out 0 here).
    let sigma = s.conditions.licq_smallest_singular_value.expect("measured");
    assert!((sigma - 3.172e-4).abs() < 1e-6, "σ_min {sigma:e}");
    check_against_re_solves(&case, &r);
}

fn check_against_re_solves(case: &DesignCase, r: &spine_run::sensitivity::SensitivityResult) {
    let s = r.sensitivity.as_ref().expect("a clean optimum");
    let case = case.clone();
    let start = r.design.result.design.clone();
    for p in &s.parameters {
        let d: &Derivative = p.derivative.as_ref().unwrap_or_else(|| panic!("{}: {:?}", p.name, p.note));
        let h = 1e-4 * p.value.abs().max(1e-2);
        let (t_plus, k_plus, j_plus) = resolve(&case, &p.name, p.value + h, &start);
        let (t_minus, k_minus, j_minus) = resolve(&case, &p.name, p.value - h, &start);
        let (dt, dk) = (central(&t_plus, &t_minus, h), central(&k_plus, &k_minus, h));
        let dj = (j_plus - j_minus) / (2.0 * h);
        // Floors, per unit of the parameter: 1e-2 rad and 1 N·m/rad over |p| (where the exact rate
        // is 0, the differences of the re-solves are their round-off, 1e-12, over 2h).
        let per_unit = 1.0 / p.value.abs().max(1e-2);
        let (et, ek) = (relative(&d.theta0, &dt, 1e-2 * per_unit), relative(&d.stiffness, &dk, per_unit));
        let ej = (d.objective - dj).abs() / dj.abs().max(1e-12);
        eprintln!(
            "{}: dθ0 {et:.1e}, dK {ek:.1e}, dJ {ej:.1e} (envelope {:.6e}, differences {dj:.6e})",
            p.name, d.objective
        );
        assert!(et < 1e-5 && ek < 1e-5 && ej < 1e-5, "{}: relative errors θ0 {et:.1e}, K {ek:.1e}, J {ej:.1e}", p.name);
        let gap = (d.objective - d.objective_direct).abs();
        assert!(gap <= 1e-8 * d.objective.abs().max(1e-12), "{}: envelope vs direct", p.name);
    }
}

/// A bound through the optimum of a free spring (`K_4` of design5, about 301 N·m/rad) is weakly
/// active: strict complementarity fails, no two-sided derivative is given, and the one-sided ones
/// match one-sided differences of re-solves (the spring leaves the bound as `δ_d` moves one way
/// and presses on it the other way).
#[test]
fn a_weakly_active_bound_gives_one_sided_derivatives() {
    let free = report(&design5(), &["delta_d"]);
    // K_4 of the optimum re-solved tightly, as the sensitivities see it.
    let k4 = resolve(&design5(), "delta_d", -0.02, &free.design.result.design).1[3];
    assert!(k4 > 150.0 && k4 < 5000.0, "K_4 = {k4} is inside its bounds");
    let case = design5().with_parameter("bounds.stiffness_max[3]", k4).unwrap();
    let r = report(&case, &["delta_d"]);
    let s = r.sensitivity.as_ref().expect("a clean optimum");
    assert!(!s.conditions.hold && !s.conditions.weakly_active.is_empty(), "{:?}", s.conditions);
    let p = &s.parameters[0];
    assert!(p.derivative.is_none(), "no two-sided derivative at a weakly active bound");
    let down = p.decrease.as_ref().expect("a one-sided derivative for a decrease");
    let start = r.design.result.design.clone();
    let h = 1e-5 * p.value.abs();
    let (_, k0, _) = resolve(&case, "delta_d", p.value, &start);
    let (_, k_minus, _) = resolve(&case, "delta_d", p.value - h, &start);
    let backward: Vec<f64> = k0.iter().zip(&k_minus).map(|(a, b)| (a - b) / h).collect();
    let e_down = relative(&down.stiffness, &backward, 1.0);
    eprintln!("decrease: K_4 rate {:.6e} (differences {:.6e}), error {e_down:.1e}", down.stiffness[3], backward[3]);
    assert!(e_down < 1e-3, "one-sided error {e_down:.1e}");
    // An increase of δ_d presses K_4 on its bound and lifts K_5 off its lower bound, a change of
    // a strictly active bound that the enumeration of the weak bounds does not cover: no
    // derivative is claimed for it (where one is given, it must match).
    if let Some(up) = &p.increase {
        let (_, k_plus, _) = resolve(&case, "delta_d", p.value + h, &start);
        let forward: Vec<f64> = k_plus.iter().zip(&k0).map(|(a, b)| (a - b) / h).collect();
        assert!(relative(&up.stiffness, &forward, 1.0) < 1e-3, "increase: {:?} vs {:?}", up.stiffness, forward);
    }
}

/// Every static run of the paper's figure cases (figs. 3–8: twelve eq. (33) optima), each from its
/// own start: `dJ*/dp`, `dθ0*/dp` and `dK*/dp` for `δ_d` and the load scale against central
/// differences of tight re-solves where the conditions hold, the one-sided derivatives against
/// one-sided differences where a bound is weakly active, and where no derivative is given the
/// conditions say why.
#[test]
fn every_static_figure_run_matches_differences_of_re_solves() {
    let names: Vec<String> = ["delta_d", "loads.scale"].iter().map(|s| s.to_string()).collect();
    let mut overrides = Overrides::default();
    overrides.design.starts = Some(0);
    let (mut two_sided, mut one_sided, mut runs, mut saddles) = (0, 0, 0, 0);
    for text in [
        include_str!("../../../paper-cases/fig3.json"),
        include_str!("../../../paper-cases/fig4.json"),
        include_str!("../../../paper-cases/fig5.json"),
        include_str!("../../../paper-cases/fig6.json"),
        include_str!("../../../paper-cases/fig7.json"),
        include_str!("../../../paper-cases/fig8.json"),
    ] {
        let case = Case::from_json(text).unwrap();
        let Case::Figure(figure) = &case else { panic!("a figure case") };
        let valid = figure.validate().unwrap();
        let result = run_sensitivity(&case, &overrides, &names, &mut spine_run::quiet).unwrap();
        let KindResult::FigureSensitivity(r) = result.result else { panic!("a figure sensitivity result") };
        assert!(r.skipped.is_empty(), "figs. 3-8 are static: {:?}", r.skipped);
        for run in &r.runs {
            runs += 1;
            let Some(Case::Design(c)) = valid.iter().find(|v| v.name == run.name).map(|v| &v.case) else {
                panic!("{} is a design run", run.name)
            };
            let start = run.result.design.result.design.clone();
            let Some(s) = run.result.sensitivity.as_ref() else {
                // Refused only where the tight re-solve leaves the point for a lower J: then the
                // point Ipopt reported at its tolerance is not a local minimum (fig8's, since
                // 2026-11-26: J 7.28338e-3, and the re-solve descends to 7.27044e-3).
                let reason = run.result.no_sensitivity.clone().expect("a reason where there are no sensitivities");
                assert!(
                    matches!(reason, spine_run::sensitivity::NoSensitivity::AnotherOptimum { .. }),
                    "{} {}: {reason}",
                    figure.figure,
                    run.name
                );
                let reported = run.result.design.result.objective;
                let valid = c.validate().unwrap();
                let polished =
                    polish(&valid.problem, &start, &valid.settings).unwrap().check(&valid.problem, &valid.settings);
                assert!(polished.is_clean(), "{} {}: {}", figure.figure, run.name, polished.solver.status);
                assert!(polished.objective < reported * (1.0 - 1e-6), "{} {}: {reason}", figure.figure, run.name);
                saddles += 1;
                continue;
            };
            for p in &s.parameters {
                let at = format!("{} {} {}", figure.figure, run.name, p.name);
                let h = 1e-4 * p.value.abs().max(1e-2);
                let plus = resolve(c, &p.name, p.value + h, &start);
                let minus = resolve(c, &p.name, p.value - h, &start);
                let per_unit = 1.0 / p.value.abs().max(1e-2);
                // `with_k`: whether K is compared. At a weakly active stiffness bound in a flat
                // valley of J (Fig. 5 at −1 N: multipliers 1e-8, below their gaps) a spring's K
                // moves J by less than the re-solves' tolerance, so their K differences do not
                // determine its one-sided rate (they keep it on the bound; the linearised KKT
                // conditions release it); J and θ0 are determined and compared.
                let close = |d: &Derivative, t: Vec<f64>, k: Vec<f64>, j: f64, tol: f64, with_k: bool| {
                    let et = relative(&d.theta0, &t, 1e-2 * per_unit);
                    let ek = if with_k { relative(&d.stiffness, &k, per_unit) } else { 0.0 };
                    let ej = (d.objective - j).abs() / j.abs().max(1e-12);
                    assert!(
                        et < tol && ek < tol && ej < tol,
                        "{at}: θ0 {et:.1e}, K {ek:.1e}, J {ej:.1e}\n dK {:?}\n fd {:?}\n dJ {} {} fd {j}",
                        d.stiffness,
                        k,
                        d.objective,
                        d.objective_direct
                    );
                };
                match (&p.derivative, &p.increase, &p.decrease) {
                    (Some(d), _, _) => {
                        two_sided += 1;
                        let dj = (plus.2 - minus.2) / (2.0 * h);
                        close(d, central(&plus.0, &minus.0, h), central(&plus.1, &minus.1, h), dj, 1e-5, true);
                    }
                    (None, Some(up), Some(down)) => {
                        one_sided += 1;
                        let here = resolve(c, &p.name, p.value, &start);
                        let forward = |a: &[f64], b: &[f64]| -> Vec<f64> { central(a, b, 0.5 * h) };
                        // One-sided differences carry O(h) curvature: looser than the central ones.
                        let (j_up, j_down) = ((plus.2 - here.2) / h, (here.2 - minus.2) / h);
                        close(up, forward(&plus.0, &here.0), forward(&plus.1, &here.1), j_up, 1e-3, false);
                        close(down, forward(&here.0, &minus.0), forward(&here.1, &minus.1), j_down, 1e-3, false);
                    }
                    _ => assert!(!s.conditions.hold, "{at}: no derivative although the conditions hold"),
                }
            }
        }
    }
    eprintln!(
        "{runs} static runs: {two_sided} two-sided and {one_sided} one-sided derivatives checked, {saddles} not minima"
    );
    // Figs. 3–8: 12 runs, and Fig. 3's two under the text's stiffness bound 1000.
    assert_eq!(runs, 14);
    assert!(saddles <= 1, "{saddles} reported points are not local minima");
    assert!(two_sided >= 12 && one_sided >= 2, "{two_sided} two-sided, {one_sided} one-sided");
}
