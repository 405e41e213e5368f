//! Sec. 3, two links: the closed forms (10), (11) and the ratio (17) beside the exact solution.

use super::*;
use serde_json::json;

/// Largest `R` of eq. (17) (corrected, errata E5) must exceed 1 at every δ; the observed orders of
/// the closed-form errors must be those errata E3 predicts, within this margin.
const ORDER_MARGIN: f64 = 0.1;

pub fn figure(title: &str, runs: &[NamedRun<'_>]) -> Result<FigureOutput, FieldError> {
    let [run] = runs else { return Err(FieldError::new("runs", "twolink needs one twolink run")) };
    let RunOutput::Twolink { study, stiffness } = run.output else {
        return Err(run.error("needs a \"twolink\" run"));
    };
    let mut out = FigureOutput::default();
    let rows: Vec<_> = study.rows.iter().filter(|r| r.theta0_exact.is_some()).collect();
    let log_err = |f: &dyn Fn(&spine_solve::twolink::StudyRow) -> Option<f64>| -> Vec<(f64, f64)> {
        rows.iter().filter_map(|r| f(r).filter(|e| *e > 0.0).map(|e| (r.delta.abs().log10(), e.log10()))).collect()
    };
    let exact = |r: &spine_solve::twolink::StudyRow| r.theta0_exact.unwrap_or(f64::NAN);
    let errors = Panel::new("(a) closed forms against the exact θ₀", "log₁₀ |δ| (δ in m)", "log₁₀ error")
        .with(
            Series::line_markers("θ₀ of eq. (10), |error| (rad)", log_err(&|r| Some((r.theta0_eq10 - exact(r)).abs())))
                .colour(0),
        )
        .with(
            Series::line_markers(
                "θ₀ of eq. (10′) (E3), |error| (rad)",
                log_err(&|r| Some((r.theta0_first_order - exact(r)).abs())),
            )
            .colour(2),
        )
        .with(
            Series::line_markers(
                "K of eq. (11), relative error",
                log_err(&|r| r.stiffness_eq11.map(|k| (k / stiffness - 1.0).abs())),
            )
            .colour(3),
        );
    let ratio = Panel::new("(b) sensitivity ratio R of eq. (17)", "log₁₀ |δ| (δ in m)", "R (N·m/rad²)")
        .with(
            Series::line_markers(
                "R as printed",
                rows.iter().filter_map(|r| r.ratio_eq17_printed.map(|v| (r.delta.abs().log10(), v))).collect(),
            )
            .colour(1),
        )
        .with(
            Series::line_markers(
                "R corrected (E5)",
                rows.iter().filter_map(|r| r.ratio.map(|v| (r.delta.abs().log10(), v))).collect(),
            )
            .colour(0),
        );
    out.figures.push(("figure".into(), Figure::new(title, 2).with(errors).with(ratio)));

    out.tables.push(("twolink.csv".into(), study_table(study)));

    let o = &study.orders;
    let near = |v: Option<f64>, want: f64| v.is_some_and(|p| (p - want).abs() <= ORDER_MARGIN);
    let fmt = |v: Option<f64>| v.map_or("—".into(), |p| format!("{p:.3}"));
    out.claims.push(Claim::new(
        "figure",
        "eqs. (10) and (11) solve eqs. (8), (9) \"for a given small δ\"",
        format!("observed orders in δ (three smallest |δ|) within {ORDER_MARGIN} of errata E3: eq. (11) relative K error 1, eq. (10) θ0 error 1, eq. (10′) θ0 error 2"),
        near(o.eq11_relative, 1.0) && near(o.eq10, 1.0) && near(o.first_order, 2.0),
        format!("eq. (11) {}, eq. (10) {}, eq. (10′) {} (eq. (10)'s error is of the order of θ0 − θ* itself: it misses part of the deflection, E3)", fmt(o.eq11_relative), fmt(o.eq10), fmt(o.first_order)),
    ));
    let ratios: Vec<f64> = study.rows.iter().filter_map(|r| r.ratio).collect();
    let min_ratio = ratios.iter().copied().fold(f64::INFINITY, f64::min);
    out.claims.push(Claim::new(
        "figure",
        "\"R is greater than 1 … change in shape is preferred to change in stiffness\" (eq. (17))",
        "R (corrected, E5) > 1 at every δ of the case",
        !ratios.is_empty() && ratios.len() == study.rows.len() && min_ratio > 1.0,
        format!("smallest R = {min_ratio:.4e} over {} of {} δ values", ratios.len(), study.rows.len()),
    ));
    out.summary.insert("orders".into(), json!(o));
    out.summary.insert("zero_moment_angle".into(), json!(study.zero_moment_angle));
    Ok(out)
}

/// `twolink.csv`: every δ of the study with the exact and closed-form answers.
fn study_table(study: &spine_solve::twolink::Study) -> String {
    let mut table = String::from("delta_m,theta0_exact_rad,theta0_eq10_printed_rad,theta0_eq10_rad,theta0_eq10_first_order_rad,stiffness_eq11_n_m_per_rad,ratio_eq17_printed,ratio_corrected\n");
    let opt = |v: Option<f64>| v.map_or(String::new(), |x| format!("{x:e}"));
    for r in &study.rows {
        let _ = writeln!(
            table,
            "{:e},{},{:e},{:e},{:e},{},{},{}",
            r.delta,
            opt(r.theta0_exact),
            r.theta0_eq10_printed,
            r.theta0_eq10,
            r.theta0_first_order,
            opt(r.stiffness_eq11),
            opt(r.ratio_eq17_printed),
            opt(r.ratio)
        );
    }
    table
}
