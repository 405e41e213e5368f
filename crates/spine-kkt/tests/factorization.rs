//! The frontal LDLᵀ against dense references (faer's symmetric eigenvalues for the inertia, the
//! residual for the solution) on random KKT-like matrices of many shapes and scales, singular
//! matrices, and Pardiso's calling convention.

use faer::{Mat, Side};
use spine_kkt::pardiso::{self, error, Call, State, PARAMETERS};
use spine_kkt::{Dump, KktError, Structure, SweepOptions, SymmetricSolver, SPLIT_FROM};

/// SplitMix64, for reproducible random matrices.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn uniform(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn symmetric(&mut self) -> f64 {
        2.0 * self.uniform() - 1.0
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// A symmetric matrix as a map of upper-triangle entries.
#[derive(Clone, Default)]
struct Upper {
    n: usize,
    entries: std::collections::BTreeMap<(usize, usize), f64>,
}

impl Upper {
    fn add(&mut self, i: usize, j: usize, v: f64) {
        *self.entries.entry((i.min(j), i.max(j))).or_insert(0.0) += v;
    }
    fn structure(&self) -> (Structure, Vec<f64>) {
        let list: Vec<(usize, usize)> = self.entries.keys().copied().collect();
        let (structure, position) = Structure::from_entries(self.n, &list).unwrap();
        let mut values = vec![0.0; list.len()];
        for (e, v) in self.entries.values().enumerate() {
            values[position[e]] = *v;
        }
        (structure, values)
    }
    fn dense(&self) -> Mat<f64> {
        Mat::from_fn(self.n, self.n, |i, j| self.entries.get(&(i.min(j), i.max(j))).copied().unwrap_or(0.0))
    }
    /// The same matrix with its rows and columns renumbered by `label`.
    fn permuted(&self, label: &[usize]) -> Upper {
        let mut out = Upper { n: self.n, ..Default::default() };
        for (&(i, j), &v) in &self.entries {
            out.add(label[i], label[j], v);
        }
        out
    }
}

/// An Ipopt-like KKT matrix of a chain: `links` blocks of `width` variables coupled to their
/// neighbours, `H` indefinite plus a barrier diagonal spanning `scales` decades, constraint rows
/// with zero diagonal each touching a few variables, and `dense` rows touching every block.
fn chain_kkt(rng: &mut Rng, links: usize, width: usize, dense: usize, scales: f64) -> Upper {
    let nv = links * width;
    let nc = links;
    let n = nv + nc + dense;
    let mut a = Upper { n, ..Default::default() };
    for i in 0..nv {
        a.add(i, i, rng.symmetric() + 10f64.powf(scales * (rng.uniform() - 0.5)));
        for j in i + 1..(i + 2 * width).min(nv) {
            if rng.uniform() < 0.5 {
                a.add(i, j, rng.symmetric());
            }
        }
    }
    for c in 0..nc {
        let row = nv + c;
        a.add(row, row, 0.0);
        for k in 0..width + 1 {
            let v = (c * width + k).min(nv - 1);
            a.add(row, v, rng.symmetric() + 2.0);
        }
    }
    for d in 0..dense {
        let row = nv + nc + d;
        a.add(row, row, 0.0);
        for c in 0..links {
            a.add(row, c * width + rng.below(width), 1.0 + rng.uniform());
        }
    }
    a
}

fn inertia_reference(a: &Upper) -> (usize, usize, usize) {
    let eig = a.dense().self_adjoint_eigenvalues(Side::Lower).unwrap();
    let scale = eig.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let tol = scale * 1e-12;
    let pos = eig.iter().filter(|&&v| v > tol).count();
    let neg = eig.iter().filter(|&&v| v < -tol).count();
    (pos, neg, eig.len() - pos - neg)
}

fn check_solves(a: &Upper, rng: &mut Rng) -> SymmetricSolver {
    let (structure, values) = a.structure();
    let mut solver = SymmetricSolver::new(structure.clone());
    let inertia = solver.factorize(&values).unwrap();
    let (pos, neg, zero) = inertia_reference(a);
    assert_eq!(zero, 0, "the test matrix should be nonsingular");
    assert_eq!((inertia.positive, inertia.negative), (pos, neg), "inertia of a matrix of order {}", a.n);
    let x_true: Vec<f64> = (0..a.n).map(|_| rng.symmetric()).collect();
    let mut b = vec![0.0; a.n];
    structure.multiply(&values, &x_true, &mut b);
    let report = solver.solve(&mut b).unwrap();
    assert!(report.normwise_error < 1e-15, "normwise backward error {:e}", report.normwise_error);
    solver
}

#[test]
fn inertia_and_solutions_match_dense_references_on_chain_kkt_matrices() {
    let mut rng = Rng(7);
    for (links, width, dense, scales) in
        [(1, 2, 0, 0.0), (3, 3, 1, 2.0), (10, 4, 3, 4.0), (40, 5, 4, 8.0), (120, 4, 5, 12.0)]
    {
        let a = chain_kkt(&mut rng, links, width, dense, scales);
        let solver = check_solves(&a, &mut rng);
        // Shuffled numbering: the ordering must find the band again.
        let mut label: Vec<usize> = (0..a.n).collect();
        for i in (1..a.n).rev() {
            label.swap(i, rng.below(i + 1));
        }
        let shuffled = check_solves(&a.permuted(&label), &mut rng);
        let (front, again) = (solver.analysis().predicted_front(), shuffled.analysis().predicted_front());
        assert!(again <= 2 * front + 4, "shuffled front {again} against {front} (links {links})");
    }
}

#[test]
fn fronts_stay_narrow_on_long_chains() {
    let mut rng = Rng(11);
    let a = chain_kkt(&mut rng, 2000, 4, 5, 6.0);
    let (structure, values) = a.structure();
    let mut solver = SymmetricSolver::new(structure);
    solver.factorize(&values).unwrap();
    let stats = solver.stats().unwrap();
    assert_eq!(solver.analysis().dense_rows(), 5);
    assert!(stats.largest_front < 40, "front {} for a chain of 2000 links", stats.largest_front);
}

/// From [`SPLIT_FROM`] variables on, the sweep of a chain is cut in two halves, swept from the
/// two ends, and a root where they meet. On a chain KKT matrix of order 10 005 whose values drift
/// (so that the later factorisations replay the pivots of the one before): the split has the
/// inertia of the single sweep (both are exact) and solves to round-off; on one thread or two, the
/// same statistics and the same solutions to the bit; and its fronts (the root's too) stay narrow.
#[test]
fn a_split_sweep_agrees_with_one_sweep_and_is_the_same_on_one_thread_or_two() {
    let mut rng = Rng(13);
    let base = chain_kkt(&mut rng, 2000, 4, 5, 6.0);
    assert!(base.n >= SPLIT_FROM);
    let structure = base.structure().0;
    let solver =
        |split, two_threads| SymmetricSolver::with_options(structure.clone(), SweepOptions { split, two_threads });
    let (mut single, mut one, mut two) = (solver(false, false), solver(true, false), solver(true, true));
    assert!(!single.analysis().is_split() && one.analysis().is_split() && two.analysis().is_split());
    for round in 0..3 {
        let mut upper = base.clone();
        for v in upper.entries.values_mut() {
            *v *= 1.0 + 0.05 * f64::from(round) * rng.symmetric();
        }
        let values = upper.structure().1;
        let inertia = single.factorize(&values).unwrap();
        let x_true: Vec<f64> = (0..upper.n).map(|_| rng.symmetric()).collect();
        let mut b = vec![0.0; upper.n];
        structure.multiply(&values, &x_true, &mut b);
        let mut solutions = Vec::new();
        for solver in [&mut single, &mut one, &mut two] {
            assert_eq!(solver.factorize(&values).unwrap(), inertia, "round {round}");
            let mut x = b.clone();
            let report = solver.solve(&mut x).unwrap();
            assert!(report.normwise_error < 1e-15, "round {round}: {report:?}");
            solutions.push(x);
        }
        assert_eq!(solutions[1], solutions[2], "round {round}: one thread and two");
        let (stats_one, stats_two) = (one.stats().unwrap(), two.stats().unwrap());
        assert_eq!(stats_one, stats_two, "round {round}");
        assert!(stats_two.largest_front < 40, "round {round}: front {}", stats_two.largest_front);
        if round > 0 {
            assert!(stats_two.replayed * 10 > stats_two.pivots * 9, "round {round}: {stats_two:?}");
        }
    }
}

#[test]
fn random_sparse_symmetric_matrices() {
    let mut rng = Rng(3);
    for n in [1, 2, 5, 17, 60] {
        for _ in 0..20 {
            let mut a = Upper { n, ..Default::default() };
            for i in 0..n {
                a.add(i, i, if rng.uniform() < 0.3 { 0.0 } else { rng.symmetric() });
                for _ in 0..2 {
                    let j = rng.below(n);
                    a.add(i, j, rng.symmetric());
                }
            }
            let (_, _, zero) = inertia_reference(&a);
            let cond_ok = {
                let eig = a.dense().self_adjoint_eigenvalues(Side::Lower).unwrap();
                let big = eig.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                let small = eig.iter().fold(f64::INFINITY, |m, v| m.min(v.abs()));
                small > 1e-8 * big
            };
            if zero == 0 && cond_ok {
                check_solves(&a, &mut rng);
            }
        }
    }
}

#[test]
fn a_rank_deficient_constraint_block_is_singular() {
    // [[I, Jᵀ], [J, 0]] with two equal rows of J.
    let mut a = Upper { n: 5, ..Default::default() };
    for i in 0..3 {
        a.add(i, i, 1.0);
    }
    for (row, coefficients) in [(3, [1.0, 2.0, 0.0]), (4, [1.0, 2.0, 0.0])] {
        a.add(row, row, 0.0);
        for (j, c) in coefficients.iter().enumerate() {
            if *c != 0.0 {
                a.add(row, j, *c);
            }
        }
    }
    let (structure, values) = a.structure();
    let mut solver = SymmetricSolver::new(structure);
    assert!(matches!(solver.factorize(&values), Err(KktError::Singular { .. })));
    assert_eq!(solver.solve(&mut [0.0; 5]), Err(KktError::NotFactorized));
}

#[test]
fn pardiso_phases_analyse_factorise_solve_and_release() {
    // The 3×3 KKT matrix [[4, 1, 1], [1, 3, 0], [1, 0, 0]] (upper triangle, 1-based rows).
    let ia = [1, 4, 5, 5];
    let ja = [1, 2, 3, 2];
    let a = [4.0, 1.0, 1.0, 3.0];
    let (mut iparm, mut dparm) = ([0i32; PARAMETERS], [0.0; PARAMETERS]);
    assert_eq!(pardiso::init(-2, &mut iparm, &mut dparm), error::NONE);
    assert_eq!(pardiso::init(11, &mut iparm, &mut dparm), error::INPUT);
    iparm[5] = 1;
    let mut state = State::default();
    let call = |state: &mut State, phase, b: &mut [f64], iparm: &mut [i32; PARAMETERS]| {
        let mut x = vec![0.0; b.len()];
        state.call(Call { phase, mtype: -2, n: 3, nrhs: 1, a: &a, ia: &ia, ja: &ja, iparm, b, x: &mut x, msglvl: 0 })
    };
    let mut b = [6.0, 4.0, 1.0]; // A [1, 1, 1]
    assert_eq!(call(&mut state, 22, &mut b, &mut iparm), error::INPUT, "a factorisation before the analysis");
    assert_eq!(call(&mut state, 11, &mut b, &mut iparm), error::NONE);
    assert_eq!(call(&mut state, 22, &mut b, &mut iparm), error::NONE);
    assert_eq!((iparm[21], iparm[22], iparm[13]), (2, 1, 0));
    assert_eq!(call(&mut state, 33, &mut b, &mut iparm), error::NONE);
    for v in b {
        assert!((v - 1.0).abs() < 1e-15);
    }
    assert_eq!(call(&mut state, -1, &mut b, &mut iparm), error::NONE);
    assert_eq!(call(&mut state, 33, &mut b, &mut iparm), error::INPUT, "a solve after release");
}

/// Reads a matrix in the format `SPINE_KKT_DUMP` writes: the order, then `ia`, `ja` and `a` as
/// lists, one per line.
fn read_dump(text: &str) -> (Upper, Structure, Vec<f64>) {
    let dump = Dump::parse(text).unwrap();
    let structure = dump.structure().unwrap();
    let mut upper = Upper { n: dump.n, ..Default::default() };
    for (r, c, e) in structure.entries() {
        upper.add(r, c, dump.a[e]);
    }
    (upper, structure, dump.a)
}

/// A KKT matrix Ipopt factorised in a cold solve of the scaled N = 100 case of `bench-peers`
/// (order 1003, 5 dense rows; recorded with `SPINE_KKT_DUMP`). Its angles have diagonals near 1e-7
/// and their largest entries in the slider row: before the dense rows were kept out of the pivot
/// tests they all waited for it, and the front grew to 146 (13 ms). Now the front stays near the
/// band, the inertia is that of the dense eigenvalues, and the solution is refined to round-off.
#[test]
fn a_recorded_eq33_kkt_matrix_keeps_a_narrow_front_and_exact_inertia() {
    let (upper, structure, values) = read_dump(include_str!("data/eq33-n100-kkt.txt"));
    let mut solver = SymmetricSolver::new(structure.clone());
    let inertia = solver.factorize(&values).unwrap();
    assert_eq!(solver.analysis().dense_rows(), 5);
    let (pos, neg, zero) = inertia_reference(&upper);
    assert_eq!(zero, 0);
    assert_eq!((inertia.positive, inertia.negative), (pos, neg));
    let stats = solver.stats().unwrap();
    assert!(stats.largest_front <= 2 * solver.analysis().predicted_front(), "front {}", stats.largest_front);
    let mut rng = Rng(17);
    let x_true: Vec<f64> = (0..upper.n).map(|_| rng.symmetric()).collect();
    let mut b = vec![0.0; upper.n];
    structure.multiply(&values, &x_true, &mut b);
    let report = solver.solve(&mut b).unwrap();
    assert!(report.normwise_error < 1e-15, "{report:?}");
}

/// Factorises `values` (of `upper`) with `solver`, keeping what it recorded before: the inertia
/// must be `(positive, negative)` and a solve must reach round-off. Returns the statistics.
fn refactorize_checked(
    solver: &mut SymmetricSolver,
    upper: &Upper,
    values: &[f64],
    (positive, negative): (usize, usize),
    rng: &mut Rng,
) -> spine_kkt::FactorStats {
    let inertia = solver.factorize(values).unwrap();
    assert_eq!((inertia.positive, inertia.negative), (positive, negative));
    let x_true: Vec<f64> = (0..upper.n).map(|_| rng.symmetric()).collect();
    let mut b = vec![0.0; upper.n];
    upper.structure().0.multiply(values, &x_true, &mut b);
    let report = solver.solve(&mut b).unwrap();
    assert!(report.normwise_error < 1e-15, "{report:?}");
    solver.stats().unwrap()
}

/// Ipopt factorises matrices of one structure with new values at every iteration, and the solver
/// replays the pivots of the factorisation before, each tested again. On a sequence of chain KKT
/// matrices whose values drift, jump by a diagonal shift (Ipopt's inertia correction) and lose
/// one pivot outright, every factorisation has the inertia of the dense eigenvalues and solves to
/// round-off; the same values give the same factor to the bit, replayed or searched; a drift
/// replays nearly every pivot; the lost pivot is searched for near it and the rest replayed.
#[test]
fn replayed_pivot_sequences_keep_exact_inertia_and_search_where_a_pivot_fails() {
    let mut rng = Rng(23);
    let base = chain_kkt(&mut rng, 60, 4, 3, 6.0);
    let (structure, values) = base.structure();
    let mut solver = SymmetricSolver::new(structure.clone());
    let check = |solver: &mut SymmetricSolver, upper: &Upper, values: &[f64], rng: &mut Rng| {
        let (pos, neg, zero) = inertia_reference(upper);
        assert_eq!(zero, 0);
        refactorize_checked(solver, upper, values, (pos, neg), rng)
    };
    let first = check(&mut solver, &base, &values, &mut rng);
    assert_eq!(first.replayed, 0, "nothing to replay at the first factorisation");

    // The same values: every pivot replayed, and the factor is the searched one to the bit (the
    // searched one with the same history, as the scaling starts from the factorisation before).
    let again = check(&mut solver, &base, &values, &mut rng);
    assert_eq!((again.replayed, again.pivots), (first.pivots, first.pivots));
    let mut searched = SymmetricSolver::new(structure.clone());
    searched.factorize(&values).unwrap();
    searched.forget_pivot_sequence();
    searched.factorize(&values).unwrap();
    assert_eq!(searched.stats().unwrap().replayed, 0);
    let b: Vec<f64> = (0..base.n).map(|i| (i as f64).cos()).collect();
    let (mut x_replayed, mut x_searched) = (b.clone(), b.clone());
    solver.solve(&mut x_replayed).unwrap();
    searched.solve(&mut x_searched).unwrap();
    assert_eq!(x_replayed, x_searched);

    // Drift, then diagonal shifts of the variables' block (as Ipopt's δ_w), then drift again.
    let variables = 60 * 4;
    let mut replayed = 0;
    let mut pivots = 0;
    for (t, shift) in [0.0, 0.0, 1e-4, 1.0, 1e2, 0.0, 0.0].into_iter().enumerate() {
        let mut upper = base.clone();
        for ((i, j), v) in upper.entries.iter_mut() {
            *v *= 1.0 + 0.02 * rng.symmetric();
            if i == j && *i < variables {
                *v += shift;
            }
        }
        let (_, values) = upper.structure();
        let stats = check(&mut solver, &upper, &values, &mut rng);
        if t < 2 {
            assert!(
                stats.replayed * 20 >= stats.pivots * 19,
                "a 2 % drift: {} of {} replayed",
                stats.replayed,
                stats.pivots
            );
        }
        replayed += stats.replayed;
        pivots += stats.pivots;
    }
    assert!(replayed * 10 >= pivots * 9, "{replayed} of {pivots} pivots replayed");

    // The pivots of the chain's middle lost: the couplings among four variables there scaled up
    // by 1e4, so that no diagonal among them passes as a 1×1 pivot.
    let (_, values) = base.structure();
    check(&mut solver, &base, &values, &mut rng);
    let mut upper = base.clone();
    for ((i, j), v) in upper.entries.iter_mut() {
        if i != j && (30 * 4..31 * 4).contains(i) && (30 * 4..31 * 4).contains(j) {
            *v *= 1e4;
        }
    }
    let (_, values) = upper.structure();
    let stats = check(&mut solver, &upper, &values, &mut rng);
    assert!(stats.replayed > 0 && stats.replayed < stats.pivots, "{} of {} replayed", stats.replayed, stats.pivots);
    assert!(stats.replayed * 10 >= stats.pivots * 8, "{} of {} replayed", stats.replayed, stats.pivots);
}

/// The scaling starts from the factorisation before; where the values' magnitudes jump (rows
/// and columns scaled by 1e6 and 1e-6, which keeps the inertia by Sylvester's law), the passes
/// continue until it has settled: the inertia stays exact and solves reach round-off.
#[test]
fn the_scaling_follows_a_jump_in_magnitudes() {
    let mut rng = Rng(5);
    let base = chain_kkt(&mut rng, 40, 4, 3, 6.0);
    let (structure, values) = base.structure();
    let mut solver = SymmetricSolver::new(structure.clone());
    let (pos, neg, _) = inertia_reference(&base);
    let first = solver.factorize(&values).unwrap();
    assert_eq!((first.positive, first.negative), (pos, neg));
    assert_eq!(solver.stats().unwrap().scaling_passes, 3, "from S = I");
    solver.factorize(&values).unwrap();
    assert_eq!(solver.stats().unwrap().scaling_passes, 1, "the same values: settled after one pass");
    let d = |i: usize| match i % 7 {
        0 => 1e6,
        3 => 1e-6,
        _ => 1.0,
    };
    for round in 0..3 {
        let mut upper = base.clone();
        for ((i, j), v) in upper.entries.iter_mut() {
            *v *= d(*i + round) * d(*j + round);
        }
        let (_, values) = upper.structure();
        let stats = refactorize_checked(&mut solver, &upper, &values, (pos, neg), &mut rng);
        assert!(stats.scaling_passes > 1, "round {round}: a jump takes more than one pass");
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 64, ..Default::default() })]

    /// Any sequence of value changes on a chain KKT matrix of fixed structure, mild or wild (each
    /// entry scaled by `1 + spread · u`, `u` uniform in [−1, 1], so entries may change sign and
    /// pivots vanish): every factorisation, replayed or searched, has the inertia of the dense
    /// eigenvalues and solves to round-off.
    #[test]
    fn replay_keeps_exact_inertia_under_any_value_changes(
        seed in 0u64..1_000_000,
        links in 3usize..30,
        spreads in proptest::collection::vec(proptest::sample::select(vec![0.0, 0.01, 0.3, 2.0]), 1..6),
    ) {
        let mut rng = Rng(seed);
        let base = chain_kkt(&mut rng, links, 3, 2, 4.0);
        let (structure, _) = base.structure();
        let mut solver = SymmetricSolver::new(structure.clone());
        for spread in spreads {
            let mut upper = base.clone();
            for v in upper.entries.values_mut() {
                *v *= 1.0 + spread * rng.symmetric();
            }
            let (pos, neg, zero) = inertia_reference(&upper);
            let well_posed = {
                let eig = upper.dense().self_adjoint_eigenvalues(Side::Lower).unwrap();
                let big = eig.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                let small = eig.iter().fold(f64::INFINITY, |m, v| m.min(v.abs()));
                zero == 0 && small > 1e-8 * big
            };
            if !well_posed {
                continue;
            }
            let (_, values) = upper.structure();
            let inertia = solver.factorize(&values).unwrap();
            proptest::prop_assert_eq!((inertia.positive, inertia.negative), (pos, neg));
            let x_true: Vec<f64> = (0..upper.n).map(|_| rng.symmetric()).collect();
            let mut b = vec![0.0; upper.n];
            structure.multiply(&values, &x_true, &mut b);
            let report = solver.solve(&mut b).unwrap();
            proptest::prop_assert!(report.normwise_error < 1e-14, "{:?}", report);
        }
    }
}
