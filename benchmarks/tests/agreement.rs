//! Every derivative that `benches/scaling.rs` times agrees with the others, computed by the same
//! calls: the benchmark never times a wrong answer.

use spine_benchmarks::{DesignFixture, HessianFixture, StateFixture};
use spine_design::adjoint::ReducedGradients;
use spine_design::full_space::StateForm;
use spine_model::sparse::BorderedTridiagonal;

fn entries(j: &BorderedTridiagonal) -> Vec<f64> {
    [&j.diag, &j.lower, &j.upper, &j.column, &j.row].into_iter().flatten().copied().collect()
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

#[test]
fn state_jacobian_by_ad_equals_the_hand_derived_one_and_central_differences() {
    for n in [5, 10, 50, 1000] {
        let f = StateFixture::new(n);
        let (r_ad, ad) = f.jacobian_ad();
        let (r_hand, hand) = f.jacobian_hand();
        let (r_fd, fd) = f.jacobian_fd();
        let (r_fused, fused) = f.jacobian_hand_fused();
        assert_eq!(r_ad, r_hand, "N = {n}: residuals");
        assert_eq!(r_fused[..n], r_hand[..n], "N = {n}: joint residuals");
        assert!((r_fused[n] - r_hand[n]).abs() <= 1e-15, "N = {n}: Φ");
        assert_eq!(fused, hand.clone(), "N = {n}: the fused hand loop writes the same entries");
        assert_eq!(r_ad, r_fd, "N = {n}: residuals");
        let (ad, hand, fd) = (entries(&ad), entries(&hand), entries(&fd));
        let scale = max_abs(&ad);
        for k in 0..ad.len() {
            assert!((ad[k] - hand[k]).abs() <= 1e-12 * scale, "N = {n} entry {k}: AD {} hand {}", ad[k], hand[k]);
            // Central differences with h = 6e-6 max(1, |v|): truncation ~ h² |r'''|, rounding ~ ε |r| / h.
            assert!((ad[k] - fd[k]).abs() <= 1e-7 * scale, "N = {n} entry {k}: AD {} FD {}", ad[k], fd[k]);
            assert!(ad[k] != 0.0, "N = {n} entry {k} is zero: the fixture must exercise every entry");
        }
    }
}

#[test]
fn one_newton_step_converges_quadratically_at_every_size() {
    for n in [5, 100, 10_000] {
        let f = StateFixture::new(n);
        let size = 1e-3;
        let start = f.perturbed(size);
        let next = f.newton_step(&start);
        let error =
            |s: &spine_model::State| s.theta.iter().zip(&f.state.theta).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!((error(&start) - size).abs() < 1e-12);
        // Quadratic convergence: the error after one step is O(size²), far below size.
        assert!(error(&next) < 100.0 * size * size, "N = {n}: error {} after one step from {size}", error(&next));
    }
}

/// Entry by entry, `|a − b| ≤ relative · |a| + absolute · scale`. For `dJ/dd` the scale is the
/// largest spring moment `|K_m Δθ|` (the adjoint formula subtracts terms of that size, so rounding
/// is relative to it, not to the difference); for `dX/dd` the largest entry.
fn assert_gradients_agree(
    f: &DesignFixture,
    what: &str,
    reference: &ReducedGradients,
    other: &ReducedGradients,
    relative: f64,
    absolute: f64,
) {
    let n = f.problem.n_links();
    assert_eq!(reference.energy, other.energy);
    assert_eq!(reference.end_x, other.end_x);
    let moments = spine_model::hand::strain_energy_partials(&f.design, &f.passive).0;
    for (name, a, b, scale) in [
        (
            "dJ/d(θ0, K)",
            &reference.energy_gradient,
            &other.energy_gradient,
            max_abs(&moments).max(max_abs(&reference.energy_gradient)),
        ),
        ("dX/d(θ0, K)", &reference.end_x_gradient, &other.end_x_gradient, max_abs(&reference.end_x_gradient)),
    ] {
        assert_eq!(a.len(), 2 * n + 1);
        assert_eq!(b.len(), 2 * n + 1);
        assert!(scale > 0.0);
        for k in 0..a.len() {
            let error = (a[k] - b[k]).abs();
            let allowed = relative * a[k].abs() + absolute * scale;
            assert!(
                error <= allowed,
                "N = {n} {name}[{k}] {what}: hand {} vs {} (error {error:e} > {allowed:e})",
                a[k],
                b[k]
            );
        }
    }
}

#[test]
fn design_gradients_by_ad_adjoint_hand_adjoint_forward_ad_and_central_differences_agree() {
    for n in [5, 10, 50] {
        let f = DesignFixture::new(n);
        let hand = f.gradients_hand();
        assert_gradients_agree(&f, "AD adjoint", &hand, &f.gradients_ad(), 1e-9, 1e-11);
        assert_gradients_agree(&f, "forward AD", &hand, &f.gradients_forward(), 1e-9, 1e-11);
        assert_gradients_agree(&f, "central differences", &hand, &f.gradients_fd(), 1e-5, 1e-7);
    }
    let f = DesignFixture::new(1000);
    assert_gradients_agree(&f, "AD adjoint", &f.gradients_hand(), &f.gradients_ad(), 1e-9, 1e-11);
}

#[test]
fn lagrangian_hessian_by_second_order_ad_equals_central_differences_of_the_gradient() {
    for (n, states) in
        [(5, StateForm::Absolute), (50, StateForm::Absolute), (5, StateForm::Deflection), (50, StateForm::Deflection)]
    {
        let f = HessianFixture::new(&DesignFixture::new(n), states);
        let pattern = &f.assembled.patterns.hessian;
        let mut values = vec![0.0; pattern.len()];
        f.hessian(&mut values);
        let dim = f.x.len();
        let mut dense = vec![vec![0.0; dim]; dim];
        for (&(r, c), v) in pattern.iter().zip(&values) {
            dense[r][c] += v;
            if r != c {
                dense[c][r] += v;
            }
        }
        let scale = max_abs(&values);
        for k in 0..dim {
            let h = 1e-6 * f.x[k].abs().max(1.0);
            let (mut plus, mut minus) = (f.x.clone(), f.x.clone());
            plus[k] += h;
            minus[k] -= h;
            let (gp, gm) = (f.lagrangian_gradient(&plus), f.lagrangian_gradient(&minus));
            for r in 0..dim {
                let fd = (gp[r] - gm[r]) / (2.0 * h);
                assert!(
                    (fd - dense[r][k]).abs() <= 1e-6 * scale.max(1.0),
                    "N = {n} ({states:?}) ∂²L/∂x{r}∂x{k}: AD {} FD {fd}",
                    dense[r][k]
                );
            }
        }
    }
}

/// The normwise backward error `‖b − A x‖∞ / (‖|A| |x|‖∞ + ‖b‖∞)` of `x` for the recorded matrix.
fn backward_error(structure: &spine_kkt::Structure, a: &[f64], x: &[f64], b: &[f64]) -> f64 {
    let (mut ax, mut size) = (vec![0.0; x.len()], vec![0.0; x.len()]);
    structure.multiply_with_magnitude(a, x, &mut ax, &mut size);
    let residual = ax.iter().zip(b).fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
    let scale = size.iter().fold(0.0f64, |m, s| m.max(*s)) + b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    residual / scale
}

/// The factorisation the benchmark times against MUMPS gives MUMPS's inertia on the same recorded
/// KKT matrices (N = 100 and 1000; N = 1000's sweep is split in two halves and a root), and both
/// solutions are backward stable and agree.
#[test]
fn spine_kkt_and_mumps_agree_on_recorded_kkt_matrices() {
    for links in spine_benchmarks::kkt::RECORDED_LINKS {
        let dump = spine_benchmarks::kkt::recorded(links).unwrap();
        let structure = dump.structure().unwrap();
        let mut spine = spine_kkt::SymmetricSolver::new(structure.clone());
        assert_eq!(spine.analysis().is_split(), dump.n >= spine_kkt::SPLIT_FROM, "N = {links}");
        let inertia = spine.factorize(&dump.a).unwrap();
        let coordinates = spine_benchmarks::kkt::coordinates(&dump).unwrap();
        let mut mumps = spine_mumps::Mumps::analyse(dump.n, &coordinates, &dump.a).unwrap();
        assert_eq!(mumps.factorize(&dump.a).unwrap(), inertia.negative, "N = {links}: negative eigenvalues");
        assert_eq!(inertia.positive + inertia.negative, dump.n, "N = {links}: no zero eigenvalue");
        let b: Vec<f64> = (0..dump.n).map(|i| ((i * 7 + 3) as f64).sin()).collect();
        let (mut x_spine, mut x_mumps) = (b.clone(), b.clone());
        spine.solve(&mut x_spine).unwrap();
        mumps.solve(&mut x_mumps).unwrap();
        // Ipopt runs MUMPS without its iterative refinement and refines on the whole system itself;
        // one step of it here, so that both solutions are backward stable.
        let mut correction = vec![0.0; dump.n];
        structure.multiply(&dump.a, &x_mumps, &mut correction);
        correction.iter_mut().zip(&b).for_each(|(r, q)| *r = q - *r);
        mumps.solve(&mut correction).unwrap();
        x_mumps.iter_mut().zip(&correction).for_each(|(x, d)| *x += d);
        let (e_spine, e_mumps) =
            (backward_error(&structure, &dump.a, &x_spine, &b), backward_error(&structure, &dump.a, &x_mumps, &b));
        assert!(e_spine < 1e-15 && e_mumps < 1e-14, "N = {links}: backward errors {e_spine:.1e}, {e_mumps:.1e}");
        let largest = x_spine.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let difference = x_spine.iter().zip(&x_mumps).fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
        eprintln!(
            "N = {links}: backward errors {e_spine:.1e} / {e_mumps:.1e}, solutions differ by {:.1e}",
            difference / largest
        );
        assert!(
            difference <= 1e-8 * largest,
            "N = {links}: solutions differ by {difference:.1e} (largest {largest:.1e})"
        );
    }
}
