//! The extremes of a periodic trace: the change from one period to the next, the local minima
//! refined on the dense output, and the golden-section search that refines them.

use crate::integrator::Trajectory;

/// The largest difference of two periods' end-displacement traces, as a fraction of the swing of
/// `trace`.
pub(super) fn relative_change(trace: &[f64], previous: &[f64]) -> f64 {
    let swing =
        trace.iter().cloned().fold(f64::NEG_INFINITY, f64::max) - trace.iter().cloned().fold(f64::INFINITY, f64::min);
    let diff = trace.iter().zip(previous).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    diff / swing.max(1e-300)
}

/// The local minima of `x` over a trajectory, lowest first, as `(value, time)`, and the maximum:
/// from its step points and `dense` equal intervals of its span, each interior minimum of those
/// points refined by golden-section search on the dense output between its two neighbours.
pub(super) fn extremes(traj: &Trajectory, x_of: &dyn Fn(&[f64]) -> f64, dense: usize) -> (Vec<(f64, f64)>, f64) {
    let (t_start, t_stop) = traj.span();
    let mut points: Vec<(f64, f64)> = (0..=dense)
        .map(|k| {
            let t = t_start + (t_stop - t_start) * k as f64 / dense as f64;
            (t, x_of(&traj.value(t)))
        })
        .chain(traj.points().map(|(t, y)| (t, x_of(y))))
        .collect();
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    points.dedup_by(|a, b| a.0 == b.0);
    let max = points.iter().fold(f64::NEG_INFINITY, |m, p| m.max(p.1));
    let last = points.len() - 1;
    let mut minima: Vec<(f64, f64)> = (0..=last)
        .filter(|&k| (k == 0 || points[k].1 < points[k - 1].1) && (k == last || points[k].1 <= points[k + 1].1))
        .map(|k| {
            if k == 0 || k == last {
                return (points[k].1, points[k].0);
            }
            let (t, x) = golden_minimum(points[k - 1].0, points[k + 1].0, &|t| x_of(&traj.value(t)));
            if x < points[k].1 {
                (x, t)
            } else {
                (points[k].1, points[k].0)
            }
        })
        .collect();
    minima.sort_by(|a, b| a.0.total_cmp(&b.0));
    if minima.is_empty() {
        // A constant trace: its start.
        minima.push((points[0].1, points[0].0));
    }
    (minima, max)
}

/// The minimiser of a unimodal `f` on `[a, b]` by golden-section search to round-off in `t`, and
/// its value.
fn golden_minimum(mut a: f64, mut b: f64, f: &dyn Fn(f64) -> f64) -> (f64, f64) {
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - r * (b - a), a + r * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    while b - a > 4.0 * f64::EPSILON * b.abs().max(1.0) && d > c {
        if fc <= fd {
            (b, d, fd) = (d, c, fc);
            c = b - r * (b - a);
            fc = f(c);
        } else {
            (a, c, fc) = (c, d, fd);
            d = a + r * (b - a);
            fd = f(d);
        }
    }
    if fc <= fd {
        (c, fc)
    } else {
        (d, fd)
    }
}
