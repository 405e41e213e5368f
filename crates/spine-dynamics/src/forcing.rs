//! Time profile of the actuation: the axial force at time `t` is `s(t)` times the case's `p_x`.

use serde::{Deserialize, Serialize};

/// The factor `s(t) ∈ [0, 1]` that multiplies the actuation (the axial force at the end).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields, from = "ForcingFile")]
pub enum Forcing {
    /// `s = 1` from `t = 0` on: the step of Sec. 5.2.1.
    Step,
    /// `s = 0`: the passive load alone.
    Off,
    /// A square pulse train (Sec. 5.2.2): `s = 1` for `delay + k·period ≤ t < delay + (k + duty)·period`,
    /// else 0. `period` in s (> 0), `duty` in (0, 1), `delay` in s (≥ 0).
    PulseTrain {
        period: f64,
        duty: f64,
        #[serde(default)]
        delay: f64,
    },
    /// `s = ½ (1 − cos Ω t)`: a smooth pulsation between no force and the full force, `Ω` in rad/s.
    /// (The paper gives only "a periodic force of angular frequency Ω"; this form never pulls the end
    /// outward and starts at rest, like the pulse train.)
    Sinusoid { angular_frequency: f64 },
}

/// [`Forcing`] as a case file writes it. Serde ignores unknown fields beside the tag of a unit
/// variant even under `deny_unknown_fields` (`{"type": "step", "bogus": 1}` would pass); as empty
/// struct variants `step` and `off` refuse them like the others.
#[derive(Deserialize, schemars::JsonSchema)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
enum ForcingFile {
    Step {},
    Off {},
    PulseTrain {
        period: f64,
        duty: f64,
        #[serde(default)]
        delay: f64,
    },
    Sinusoid {
        angular_frequency: f64,
    },
}

impl From<ForcingFile> for Forcing {
    fn from(f: ForcingFile) -> Self {
        match f {
            ForcingFile::Step {} => Forcing::Step,
            ForcingFile::Off {} => Forcing::Off,
            ForcingFile::PulseTrain { period, duty, delay } => Forcing::PulseTrain { period, duty, delay },
            ForcingFile::Sinusoid { angular_frequency } => Forcing::Sinusoid { angular_frequency },
        }
    }
}

impl Forcing {
    /// `s(t)`. `piece` is any time inside the current smooth piece (between two
    /// [`Self::breakpoints`]); it decides the on/off state of a pulse train, so that the value at a
    /// switching instant belongs to the piece being integrated.
    pub fn factor(&self, t: f64, piece: f64) -> f64 {
        match *self {
            Forcing::Step => 1.0,
            Forcing::Off => 0.0,
            Forcing::PulseTrain { period, duty, delay } => {
                if piece < delay {
                    return 0.0;
                }
                let phase = ((piece - delay) / period).fract();
                if phase < duty {
                    1.0
                } else {
                    0.0
                }
            }
            Forcing::Sinusoid { angular_frequency } => 0.5 * (1.0 - (angular_frequency * t).cos()),
        }
    }

    /// Times in `(t0, t1)` where `s` jumps, in increasing order: the integrator steps onto them.
    pub fn breakpoints(&self, t0: f64, t1: f64) -> Vec<f64> {
        match *self {
            Forcing::PulseTrain { period, duty, delay } => {
                let mut out = Vec::new();
                let first = ((t0 - delay) / period).floor().max(0.0) as u64;
                let mut k = first;
                loop {
                    let on = delay + k as f64 * period;
                    if on >= t1 {
                        break;
                    }
                    for b in [on, on + duty * period] {
                        if b > t0 && b < t1 {
                            out.push(b);
                        }
                    }
                    k += 1;
                }
                out
            }
            _ => Vec::new(),
        }
    }

    /// The period, s, of a periodic forcing.
    pub fn period(&self) -> Option<f64> {
        match *self {
            Forcing::PulseTrain { period, .. } => Some(period),
            Forcing::Sinusoid { angular_frequency } => Some(std::f64::consts::TAU / angular_frequency),
            _ => None,
        }
    }

    /// Checks the parameters; the error names the field and what is allowed.
    pub fn validate(&self) -> Result<(), spine_check::FieldError> {
        let bad = |f: &str, m: String| Err(spine_check::FieldError::new(f, m));
        match *self {
            Forcing::PulseTrain { period, duty, delay } => {
                if !(period.is_finite() && period > 0.0) {
                    return bad("period", format!("must be a finite time > 0 s, got {period}"));
                }
                if !(duty > 0.0 && duty < 1.0) {
                    return bad("duty", format!("must be in (0, 1), got {duty}"));
                }
                if !(delay.is_finite() && delay >= 0.0) {
                    return bad("delay", format!("must be a finite time ≥ 0 s, got {delay}"));
                }
                Ok(())
            }
            Forcing::Sinusoid { angular_frequency } => {
                if !(angular_frequency.is_finite() && angular_frequency > 0.0) {
                    return bad(
                        "angular_frequency",
                        format!("must be a finite rate > 0 rad/s, got {angular_frequency}"),
                    );
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_forcing_refuses_unknown_fields_and_round_trips() {
        for text in [
            r#"{"type": "step", "bogus": true}"#,
            r#"{"type": "off", "period": 5}"#,
            r#"{"type": "pulse_train", "period": 1, "duty": 0.5, "bogus": 1}"#,
            r#"{"type": "sinusoid", "angular_frequency": 2, "bogus": 1}"#,
        ] {
            let e = serde_json::from_str::<Forcing>(text).unwrap_err().to_string();
            assert!(e.contains("unknown field"), "{text}: {e}");
        }
        for f in [
            Forcing::Step,
            Forcing::Off,
            Forcing::PulseTrain { period: 1.0, duty: 0.25, delay: 0.5 },
            Forcing::Sinusoid { angular_frequency: 3.0 },
        ] {
            let text = serde_json::to_string(&f).unwrap();
            assert_eq!(serde_json::from_str::<Forcing>(&text).unwrap(), f, "{text}");
        }
        assert_eq!(serde_json::to_string(&Forcing::Step).unwrap(), r#"{"type":"step"}"#);
    }
}
