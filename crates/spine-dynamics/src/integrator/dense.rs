//! Dense output (Radau IIA's collocation polynomial, or cubic Hermite, on each accepted step) and
//! event location.

use super::options::{Outcome, Stats};
use nalgebra::DMatrix;

/// One accepted step: the data of its interpolant.
#[derive(Clone, Debug)]
pub struct Interval {
    /// The collocation polynomial `y(t0 + x h) = y0 + Σ_k q_k x^{k+1}` of a Radau IIA step (its
    /// stage values interpolated, Hairer & Wanner's dense output), used for `y(t)` and `ẏ(t)` when
    /// present; otherwise the cubic Hermite interpolant of the ends. Sensitivities always use the
    /// Hermite form of `(S, Ṡ)`.
    pub collocation: Option<[Vec<f64>; 3]>,
    pub t0: f64,
    pub t1: f64,
    pub y0: Vec<f64>,
    pub y1: Vec<f64>,
    pub f0: Vec<f64>,
    pub f1: Vec<f64>,
    /// Sensitivities and their time derivatives at both ends (when requested).
    pub sens: Option<[DMatrix<f64>; 4]>,
}

/// Hermite basis `(h00, h10, h01, h11)` and derivatives at `s ∈ [0, 1]` of an interval of length `h`.
fn hermite(s: f64, h: f64) -> ([f64; 4], [f64; 4]) {
    let (s2, s3) = (s * s, s * s * s);
    (
        [2.0 * s3 - 3.0 * s2 + 1.0, (s3 - 2.0 * s2 + s) * h, -2.0 * s3 + 3.0 * s2, (s3 - s2) * h],
        [(6.0 * s2 - 6.0 * s) / h, 3.0 * s2 - 4.0 * s + 1.0, (-6.0 * s2 + 6.0 * s) / h, 3.0 * s2 - 2.0 * s],
    )
}

/// The sensitivities `(S, Ṡ)` at one end of a step.
pub(super) type SensitivityEnd = (DMatrix<f64>, DMatrix<f64>);

impl Interval {
    /// An accepted step from `(t0, y0, f0)` to `(t1, y1, f1)`; its sensitivities when propagated
    /// at both ends.
    pub(super) fn accepted(
        (t0, y0, f0): (f64, Vec<f64>, Vec<f64>),
        (t1, y1, f1): (f64, Vec<f64>, Vec<f64>),
        sensitivities: (Option<SensitivityEnd>, Option<SensitivityEnd>),
        collocation: Option<[Vec<f64>; 3]>,
    ) -> Self {
        let sens = match sensitivities {
            (Some((s0, sd0)), Some((s1, sd1))) => Some([s0, sd0, s1, sd1]),
            _ => None,
        };
        Self { collocation, t0, t1, y0, y1, f0, f1, sens }
    }

    /// A time inside the step, and so inside its smooth piece of `f` (steps never cross a
    /// breakpoint of the forcing): the `piece` argument of the system's functions on this step.
    pub fn piece(&self) -> f64 {
        0.5 * (self.t0 + self.t1)
    }

    /// The cubic Hermite weights `(b, ḃ)` of `(y₀, ẏ₀, y₁, ẏ₁)` at `t`.
    pub(super) fn weights(&self, t: f64) -> ([f64; 4], [f64; 4]) {
        let h = self.t1 - self.t0;
        hermite(((t - self.t0) / h).clamp(0.0, 1.0), h)
    }

    /// `y(t)` on this interval.
    pub fn value(&self, t: f64) -> Vec<f64> {
        let mut y = vec![0.0; self.y0.len()];
        self.value_into(t, &mut y);
        y
    }

    /// [`Self::value`] into `y` (of the state's length).
    pub fn value_into(&self, t: f64, y: &mut [f64]) {
        if let Some(q) = &self.collocation {
            let x = ((t - self.t0) / (self.t1 - self.t0)).clamp(0.0, 1.0);
            for (i, v) in y.iter_mut().enumerate() {
                *v = self.y0[i] + x * (q[0][i] + x * (q[1][i] + x * q[2][i]));
            }
            return;
        }
        let (b, _) = self.weights(t);
        for (i, v) in y.iter_mut().enumerate() {
            *v = b[0] * self.y0[i] + b[1] * self.f0[i] + b[2] * self.y1[i] + b[3] * self.f1[i];
        }
    }

    /// `ẏ(t)` of the interpolant.
    pub fn derivative(&self, t: f64) -> Vec<f64> {
        if let Some(q) = &self.collocation {
            let h = self.t1 - self.t0;
            let x = ((t - self.t0) / h).clamp(0.0, 1.0);
            return (0..self.y0.len()).map(|i| (q[0][i] + x * (2.0 * q[1][i] + x * 3.0 * q[2][i])) / h).collect();
        }
        let (_, d) = self.weights(t);
        (0..self.y0.len())
            .map(|i| d[0] * self.y0[i] + d[1] * self.f0[i] + d[2] * self.y1[i] + d[3] * self.f1[i])
            .collect()
    }

    /// `S(t) = ∂y(t)/∂p` on this interval.
    pub fn sensitivity(&self, t: f64) -> Option<DMatrix<f64>> {
        let (b, _) = self.weights(t);
        self.sens.as_ref().map(|[s0, sd0, s1, sd1]| s0 * b[0] + sd0 * b[1] + s1 * b[2] + sd1 * b[3])
    }

    /// Whether `sign0 · g(y(t)) > 0` for every `t` in `[from, t1]` by the event's Lipschitz bound:
    /// on the collocation polynomial `y_i(x) = y0_i + Σ_k q_ki x^{k+1}` (`x ∈ [0, 1]`) no component
    /// moves by more than `Σ_k |q_ki|`, so `g` moves by at most `Σ_i w_i Σ_k |q_ki|`. Needs the
    /// weights and the collocation polynomial (`false` without them). `y` is scratch.
    fn clear_of_zero(&self, from: f64, event: &EventFunction<'_>, sign0: f64, y: &mut [f64]) -> bool {
        let (Some(w), Some(q)) = (event.lipschitz, &self.collocation) else {
            return false;
        };
        self.value_into(from, y);
        let g0 = (event.g)(y) * sign0;
        let (mut reach, mut size) = (0.0, 0.0);
        for (i, &wi) in w.iter().enumerate() {
            if wi != 0.0 {
                reach += wi * (q[0][i].abs() + q[1][i].abs() + q[2][i].abs());
                size += wi * y[i].abs();
            }
        }
        // The margin covers the round-off of the scan's own evaluations of `y(t)` and `g`.
        g0 > reach * (1.0 + 1e-9) + 1e-11 * (g0.abs() + reach + size)
    }
}

/// A computed solution.
#[derive(Clone, Debug)]
pub struct Trajectory {
    /// The start `(t0, y0)` after projection (the trajectory when no step was accepted: a run
    /// stopped before its first step).
    pub start: (f64, Vec<f64>),
    pub intervals: Vec<Interval>,
    pub outcome: Outcome,
    pub stats: Stats,
}

/// A scalar event function `g(y)` whose sign changes are searched for ([`Trajectory::first_root`],
/// [`super::first_event`]), with its gradient.
#[derive(Clone, Copy)]
pub struct EventFunction<'a> {
    /// `g(y)`.
    pub g: &'a dyn Fn(&[f64]) -> f64,
    /// `∇g(y)`, for `dt/dp` and the Newton steps of [`super::first_event`].
    pub grad: &'a dyn Fn(&[f64]) -> Vec<f64>,
    /// Optional weights `w ≥ 0` with `|g(y) − g(z)| ≤ Σ_i w_i |y_i − z_i|` for all `y, z`: a step
    /// of the collocation dense output along which this bound keeps `g` from zero (with a margin
    /// for round-off) is not scanned. Wrong weights can miss roots; `None` scans every step.
    pub lipschitz: Option<&'a [f64]>,
}

impl<'a> EventFunction<'a> {
    /// `g` and `∇g`, every step scanned.
    pub fn new(g: &'a dyn Fn(&[f64]) -> f64, grad: &'a dyn Fn(&[f64]) -> Vec<f64>) -> Self {
        Self { g, grad, lipschitz: None }
    }

    /// With the Lipschitz weights [`Self::lipschitz`].
    pub fn with_lipschitz(self, weights: &'a [f64]) -> Self {
        Self { lipschitz: Some(weights), ..self }
    }
}

/// A located event: the first time `g(y(t))` reaches zero.
#[derive(Clone, Debug)]
pub struct Event {
    pub t: f64,
    pub y: Vec<f64>,
    /// `dt/dp` of the event time, when sensitivities were propagated.
    pub t_sensitivity: Option<Vec<f64>>,
}

impl Trajectory {
    /// Start and end times (equal when no step was accepted).
    pub fn span(&self) -> (f64, f64) {
        (self.start.0, self.intervals.last().map_or(self.start.0, |i| i.t1))
    }

    /// The accepted step whose interval holds `t` (`t0 < t ≤ t1`; the first or last step outside
    /// the span).
    pub(super) fn interval_at(&self, t: f64) -> Option<&Interval> {
        let k = self.intervals.partition_point(|iv| iv.t1 < t);
        self.intervals.get(k.min(self.intervals.len().saturating_sub(1)))
    }

    /// `y(t)` from the dense output (the start state when no step was accepted).
    pub fn value(&self, t: f64) -> Vec<f64> {
        self.interval_at(t).map_or_else(|| self.start.1.clone(), |iv| iv.value(t))
    }

    /// `S(t) = ∂y(t)/∂p` from the dense output, when sensitivities were propagated.
    pub fn sensitivity(&self, t: f64) -> Option<DMatrix<f64>> {
        self.interval_at(t).and_then(|iv| iv.sensitivity(t))
    }

    /// `S` at the last state reached (`None` without sensitivities or accepted steps).
    pub fn end_sensitivity(&self) -> Option<DMatrix<f64>> {
        self.intervals.last().and_then(|iv| iv.sens.as_ref()).map(|[_, _, s1, _]| s1.clone())
    }

    /// The last state reached.
    pub fn end(&self) -> &[f64] {
        self.intervals.last().map_or(&self.start.1, |iv| &iv.y1)
    }

    /// The accepted step points `(t, y)`, the start included.
    pub fn points(&self) -> impl Iterator<Item = (f64, &[f64])> {
        std::iter::once((self.start.0, self.start.1.as_slice()))
            .chain(self.intervals.iter().map(|iv| (iv.t1, iv.y1.as_slice())))
    }

    /// The first time after `after` where the scalar event function `g(y)` changes sign from its
    /// sign at `after`, located on the dense output to round-off (bisection refined by the secant
    /// rule). Each step is scanned at `SCAN` sub-points so that a crossing and return inside one step
    /// is not missed, unless the event's Lipschitz bound keeps `g` away from zero along the whole
    /// step ([`EventFunction::lipschitz`]; such a step has no root, so the result is the same). With
    /// sensitivities, also `dt/dp = −(∇g · S) / (∇g · ẏ)` at the root. The root of the
    /// interpolant, whose error does not follow the tolerance; [`super::first_event`] moves it onto
    /// the integration steps.
    pub fn first_root(&self, after: f64, event: &EventFunction<'_>) -> Option<Event> {
        const SCAN: usize = 8;
        let (g, grad) = (event.g, event.grad);
        let start = self.value(after);
        let sign0 = if g(&start) < 0.0 { -1.0 } else { 1.0 };
        let mut y = vec![0.0; start.len()];
        for iv in self.intervals.iter().filter(|iv| iv.t1 > after) {
            let lo0 = iv.t0.max(after);
            if iv.clear_of_zero(lo0, event, sign0, &mut y) {
                continue;
            }
            let mut prev = lo0;
            for k in 1..=SCAN {
                let t = lo0 + (iv.t1 - lo0) * k as f64 / SCAN as f64;
                iv.value_into(t, &mut y);
                if g(&y) * sign0 <= 0.0 {
                    let root = refine(prev, t, &|s| g(&iv.value(s)) * sign0);
                    let y = iv.value(root);
                    let t_sensitivity = iv.sensitivity(root).map(|s| {
                        let dg = grad(&y);
                        let rate: f64 = dg.iter().zip(iv.derivative(root)).map(|(a, b)| a * b).sum();
                        (0..s.ncols()).map(|p| -(0..s.nrows()).map(|i| dg[i] * s[(i, p)]).sum::<f64>() / rate).collect()
                    });
                    return Some(Event { t: root, y, t_sensitivity });
                }
                prev = t;
            }
        }
        None
    }
}

/// Root of `f` in `[a, b]` with `f(a) > 0 ≥ f(b)`: Illinois (regula falsi) iterations.
fn refine(mut a: f64, mut b: f64, f: &dyn Fn(f64) -> f64) -> f64 {
    let (mut fa, mut fb) = (f(a), f(b));
    let mut side = 0;
    for _ in 0..200 {
        if fb == 0.0 || (b - a).abs() <= 4.0 * f64::EPSILON * b.abs().max(1e-300) {
            break;
        }
        let c = (a * fb - b * fa) / (fb - fa);
        let c = if c > a.min(b) && c < a.max(b) { c } else { 0.5 * (a + b) };
        let fc = f(c);
        if fc > 0.0 {
            a = c;
            fa = fc;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            b = c;
            fb = fc;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    b
}
