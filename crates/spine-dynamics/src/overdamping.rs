//! Whether a step response is over-damped: the end point moving toward `Δ∞` without ever turning
//! back. The paper chooses the dampers' lower limit "through trial and error" to ensure an
//! over-damped structure (Sec. 4.2); this measures it on the sampled response.

use crate::sample::Sample;
use serde::Serialize;

/// A retreat smaller than this fraction of the swing is not counted as a reversal (the samples'
/// interpolation and the integrator's tolerance move the end by far less).
pub const REVERSAL_THRESHOLD: f64 = 1e-3;

/// The end point's progress `p(t) = Δ(t)/Δ∞` over a step response.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Overdamping {
    /// Largest retreat from the furthest progress reached so far, `max_t (max_{s≤t} p(s) − p(t))`,
    /// as a fraction of the swing `|Δ∞|`: 0 for a response that never moves back.
    pub fall_back: f64,
    /// When the largest retreat ends (its trough), s.
    pub fall_back_at: Option<f64>,
    /// The progress it fell back from, and to (fractions of the swing).
    pub fall_back_from: f64,
    pub fall_back_to: f64,
    /// Turns of the end point's direction by more than [`REVERSAL_THRESHOLD`] of the swing.
    pub reversals: usize,
    /// The largest progress reached (above 1: an overshoot), fraction of the swing.
    pub peak: f64,
}

impl Overdamping {
    /// Measures the sampled step response `samples` of swing `delta_inf` (m, nonzero).
    pub fn measure(samples: &[Sample], delta_inf: f64) -> Self {
        let mut out = Self {
            fall_back: 0.0,
            fall_back_at: None,
            fall_back_from: 0.0,
            fall_back_to: 0.0,
            reversals: 0,
            peak: 0.0,
        };
        if delta_inf == 0.0 || !delta_inf.is_finite() {
            return out;
        }
        let (mut furthest, mut extreme, mut rising) = (f64::NEG_INFINITY, 0.0, true);
        for s in samples {
            let p = s.delta / delta_inf;
            if !p.is_finite() {
                continue;
            }
            furthest = furthest.max(p);
            if furthest - p > out.fall_back {
                (out.fall_back, out.fall_back_at, out.fall_back_from, out.fall_back_to) =
                    (furthest - p, Some(s.t), furthest, p);
            }
            // Direction changes with hysteresis: a turn counts once the motion has gone back by
            // the threshold from the last extreme.
            if rising {
                if p > extreme {
                    extreme = p;
                } else if extreme - p > REVERSAL_THRESHOLD {
                    (out.reversals, rising, extreme) = (out.reversals + 1, false, p);
                }
            } else if p < extreme {
                extreme = p;
            } else if p - extreme > REVERSAL_THRESHOLD {
                (out.reversals, rising, extreme) = (out.reversals + 1, true, p);
            }
        }
        out.peak = furthest.max(0.0);
        out
    }

    /// Over-damped: the end point never turns back by more than [`REVERSAL_THRESHOLD`] of the
    /// swing, and does not overshoot `Δ∞` by more than that.
    pub fn is_overdamped(&self) -> bool {
        self.reversals == 0 && self.fall_back <= REVERSAL_THRESHOLD && self.peak <= 1.0 + REVERSAL_THRESHOLD
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn samples(progress: &[f64]) -> Vec<Sample> {
        progress
            .iter()
            .enumerate()
            .map(|(k, &p)| Sample {
                t: k as f64 * 0.01,
                load_factor: 1.0,
                delta: -0.02 * p,
                end_displacement: 0.0,
                theta: vec![],
            })
            .collect()
    }

    #[test]
    fn a_first_order_rise_is_overdamped_and_a_dip_or_an_overshoot_is_not() {
        let rise: Vec<f64> = (0..300).map(|k| 1.0 - (-(k as f64) * 0.05).exp()).collect();
        let m = Overdamping::measure(&samples(&rise), -0.02);
        assert!(m.is_overdamped() && m.reversals == 0 && m.fall_back == 0.0, "{m:?}");
        // 0.339 of the swing, back to 0.315, then on: one retreat of 0.024 and two turns.
        let dip = [0.0, 0.2, 0.339, 0.33, 0.315, 0.4, 0.7, 0.95, 1.0, 1.0];
        let m = Overdamping::measure(&samples(&dip), -0.02);
        assert!(!m.is_overdamped());
        assert_eq!(m.reversals, 2);
        assert!((m.fall_back - 0.024).abs() < 1e-12 && m.fall_back_at == Some(0.04), "{m:?}");
        assert_eq!((m.fall_back_from, m.fall_back_to), (0.339, 0.315));
        // An overshoot that settles back is a reversal too.
        let over = [0.0, 0.6, 1.05, 1.01, 1.0, 1.0];
        let m = Overdamping::measure(&samples(&over), -0.02);
        assert!(!m.is_overdamped() && m.reversals == 1 && (m.peak - 1.05).abs() < 1e-12, "{m:?}");
    }
}
