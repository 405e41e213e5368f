//! The pivot test of the frontal sweep ([`crate::factor`]): Bunch–Kaufman among the fully summed
//! variables, threshold and Duff–Reid tests where the partner is not summed yet, a test against
//! the dense rows, and the thresholds that relax while a variable waits.

use crate::front::{ColumnScan, Front};
use crate::KktError;

/// Bunch and Kaufman's α = (1 + √17)/8, which minimises the bound on element growth.
const ALPHA: f64 = 0.640_388_203_202_207_6;
/// The threshold `u` for a 1×1 pivot whose Bunch–Kaufman partner is not yet fully summed.
pub const THRESHOLD: f64 = 0.01;
/// A fully summed column of the scaled matrix with no entry above this is a zero column: the
/// matrix is singular (to working precision).
pub const SINGULAR: f64 = 1e-14;
/// The threshold of a pivot against the dense rows, which stay out of the Bunch–Kaufman tests
/// until the last step.
pub const BORDER_THRESHOLD: f64 = 1e-6;
/// A variable that has waited this many steps is tested with [`RELAXED_THRESHOLD`], and after
/// four times as many with [`LAST_RESORT_THRESHOLD`].
pub const PATIENCE: usize = 4;
/// The threshold for a variable that has waited [`PATIENCE`] steps; the dense rows no longer
/// take part in its test.
pub const RELAXED_THRESHOLD: f64 = 1e-4;
/// The threshold for a variable that has waited `4 PATIENCE` steps (the default of Ipopt's MA27
/// and MA57 pivot tolerance).
pub const LAST_RESORT_THRESHOLD: f64 = 1e-8;

/// The thresholds of one pivot test: `u` against the fully summed rows and against the dense
/// rows.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Thresholds {
    sparse: f64,
    border: f64,
}

impl Thresholds {
    /// For a variable that has waited `periods` times [`PATIENCE`] steps.
    pub(crate) fn after_waiting(periods: usize) -> Self {
        match periods {
            0 => Thresholds { sparse: THRESHOLD, border: BORDER_THRESHOLD },
            1..=3 => Thresholds { sparse: RELAXED_THRESHOLD, border: 0.0 },
            _ => Thresholds { sparse: LAST_RESORT_THRESHOLD, border: 0.0 },
        }
    }
}
/// The outcome of the pivot test on one fully summed variable.
pub(crate) enum Choice {
    One(usize),
    Two(usize, usize),
    Delay,
}

/// [`choose_sparse`], with the pivot it finds tested against the dense rows too: their entries
/// in the pivot's column(s) may exceed the pivot by at most `1/BORDER_THRESHOLD`; otherwise the
/// variable waits.
pub(crate) fn choose(front: &Front, p: usize, border: usize, limits: Thresholds) -> Result<Choice, KktError> {
    let (choice, dense_max) = choose_sparse(front, p, border, limits.sparse)?;
    if border == 0 {
        return Ok(choice);
    }
    let ok = match choice {
        Choice::One(q) => front.at(q, q).abs() >= limits.border * dense_max,
        Choice::Two(a, b) => {
            let det = (front.at(a, a) * front.at(b, b) - front.at(a, b) * front.at(a, b)).abs();
            let size = front.at(a, a).abs().max(front.at(b, b).abs()).max(front.at(a, b).abs());
            det / size >= limits.border * dense_max
        }
        Choice::Delay => true,
    };
    Ok(if ok { choice } else { Choice::Delay })
}

/// The Bunch–Kaufman rule on the fully summed variable in slot `p`, restricted to fully summed
/// partners (see the module docs), with the largest entry of the pivot's column(s) in the dense
/// rows.
fn choose_sparse(front: &Front, p: usize, border: usize, u: f64) -> Result<(Choice, f64), KktError> {
    let a_pp = front.at(p, p).abs();
    let column = front.scan(p, NONE, border);
    let gamma_p = column.largest;
    let Some(r) = column.row.filter(|_| gamma_p > SINGULAR) else {
        return if a_pp > SINGULAR {
            Ok((Choice::One(p), column.border))
        } else if border > 0 && gamma_p.max(column.border) > SINGULAR {
            Ok((Choice::Delay, 0.0))
        } else {
            Err(KktError::Singular { pivot: front.var[p] })
        };
    };
    if a_pp >= ALPHA * gamma_p {
        return Ok((Choice::One(p), column.border));
    }
    if !front.is_summed(r) {
        if a_pp >= u * gamma_p {
            return Ok((Choice::One(p), column.border));
        }
        return Ok(match summed_partner(front, p, &column, border, u) {
            Some((q, dense_q)) => (Choice::Two(p, q), column.border.max(dense_q)),
            None => (Choice::Delay, 0.0),
        });
    }
    let partner = front.scan(r, NONE, border);
    let gamma_r = partner.largest;
    if a_pp * gamma_r >= ALPHA * gamma_p * gamma_p {
        Ok((Choice::One(p), column.border))
    } else if front.at(r, r).abs() >= ALPHA * gamma_r {
        Ok((Choice::One(r), partner.border))
    } else {
        Ok((Choice::Two(p, r), column.border.max(partner.border)))
    }
}

/// How much the pivot in slot `p` (1×1) or slots `p, r` (2×2) lets entries grow: against the
/// sparse rows `γ_p / |a_pp|` for a 1×1 pivot and Duff and Reid's `max |B⁻¹| (γ_p, γ_r)ᵀ` for a
/// 2×2 block `B` (the test [`choose`] passes with `1/u`), and against the dense rows the inverse
/// of the ratio [`choose`] tests. `None` for a (numerically) singular pivot. The pivots' columns
/// must be loaded ([`Front::load`], `p` first).
pub(crate) fn growth(front: &Front, p: usize, r: Option<usize>, border: usize) -> Option<Growth> {
    match r {
        None => {
            let a_pp = front.at(p, p).abs();
            let (largest, dense) = front.loaded_maxima(0, NONE, border);
            (a_pp > SINGULAR).then(|| Growth { sparse: largest / a_pp, border: dense / a_pp })
        }
        Some(r) => {
            let (a, b, c) = (front.at(p, p).abs(), front.at(r, p).abs(), front.at(r, r).abs());
            let det = (front.at(p, p) * front.at(r, r) - front.at(r, p) * front.at(r, p)).abs();
            if det <= SINGULAR * SINGULAR {
                return None;
            }
            let ((gp, dense_p), (gr, dense_r)) = (front.loaded_maxima(0, r, border), front.loaded_maxima(1, p, border));
            let size = a.max(b).max(c);
            Some(Growth {
                sparse: (c * gp + b * gr).max(b * gp + a * gr) / det,
                border: dense_p.max(dense_r) * size / det,
            })
        }
    }
}

/// The growth measures of one pivot ([`growth`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Growth {
    pub sparse: f64,
    pub border: f64,
}

impl Growth {
    /// What a pivot search records for a pivot too small to measure: its replay must pass the
    /// threshold test alone.
    pub(crate) const THRESHOLD: Growth = Growth { sparse: 0.0, border: 0.0 };

    /// Whether a pivot of this growth may replay one chosen with `limits` and growth `chosen`: a
    /// growth within the threshold test, or within twice what the pivot search accepted (the
    /// Bunch–Kaufman choices among fully summed variables bound the growth of the whole
    /// factorisation, not of each pivot), and the test against the dense rows.
    pub(crate) fn replays(self, chosen: Growth, limits: Thresholds, border: usize) -> bool {
        self.sparse <= (1.0 / limits.sparse).max(2.0 * chosen.sparse)
            && (border == 0 || limits.border == 0.0 || self.border * limits.border <= 1.0)
    }
}

/// No row left out of a scan.
const NONE: usize = usize::MAX;

/// A 2×2 pivot of `p` with the fully summed row `q` of largest `|a_qp|`, if the block passes Duff
/// and Reid's threshold test: `|B⁻¹| (γ_p, γ_q)ᵀ ≤ (1/u, 1/u)`, with `γ` the largest entries of the
/// two columns outside the block; also the largest entry of column `q` in the dense rows.
///
/// Called only when the row `r` of `γ_p` is not fully summed, so `r ≠ q` and `γ_p` outside the
/// block is `column.largest`.
fn summed_partner(front: &Front, p: usize, column: &ColumnScan, border: usize, u: f64) -> Option<(usize, f64)> {
    let q = column.summed_row?;
    let (a, b, c) = (front.at(p, p), front.at(q, p), front.at(q, q));
    let det = a * c - b * b;
    if det.abs() <= SINGULAR * SINGULAR || det == 0.0 {
        return None;
    }
    let outside_q = front.scan(q, p, border);
    let (gp, gq) = (column.largest, outside_q.largest);
    let bound = 1.0 / u;
    let first = (c.abs() * gp + b.abs() * gq) / det.abs();
    let second = (b.abs() * gp + a.abs() * gq) / det.abs();
    (first <= bound && second <= bound).then_some((q, outside_q.border))
}
