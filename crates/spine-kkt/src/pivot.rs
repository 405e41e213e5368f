//! The pivot test of the frontal sweep ([`crate::factor`]): Bunch–Kaufman among the fully summed
//! variables, threshold and Duff–Reid tests where the partner is not summed yet, a test against
//! the dense rows, and the thresholds that relax while a variable waits.

use crate::front::Front;
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
pub(crate) fn choose(
    front: &Front,
    p: usize,
    summed: &[bool],
    border: usize,
    limits: Thresholds,
) -> Result<Choice, KktError> {
    let choice = choose_sparse(front, p, summed, border, limits.sparse)?;
    if border == 0 {
        return Ok(choice);
    }
    let dense_max = |col: usize| front.border_max(col, border);
    let ok = match choice {
        Choice::One(q) => front.at(q, q).abs() >= limits.border * dense_max(q),
        Choice::Two(a, b) => {
            let det = (front.at(a, a) * front.at(b, b) - front.at(a, b) * front.at(a, b)).abs();
            let size = front.at(a, a).abs().max(front.at(b, b).abs()).max(front.at(a, b).abs());
            det / size >= limits.border * dense_max(a).max(dense_max(b))
        }
        Choice::Delay => true,
    };
    Ok(if ok { choice } else { Choice::Delay })
}

/// The Bunch–Kaufman rule on the fully summed variable in slot `p`, restricted to fully summed
/// partners (see the module docs).
fn choose_sparse(front: &Front, p: usize, summed: &[bool], border: usize, u: f64) -> Result<Choice, KktError> {
    let a_pp = front.at(p, p).abs();
    let (gamma_p, r) = front.column_max(p, border);
    let Some(r) = r.filter(|_| gamma_p > SINGULAR) else {
        return if a_pp > SINGULAR {
            Ok(Choice::One(p))
        } else if border > 0 && front.column_max(p, 0).0 > SINGULAR {
            Ok(Choice::Delay)
        } else {
            Err(KktError::Singular { pivot: front.var[p] })
        };
    };
    if a_pp >= ALPHA * gamma_p {
        return Ok(Choice::One(p));
    }
    if !summed[front.var[r]] {
        if a_pp >= u * gamma_p {
            return Ok(Choice::One(p));
        }
        return Ok(summed_partner(front, p, summed, border, u).map_or(Choice::Delay, |q| Choice::Two(p, q)));
    }
    let (gamma_r, _) = front.column_max(r, border);
    if a_pp * gamma_r >= ALPHA * gamma_p * gamma_p {
        Ok(Choice::One(p))
    } else if front.at(r, r).abs() >= ALPHA * gamma_r {
        Ok(Choice::One(r))
    } else {
        Ok(Choice::Two(p, r))
    }
}

/// A 2×2 pivot of `p` with the fully summed row `q` of largest `|a_qp|`, if the block passes Duff
/// and Reid's threshold test: `|B⁻¹| (γ_p, γ_q)ᵀ ≤ (1/u, 1/u)`, with `γ` the largest entries of the
/// two columns outside the block.
fn summed_partner(front: &Front, p: usize, summed: &[bool], border: usize, u: f64) -> Option<usize> {
    let q = front
        .row(p)
        .iter()
        .zip(&front.var)
        .enumerate()
        .filter(|&(i, (_, &var))| i != p && summed[var] && var >= border)
        .max_by(|(_, (x, _)), (_, (y, _))| x.abs().total_cmp(&y.abs()))
        .map(|(i, _)| i)?;
    let (a, b, c) = (front.at(p, p), front.at(q, p), front.at(q, q));
    let det = a * c - b * b;
    if det.abs() <= SINGULAR * SINGULAR || det == 0.0 {
        return None;
    }
    let outside = |col: usize| {
        front.row(col).iter().zip(&front.var).enumerate().fold(0.0f64, |m, (i, (v, &var))| {
            if i != p && i != q && var >= border {
                m.max(v.abs())
            } else {
                m
            }
        })
    };
    let (gp, gq) = (outside(p), outside(q));
    let bound = 1.0 / u;
    let first = (c.abs() * gp + b.abs() * gq) / det.abs();
    let second = (b.abs() * gp + a.abs() * gq) / det.abs();
    (first <= bound && second <= bound).then_some(q)
}
