//! The order of a multi-start's optima does not depend on rounding: the two members of a mirror
//! pair, whose `J` agree only to round-off, are listed with the one reached from the earlier start
//! first, whichever `J` is lower in the last digits.

use spine_design::fixtures::paper_problem;
use spine_design::multistart::{cluster, feasible_starts, mirror};
use spine_design::settings::SolverPreset;
use spine_design::solve::Solver;
use spine_design::{DesignResult, Formulation, SolverSettings};

/// A clean optimum of fig. 6's problem (10 links, C_K = 1, symmetric loads) that is not its own
/// mirror image, and that image with `J` moved by a few units in the last place.
fn optimum_and_image(shift_ulps: f64) -> (DesignResult, DesignResult) {
    let problem = paper_problem(10, -5.0, -400.0, -0.02, 1.0);
    let optimum = feasible_starts(&problem, 6, 0)
        .iter()
        .map(|s| {
            Solver::new(SolverPreset::Exact, Formulation::Full, &SolverSettings::default())
                .solve(&problem, s, &mut |_| true)
                .unwrap()
        })
        .find(|r| {
            let image = mirror(&r.design);
            r.is_clean() && r.design.theta0.iter().zip(&image.theta0).any(|(a, b)| (a - b).abs() > 1e-3)
        })
        .expect("one of six seeded starts reaches an asymmetric clean optimum");
    let mut image = optimum.clone();
    image.design = mirror(&optimum.design);
    image.objective = optimum.objective * (1.0 + shift_ulps * f64::EPSILON);
    (optimum, image)
}

#[test]
fn the_earlier_start_leads_a_mirror_pair() {
    for shift in [-4.0, 4.0] {
        let (optimum, image) = optimum_and_image(shift);
        let j = optimum.objective;
        // The image from start 0, the optimum from start 1.
        let summary = cluster(vec![image.clone(), optimum.clone()], 0);
        assert_eq!(summary.optima.len(), 2, "shift {shift}");
        assert_eq!(summary.optima[0].starts, vec![0], "shift {shift}: the image's J {} vs {j}", image.objective);
        assert_eq!(summary.optima[1].mirror_of, Some(0), "shift {shift}");
        // And the other way round.
        let summary = cluster(vec![optimum, image], 0);
        assert_eq!(summary.optima[0].starts, vec![0], "shift {shift}");
        assert_eq!(summary.optima[0].objective(), j, "shift {shift}");
        assert_eq!(summary.optima[1].mirror_of, Some(0), "shift {shift}");
    }
}

#[test]
fn the_census_counts_a_mirror_pair_as_one_class() {
    let (optimum, image) = optimum_and_image(0.0);
    let summary = cluster(vec![optimum.clone(), image.clone(), optimum.clone()], 0);
    assert_eq!(summary.optima.len(), 2, "both members are listed");
    assert_eq!(summary.optima.iter().map(|o| o.count).collect::<Vec<_>>(), vec![2, 1]);
    assert_eq!((summary.census.searches, summary.census.distinct), (3, 1));
    assert_eq!(summary.census.reached, vec![3]);
    // Without its image the optimum is alone in its class: one class either way.
    let alone = cluster(vec![optimum.clone(), optimum], 0);
    assert_eq!((alone.census.searches, alone.census.distinct), (2, 1));
}
