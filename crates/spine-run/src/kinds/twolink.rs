//! Kind `twolink`: the two-link analysis of Sec. 3, closed forms beside the exact solution.

use crate::output::TwoLinkResult;
use spine_case::{TwoLinkCase, ValidTwoLink};
use spine_solve::twolink::study;

/// The study of Sec. 3 on the case's δ values.
pub fn run_twolink_case(case: &TwoLinkCase, valid: &ValidTwoLink) -> TwoLinkResult {
    let clock = std::time::Instant::now();
    let study = study(&valid.twolink, &valid.spec, &valid.options);
    let tl = &valid.twolink;
    TwoLinkResult {
        title: case.title.clone(),
        length: tl.length,
        stiffness: valid.spec.stiffness,
        p_y: tl.p_y,
        p_x: tl.p_x,
        study,
        total_seconds: clock.elapsed().as_secs_f64(),
    }
}

impl crate::KindOutput for TwoLinkResult {
    /// The exact θ0 found for every δ.
    fn is_clean(&self) -> bool {
        self.study.rows.iter().all(|r| r.theta0_exact.is_some())
    }
}

fn fmt_opt(v: Option<f64>, digits: usize) -> String {
    v.map_or("—".into(), |x| format!("{x:.digits$e}"))
}

impl std::fmt::Display for TwoLinkResult {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let study = &self.study;
        writeln!(
            f,
            "two-link analysis (Sec. 3): L = {} m, K = {} N·m/rad, P_Y = {} N, P_X = {} N; zero-moment angle θ* = {:.9} rad",
            self.length, self.stiffness, self.p_y, self.p_x, study.zero_moment_angle
        )?;
        writeln!(
            f,
            "θ0 for each δ: exact (general N = 2 solver) vs eq. (10) as printed, on the right branch, and made first-order consistent"
        )?;
        writeln!(
            f,
            "{:>11} {:>16} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12}",
            "δ (m)", "θ0 exact", "err (10) pr.", "err (10)", "err (10′)", "K(11)/K−1", "R (17) pr.", "R corrected"
        )?;
        for r in &study.rows {
            let err = |v: f64| r.theta0_exact.map(|t| (v - t).abs());
            writeln!(
                f,
                "{:>11.3e} {:>16} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12}",
                r.delta,
                r.theta0_exact.map_or("not found".into(), |t| format!("{t:.12}")),
                fmt_opt(err(r.theta0_eq10_printed), 3),
                fmt_opt(err(r.theta0_eq10), 3),
                fmt_opt(err(r.theta0_first_order), 3),
                fmt_opt(r.stiffness_eq11.map(|k| k / self.stiffness - 1.0), 3),
                fmt_opt(r.ratio_eq17_printed, 5),
                fmt_opt(r.ratio, 5),
            )?;
        }
        let o = &study.orders;
        writeln!(
            f,
            "observed orders in δ: eq. (10) θ0 error {}, first-order-consistent θ0 error {}, eq. (11) relative K error {}",
            fmt_opt(o.eq10, 3),
            fmt_opt(o.first_order, 3),
            fmt_opt(o.eq11_relative, 3)
        )?;
        writeln!(f, "see docs/errata.md E2–E5 for the slips these columns show")?;
        for o in study.optima.iter().flatten() {
            writeln!(
                f,
                "eq. (12) at δ = {} m, {} ≤ K ≤ {}: {}, K = {:.6} N·m/rad, θ0 = {:.6} rad, J = {:.4e} J; eq. (19) with λ1 of eq. (20): {:.4e}, central difference {}",
                o.delta,
                o.bounds.0,
                o.bounds.1,
                o.place.describe(),
                o.stiffness,
                o.theta0,
                o.objective,
                o.dl_dk,
                fmt_opt(o.dl_dk_central_difference, 4)
            )?;
        }
        if let Some(sd) = &study.small_deflection {
            writeln!(
                f,
                "eq. (26) against the exact small deflections: order {} (corrected, E8), {} as printed",
                fmt_opt(sd.order, 3),
                fmt_opt(sd.order_printed, 3)
            )?;
            if let Some(g) = &sd.gradients {
                writeln!(
                    f,
                    "eqs. (27)–(30) at Λ = ({:.4e}, {:.4e}): ∂ℒ/∂K1 printed {:.4e}, exact {:.4e}; ∂ℒ/∂K2 printed {:.4e}, exact {:.4e}; (29), (30) within {:.1e} of exact; (27), (28) with E10's term within {:.1e}",
                    g.multipliers[0],
                    g.multipliers[1],
                    g.printed[0],
                    g.exact[0],
                    g.printed[1],
                    g.exact[1],
                    (2..4).map(|i| (g.printed[i] - g.exact[i]).abs() / g.angle_scale).fold(0.0, f64::max),
                    g.gap(true)
                )?;
            }
        }
        Ok(())
    }
}

impl crate::RunKind for TwoLinkCase {
    type Output = TwoLinkResult;
    const IN_FIGURE: bool = true;

    fn run(&self, _: &mut crate::RunContext<'_>) -> Result<TwoLinkResult, crate::RunError> {
        Ok(run_twolink_case(self, &self.validate()?))
    }

    /// The same study as the kind's own run: a figure draws its rows.
    fn in_figure(
        &self,
        _: Option<&crate::workers::Workers>,
        _: &mut dyn FnMut(crate::Progress<'_>),
    ) -> Option<Result<crate::RunOutput, crate::RunError>> {
        Some(self.validate().map(|valid| crate::RunOutput::new(run_twolink_case(self, &valid))).map_err(Into::into))
    }
}
