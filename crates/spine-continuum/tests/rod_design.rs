//! Eq. (33) for one rod: the problem of each `N` is the same physical problem, the prolongation
//! keeps the design constraints, and the optima of a short ladder settle into one pattern.

use spine_continuum::design::paper_rod;
use spine_continuum::design_study::{runs, study, StudySettings};
use spine_design::problem::height_floor;
use spine_model::kinematics::end_constraint;

#[test]
fn every_n_poses_the_same_rod() {
    let rod = paper_rod();
    for n in [10, 37, 1000] {
        let p = rod.problem(n);
        let a = 1.0 / n as f64;
        let b = &p.bounds;
        // EI = K a inside, the clamps' springs twice that; C_K = EI_max / a.
        assert!((b.stiffness_min[1] * a - 10.0).abs() < 1e-9 && (b.stiffness_max[n / 2] * a - 1000.0).abs() < 1e-9);
        assert!((b.stiffness_min[0] * a - 20.0).abs() < 1e-9 && (b.stiffness_max[n] * a - 2000.0).abs() < 1e-9);
        assert!((p.stiffness_scale * a - 1000.0).abs() < 1e-9);
        // The curvature bound: the relative angle over one span.
        assert!((b.relative_angle_max - rod.curvature_max * a).abs() < 1e-15);
        // The transverse load per unit length: q a on the interior nodes, half on the slider.
        let total: f64 = p.structure.passive.p_y.iter().sum();
        assert!((total - (-50.0) * (1.0 - 0.5 * a)).abs() < 1e-9, "{total}");
        assert_eq!(p.structure.actuation.p_x[n], -400.0);
    }
    // At N = 10 the ramped height bound is the paper's 0.01 m at every interior node; finer, it
    // falls to zero at the ends.
    let floors = paper_rod().problem(10).bounds.height_floors(&[0.1; 10]);
    assert!(floors.iter().all(|f| (f - 0.01).abs() < 1e-15), "{floors:?}");
    let floors = paper_rod().problem(100).bounds.height_floors(&[0.01; 100]);
    assert!(
        (floors[0] - 0.001).abs() < 1e-15 && (floors[49] - 0.01).abs() < 1e-15 && (floors[98] - 0.001).abs() < 1e-12
    );
}

#[test]
fn the_height_floor_is_differentiated_exactly() {
    use num_dual::Dual64;
    // d/dx of the floor on the ramp, against central differences (the sensitivities lift it).
    for (x, ramp) in [(0.03, 0.1), (0.95, 0.1), (0.5, 0.1), (0.2, 0.0)] {
        let exact = height_floor(Dual64::from(0.01), Dual64::from(ramp), Dual64::new(x, 1.0), Dual64::from(1.0)).eps;
        let h = 1e-7;
        let fd = (height_floor(0.01, ramp, x + h, 1.0) - height_floor(0.01, ramp, x - h, 1.0)) / (2.0 * h);
        assert!((exact - fd).abs() < 1e-8, "x {x}, ramp {ramp}: {exact} vs {fd}");
    }
}

#[test]
fn the_prolongation_keeps_the_end_on_the_axis_and_the_curvature_bound() {
    let rod = paper_rod();
    let coarse = rod.start(20);
    for n in [7, 20, 53, 400] {
        let fine = rod.prolong(&coarse, n);
        let spans = vec![1.0 / n as f64; n];
        assert!(end_constraint(&spans, &fine.theta0, &fine.theta0).abs() < 1e-12, "N = {n}");
        let bound = rod.curvature_max / n as f64;
        if n >= 20 {
            assert!(fine.theta0.windows(2).all(|w| (w[0] - w[1]).abs() <= bound * (1.0 + 1e-9)), "N = {n}");
        }
        assert!(fine.stiffness.iter().enumerate().all(|(j, k)| {
            let ei = rod.bending_stiffness_of(n, j, *k);
            (10.0 * (1.0 - 1e-12)..=1000.0 * (1.0 + 1e-12)).contains(&ei)
        }));
    }
}

#[test]
fn a_short_ladder_settles_into_three_soft_zones_near_the_limit() {
    let rod = paper_rod();
    let s = study(&rod, &[10, 20, 50], &StudySettings::default(), &mut |_, _| {}).unwrap();
    for level in &s.levels {
        assert!(level.is_clean(), "N = {}: {:?}", level.links, level.attempts);
        assert!(level.result.certificate.is_some(), "N = {}", level.links);
    }
    // N = 50: three runs of joints on EI's lower bound between stiff stretches (the pattern of
    // every finer level, docs/continuum.md), J* within 0.2 % of the limit 4.8945 mJ.
    let fifty = &s.levels[2];
    let soft_zones = runs(&fifty.pattern).split(' ').filter(|r| r.starts_with('L')).count();
    assert_eq!(soft_zones, 3, "{}", runs(&fifty.pattern));
    assert!((fifty.result.objective / 4.8945e-3 - 1.0).abs() < 2e-3, "{}", fifty.result.objective);
    // The second pass (from the finest, carried back) found the coarse levels' lower optima.
    assert!(s.levels[0].result.objective < 5.0e-3, "N = 10: {}", s.levels[0].result.objective);
}
