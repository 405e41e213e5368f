//! The summary of a design case that a person reads (`spine design`): the multi-start's census,
//! the solver's status, the optimum, its certificate and its warnings, each number with its unit.

use crate::design::DesignCaseResult;
use crate::text::list;
use spine_design::multistart::MultiStartSummary;

impl DesignCaseResult {
    /// The multi-start's census: its optima and which one is reported.
    fn fmt_multistart(&self, summary: &MultiStartSummary, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "multi-start: {} runs (the case's start and {} seeded starts, seed {}), {} converged, {} distinct optima",
            summary.starts,
            summary.starts - 1,
            summary.seed,
            summary.converged,
            summary.optima.len()
        )?;
        let (symbol, unit) = self.result.criterion.symbol_and_unit();
        for (k, o) in summary.optima.iter().enumerate() {
            writeln!(
                f,
                "  optimum {k}: {symbol} = {:.10e}{unit}, reached by {} run(s), first from start {}{}{}",
                o.objective(),
                o.count,
                o.starts[0],
                o.mirror_of.map_or(String::new(), |m| format!(" (mirror image of optimum {m})")),
                if o.clean { "" } else { " (not clean: see its warnings in result.json)" }
            )?;
        }
        if let Some(c) = &summary.confidence {
            writeln!(
                f,
                "census to confidence: target P(a better one unseen) ≤ {} {} after {} seeded start(s) in {} batch(es) (batches of {}, cap {})",
                c.target,
                if c.reached { "REACHED" } else { "NOT REACHED" },
                c.seeded,
                c.batches,
                c.batch,
                c.cap
            )?;
        }
        let e = &summary.census;
        let number =
            |v: Option<f64>, digits: usize| v.map_or("n/a (too few runs)".to_string(), |v| format!("{v:.digits$}"));
        writeln!(
            f,
            "census (Boender-Rinnooy Kan): {} classes of clean optima (an optimum and its mirror image one class) from {} runs; estimated number of classes {}, P(all seen) {}, P(a better one unseen) {}",
            e.distinct,
            e.searches,
            number(e.estimated_optima, 1),
            number(e.probability_all_seen, 3),
            number(e.probability_better_unseen, 3)
        )?;
        match summary.best_clean() {
            Some(_) if self.reported_start == 0 => {
                writeln!(f, "reported below: the best clean optimum, reached from the case's own start")?
            }
            Some(_) => writeln!(
                f,
                "reported below: the best clean optimum, reached first from seeded start {}",
                self.reported_start
            )?,
            None => writeln!(f, "no start reached a clean optimum; reported below: the case's own start")?,
        }
        Ok(())
    }
}

impl std::fmt::Display for DesignCaseResult {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if let Some(summary) = &self.multistart {
            self.fmt_multistart(summary, f)?;
        }
        self.fmt_solver(f)?;
        self.fmt_certificate(f)?;
        let r = &self.result;
        writeln!(f, "θ0 (rad) = {}", list(&r.design.theta0, 6))?;
        writeln!(f, "K (N·m/rad) = {}", list(&r.design.stiffness, 3))?;
        for note in &r.start_notes {
            writeln!(f, "start: {note}")?;
        }
        for w in &r.warnings {
            writeln!(f, "WARNING: {w}")?;
        }
        if let Some(s) = &self.sensitivity {
            let given = s.parameters.iter().filter(|p| p.derivative.is_some()).count();
            writeln!(
                f,
                "sensitivity: conditions {}; derivatives for {given} of {} parameters (result.json: sensitivity)",
                if s.conditions.hold { "hold" } else { "FAIL (see result.json: sensitivity.conditions)" },
                s.parameters.len()
            )?;
        }
        Ok(())
    }
}

/// The criterion's value (the paper's `J` as always), and every criterion's measure of the design.
fn fmt_objective(f: &mut std::fmt::Formatter<'_>, r: &spine_design::DesignResult) -> std::fmt::Result {
    use spine_design::Objective;
    let v = r.objective;
    match &r.criterion {
        Objective::StrainEnergy => writeln!(f, "J = U(θ1) = {v:.10e} J")?,
        Objective::TotalStiffness => writeln!(f, "objective total_stiffness: Σ K = {v:.10e} N·m/rad")?,
        Objective::PeakMoment { exponent, reference } => writeln!(
            f,
            "objective peak_moment: Σ (M/M_ref)^{exponent} = {v:.10e} (M_ref = {reference:.6e} N·m; p-norm {:.6e} N·m)",
            reference * v.powf(1.0 / *exponent as f64)
        )?,
        Objective::Compliance { .. } => writeln!(f, "objective compliance: Pᵀu = {v:.10e} J")?,
    }
    if let Some(m) = &r.measures {
        let compliance = m.compliance.map_or(String::new(), |c| format!(", compliance {c:.6e} J"));
        writeln!(
            f,
            "measures: J = U(θ1) {:.6e} J, Σ K {:.6e} N·m/rad, max |M| {:.6e} N·m{compliance}",
            m.strain_energy, m.total_stiffness, m.peak_moment
        )?;
    }
    Ok(())
}

impl DesignCaseResult {
    /// The run's headline, Ipopt's status (and each level of a ladder), `J`, the violations and
    /// the end displacement.
    fn fmt_solver(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let r = &self.result;
        writeln!(
            f,
            "{} — {} links, {} space, C_K = {}",
            self.title,
            r.design.theta0.len(),
            r.formulation.name(),
            r.stiffness_scale
        )?;
        writeln!(
            f,
            "Ipopt: {} after {} iterations ({:.3} s, {:.3} s in evaluations)",
            r.solver.status, r.solver.iterations, r.solver.ipopt_seconds, r.solver.evaluation_seconds
        )?;
        if let Some(refinement) = &r.refinement {
            let (symbol, unit) = r.criterion.symbol_and_unit();
            let finest = refinement.levels.last().map(|l| l.links);
            for l in &refinement.levels {
                let restarts = match l.restarts {
                    0 => String::new(),
                    1 => " (1 restart)".to_string(),
                    r => format!(" ({r} restarts)"),
                };
                // A coarse level of a barrier schedule ends on its barrier problem, the chain
                // itself starts there (`refine::BarrierSchedule`).
                let barrier = match l.barrier {
                    Some(mu) if Some(l.links) == finest => format!(" from barrier μ = {mu:.1e}"),
                    Some(mu) => format!(" at barrier μ = {mu:.1e}"),
                    None => String::new(),
                };
                writeln!(
                    f,
                    "  level {:>5} links ({} start): {}{barrier} after {} iterations{restarts}, {symbol} = {:.10e}{unit}",
                    l.links, l.start, l.status, l.iterations, l.objective
                )?;
            }
        }
        fmt_objective(f, r)?;
        if let Some(v) = &r.violations {
            writeln!(
                f,
                "largest constraint violation {:.2e} (equilibria {:.1e} / {:.1e} N·m, end {:.1e} m)",
                v.max, v.passive_equilibrium, v.loaded_equilibrium, v.end_displacement
            )?;
        }
        match r.end_displacement {
            Some(d) => writeln!(f, "end displacement X(θ2) − L_x = {d:.9e} m (target δ_d = {:.9e} m)", r.delta_d)?,
            None => writeln!(f, "end displacement: none")?,
        }
        Ok(())
    }

    /// The stability of both equilibria, the second-order certificate and any escape from a point
    /// that is not a minimum.
    fn fmt_certificate(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let r = &self.result;
        for (name, s) in [("θ1 passive", &r.passive), ("θ2 loaded", &r.loaded), ("θ3 probe", &r.probe)] {
            if let Some(s) = s {
                let eig = s.stability.min_eigenvalue.map_or("none".into(), |e| format!("{e:.4e}"));
                writeln!(
                    f,
                    "{name:<11} {} (smallest reduced-Hessian eigenvalue {eig} N·m/rad)",
                    if s.stability.stable { "stable" } else { "UNSTABLE" }
                )?;
            }
        }
        match &r.certificate {
            Some(c) => writeln!(
                f,
                "second-order certificate: {} ({} free variables, {} active rows, null space {}, {} weakly active; smallest curvature {}; reduced KKT inertia {})",
                c.status,
                c.free_variables,
                c.active_rows,
                c.null_space_dimension,
                c.weakly_active,
                c.smallest_curvature.map_or("none (a vertex or too large to form)".into(), |v| format!("{v:.3e}")),
                c.reduced_kkt_inertia.map_or("n/a".into(), |[p, n, z]| format!("(n₊, n₋, n₀) = ({p}, {n}, {z})"))
            )?,
            None => writeln!(f, "second-order certificate: none (the run did not converge)")?,
        }
        let (symbol, unit) = r.criterion.symbol_and_unit();
        for e in &r.escapes {
            writeln!(
                f,
                "NOTE: left a point that is not a minimum ({symbol} = {:.10e}{unit}, certificate {}) by {}; reached {symbol} = {:.10e}{unit} in {} iterations",
                e.objective,
                e.status.map_or("none", |s| s.name()),
                e.how.name(),
                e.reached,
                e.iterations
            )?;
        }
        Ok(())
    }
}
