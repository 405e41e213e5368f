//! The triangular solves with a sweep's pivots: `L⁻¹`, `D⁻¹` and `L⁻ᵀ`.

use super::{Pivot, StageFactor};

impl StageFactor {
    /// `y ← L⁻¹ y` for this stage's pivots.
    pub(crate) fn forward(&self, y: &mut [f64]) {
        for pivot in &self.pivots {
            match *pivot {
                Pivot::One { p, start, end, lower, .. } => {
                    let yp = y[p];
                    for (&i, &l) in self.index[start..end].iter().zip(&self.lower[lower..]) {
                        y[i] -= l * yp;
                    }
                }
                Pivot::Two { p, r, start, end, lower, .. } => {
                    let (yp, yr) = (y[p], y[r]);
                    for (e, &i) in self.index[start..end].iter().enumerate() {
                        let at = lower + 2 * e;
                        y[i] -= self.lower[at] * yp + self.lower[at + 1] * yr;
                    }
                }
            }
        }
    }

    /// `y ← D⁻¹ y` for this stage's pivots.
    pub(crate) fn diagonal(&self, y: &mut [f64]) {
        for pivot in &self.pivots {
            match *pivot {
                Pivot::One { p, inverse, .. } => y[p] *= inverse,
                Pivot::Two { p, r, inverse, .. } => {
                    let (yp, yr) = (y[p], y[r]);
                    y[p] = inverse[0][0] * yp + inverse[0][1] * yr;
                    y[r] = inverse[1][0] * yp + inverse[1][1] * yr;
                }
            }
        }
    }

    /// `y ← L⁻ᵀ y` for this stage's pivots.
    pub(crate) fn backward(&self, y: &mut [f64]) {
        for pivot in self.pivots.iter().rev() {
            match *pivot {
                Pivot::One { p, start, end, lower, .. } => {
                    let sum: f64 =
                        self.index[start..end].iter().zip(&self.lower[lower..]).map(|(&i, &l)| l * y[i]).sum();
                    y[p] -= sum;
                }
                Pivot::Two { p, r, start, end, lower, .. } => {
                    let (mut sp, mut sr) = (0.0, 0.0);
                    for (e, &i) in self.index[start..end].iter().enumerate() {
                        let at = lower + 2 * e;
                        sp += self.lower[at] * y[i];
                        sr += self.lower[at + 1] * y[i];
                    }
                    y[p] -= sp;
                    y[r] -= sr;
                }
            }
        }
    }
}
