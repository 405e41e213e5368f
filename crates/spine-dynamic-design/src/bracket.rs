//! A bracketing root search on one scalar: Illinois regula falsi with a bisection step where an end
//! has no finite value. The uniform starts of eq. (35) (one common `ln C`) and of eq. (37) (one
//! common `log10 K`) use it.

/// The root of `f` in `[lo, hi]`, where `f(lo) = ends.0 < 0 ≤ ends.1 = f(hi)`. `f` may return `+∞`
/// or `−∞` for a point whose side is known but whose value is not (a response that does not rise,
/// a design that buckles): the next point is then the midpoint. Stops when `done(f(x))` or when
/// the bracket is narrower than `width` (then the midpoint); at most 60 evaluations.
pub(crate) fn illinois(
    (mut lo, mut hi): (f64, f64),
    mut ends: (f64, f64),
    f: &mut dyn FnMut(f64) -> f64,
    done: &dyn Fn(f64) -> bool,
    width: f64,
) -> f64 {
    let mut side = 0i8;
    let mut x = 0.5 * (lo + hi);
    for _ in 0..60 {
        x = match ends {
            (a, b) if a.is_finite() && b.is_finite() && b > a => {
                (lo - a * (hi - lo) / (b - a)).clamp(lo + 1e-3 * (hi - lo), hi - 1e-3 * (hi - lo))
            }
            _ => 0.5 * (lo + hi),
        };
        let r = f(x);
        if done(r) {
            break;
        }
        if r < 0.0 {
            (lo, ends.0) = (x, r);
            // Illinois: the end that stayed twice in a row counts half.
            if side == -1 {
                ends.1 *= 0.5;
            }
            side = -1;
        } else {
            (hi, ends.1) = (x, r);
            if side == 1 {
                ends.0 *= 0.5;
            }
            side = 1;
        }
        if hi - lo < width {
            x = 0.5 * (lo + hi);
            break;
        }
    }
    x
}

#[cfg(test)]
mod tests {
    use super::illinois;

    #[test]
    fn finds_a_root_and_bisects_past_ends_without_values() {
        let mut calls = 0;
        let root = illinois(
            (0.0, 3.0),
            (-2.0, 7.0),
            &mut |x| {
                calls += 1;
                x * x - 2.0
            },
            &|r| r.abs() < 1e-12,
            1e-14,
        );
        assert!((root - 2f64.sqrt()).abs() < 1e-12 && calls < 20, "{root} after {calls}");
        // The upper end has no value (+∞): the first step bisects.
        let mut first = None;
        let root = illinois(
            (0.0, 4.0),
            (-2.0, f64::INFINITY),
            &mut |x| {
                first.get_or_insert(x);
                if x > 3.0 {
                    f64::INFINITY
                } else {
                    x * x - 2.0
                }
            },
            &|r| r.abs() < 1e-12,
            1e-14,
        );
        assert_eq!(first, Some(2.0));
        assert!((root - 2f64.sqrt()).abs() < 1e-12);
    }
}
