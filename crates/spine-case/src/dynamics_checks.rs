//! The checks of a dynamic case's settings that do not depend on its kind: the step response's
//! (`simulation`), a periodic response's (`periodic`, `periodic_design.settings.response`) and a
//! periodic forcing against the response that simulates it.

use crate::error::CaseError;
use crate::specs::positive;
use spine_dynamics::Forcing;

/// Longest simulated time, s (the paper's responses settle within seconds).
pub const MAX_T_END: f64 = 1e4;
/// Most output samples of a response (and per period of a periodic one).
pub const MAX_SAMPLES: usize = 1_000_000;
/// Most forcing periods of a periodic response.
pub const MAX_PERIODS: usize = 10_000;

/// A periodic response's settings (`prefix`: `periodic` or `periodic_design.settings.response`).
pub(crate) fn check_periodic(prefix: &str, p: &spine_dynamics::PeriodicSettings) -> Result<(), CaseError> {
    let field = |name: &str| format!("{prefix}.{name}");
    if !(2..=MAX_PERIODS).contains(&p.max_periods) {
        let message = format!("must be between 2 and {MAX_PERIODS}, got {}", p.max_periods);
        return Err(CaseError::invalid(field("max_periods"), message));
    }
    if !(2..=MAX_SAMPLES).contains(&p.samples_per_period) {
        let message = format!("must be between 2 and {MAX_SAMPLES}, got {}", p.samples_per_period);
        return Err(CaseError::invalid(field("samples_per_period"), message));
    }
    positive(&field("settle_tolerance"), p.settle_tolerance, "")?;
    check_fraction(&field("reach_fraction"), p.reach_fraction)?;
    check_integrator(&field("integrator"), &p.integrator)?;
    Ok(p.continuation.validate().map_err(|e| e.under(&field("continuation")))?)
}

/// A periodic forcing against the periodic response that simulates it (`prefix`: the response's
/// settings): the response runs up to `max_periods` periods after the delay, within
/// [`MAX_T_END`] in all (a longer period is a step response the integrator cannot resolve at the
/// chain's time scale), and each period within the integrator's reach ([`spine_dynamics::Options::check_reach`]).
pub(crate) fn check_periodic_forcing(
    prefix: &str,
    forcing: &Forcing,
    p: &spine_dynamics::PeriodicSettings,
    n: usize,
) -> Result<(), CaseError> {
    let Some(period) = forcing.period() else { return Ok(()) };
    let (field, delay) = match *forcing {
        Forcing::PulseTrain { delay, .. } => ("forcing.period", delay),
        _ => ("forcing.angular_frequency", 0.0),
    };
    let longest = (MAX_T_END - delay) / p.max_periods as f64;
    if period.is_nan() || period > longest {
        let given = match *forcing {
            Forcing::Sinusoid { angular_frequency } => {
                format!("at least {} rad/s, got {angular_frequency}", std::f64::consts::TAU / longest)
            }
            _ => format!("a period of at most {longest} s, got {period}"),
        };
        let message = format!(
            "the periodic response simulates up to {prefix}.max_periods = {} periods after the delay, at most {MAX_T_END} s in all: {given}",
            p.max_periods
        );
        return Err(CaseError::invalid(field, message));
    }
    p.integrator.check_reach(period, 2 * n).map_err(|e| CaseError::from(e.under(&format!("{prefix}.integrator"))))
}

/// The step response's settings (`simulation`): time span, samples, rise fraction, settling
/// tolerance, integrator and continuation.
pub(crate) fn check_simulation(s: &spine_dynamics::StepSettings) -> Result<(), CaseError> {
    positive("simulation.t_end", s.t_end, "s")?;
    let counts = [
        ("simulation.t_end", s.t_end <= MAX_T_END, format!("at most {MAX_T_END} s, got {}", s.t_end)),
        ("simulation.samples", s.samples <= MAX_SAMPLES, format!("at most {MAX_SAMPLES}, got {}", s.samples)),
    ];
    for (field, ok, message) in counts {
        if !ok {
            return Err(CaseError::invalid(field, message));
        }
    }
    check_fraction("simulation.rise_fraction", s.rise_fraction)?;
    positive("simulation.settle_tolerance", s.settle_tolerance, "")?;
    if s.samples < 2 {
        return Err(CaseError::invalid("simulation.samples", format!("must be at least 2, got {}", s.samples)));
    }
    check_integrator("simulation.integrator", &s.integrator)?;
    s.continuation.validate().map_err(|e| e.under("simulation.continuation"))?;
    Ok(())
}

fn check_integrator(prefix: &str, o: &spine_dynamics::Options) -> Result<(), CaseError> {
    Ok(o.validate().map_err(|e| e.under(prefix))?)
}

pub(crate) fn check_fraction(field: &str, v: f64) -> Result<(), CaseError> {
    if v > 0.0 && v < 1.0 {
        Ok(())
    } else {
        Err(CaseError::invalid(field, format!("must be in (0, 1), got {v}")))
    }
}
