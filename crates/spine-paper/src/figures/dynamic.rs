//! Figures of the dynamics, Sec. 5.2: Fig. 9 (step responses of damping designs), Fig. 10 (the
//! periodic-load design of eq. (37)), Fig. 11 (a fast design under a pulse train), Fig. 12 (damping
//! designs for three rise times).

use super::*;
use serde_json::json;
use spine_dynamic_design::DampingDesign;
use spine_dynamics::{PeriodicResponse, StepResponse};
use spine_run::text::quantity;
use spine_run::{samples_table, Animation, Track};
use std::f64::consts::LN_10;

/// RMS misfit of `Δ∞(1 − e^{−τt})`, as a fraction of `|Δ∞|`, below which a response is "first-order-like".
const FIRST_ORDER_RMS: f64 = 0.05;
/// Relative gap allowed between the fitted rate and `ln(10)/T_d`.
const TAU_TOLERANCE: f64 = 0.10;
/// Sec. 5.2.1's "τ = 11.5 sec⁻¹" (s⁻¹), held to the digits it gives (±[`PAPER_TAU_DIGITS`]).
const PAPER_TAU: f64 = 11.5;
const PAPER_TAU_DIGITS: f64 = 0.05;

pub(super) fn damping_designs<'a>(
    run: &NamedRun<'a>,
) -> Result<(&'a UsedDesign, &'a [DampingDesign], &'a [PeriodicResponse]), FieldError> {
    match expect_dynamics(run)? {
        (used, DynamicOutput::Damping { designs, periodic }) => Ok((used, designs, periodic)),
        _ => Err(run.error("this figure needs a \"damping\" run (eq. (35))")),
    }
}

/// The span a step response's panel shows: until 1.5 times the moment Δ(t) last leaves the band
/// of ±1 % of Δ∞ (at least three times the target rise time, at most the simulation), so the
/// rise and the T₉₀ marker fill the panel; the CSV keeps the whole simulation.
fn response_window(r: &StepResponse, target: Option<f64>) -> f64 {
    let t_end = r.samples.last().map_or(0.0, |s| s.t);
    let last_out =
        r.samples.iter().rev().find(|s| (s.delta - r.delta_inf).abs() > 0.01 * r.delta_inf.abs()).map_or(0.0, |s| s.t);
    let floor = 3.0 * target.or(r.rise_time).unwrap_or(0.0);
    (1.5 * last_out).max(floor).min(t_end)
}

/// Δ(t) with the first-order model that reaches 90 % at `T_d`, and the T₉₀ point, over the
/// response's window ([`response_window`]; the caption says when it is shorter than the run).
fn response_panel(title: &str, r: &StepResponse, target: Option<f64>, colour: usize) -> Panel {
    let t_end = r.samples.last().map_or(0.0, |s| s.t);
    let window = response_window(r, target);
    let title = if window < t_end {
        format!("{title} (first {} s of {} s)", round_time(window), round_time(t_end))
    } else {
        title.to_string()
    };
    let shown: Vec<(f64, f64)> = r.samples.iter().filter(|s| s.t <= window).map(|s| (s.t, s.delta)).collect();
    let mut panel = Panel::new(title, "t (s)", "end displacement Δ(t) (m)")
        .x_range(0.0, window)
        .with(Series::line("Δ(t), simulated", shown).colour(colour));
    if let Some(td) = target {
        let model = (0..=200).map(|k| {
            let t = window * k as f64 / 200.0;
            (t, r.delta_inf * (1.0 - (-LN_10 * t / td).exp()))
        });
        panel = panel.with(Series::dashed(format!("Δ∞ (1 − exp(−t·ln 10 / {td} s))"), model.collect()).colour(7));
    }
    if let Some(t90) = r.rise_time {
        panel = panel.with(Series::markers(format!("T₉₀ = {t90:.4} s"), vec![(t90, 0.9 * r.delta_inf)]).colour(3));
    }
    panel
}

/// A time for a caption: two significant digits (0.45 s, 1.2 s, 12 s).
fn round_time(t: f64) -> String {
    let digits = (1 - t.abs().max(1e-9).log10().floor() as i32).max(0) as usize;
    format!("{t:.digits$}")
}

fn damping_panel(title: &str, series: Vec<Series>) -> Panel {
    series.into_iter().fold(Panel::new(title, "joint j", "Cⱼ (N·m·s/rad)").x_integer(), Panel::with)
}

/// The claims on one eq. (35) design.
pub(super) fn damping_claims(scope: &str, d: &DampingDesign, with_first_order: bool) -> Vec<Claim> {
    let target = d.target_rise_time;
    let err = d.rise_time_error.unwrap_or(f64::INFINITY);
    let r = &d.response;
    let mut claims = vec![Claim::solver(
        scope,
        &format!("eq. (35): the designed structure rises to 90 % in T_d = {target} s"),
        format!("Ipopt converged and |T_90 − T_d| / T_d ≤ {:.1} %", 100.0 * spine_dynamic_design::RISE_TIME_ACCEPTANCE),
        d.meets_target(),
        format!(
            "{} after {} iterations ({} simulations); T_90 = {} s (error {:.2e}); ½ΣC² = {:.4e}",
            d.status,
            d.iterations,
            d.simulations,
            d.rise_time.map_or("not reached".into(), |t| format!("{t:.6}")),
            err,
            d.objective
        ),
    )];
    let o = &r.overdamping;
    // Where the lower limit was raised until the design is over-damped, the check cannot fail:
    // it verifies the search, and is reported as a solver check, not as the paper's statement.
    let overdamped_claim = if d.lower_limit.is_some() { Claim::solver } else { Claim::new };
    claims.push(overdamped_claim(
        scope,
        "the damper lower limit is set \"to ensure the end-point motion will be always a second order over damped motion\" (Sec. 4.2)",
        format!(
            "the end point never turns back on its way to Δ∞: no reversal and no retreat or overshoot beyond {:.1} % of the swing (on the sampled response){}",
            100.0 * spine_dynamics::overdamping::REVERSAL_THRESHOLD,
            if d.lower_limit.is_some() { "; the lower limit was raised until it holds, so this checks that search" } else { "" }
        ),
        o.is_overdamped(),
        format!(
            "{} reversals; largest fall-back {:.2} % of the swing ({:.3} → {:.3}{}); peak {:.3} of the swing{}",
            o.reversals,
            100.0 * o.fall_back,
            o.fall_back_from,
            o.fall_back_to,
            o.fall_back_at.map_or(String::new(), |t| format!(" at t = {t:.4} s")),
            o.peak,
            d.lower_limit.as_ref().map_or(String::new(), |l| match l.used {
                Some(used) if used > l.stated => format!(
                    "; lower limit raised from {} to {used:.3} N·m·s/rad ({} trials)",
                    l.stated,
                    l.trials.len()
                ),
                Some(_) => format!("; the stated lower limit {} N·m·s/rad suffices", l.stated),
                None => format!("; no lower limit up to the uniform start gives an over-damped design ({} trials)", l.trials.len()),
            })
        ),
    ));
    if with_first_order {
        let tau = LN_10 / target;
        let gap = (r.fit.tau - tau).abs() / tau;
        claims.push(Claim::new(
            scope,
            "\"one can predict the response of the structure quite accurately\" with a first-order model (eq. (36))",
            format!("least-squares fit of Δ∞(1 − e^(−τt)) has RMS error ≤ {:.0} % of |Δ∞|", 100.0 * FIRST_ORDER_RMS),
            r.fit.rms_error <= FIRST_ORDER_RMS,
            format!(
                "RMS error {:.2} %, largest {:.2} % of |Δ∞|; settled in θ2: {}",
                100.0 * r.fit.rms_error,
                100.0 * r.fit.max_error,
                r.settled
            ),
        ));
        // τ = 11.5 s⁻¹ is T_d = 0.2 s restated (E6), and eq. (35) designs for T_d: a check of the
        // fit, not of the paper.
        let rate = |t: Option<f64>| t.map_or("—".into(), |t| format!("{t:.3} s⁻¹"));
        let rise_from_theta0 = r.from_unloaded.rise_time.map_or("not reached".into(), |t| format!("{t:.4} s"));
        claims.push(Claim::solver(
            scope,
            "the fitted time constant is the designed one: τ = ln(10)/T_d (eq. (36), errata E6; the paper's τ = 11.5 s⁻¹ is T_d = 0.2 s)",
            format!("fitted τ within {:.0} % of ln(10)/T_d", 100.0 * TAU_TOLERANCE),
            gap <= TAU_TOLERANCE,
            format!(
                "fitted τ = {:.3} s⁻¹, ln(10)/T_d = {tau:.3} s⁻¹ (gap {:.1} %), ln(10)/T_90 = {}; eq. (36)'s reading, the end measured from θ0 as δ_d is: T_90 = {rise_from_theta0}, ln(10)/T_90 = {}",
                r.fit.tau,
                100.0 * gap,
                rate(r.tau_from_rise_time),
                rate(r.from_unloaded.tau)
            ),
        ));
        // The paper's τ belongs to the design whose target restates it (E6). Read with eq. (36)'s
        // Δ (the end measured from θ0, as δ_d is), the time constant is not the one eq. (35)
        // enforces, so the paper's number can fail there.
        if (tau - PAPER_TAU).abs() < PAPER_TAU_DIGITS {
            claims.push(Claim::new(
                scope,
                "\"the time constant of the structure is obtained as tau = 11.5 sec^-1\" (Sec. 5.2.1)",
                format!("eq. (36)'s reading, Δ measured from θ0 as δ_d is: ln(10)/T_90 equals the paper's {PAPER_TAU} s⁻¹ to its digits (within ±{PAPER_TAU_DIGITS}; from θ1, the rise eq. (35) designs, it holds by the design)"),
                r.from_unloaded.tau.is_some_and(|t| (t - PAPER_TAU).abs() < PAPER_TAU_DIGITS),
                format!(
                    "from θ0: T_90 = {rise_from_theta0}, τ = ln(10)/T_90 = {}; from θ1: τ = {}",
                    rate(r.from_unloaded.tau),
                    rate(r.tau_from_rise_time)
                ),
            ));
        }
    }
    claims
}

fn damping_summary(d: &DampingDesign) -> Value {
    json!({
        "target_rise_time": d.target_rise_time,
        "rise_time": d.rise_time,
        "rise_time_error": d.rise_time_error,
        "converged": d.converged,
        "damping": d.damping,
        "objective": d.objective,
        "fit_tau": d.response.fit.tau,
        "fit_rms_error": d.response.fit.rms_error,
        "delta_inf": d.response.delta_inf,
    })
}

/// Fig. 9: for each run (10 links, 5 links) the step response, the dampers and the shapes.
pub fn step_designs_figure(title: &str, runs: &[NamedRun<'_>]) -> Result<FigureOutput, FieldError> {
    let mut out = FigureOutput::default();
    let columns = runs.len();
    let (mut responses, mut dampers, mut shapes, mut tracks) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (k, run) in runs.iter().enumerate() {
        let (used, designs, _) = damping_designs(run)?;
        let d = designs.first().ok_or_else(|| run.error("no damping design"))?;
        let r = &d.response;
        responses.push(response_panel(
            &format!("({}) {}: end-point response", letter(k), run.title()),
            r,
            Some(d.target_rise_time),
            k,
        ));
        dampers.push(damping_panel(
            &format!("({}) {}: nodal damping", letter(columns + k), run.title()),
            vec![Series::bars("", points(&d.damping, 1)).colour(k)],
        ));
        let s = Shapes::of_ends(&used.spans, &used.design, &r.ends);
        shapes.push(s.panel(&format!("({}) {}: undeformed and deformed", letter(2 * columns + k), run.title())));
        tracks.push(Track::new(run.title(), &used.spans, &used.design.theta0, &r.samples));
        out.tables.push((format!("response_{}.csv", run.name), samples_table(&r.samples)));
        out.tables.push((format!("shape_{}.csv", run.name), s.table()));
        out.tables.push((format!("damping_{}.csv", run.name), values_table("damping_n_m_s_per_rad", &d.damping)));
        out.claims.extend(damping_claims(run.name, d, true));
        out.summary.insert(run.name.to_string(), damping_summary(d));
    }
    let fig = responses.into_iter().chain(dampers).chain(shapes).fold(Figure::new(title, columns), Figure::with);
    out.figures.push(("figure".into(), fig));
    let title = "Fig. 9: step responses of the eq. (35) designs".to_string();
    out.animations.push(("animation".into(), Animation { title, tracks, options: Default::default() }));
    Ok(out)
}

/// Fig. 12: one damping run with several targets; one response panel per target and the dampers.
pub fn rise_time_figure(title: &str, runs: &[NamedRun<'_>]) -> Result<FigureOutput, FieldError> {
    let [run] = runs else { return Err(FieldError::new("runs", "fig12 needs one damping run with its targets")) };
    let (_, designs, periodic) = damping_designs(run)?;
    let mut out = FigureOutput::default();
    let mut fig = Figure::new(title, 2);
    let mut bars = Vec::new();
    let mut list = Vec::new();
    for (k, d) in designs.iter().enumerate() {
        let t = d.target_rise_time;
        fig = fig.with(response_panel(
            &format!("({}) response time {t} s for 90 % of the deflection", letter(k)),
            &d.response,
            Some(t),
            k,
        ));
        bars.push(Series::bars(format!("T_d = {t} s"), points(&d.damping, 1)).colour(k));
        out.tables.push((format!("response_T{t}.csv"), samples_table(&d.response.samples)));
        out.tables.push((format!("damping_T{t}.csv"), values_table("damping_n_m_s_per_rad", &d.damping)));
        out.claims.extend(damping_claims(&format!("T_d = {t} s"), d, false));
        // Under the case's pulse train, where it has one ("even if the actuating force is not
        // constant").
        if let Some(r) = periodic.get(k) {
            out.tables.push((format!("pulse_T{t}.csv"), samples_table(&r.samples)));
            out.claims.extend(pulse_claims(&format!("T_d = {t} s, pulse train"), r));
        }
        list.push(damping_summary(d));
    }
    fig = fig.with(damping_panel(&format!("({}) nodal damping for each rise time", letter(designs.len())), bars));
    out.summary.insert("designs".into(), Value::Array(list));
    out.figures.push(("figure".into(), fig));
    Ok(out)
}

/// The samples of the last simulated period of `r`.
pub(super) fn last_period(r: &PeriodicResponse) -> Vec<&Sample> {
    let t_end = r.samples.last().map_or(0.0, |s| s.t);
    r.samples.iter().filter(|s| s.t >= t_end - r.period).collect()
}

/// Whether the settled response `r` reaches the static loaded displacement and returns to the
/// passive one, each within 1 % of the static swing ("motion as per our requirement").
pub(super) fn follows_its_static_states(r: &PeriodicResponse) -> bool {
    let swing = r.ends.loaded_displacement - r.ends.passive_displacement;
    (r.min_end_displacement - r.ends.loaded_displacement).abs() <= 0.01 * swing.abs()
        && (r.max_end_displacement - r.ends.passive_displacement).abs() <= 0.01 * swing.abs()
}

/// Whether the settled response `r` keeps up with its pulses: reach (90 %) shorter than the time
/// the force is on and return (90 %) shorter than the time it is off, with those two times (s,
/// from the samples of the last period).
pub(super) fn keeps_up(r: &PeriodicResponse) -> (bool, f64, f64) {
    let last = last_period(r);
    let on_fraction = last.iter().filter(|s| s.load_factor >= 0.5).count() as f64 / last.len().max(1) as f64;
    let (on, off) = (on_fraction * r.period, (1.0 - on_fraction) * r.period);
    (matches!((r.reach_time, r.return_time), (Some(a), Some(b)) if a < on && b < off), on, off)
}

/// The paper's two statements on a damping design under a pulse train (Sec. 5.2.2, "from Fig. 11
/// and Fig 12."), on the settled periodic response `r`.
pub(super) fn pulse_claims(scope: &str, r: &PeriodicResponse) -> Vec<Claim> {
    let mut claims = Vec::new();
    let (keeps, on, off) = keeps_up(r);
    let follows = follows_its_static_states(r);
    claims.push(Claim::new(
        scope,
        "\"fast responsive structure can generate motion as per our requirement even if the actuating force is not constant\" (Sec. 5.2.2)",
        "over a settled period the end reaches the static loaded displacement and returns to the passive one, each within 1 % of the swing",
        r.settled && follows,
        format!("min X − L_x = {:.6} m (static loaded {:.6} m), max {:.6} m (static passive {:.6} m); settled: {}",
            r.min_end_displacement, r.ends.loaded_displacement, r.max_end_displacement, r.ends.passive_displacement, r.settled),
    ));
    claims.push(Claim::new(
        scope,
        "the response keeps up with the pulses (\"valid only for loading patterns with lower frequency\")",
        "reach (90 %) shorter than the time the force is on, return (90 %) shorter than the time it is off",
        keeps,
        format!(
            "reach {} (on for {on:.3} s), return {} (off for {off:.3} s)",
            quantity(r.reach_time, 4, "s", "not reached"),
            quantity(r.return_time, 4, "s", "not reached")
        ),
    ));
    claims
}
