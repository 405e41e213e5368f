//! The fmincon-like preset: a design case solved like the paper's optimiser, alone or beside the
//! exact solve.

use spine_case::{Case, DesignCase, ObjectiveSpec};
use spine_design::{Formulation, SolverPreset};
use spine_run::run_design;

fn design5() -> DesignCase {
    let Case::Design(c) = Case::from_json(include_str!("../../../paper-cases/design5.json")).unwrap() else {
        panic!("design5 is a design case")
    };
    c
}

#[test]
fn the_preset_replaces_the_formulation_and_the_stopping_rules() {
    let exact = design5().validate().unwrap();
    let fmincon = DesignCase { preset: SolverPreset::FminconLike, ..design5() }.validate().unwrap();
    assert_eq!((exact.formulation, exact.preset), (Formulation::Full, SolverPreset::Exact));
    assert_eq!((fmincon.formulation, fmincon.preset), (Formulation::Reduced, SolverPreset::FminconLike));
    assert_eq!(fmincon.settings, exact.settings.fmincon_like());
    assert_eq!(exact.with_preset(SolverPreset::FminconLike).settings, fmincon.settings);
    // A case the reduced space cannot solve says which field asks for it.
    let material = || DesignCase { objective: ObjectiveSpec::TotalStiffness, ..design5() };
    let e = DesignCase { fmincon_like_beside: true, ..material() }.validate().unwrap_err();
    assert_eq!(e.field(), "fmincon_like_beside", "{e}");
    let e = DesignCase { preset: SolverPreset::FminconLike, ..material() }.validate().unwrap_err();
    assert_eq!(e.field(), "preset", "{e}");
    assert!(material().validate().is_ok());
}

#[test]
fn beside_the_exact_design_the_fmincon_like_one_is_solved_from_the_same_start() {
    let valid = DesignCase { fmincon_like_beside: true, ..design5() }.validate().unwrap();
    let d = run_design(&valid, None).unwrap();
    assert_eq!(d.preset, SolverPreset::Exact);
    assert!(d.result.is_clean(), "{:?}", d.result.warnings);
    let f = d.fmincon_like.as_deref().expect("solved beside");
    assert_eq!((f.preset, f.result.formulation), (SolverPreset::FminconLike, Formulation::Reduced));
    assert_eq!(f.start, d.start, "the same (projected) start");
    assert!(f.result.is_feasible(), "{:?}", f.result.warnings);
    assert!(f.result.solver.iterations <= 1000);
    assert!(f.fmincon_like.is_none() && f.best.is_none());
    // Both meet eq. (33)'s end condition; the exact optimum is no worse than fmincon-like's
    // within its tolerance 1e-6.
    assert!((f.result.end_displacement.unwrap() - f.result.delta_d).abs() < 1e-6);
    assert!(d.result.objective <= f.result.objective * (1.0 + 1e-6), "{} {}", d.result.objective, f.result.objective);
}
