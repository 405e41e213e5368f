//! Figures of the static design, eq. (33): Figs. 3, 4, 6–8 (shape and stiffness of each run) and
//! Fig. 5 (the design as the transverse load varies).

use super::*;
use serde_json::json;
use spine_run::claims::BranchOf;
use spine_run::metrics::{relative_sensitivity_ratio, sensitivity_ratio, DesignChange};
use spine_run::text::quantity;

/// Tolerance on `|X_{N+1}(θ2) − L_x − δ_d|`, m: the constraint tolerance of the solves (1e-8) with room.
const END_TOLERANCE: f64 = 1e-6;
/// "A is larger than B" means `A > (1 + MARGIN) B`: a difference of a few per cent between local
/// optima is no tendency.
const MARGIN: f64 = 0.05;

fn eig(s: &Option<spine_design::result::StateReport>) -> String {
    match s {
        Some(r) => format!(
            "{} (λ_min {})",
            if r.stability.stable { "stable" } else { "UNSTABLE" },
            r.stability.min_eigenvalue.map_or("none".into(), |e| format!("{e:.3e} N·m/rad"))
        ),
        None => "none".into(),
    }
}

/// The claims every static design run is held to (Sec. 5.1 and the conclusions).
pub(super) fn design_claims(scope: &str, s: &StaticDesign) -> (Vec<Claim>, Value) {
    let r = &s.result;
    let n = r.design.theta0.len();
    let change = DesignChange::new(&r.design, &s.start);
    let end_error = r.end_displacement.map_or(f64::INFINITY, |d| (d - r.delta_d).abs());
    let stable = |x: &Option<spine_design::result::StateReport>| x.as_ref().is_some_and(|x| x.stability.stable);
    // The fmincon-like solver is read as fmincon returns: its last iterate, converged or stopped at
    // its iteration limit, if it meets the constraints (how it stopped is in the numbers).
    let fmincon = s.preset == spine_design::SolverPreset::FminconLike;
    let (how, ended) = if fmincon {
        (
            "fmincon-like (reduced space, L-BFGS, 1e-6, 1000 iterations) returned a design within the constraints",
            r.is_feasible(),
        )
    } else {
        ("Ipopt converged", r.is_clean())
    };
    let mut claims = vec![Claim::solver(
        scope,
        "the end displacement equals δ_d and both loaded equilibria are stable (eq. (33))",
        format!("{how}, |X(θ2) − L_x − δ_d| ≤ {END_TOLERANCE:.0e} m, θ1 and θ2 stable and on the load path"),
        ended && end_error <= END_TOLERANCE && stable(&r.passive) && stable(&r.loaded),
        format!(
            "{} after {} iterations; X(θ2) − L_x = {} m against δ_d = {} m (error {end_error:.1e} m); θ1 {}; θ2 {}; load path {}",
            r.solver.status,
            r.solver.iterations,
            r.end_displacement.map_or("none".into(), |d| format!("{d:.9}")),
            r.delta_d,
            eig(&r.passive),
            eig(&r.loaded),
            if r.load_path.consistent { "consistent" } else { "NOT consistent" }
        ),
    )];
    claims.push(Claim::new(
        scope,
        "\"change in orientation is preferred to change in stiffness\" (Conclusions)",
        format!(
            "relative change from the start ‖θ0 − θ0_s‖/‖θ0_s‖ more than {:.0} % larger than ‖K − K_s‖/‖K_s‖",
            100.0 * MARGIN
        ),
        change.theta0_relative_change > (1.0 + MARGIN) * change.stiffness_relative_change,
        format!(
            "θ0 changed by {:.3} (relative), K by {:.3} (relative); ‖Δθ0‖ = {:.4} rad",
            change.theta0_relative_change, change.stiffness_relative_change, change.theta0_change
        ),
    ));
    let ratio = s.gradients.as_ref().map(|g| sensitivity_ratio(&g.energy_gradient, n));
    // Raw R carries units (N·m/rad²): it holds wherever K ≫ 1 N·m/rad, so it is reported as a
    // check, not counted as the paper's statement; reading 2 is the paper's.
    claims.push(Claim::solver(
        scope,
        "\"the objective function is more sensitive to change in θ0 in comparison to change in K\" (R > 1, eq. (17))",
        "reading 1, R = ‖∂J/∂θ0‖₂ / ‖∂J/∂K‖₂ at the optimum (reduced gradients by the hand adjoint) > 1 (N·m/rad², so it holds by units wherever K ≫ 1 N·m/rad: not counted as the paper's)",
        ratio.is_some_and(|r| r > 1.0),
        ratio.map_or("no gradient (no equilibria at the optimum)".into(), |r| format!("R = {r:.4e} (N·m/rad²)")),
    ));
    let relative = s.gradients.as_ref().map(|g| relative_sensitivity_ratio(&g.energy_gradient, &r.design));
    claims.push(Claim::new(
        scope,
        "\"the objective function is more sensitive to change in θ0 in comparison to change in K\" (R > 1, eq. (17))",
        "reading 2, R as the ratio of percentage changes eq. (17) derives: ‖θ0 ∘ ∂J/∂θ0‖₂ / ‖K ∘ ∂J/∂K‖₂ > 1 (dimensionless)",
        relative.is_some_and(|r| r > 1.0),
        relative.map_or("no gradient (no equilibria at the optimum)".into(), |r| format!("R_rel = {r:.4e}")),
    ));
    let end_load = "\"the change is more pronounced near the point of end-point load\" (Conclusions)";
    claims.push(Claim::new(
        scope,
        end_load,
        format!("mean |θ0_i − θ0_s,i| over the links nearer the end (i > N/2, the middle link of odd N counted there) more than {:.0} % larger than over the links nearer the base", 100.0 * MARGIN),
        change.end_half_change > (1.0 + MARGIN) * change.base_half_change,
        format!("end half {:.4} rad, base half {:.4} rad", change.end_half_change, change.base_half_change),
    ));
    if n % 2 == 1 {
        claims.push(Claim::new(
            scope,
            end_load,
            format!("reading 2, halves split symmetrically (odd N: the middle link in neither): end-half mean change more than {:.0} % larger than the base half's", 100.0 * MARGIN),
            change.end_half_change_symmetric > (1.0 + MARGIN) * change.base_half_change_symmetric,
            format!("end half {:.4} rad, base half {:.4} rad", change.end_half_change_symmetric, change.base_half_change_symmetric),
        ));
    }
    let summary = json!({
        "links": n,
        "stiffness_scale": r.stiffness_scale,
        "objective": r.objective,
        "end_displacement": r.end_displacement,
        "delta_d": r.delta_d,
        "clean": r.is_clean(),
        "solver": s.preset.name(),
        "status": r.solver.status,
        "iterations": r.solver.iterations,
        "change": change,
        "sensitivity_ratio": ratio,
        "relative_sensitivity_ratio": relative,
        "theta0": r.design.theta0,
        "stiffness": r.design.stiffness,
    });
    (claims, summary)
}

/// [`design_claims`] of a drawn design, held to each optimum of its knife edge where its moved
/// starts reached more than one (the verdicts per branch, [`Claim::branched`]); the summary says
/// what the moved starts reached.
pub(super) fn held_claims(scope: &str, s: &StaticDesign) -> (Vec<Claim>, Value) {
    let (claims, mut summary) = design_claims(scope, s);
    let Some(k) = s.knife_edge.as_deref() else {
        return (claims, summary);
    };
    let edge = &k.edge;
    summary["knife_edge"] = json!(edge);
    let unmoved = edge.branch_of(0);
    if !edge.split && unmoved.is_some() {
        return (claims, summary);
    }
    let of = |b: &spine_design::knife_edge::Branch| BranchOf {
        objective: b.objective,
        starts: b.starts.len(),
        unmoved: b.starts.contains(&0),
        counted: true,
    };
    let mut per_branch: Vec<(BranchOf, Vec<Claim>)> =
        edge.branches.iter().zip(&k.designs).map(|(b, d)| (of(b), design_claims(scope, d).0)).collect();
    let unmoved_failed = edge.failed.iter().any(|(k, _)| *k == 0);
    if let Some(failed) = &k.failed {
        let starts = edge.failed.iter().filter(|(k, _)| *k > 0).count();
        let of = BranchOf { objective: failed.result.objective, starts, unmoved: unmoved_failed, counted: true };
        per_branch.push((of, design_claims(scope, failed).0));
    }
    // The unmoved start's own outcome, where no moved start had it (an optimum only it reached,
    // or a failure where every moved start converged): shown, not counted.
    if unmoved.is_none() && !(unmoved_failed && k.failed.is_some()) {
        let of = BranchOf { objective: s.result.objective, starts: 1, unmoved: true, counted: false };
        per_branch.push((of, claims));
    }
    (Claim::branched(per_branch), summary)
}

/// Which design of a run a static figure draws.
#[derive(Clone, Copy)]
enum Drawn<'a> {
    /// The optimum from the case's (the paper's) start.
    Start,
    /// The best optimum of a census.
    Best(&'a spine_run::BestDesign),
    /// The fmincon-like solver's design from the same start.
    FminconLike,
    /// An optimum of the start's knife edge that the unmoved start did not reach: `(branch, its
    /// starts, moved starts in all)`.
    Branch(usize, usize, usize),
}

/// One shape panel and one stiffness panel per run: Figs. 3, 4, 6, 7, 8.
pub fn design_figure(figure: &str, title: &str, runs: &[NamedRun<'_>]) -> Result<FigureOutput, FieldError> {
    let mut out = FigureOutput::default();
    let mut fig = Figure::new(title, 2);
    let mut designs = Vec::new();
    let mut panel = 0;
    for (k, run) in runs.iter().enumerate() {
        let s = expect_design(run)?;
        designs.push(s);
        // The optimum from the paper's start, then (with a census) the best optimum found.
        // and (when asked) the fmincon-like solver's design from the paper's start.
        let best = s.best.as_deref().map(|b| (&b.design, Drawn::Best(b)));
        let fmincon = s.fmincon_like.as_deref().map(|d| (d, Drawn::FminconLike));
        // The optima of the start's knife edge that the unmoved start did not reach.
        let branches = s.knife_edge.as_deref().into_iter().flat_map(|k| {
            let moved = 2 * k.edge.settings.pairs;
            let others =
                k.edge.branches.iter().zip(&k.designs).enumerate().filter(|(_, (b, _))| !b.starts.contains(&0));
            others.map(move |(i, (b, d))| (d, Drawn::Branch(i, b.starts.len(), moved)))
        });
        let drawn = std::iter::once((s, Drawn::Start)).chain(branches).chain(best).chain(fmincon);
        for (d, kind) in drawn {
            let census = match kind {
                Drawn::Best(b) => Some(b),
                _ => None,
            };
            let (suffix, label) = match (kind, &s.best) {
                (Drawn::Start, None) => (String::new(), run.title().to_string()),
                (Drawn::Start, Some(_)) => (String::new(), format!("{}, paper's start", run.title())),
                (Drawn::Branch(i, n, moved), _) => (
                    format!("_branch{i}"),
                    format!("{}, knife-edge branch {i} ({n} of {moved} moved starts)", run.title()),
                ),
                (Drawn::Best(b), _) => ("_best".into(), format!("{}, best of {} optima", run.title(), b.optima)),
                (Drawn::FminconLike, _) => ("_fmincon".into(), format!("{}, fmincon-like", run.title())),
            };
            let shapes = Shapes::of_static(d).ok_or_else(|| run.error("the design has no equilibria to draw"))?;
            fig = fig.with(shapes.panel(&format!("({}) {label}: shapes", letter(panel)))).with(stiffness_panel(
                &format!("({}) {label}: nodal stiffness", letter(panel + 1)),
                vec![Series::bars("", points(&d.result.design.stiffness, 1)).colour(k)],
            ));
            panel += 2;
            out.tables.push((format!("shape_{}{suffix}.csv", run.name), shapes.table()));
            out.tables.push((format!("design_{}{suffix}.csv", run.name), design_table(&d.result.design)));
            let scope = format!(
                "{}{}",
                run.name,
                match kind {
                    Drawn::Start => "",
                    Drawn::Best(_) => " best",
                    Drawn::FminconLike => " fmincon-like",
                    // Its claims are the start's, held to each branch (`held_claims`).
                    Drawn::Branch(..) => continue,
                }
            );
            let (claims, mut summary) = held_claims(&scope, d);
            if let Some(b) = census {
                summary["census"] = json!({
                    "optima": b.optima,
                    "reported_start": b.reported_start,
                    "same_as_start": b.same_as_start,
                    "estimate": b.census,
                    "confidence": b.confidence,
                });
            }
            out.claims.extend(claims);
            out.summary.insert(format!("{}{suffix}", run.name), summary);
        }
        // The best optimum's mirror image has the same `J`: the claims are held to it too, so
        // that a verdict that turns with the image shows as such.
        if let Some(image) = s.best.as_deref().and_then(|b| b.mirror_image.as_ref()) {
            let (claims, summary) = design_claims(&format!("{} best, mirror image", run.name), image);
            out.claims.extend(claims);
            out.summary.insert(format!("{}_best_mirror_image", run.name), summary);
        }
    }
    if figure == "fig4" {
        out.claims.extend(localized_load_claims(runs, &designs)?);
    }
    out.figures.push(("figure".into(), fig));
    Ok(out)
}

/// Fig. 4: the first run carries the localized load, the second the uniform one.
fn localized_load_claims(runs: &[NamedRun<'_>], designs: &[&StaticDesign]) -> Result<Vec<Claim>, FieldError> {
    let [local, uniform] = designs else {
        return Err(FieldError::new("runs", "fig4 needs two runs: the localized load first, then the uniform load"));
    };
    let (pl, pu) = (&local.problem.structure.passive.p_y, &uniform.problem.structure.passive.p_y);
    if pl.len() != pu.len() {
        return Err(FieldError::new("runs", "fig4: both runs need the same number of links"));
    }
    // Loaded nodes: where the localized run's transverse load is larger in magnitude.
    let loaded: Vec<usize> = (0..pl.len()).filter(|&j| pl[j].abs() > pu[j].abs() + 1e-12).collect();
    if loaded.is_empty() || loaded.len() == pl.len() {
        return Err(runs[0].error(format!("must load some nodes more than {:?}, not all", runs[1].name)));
    }
    let n = local.result.design.theta0.len();
    let mean_at = |k: &[f64], idx: &[usize]| idx.iter().map(|&j| k[j]).sum::<f64>() / idx.len() as f64;
    let (kl, ku) = (&local.result.design.stiffness, &uniform.result.design.stiffness);
    let (k_local, k_uniform) = (mean_at(kl, &loaded), mean_at(ku, &loaded));
    // Links touching a loaded node (link i joins nodes i and i + 1, 0-based).
    let in_region: Vec<bool> = (0..n).map(|i| loaded.contains(&i) || loaded.contains(&(i + 1))).collect();
    let dtheta: Vec<f64> =
        (0..n).map(|i| (local.result.design.theta0[i] - uniform.result.design.theta0[i]).abs()).collect();
    let mean_where = |want: bool| {
        let v: Vec<f64> = (0..n).filter(|&i| in_region[i] == want).map(|i| dtheta[i]).collect();
        v.iter().sum::<f64>() / v.len().max(1) as f64
    };
    let (d_in, d_out) = (mean_where(true), mean_where(false));
    let (el, eu) = (local.result.end_displacement, uniform.result.end_displacement);
    let gap = match (el, eu) {
        (Some(a), Some(b)) => (a - b).abs(),
        _ => f64::INFINITY,
    };
    let nodes: Vec<usize> = loaded.iter().map(|j| j + 1).collect();
    Ok(vec![
        // δ_d is a constraint of eq. (33): both designs meet it by construction, so this checks
        // the solves, not the paper.
        Claim::solver(
            "figure",
            "\"end-point motion indifference to the variation of localized loading\" (Sec. 5.1): both designs meet the same δ_d, a constraint of eq. (33)",
            format!("both designs end clean and their end displacements differ by ≤ {END_TOLERANCE:.0e} m"),
            local.result.is_clean() && uniform.result.is_clean() && gap <= END_TOLERANCE,
            format!(
                "X(θ2) − L_x: localized {}, uniform {} (difference {gap:.1e} m)",
                quantity(el, 6, "m", "no loaded equilibrium"),
                quantity(eu, 6, "m", "no loaded equilibrium")
            ),
        ),
        Claim::new(
            "figure",
            "\"localized stiffening of the structure\" (Sec. 5.1)",
            format!("mean K at the more loaded nodes {} (paper numbering, base = 1) more than {:.0} % higher under the localized load than under the uniform load", spine_run::text::joined(&nodes), 100.0 * MARGIN),
            k_local > (1.0 + MARGIN) * k_uniform,
            format!("mean K there: localized {k_local:.1} N·m/rad, uniform {k_uniform:.1} N·m/rad (ratio {:.3})", k_local / k_uniform),
        ),
        Claim::new(
            "figure",
            "\"by changing the orientation of links of the loaded region the effect of the extra load is mitigated\" (Sec. 5.1)",
            format!("mean |θ0_localized − θ0_uniform| more than {:.0} % larger on the links touching the loaded nodes than on the others", 100.0 * MARGIN),
            d_in > (1.0 + MARGIN) * d_out,
            format!("loaded region {d_in:.4} rad, elsewhere {d_out:.4} rad"),
        ),
    ])
}

/// Fig. 5: `θ0` and `K` of every run (one per transverse load) on one pair of panels.
pub fn load_sweep_figure(title: &str, runs: &[NamedRun<'_>]) -> Result<FigureOutput, FieldError> {
    let mut out = FigureOutput::default();
    let mut shape = Panel::new("(a) design angle θ₀ under various loads", "link i", "θ₀,ᵢ (rad)").x_integer();
    let mut stiffness =
        Panel::new("(b) nodal stiffness K under various loads", "node j", "Kⱼ (N·m/rad)").x_integer().y_log();
    let mut table = Table::new();
    for (k, run) in runs.iter().enumerate() {
        let s = expect_design(run)?;
        let d = &s.result.design;
        shape = shape.with(Series::line_markers(run.title(), points(&d.theta0, 1)).colour(k));
        stiffness = stiffness.with(Series::line_markers(run.title(), points(&d.stiffness, 1)).colour(k));
        let mut rows = design_table(d);
        let run_names = spine_run::Cells::Labels(vec![run.name.to_string(); d.stiffness.len()]);
        rows.columns.insert(0, spine_run::Column { name: "run".into(), cells: run_names });
        table.extend(rows);
        let (claims, summary) = held_claims(run.name, s);
        out.claims.extend(claims);
        out.summary.insert(run.name.to_string(), summary);
        if let Some(f) = s.fmincon_like.as_deref() {
            let fd = &f.result.design;
            let label = format!("{}, fmincon-like", run.title());
            shape = shape.with(Series::dashed(label.clone(), points(&fd.theta0, 1)).colour(k));
            stiffness = stiffness.with(Series::dashed(label, points(&fd.stiffness, 1)).colour(k));
            let mut rows = design_table(fd);
            let run_names = spine_run::Cells::Labels(vec![format!("{}_fmincon", run.name); fd.stiffness.len()]);
            rows.columns.insert(0, spine_run::Column { name: "run".into(), cells: run_names });
            table.extend(rows);
            let (claims, summary) = held_claims(&format!("{} fmincon-like", run.name), f);
            out.claims.extend(claims);
            out.summary.insert(format!("{}_fmincon", run.name), summary);
        }
    }
    out.tables.push(("designs.csv".into(), table));
    out.figures.push(("figure".into(), Figure::new(title, 2).with(shape).with(stiffness)));
    Ok(out)
}
