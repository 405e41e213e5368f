//! Fig. 11: a fast design (eq. (33), then eq. (35)) under a pulse train, beside the paper's genetic
//! algorithm on the same structure (eq. (37)), and the two statements on pulsed forcing that
//! Fig. 12 shares.

use super::dynamic::{damping_claims, damping_designs, last_period, pulse_claims};
use super::frequency::{frequency_sweep, SweepPoint};
use super::*;
use serde_json::json;
use spine_dynamic_design::{DampingDesign, PeriodicDesign};
use spine_dynamics::PeriodicResponse;
use spine_run::text::quantity;
use spine_run::{samples_table, Animation, Track};

/// The largest RMS gap between two end-point motions over a period, as a fraction of the swing,
/// that counts as "similar".
const SIMILAR: f64 = 0.10;
/// "Much faster": at least this many times fewer simulations.
const MUCH_FEWER: f64 = 5.0;

/// The end point's displacement over the last simulated period against the phase `t − t_start`.
fn last_trace(r: &PeriodicResponse) -> Vec<(f64, f64)> {
    let start = r.samples.last().map_or(0.0, |s| s.t) - r.period;
    last_period(r).iter().map(|s| (s.t - start, s.end_displacement)).collect()
}

/// Linear interpolation of `trace` (sorted by its first entry) at `x`, clamped at its ends.
fn at(trace: &[(f64, f64)], x: f64) -> f64 {
    let k = trace.partition_point(|p| p.0 < x);
    match (k.checked_sub(1).and_then(|j| trace.get(j)), trace.get(k)) {
        (Some(a), Some(b)) if b.0 > a.0 => a.1 + (b.1 - a.1) * (x - a.0) / (b.0 - a.0),
        (_, Some(b)) => b.1,
        (Some(a), None) => a.1,
        (None, None) => f64::NAN,
    }
}

/// Sec. 5.2.2 on Fig. 11 against the GA (`name`'s eq. (37) design `q` on the same structure, beside
/// the eq. (33) + eq. (35) design `d` with its response `r`): "the response at the end-point is
/// similar" and "the gradient-based approach is however much faster".
fn ga_claims(name: &str, d: &DampingDesign, r: &PeriodicResponse, q: &PeriodicDesign) -> Vec<Claim> {
    let (mine, theirs) = (last_trace(r), last_trace(&q.response));
    let swing = (r.ends.loaded_displacement - r.ends.passive_displacement).abs();
    let squares: f64 = mine.iter().map(|&(x, y)| (y - at(&theirs, x)).powi(2)).sum();
    let rms = (squares / mine.len().max(1) as f64).sqrt() / swing;
    vec![
        Claim::new(
            name,
            "\"comparing this result with that obtained by genetic algorithm shows that for a fast responsive structure, the response at the end-point is similar\" (Sec. 5.2.2)",
            format!("over the last period, by phase, the RMS gap between the two end-point motions at most {:.0} % of the swing", 100.0 * SIMILAR),
            rms.is_finite() && rms <= SIMILAR,
            format!(
                "RMS gap {:.1} % of the swing {swing:.4} m; reach (90 %) {} against the GA's {}, return {} against {}",
                100.0 * rms,
                quantity(r.reach_time, 4, "s", "not reached"),
                quantity(q.response.reach_time, 4, "s", "not reached"),
                quantity(r.return_time, 4, "s", "not reached"),
                quantity(q.response.return_time, 4, "s", "not reached")
            ),
        ),
        Claim::new(
            name,
            "\"the gradient-based approach is however much faster for simulation\" (Sec. 5.2.2)",
            format!("eq. (35) by gradients needs at least {MUCH_FEWER:.0} times fewer simulations than eq. (37) by the GA (simulations, not wall time, so that result.json stays deterministic)"),
            (d.simulations as f64) * MUCH_FEWER <= q.simulations as f64,
            format!("{} simulations for eq. (35) (eq. (33) simulates nothing) against {} for the GA", d.simulations, q.simulations),
        ),
    ]
}

/// Fig. 11: a gradient-based design (eq. (33) then eq. (35)) under a pulse train.
pub fn pulse_figure(title: &str, runs: &[NamedRun<'_>]) -> Result<FigureOutput, FieldError> {
    let Some((run, rest)) = runs.split_first() else {
        return Err(FieldError::new("runs", "fig11 needs one damping run with a periodic forcing"));
    };
    // Beside the first run: at most one eq. (37) run, and damping runs of the same design under
    // other pulse periods (the frequency sweep).
    let mut ga = None;
    let mut sweep = Vec::new();
    for other in rest {
        match super::expect_dynamics(other)?.1 {
            DynamicOutput::PeriodicDesign { design } if ga.is_none() => ga = Some((other.name, &**design)),
            DynamicOutput::Damping { periodic, .. } => match periodic.first() {
                Some(response) => sweep.push(SweepPoint { name: other.name, response }),
                None => return Err(other.error("a frequency-sweep run of fig11 needs a periodic forcing")),
            },
            _ => return Err(other.error(
                "fig11's runs: one damping run, at most one eq. (37) run, and damping runs under other pulse periods",
            )),
        }
    }
    let (used, designs, periodic) = damping_designs(run)?;
    let (Some(d), Some(r)) = (designs.first(), periodic.first()) else {
        return Err(run.error("fig11 needs a damping design and a periodic forcing to simulate it under"));
    };
    sweep.push(SweepPoint { name: run.name, response: r });
    let mut out = FigureOutput::default();
    // Shapes at eight instants of the last simulated period.
    let last = last_period(r);
    let mut shapes = Panel::new("(b) structure responding to the pulsating force", "X (m)", "Y (m)").equal_aspect();
    for k in 0..8 {
        if let Some(s) = last.get(k * last.len().saturating_sub(1) / 7) {
            shapes = shapes.with(
                Series::line(format!("t = {:.3} s", s.t), nodes_of(&used.spans, &used.design.theta0, &s.theta))
                    .colour(k),
            );
        }
    }
    let mut motion = periodic_panel("(a) pulsating force and end-point motion", r, r.ends.loaded_displacement, None);
    if let Some((_, q)) = &ga {
        motion.series[0].label = "end-point motion, eq. (33) + eq. (35) design".into();
        let samples = q.response.samples.iter().map(|s| (s.t, s.end_displacement)).collect();
        motion = motion.with(
            Series::line(format!("end-point motion, eq. (37) by the {}", q.method.describe()), samples).colour(2),
        );
    }
    let fig = Figure::new(title, 2).with(motion).with(shapes);
    out.tables.push(("response.csv".into(), samples_table(&r.samples)));
    out.tables.push(("damping.csv".into(), values_table("damping_n_m_s_per_rad", &d.damping)));
    out.animations.push((
        "animation".into(),
        Animation {
            title: "Fig. 11: the fast design under the pulse train".into(),
            tracks: vec![Track::new(run.title(), &used.spans, &used.design.theta0, &r.samples)],
            options: Default::default(),
        },
    ));
    out.claims.extend(damping_claims(run.name, d, false));
    out.claims.extend(pulse_claims(run.name, r));
    if let Some((name, q)) = &ga {
        out.claims.extend(ga_claims(name, d, r, q));
        out.tables.push(("response_ga.csv".into(), samples_table(&q.response.samples)));
        out.tables.push(("stiffness_ga.csv".into(), values_table("stiffness_n_m_per_rad", &q.stiffness)));
    }
    out.summary.insert(
        run.name.to_string(),
        json!({
            "damping": d.damping, "rise_time": d.rise_time, "min_end_displacement": r.min_end_displacement,
            "reach_time": r.reach_time, "return_time": r.return_time, "period": r.period,
        }),
    );
    if let Some((claim, table, summary)) = frequency_sweep(&mut sweep) {
        out.claims.push(claim);
        out.tables.push(("frequency_sweep.csv".into(), table));
        out.summary.insert("frequency_sweep".into(), summary);
    }
    out.figures.push(("figure".into(), fig));
    Ok(out)
}
