//! The smallest singular value of a small dense matrix (LICQ's measure: the active rows'
//! Jacobian on the free variables), without the others and without squaring it: Householder
//! bidiagonalisation (Golub–Kahan), then multisection on the Sturm count of the bidiagonal's
//! Golub–Kahan form, the symmetric tridiagonal matrix with zero diagonal whose eigenvalues are
//! `±σ_i`. Its absolute error is a few `ε ‖A‖`.
//!
//! The Gram matrix `A Aᵀ` (used here until 2026-11-28) squares the condition: `σ_min²` then
//! carries an absolute error of about `ε ‖A‖²`, and at design10's optimum (`‖A‖` about 1e4,
//! `σ_min` about 3e-4) `σ_min` came out 0. At design10's size (34 × 34) this costs about as much
//! as that Gram route did.

/// The smallest singular value of the `rows × cols` matrix `a` (row-major) with `rows ≥ cols`;
/// `a` is overwritten. Zero for an empty matrix.
pub(crate) fn smallest_singular_value(a: &mut [f64], rows: usize, cols: usize) -> f64 {
    assert!(a.len() == rows * cols && rows >= cols, "a tall matrix");
    if cols == 0 {
        return 0.0;
    }
    let (d, e) = bidiagonalise(a, rows, cols);
    // The Golub–Kahan form: zero diagonal, off-diagonal d₀, e₀, d₁, e₁, …, d_{n−1}.
    let off: Vec<f64> = (0..2 * cols - 1).map(|t| if t % 2 == 0 { d[t / 2] } else { e[t / 2] }).collect();
    let bound = off.iter().fold(0.0f64, |m, v| m.max(v.abs())) * 2.0;
    // Its eigenvalues are −σ_i (all `cols` below any positive shift) and +σ_i: σ_min is where
    // the count below first exceeds `cols`.
    smallest_with_count_above(&vec![0.0; 2 * cols], &off, cols, 0.0, bound).max(0.0)
}

/// The reflector `H = I − τ v vᵀ` with `H x = α e₁` for the `x` held in `v` (overwritten with
/// `v`): `(α, τ)`, `τ = 0` for `x = 0`.
fn reflector(v: &mut [f64]) -> (f64, f64) {
    let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    if norm == 0.0 {
        return (0.0, 0.0);
    }
    let x0 = v[0];
    let alpha = if x0 > 0.0 { -norm } else { norm };
    v[0] -= alpha;
    // τ = 2 / vᵀv, vᵀv = 2 (‖x‖² − x₀ α).
    (alpha, 1.0 / (norm * norm - x0 * alpha))
}

/// Householder bidiagonalisation `a = U B Vᵀ` of the `m × n` matrix `a` (`m ≥ n`, values only):
/// `B`'s diagonal (`n`) and superdiagonal (`n − 1`).
fn bidiagonalise(a: &mut [f64], m: usize, n: usize) -> (Vec<f64>, Vec<f64>) {
    let (mut d, mut e) = (vec![0.0; n], vec![0.0; n.saturating_sub(1)]);
    let (mut v, mut w) = (vec![0.0; m.max(n)], vec![0.0; m.max(n)]);
    for j in 0..n {
        // From the left: column j below the diagonal onto d_j e₁; then the columns right of j.
        let v = &mut v[..m - j];
        for (t, i) in (j..m).enumerate() {
            v[t] = a[i * n + j];
        }
        let (alpha, tau) = reflector(v);
        d[j] = alpha;
        if tau != 0.0 && j + 1 < n {
            let w = &mut w[..n - j - 1];
            w.fill(0.0);
            for (t, i) in (j..m).enumerate() {
                let row = &a[i * n + j + 1..(i + 1) * n];
                w.iter_mut().zip(row).for_each(|(wc, b)| *wc += v[t] * b);
            }
            for (t, i) in (j..m).enumerate() {
                let row = &mut a[i * n + j + 1..(i + 1) * n];
                row.iter_mut().zip(w.iter()).for_each(|(b, wc)| *b -= tau * v[t] * wc);
            }
        }
        if j + 1 >= n {
            continue;
        }
        // From the right: row j right of the superdiagonal onto e_j e₁; then the rows below j.
        let v = &mut v[..n - j - 1];
        v.copy_from_slice(&a[j * n + j + 1..(j + 1) * n]);
        let (alpha, tau) = reflector(v);
        e[j] = alpha;
        if tau != 0.0 {
            for i in j + 1..m {
                let row = &mut a[i * n + j + 1..(i + 1) * n];
                let s = tau * row.iter().zip(v.iter()).map(|(b, x)| b * x).sum::<f64>();
                row.iter_mut().zip(v.iter()).for_each(|(b, x)| *b -= s * x);
            }
        }
    }
    (d, e)
}

/// Shifts per pass of [`counts_below`]: independent recurrences the processor runs side by side
/// (one Sturm count is a chain of dependent divisions, so eight cost little more than one).
const LANES: usize = 8;

/// How many eigenvalues of the symmetric tridiagonal matrix lie below each shift `sigma[l]`
/// (Sylvester's law: the negative pivots of `T − σ I = L D Lᵀ`); `off2` holds the squared
/// off-diagonal entries.
fn counts_below(diagonal: &[f64], off2: &[f64], sigma: &[f64; LANES]) -> [usize; LANES] {
    let mut count = [0; LANES];
    let mut q: [f64; LANES] = std::array::from_fn(|l| diagonal[0] - sigma[l]);
    for l in 0..LANES {
        count[l] += usize::from(q[l] < 0.0);
    }
    for (d, e2) in diagonal[1..].iter().zip(off2) {
        for l in 0..LANES {
            // A zero pivot is nudged to the smallest normal number (the standard guard).
            let previous = if q[l] == 0.0 { f64::MIN_POSITIVE } else { q[l] };
            q[l] = d - sigma[l] - e2 / previous;
            count[l] += usize::from(q[l] < 0.0);
        }
    }
    count
}

/// The smallest `σ` in `[lo, hi]` with more than `count` eigenvalues of the symmetric
/// tridiagonal matrix below it (its eigenvalue number `count` from the bottom), by multisection
/// (each pass splits the interval at [`LANES`] shifts) to an absolute width of `4 ε` times the
/// interval's scale.
fn smallest_with_count_above(diagonal: &[f64], off: &[f64], count: usize, mut lo: f64, mut hi: f64) -> f64 {
    let scale = lo.abs().max(hi.abs()).max(f64::MIN_POSITIVE);
    let off2: Vec<f64> = off.iter().map(|e| e * e).collect();
    while hi - lo > 4.0 * f64::EPSILON * scale {
        let width = hi - lo;
        let sigma: [f64; LANES] = std::array::from_fn(|l| lo + width * (l + 1) as f64 / (LANES + 1) as f64);
        if sigma.iter().all(|&s| s <= lo || s >= hi) {
            break;
        }
        let counts = counts_below(diagonal, &off2, &sigma);
        // The eigenvalue lies between the last shift with at most `count` below and the first
        // with more.
        match counts.iter().position(|&c| c > count) {
            Some(0) => hi = sigma[0],
            Some(l) => (lo, hi) = (sigma[l - 1], sigma[l]),
            None => lo = sigma[LANES - 1],
        }
        if hi - lo >= width {
            break;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use spine_model::rng::SplitMix64;

    /// Against nalgebra's SVD: random tall and square matrices, a nearly dependent row
    /// (`σ_min ≈ 1e-7`), rows scaled as design10's (entries to 1e4 beside a `σ_min` of about
    /// 1e-4, where the Gram matrix's eigenvalue gives 0), a diagonal matrix (no reflection
    /// needed), and the sizes 1, 2 and 3 where the reduction does little or nothing.
    #[test]
    fn the_smallest_singular_value_is_nalgebras() {
        let mut rng = SplitMix64::new(11);
        for k in [1usize, 2, 3, 7, 34, 60] {
            for extra in [0usize, 5] {
                for kind in 0..4 {
                    let (rows, cols) = (k + extra, k);
                    let mut b = nalgebra::DMatrix::<f64>::from_fn(rows, cols, |_, _| rng.uniform(-1.0, 1.0));
                    match kind {
                        1 if k > 1 => {
                            // The last column nearly repeats the first.
                            let first = b.column(0).clone_owned();
                            b.set_column(k - 1, &(first * 1.0000001));
                        }
                        2 if k > 1 => {
                            // Entries of 1e4, the last column the first but for 1e-4.
                            b.scale_mut(1e4);
                            let nudge = nalgebra::DVector::from_fn(rows, |_, _| rng.uniform(-1e-4, 1e-4));
                            let first = b.column(0).clone_owned();
                            b.set_column(k - 1, &(first + nudge));
                        }
                        3 => {
                            b = nalgebra::DMatrix::<f64>::from_fn(
                                rows,
                                cols,
                                |i, j| if i == j { 3.0 - i as f64 } else { 0.0 },
                            )
                        }
                        _ => {}
                    }
                    let reference = b.clone().singular_values().min();
                    let mut flat: Vec<f64> = (0..rows * cols).map(|e| b[(e / cols, e % cols)]).collect();
                    let ours = smallest_singular_value(&mut flat, rows, cols);
                    let tolerance = 1e-14 * b.norm().max(1.0);
                    assert!(
                        (ours - reference).abs() <= tolerance,
                        "{rows} × {cols}, kind {kind}: {ours:e} vs {reference:e}"
                    );
                    if kind == 2 && k == 34 {
                        // The Gram matrix's smallest eigenvalue loses this σ_min (what this
                        // measure did until 2026-11-28).
                        let gram = &b.transpose() * &b;
                        let through_gram = gram.symmetric_eigenvalues().min().max(0.0).sqrt();
                        let error = (through_gram - reference).abs();
                        assert!(error > 1e3 * tolerance, "{rows} × {cols}: the Gram route's error {error:e}");
                    }
                }
            }
        }
    }
}
