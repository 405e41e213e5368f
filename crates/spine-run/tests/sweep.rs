//! Followed sweeps of eq. (33)'s optimum (`spine_run::run_sweep`) on Fig. 5's 10-link case along
//! the transverse load: the branch against its own tangents and against independent tight
//! solves, the events against the points around them, and the census.

use spine_case::{Case, DesignCase};
use spine_design::solve::polish::polish;
use spine_design::sweep::settings::SweepSettings;
use spine_design::sweep::{EventKind, PointStatus};
use spine_run::sweep::{CensusPlan, SweepCaseResult};
use spine_run::{run_sweep, KindResult, Overrides};

fn fig5_base() -> DesignCase {
    let Case::Design(c) = Case::from_json(include_str!("../../../paper-cases/fig5-base.json")).unwrap() else {
        panic!("fig5-base is a design case")
    };
    c
}

fn sweep(from: f64, to: f64, points: usize, plan: Option<CensusPlan>) -> SweepCaseResult {
    let case = Case::Design(fig5_base());
    let settings = SweepSettings::new(from, to, points);
    let result = run_sweep(&case, &Overrides::default(), "loads.p_y", settings, plan, &mut spine_run::quiet).unwrap();
    let KindResult::Sweep(r) = result.result else { panic!("a sweep result") };
    r
}

/// Along the followed branch, `J*(p_{k+1}) − J*(p_k)` is the integral of the tangent's `dJ*/dp`
/// (Simpson's rule with the midpoint value from a tight solve there), and each point is the
/// optimum a tight solve reaches from the previous point's design.
#[test]
fn the_followed_branch_agrees_with_its_tangents_and_with_independent_solves() {
    let r = sweep(-1.0, -8.0, 8, None);
    let s = &r.sweep;
    assert_eq!(s.points.len(), 8);
    // At −1 N six stiffness upper bounds are weakly active (in a flat valley of J): the one-sided
    // tangent keeps them in the box, so no step is refused (a two-sided tangent that treats them
    // as inactive moves them 5000 N·m/rad past 10⁴ per 0.5 N and halves every step).
    assert_eq!(s.rejected_steps, 0);
    assert!(
        s.points.iter().all(|p| p.status == PointStatus::Followed),
        "{:?}",
        s.points.iter().map(|p| p.status).collect::<Vec<_>>()
    );
    let values: Vec<f64> = s.points.iter().map(|p| p.parameter).collect();
    assert_eq!(values, (0..8).map(|k| -1.0 - k as f64).collect::<Vec<_>>());
    let case = fig5_base();
    for w in s.points.windows(2) {
        let (a, b) = (&w[0], &w[1]);
        // The point is the tight optimum from the previous design at b's load.
        let valid = case.with_parameter("loads.p_y", b.parameter).unwrap().validate().unwrap();
        let again = polish(&valid.problem, &a.design, &valid.settings).unwrap().check(&valid.problem, &valid.settings);
        assert!(again.is_clean());
        assert!((again.objective - b.objective).abs() <= 1e-9 * b.objective, "{} vs {}", again.objective, b.objective);
        // ΔJ* = ∫ dJ*/dp: J* is smooth between the points (no event in these intervals but the
        // bounds that become active, where dJ*/dp stays continuous).
        let slope = |p: &spine_design::sweep::SweepPoint| p.tangent.as_ref().expect("a tangent").objective;
        let mid = 0.5 * (a.parameter + b.parameter);
        let valid = case.with_parameter("loads.p_y", mid).unwrap().validate().unwrap();
        let middle = polish(&valid.problem, &a.design, &valid.settings).unwrap().check(&valid.problem, &valid.settings);
        let h = b.parameter - a.parameter;
        // Simpson's rule on J* itself: the middle value enters through the interpolating parabola's
        // slope at the ends, J'(a) ≈ (−3 J_a + 4 J_m − J_b)/h.
        let parabola_slope = (-3.0 * a.objective + 4.0 * middle.objective - b.objective) / h;
        let scale = slope(a).abs().max(1e-12);
        assert!(
            (parabola_slope - slope(a)).abs() <= 5e-3 * scale,
            "at {}: {parabola_slope} vs {}",
            a.parameter,
            slope(a)
        );
    }
}

/// Every event lies between the last point before it and the first point after it, and a bound
/// reported as becoming active is not active at the point before and active at the point after.
#[test]
fn events_lie_where_the_points_around_them_change() {
    let r = sweep(-1.0, -4.0, 7, None);
    let s = &r.sweep;
    assert!(!s.events.is_empty(), "K bounds become active between -1 and -3 N per node");
    for e in &s.events {
        let (lo, hi) = (e.bracket[0].max(e.bracket[1]), e.bracket[0].min(e.bracket[1]));
        assert!((lo - hi).abs() <= 0.5 / 2f64.powi(9), "bisected to a narrow bracket: {e:?}");
        let before = s.points.iter().rev().find(|p| p.parameter >= lo).unwrap();
        let after = s.points.iter().find(|p| p.parameter <= hi).unwrap();
        match e.kind {
            EventKind::BoundActive => {
                assert!(!before.active.contains(&e.what) && after.active.contains(&e.what), "{e:?}")
            }
            EventKind::BoundInactive => {
                assert!(before.active.contains(&e.what) && !after.active.contains(&e.what), "{e:?}")
            }
            _ => {}
        }
    }
}

/// The census: a multi-start at the chosen points with its Boender–Rinnooy Kan estimate, and the
/// best known `J*` never above the followed one.
#[test]
fn the_census_reports_the_best_known_optimum_and_its_completeness() {
    let r = sweep(-1.0, -3.0, 3, Some(CensusPlan { starts: 6, every: 2 }));
    assert_eq!(r.census.iter().map(|c| c.point).collect::<Vec<_>>(), vec![0, 2]);
    for c in &r.census {
        let best = c.best_objective.expect("some start ends clean");
        assert!(best <= c.followed_objective);
        assert_eq!(c.followed_is_best, c.followed_objective <= best * (1.0 + 1e-6));
        let e = c.estimate.as_ref().expect("a multi-start");
        assert!(e.searches <= 7 && e.distinct >= 1 && e.reached.iter().sum::<usize>() == e.searches);
    }
    let csv = r.table().to_csv();
    assert_eq!(csv.lines().count(), 4, "{csv}");
    assert!(
        csv.lines().nth(1).unwrap().rsplit(',').next().is_some_and(|b| !b.is_empty()),
        "census point 0 has its best J*"
    );
    assert!(csv.lines().nth(2).unwrap().ends_with(','), "no census at point 1");
}
