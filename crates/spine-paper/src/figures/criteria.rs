//! Beyond the paper: eq. (33)'s constraints with another criterion in place of the strain energy
//! (`objective` of a design case, docs/objectives.md). One shape panel and one stiffness panel per
//! run, a table of every criterion's measure of every design, and the checks that make the
//! comparison meaningful: each run a clean optimum, and each design the best of the figure's
//! designs under its own criterion.

use super::*;
use serde_json::json;
use spine_design::Objective;

/// A design is "the best under its criterion" when no other design of the figure measures lower by
/// more than this relative margin (the runs are local optima of different problems; a margin of
/// round-off size keeps ties honest).
const TIE: f64 = 1e-9;

/// The figure `objectives`: the same problem under each criterion.
pub fn criteria_figure(title: &str, runs: &[NamedRun<'_>]) -> Result<FigureOutput, FieldError> {
    let mut out = FigureOutput::default();
    let mut fig = Figure::new(title, 2);
    let designs = runs.iter().map(|r| expect_design(r).map(best)).collect::<Result<Vec<_>, _>>()?;
    for (k, (run, s)) in runs.iter().zip(&designs).enumerate() {
        let r = &s.result;
        let shapes = Shapes::of_static(s).ok_or_else(|| run.error("the design has no equilibria to draw"))?;
        fig = fig.with(shapes.panel(&format!("({}) {}: shapes", letter(2 * k), run.title()))).with(stiffness_panel(
            &format!("({}) {}: nodal stiffness", letter(2 * k + 1), run.title()),
            vec![Series::bars("", points(&r.design.stiffness, 1)).colour(k)],
        ));
        out.tables.push((format!("shape_{}.csv", run.name), shapes.table()));
        out.tables.push((format!("design_{}.csv", run.name), design_table(&r.design)));
        let certificate = r.certificate.as_ref().map(|c| c.status);
        let minimum = certificate.is_some_and(|c| c != spine_design::certificate::MinimumStatus::NotAMinimum);
        out.claims.push(Claim::solver(
            run.name,
            &format!("the optimum under {} is a clean, certified minimum of eq. (33)'s constraints", r.criterion.name()),
            "Ipopt converged, constraints met, every equilibrium stable and on its load path, second-order certificate a minimum",
            r.is_clean() && minimum,
            format!(
                "{} after {} iterations; certificate {}; warnings: {}",
                r.solver.status,
                r.solver.iterations,
                certificate.map_or("none", |c| c.name()),
                if r.warnings.is_empty() {
                    "none".to_string()
                } else {
                    r.warnings.iter().map(|w| w.to_string()).collect::<Vec<_>>().join("; ")
                }
            ),
        ));
        out.summary.insert(
            run.name.to_string(),
            json!({
                "criterion": r.criterion,
                "objective": r.objective,
                "measures": r.measures,
                "clean": r.is_clean(),
                "theta0": r.design.theta0,
                "stiffness": r.design.stiffness,
            }),
        );
    }
    out.claims.extend(best_under_own_criterion(runs, &designs));
    out.tables.push(("measures.csv".into(), measures_table(runs, &designs)));
    out.figures.push(("figure".into(), fig));
    Ok(out)
}

/// A run's best clean optimum of its census (the case's own start's where there is none).
fn best(s: &StaticDesign) -> &StaticDesign {
    s.best.as_deref().map_or(s, |b| &b.design)
}

/// Whether design `d` is a clean design of `s`'s problem: it meets `s`'s strain-energy budget
/// too (the paper's constraints every run meets).
fn feasible_for(s: &StaticDesign, d: &StaticDesign) -> bool {
    let budget = s.problem.strain_energy_max.unwrap_or(f64::INFINITY);
    // Within the budget up to Ipopt's relaxation of bounds (1e-8 · max(U_max, 1)) and its tolerance.
    let allowed = budget + 1.1e-8 * budget.max(1.0);
    d.result.is_clean() && d.result.measures.as_ref().is_some_and(|m| m.strain_energy <= allowed)
}

/// Each criterion's measure of a design, where every design has it (the compliance only where
/// its load case was solved).
fn measure(criterion: &Objective, s: &StaticDesign) -> Option<f64> {
    let m = s.result.measures.as_ref()?;
    match criterion {
        Objective::StrainEnergy => Some(m.strain_energy),
        Objective::TotalStiffness => Some(m.total_stiffness),
        Objective::PeakMoment { .. } => Some(m.peak_moment),
        Objective::Compliance { .. } => None,
    }
}

/// For each clean run of a criterion measured on every design: no other clean design that meets
/// the run's own constraints (its budget) measures lower. A failure is a finding, not a failed
/// computation (each run is the best of a census, a local optimum; the peak moment is compared as
/// `max |M|`, which the smooth `p`-norm approximates).
fn best_under_own_criterion(runs: &[NamedRun<'_>], designs: &[&StaticDesign]) -> Vec<Claim> {
    let mut claims = Vec::new();
    for (run, s) in runs.iter().zip(designs) {
        let criterion = &s.result.criterion;
        let Some(own) = measure(criterion, s).filter(|_| s.result.is_clean()) else { continue };
        let others: Vec<(String, f64)> = runs
            .iter()
            .zip(designs)
            .filter(|(r, d)| r.name != run.name && feasible_for(s, d))
            .filter_map(|(r, d)| measure(criterion, d).map(|v| (r.name.to_string(), v)))
            .collect();
        let pass = others.iter().all(|(_, v)| own <= v + TIE * v.abs().max(own.abs()));
        let listed = others.iter().map(|(n, v)| format!("{n} {v:.6e}")).collect::<Vec<_>>().join(", ");
        let statement =
            format!("the design optimised for {} is the best of the figure's designs under it", criterion.name());
        let test = "its measure ≤ that of every other clean design meeting its constraints";
        let measured = format!("{} {own:.6e}; others: {listed}", run.name);
        let test = match criterion {
            Objective::PeakMoment { .. } => format!("{test} (max |M|, which the p-norm smooths)"),
            _ => test.to_string(),
        };
        claims.push(Claim::new(run.name, &statement, test, pass, measured));
    }
    claims
}

/// Every criterion's measure of every design: `J` (J), `Σ K` (N·m/rad), `max |M|` (N·m) and the
/// compliance (J, where solved).
fn measures_table(runs: &[NamedRun<'_>], designs: &[&StaticDesign]) -> Table {
    let get = |f: &dyn Fn(&spine_design::objective::Measures) -> Option<f64>| {
        designs.iter().map(|s| s.result.measures.as_ref().and_then(f)).collect::<Vec<_>>()
    };
    Table::new()
        .labels("run", runs.iter().map(|r| r.name))
        .labels("criterion", designs.iter().map(|s| s.result.criterion.name()))
        .optional("strain_energy_j", get(&|m| Some(m.strain_energy)))
        .optional("total_stiffness_n_m_per_rad", get(&|m| Some(m.total_stiffness)))
        .optional("peak_moment_n_m", get(&|m| Some(m.peak_moment)))
        .optional("compliance_j", get(&|m| m.compliance))
}
