//! The summary of a dynamic case that a person reads (`spine simulate`, `damping`, `periodic`):
//! the design's origin, each response's rise, settling and drift, the damping designs and the
//! periodic design, each number with its unit.

use crate::kinds::dynamics::{DesignOrigin, DynamicsResult};
use crate::text::{list, quantity};
use spine_dynamics::{PeriodicResponse, StepResponse};

/// A time in seconds to a tenth of a millisecond, or in scientific form below a millisecond (a
/// microsecond pulse is not `0.0000 s`).
fn seconds(t: f64) -> String {
    if t == 0.0 || t.abs() >= 1e-3 {
        format!("{t:.4} s")
    } else {
        format!("{t:.4e} s")
    }
}

fn write_periodic(f: &mut std::fmt::Formatter<'_>, r: &PeriodicResponse) -> std::fmt::Result {
    let unread =
        if r.swing_resolved { "not reached" } else { "not read (the swing is below the integrator's resolution)" };
    let opt = |v: Option<f64>| v.map_or(unread.to_string(), seconds);
    writeln!(
        f,
        "periodic response: {} after {} periods (last two differ by {:.1e} of the swing), period {}",
        if r.settled { "settled" } else { "NOT settled" },
        r.periods_run,
        r.period_change,
        seconds(r.period)
    )?;
    writeln!(
        f,
        "first on-phase: from rest at θ1, the end covers 90 % of the static swing (X(θ2) − X(θ1)) in {}",
        opt(r.first_rise_time)
    )?;
    writeln!(
        f,
        "last period: min X − L_x = {:.6e} m ({} after onset), max {:.6e} m; reach (90 %) {}, return (90 %) {}",
        r.min_end_displacement,
        seconds(r.time_of_minimum),
        r.max_end_displacement,
        opt(r.reach_time),
        opt(r.return_time)
    )?;
    writeln!(
        f,
        "constraint drift: |Φ| ≤ {:.1e} m at steps, {:.1e} m on the dense output",
        r.drift.max_constraint, r.drift.max_constraint_dense
    )
}

fn write_step(f: &mut std::fmt::Formatter<'_>, r: &StepResponse, rise_fraction: f64) -> std::fmt::Result {
    writeln!(
        f,
        "static ends: θ1 {} (X − L_x = {:.6e} m), θ2 {} (X − L_x = {:.6e} m)",
        r.ends.passive_status, r.ends.passive_displacement, r.ends.loaded_status, r.ends.loaded_displacement
    )?;
    writeln!(
        f,
        "integration: {}, {} steps ({} rejected), {} f-evaluations, {} Jacobians, {:.3} s",
        r.outcome,
        r.stats.accepted_steps,
        r.stats.rejected_steps,
        r.stats.rhs_evaluations,
        r.stats.jacobian_evaluations,
        r.time_seconds
    )?;
    writeln!(
        f,
        "Δ∞ = {:.6e} m; T_{:.0} = {} ; τ = ln(10)/T_90 = {}",
        r.delta_inf,
        100.0 * rise_fraction,
        quantity(r.rise_time, 6, "s", "not reached"),
        r.tau_from_rise_time.map_or("—".into(), |t| format!("{t:.4} 1/s"))
    )?;
    let u = &r.from_unloaded;
    writeln!(
        f,
        "eq. (36)'s reading, the end measured from θ0: δ_d = {:.6e} m; T_{:.0} = {}; τ = {} (travel from θ1 {:.3} × that of 0.9 Δ∞)",
        u.delta_d,
        100.0 * rise_fraction,
        quantity(u.rise_time, 6, "s", "not reached"),
        u.tau.map_or("—".into(), |t| format!("{t:.4} 1/s")),
        u.threshold_ratio
    )?;
    writeln!(
        f,
        "first-order fit Δ∞(1 − e^(−τt)): τ = {:.4} 1/s, RMS error {:.2} % of Δ∞ (max {:.2} %)",
        r.fit.tau,
        100.0 * r.fit.rms_error,
        100.0 * r.fit.max_error
    )?;
    writeln!(
        f,
        "settled in θ2: {} (|Δ(t_end) − Δ∞| = {:.2e} of Δ∞, max |θ − θ2| = {:.2e} rad)",
        if r.settled { "yes" } else { "NO" },
        r.settle_error,
        r.final_state_gap
    )?;
    writeln!(
        f,
        "constraint drift: |Φ| ≤ {:.1e} m, |Φ̇| ≤ {:.1e} m/s at steps; {:.1e} m, {:.1e} m/s on the dense output; largest projection {:.1e}",
        r.drift.max_constraint,
        r.drift.max_constraint_rate,
        r.drift.max_constraint_dense,
        r.drift.max_constraint_rate_dense,
        r.drift.max_projection
    )
}

impl std::fmt::Display for DynamicsResult {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if let DesignOrigin::Eq33(s) = &self.design.source {
            writeln!(
                f,
                "eq. (33) design: {} after {} iterations, J = {:.6e} J, δ = {}, {}",
                s.status,
                s.iterations,
                s.objective,
                quantity(s.end_displacement, 6, "m", "no loaded equilibrium"),
                if s.clean { "clean" } else { "NOT clean: no dynamics ran on it" }
            )?;
            for w in &s.warnings {
                writeln!(f, "WARNING (eq. (33)): {w}")?;
            }
        }
        writeln!(f, "{} — {} links", self.title, self.n_links)?;
        if let Some(r) = &self.step_response {
            write_step(f, r, self.rise_fraction)?;
        }
        if let Some(r) = &self.periodic_response {
            write_periodic(f, r)?;
        }
        if let Some(designs) = &self.damping_designs {
            writeln!(
                f,
                "{:>8} {:>10} {:>12} {:>10} {:>5}  dampers C (N·m·s/rad)",
                "T_d (s)", "status", "T_90 (s)", "error", "iter"
            )?;
            for d in designs {
                if let Some(p) = &d.periodic_response {
                    write_periodic(f, p)?;
                }
                let r = &d.design;
                writeln!(
                    f,
                    "{:>8} {:>10} {:>12} {:>9.2e} {:>5}  {}",
                    r.target_rise_time,
                    if r.converged { "converged" } else { "FAILED" },
                    r.rise_time.map_or("—".into(), |t| format!("{t:.6}")),
                    r.rise_time_error.unwrap_or(f64::INFINITY),
                    r.iterations,
                    list(&r.damping, 3)
                )?;
            }
        }
        if let Some(r) = &self.periodic_design {
            writeln!(
                f,
                "eq. (37) by {}: {} after {} iterations, {} simulations; {}",
                r.method,
                r.status(),
                r.iterations(),
                r.simulations,
                if r.feasible { "feasible" } else { "NOT feasible" }
            )?;
            writeln!(
                f,
                "U(θ1) = {:.6e} J (start {:.6e} J, violation {:.2e})",
                r.objective, r.start.objective, r.start.violation
            )?;
            writeln!(
                f,
                "min_t (X − L_x) = {:.6e} m against δ_d = {:.6e} m ({:.2} % off)",
                r.min_end_displacement,
                r.delta_d,
                100.0 * r.relative_error
            )?;
            writeln!(f, "K (N·m/rad) = {}", list(&r.stiffness, 1))?;
            write_periodic(f, &r.response)?;
        }
        Ok(())
    }
}
