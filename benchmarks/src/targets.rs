//! The targets the benchmark issues set, checked against the measurements: criterion's (AD
//! against the hand code, the Hessian, the fitted exponents, the KKT factorisation) and the peers
//! run's (eq. (33) against CasADi).

use crate::peers::PeerRow;
use crate::report::{fit_exponent, format_time, ratios, series, Measurement, FIT_FROM_N};

/// A target of the benchmark issue and whether the measurements meet it.
#[derive(Clone, Debug)]
pub struct Target {
    pub statement: String,
    pub measured: String,
    pub met: Option<bool>,
}

/// Checks the targets that criterion measures (the eq. (33) and CasADi targets come from
/// the peers run).
pub fn targets(measurements: &[Measurement], peers: &[PeerRow]) -> Vec<Target> {
    let by_name = series(measurements);
    let mut out = Vec::new();
    // Issue 51: AD at the speed of hand derivation.
    for (a, b, limit, statement) in [
        (
            "jacobian/ad",
            "jacobian/hand",
            1.1,
            "AD Jacobian ≤ 1.1 × the hand-derived one (residual and Jacobian) at every N",
        ),
        ("jacobian/ad", "jacobian/hand_fused", 1.5, "AD Jacobian ≤ 1.5 × the fused hand loop at every N"),
        ("gradients/ad", "gradients/hand", 1.3, "AD adjoint gradients ≤ 1.3 × the hand adjoint at every N"),
    ] {
        if let (Some(sa), Some(sb)) = (by_name.get(a), by_name.get(b)) {
            let ratios = ratios(sa, sb);
            let worst = ratios.iter().fold(0.0f64, |m, r| m.max(r.1));
            out.push(Target {
                statement: statement.into(),
                measured: ratios.iter().map(|(n, r)| format!("N={n}: {r:.2}×")).collect::<Vec<_>>().join(", "),
                met: Some(worst <= limit),
            });
        }
    }
    if let Some(at_1000) = by_name.get("hessian").and_then(|s| s.iter().find(|(n, _)| *n == 1000)) {
        out.push(Target {
            statement: "Hessian of the Lagrangian at N = 1000 ≤ 0.8 ms".into(),
            measured: format_time(at_1000.1),
            met: Some(at_1000.1 <= 0.8e-3),
        });
    }
    // Issue 51, item 3: the sensitivity step of design10 (19 parameters) at most twice its reduced
    // KKT factorisation and solves.
    let step = by_name.get("optimum_parameters/sensitivity_step");
    let baseline = by_name.get("optimum_parameters/factorisation_and_solves");
    if let (Some(step), Some(baseline)) = (step, baseline) {
        if let Some(&(n, r)) = ratios(step, baseline).first() {
            out.push(Target {
                statement: "the sensitivity step (design10, 19 parameters) ≤ 2 × its factorisation and solves".into(),
                measured: format!("N={n}: {r:.2}×"),
                met: Some(r <= 2.0),
            });
        }
    }
    for name in ["residual", "jacobian/ad", "hessian", "newton_step"] {
        let p = by_name.get(name).and_then(|s| fit_exponent(s, FIT_FROM_N));
        out.push(Target {
            statement: format!("p ≤ 1.2 for {name}"),
            measured: p.map_or("not measured".into(), |p| format!("p = {p:.2}")),
            met: p.map(|p| p <= 1.2),
        });
    }
    let (spine, mumps) = (by_name.get("kkt_factorization/spine"), by_name.get("kkt_factorization/mumps"));
    if let (Some(spine), Some(mumps)) = (spine, mumps) {
        let replayed = ratios(spine, mumps);
        let at_1000 = replayed.iter().find(|(n, _)| *n == 1000).map(|r| r.1);
        let mut measured = replayed.iter().map(|(n, r)| format!("N={n}: {r:.2}×")).collect::<Vec<_>>().join(", ");
        if let Some(search) = by_name.get("kkt_factorization/spine_search") {
            let searched = ratios(search, mumps);
            measured += &format!(
                " (pivots replayed); every pivot searched: {}",
                searched.iter().map(|(n, r)| format!("N={n}: {r:.2}×")).collect::<Vec<_>>().join(", ")
            );
        }
        out.push(Target {
            statement: "one KKT factorisation at N = 1000 at most 0.3 × MUMPS's on the same matrix".into(),
            measured,
            met: at_1000.map(|r| r <= 0.3),
        });
    }
    out.extend(peer_targets(peers));
    out
}

/// The eq. (33) targets, from the peers run: convergence of the refined path at every N,
/// N = 1000 within 20 s (Debian's Ipopt) and 5 s (Ipopt 3.14), and the wall-time ratios to CasADi.
pub fn peer_targets(peers: &[PeerRow]) -> Vec<Target> {
    let mut out = Vec::new();
    let measured =
        |v: Vec<String>| if v.is_empty() { "not measured (run `just bench-peers`)".to_string() } else { v.join(", ") };
    let refined: Vec<_> = peers.iter().filter_map(|r| r.ours_refined.as_ref().map(|x| (r.n, x))).collect();
    out.push(Target {
        statement: "refined path, default backend: `solve_succeeded` (tol 1e-8) at every N".into(),
        measured: measured(
            refined
                .iter()
                .map(|(n, x)| format!("N={n}: {}", if x.converged { "yes".to_string() } else { x.status.clone() }))
                .collect(),
        ),
        met: (!refined.is_empty()).then(|| refined.iter().all(|(_, x)| x.converged)),
    });
    let at_1000 = peers.iter().find(|r| r.n == 1000);
    for (statement, run, limit) in [
        (
            "N = 1000 converged in under 20 s, default backend (refined)",
            at_1000.and_then(|r| r.ours_refined.as_ref()),
            20.0,
        ),
        (
            "N = 1000 converged in under 5 s, Ipopt 3.14 backend (refined)",
            at_1000.and_then(|r| r.ipopt314_refined.as_ref()),
            5.0,
        ),
    ] {
        out.push(Target {
            statement: statement.into(),
            measured: run.map_or("not measured (run `just bench-peers`)".into(), |x| {
                format!(
                    "{} in {} ({} iterations at N, the certificate's re-solves included)",
                    x.status,
                    format_time(x.wall_seconds),
                    x.iterations
                )
            }),
            met: run.map(|x| x.converged && x.wall_seconds < limit),
        });
    }
    let ratios: Vec<_> =
        peers.iter().filter_map(|r| r.best_ratio().map(|x| (r.n, x, r.best().map_or("", |b| b.0)))).collect();
    let same_ladder: Vec<_> = peers
        .iter()
        .filter_map(|r| match (r.ours_refined.as_ref(), r.casadi_refined.as_ref()) {
            (Some(a), Some(b)) if a.converged && !a.levels.is_empty() => Some((r.n, a.wall_seconds / b.wall_seconds)),
            _ => None,
        })
        .collect();
    out.push(Target {
        statement: "refined, default backend ≤ 1.0 × CasADi through the same ladder".into(),
        measured: measured(same_ladder.iter().map(|(n, x)| format!("N={n}: {x:.2}")).collect()),
        met: (!same_ladder.is_empty()).then(|| same_ladder.iter().all(|(_, x)| *x <= 1.0)),
    });
    out.push(Target {
        statement: "best converged path of ours ≤ 0.5 × CasADi's cold wall time at every N".into(),
        measured: measured(ratios.iter().map(|(n, x, name)| format!("N={n}: {x:.2} ({name})")).collect()),
        met: (!ratios.is_empty()).then(|| ratios.len() == peers.len() && ratios.iter().all(|(_, x, _)| *x <= 0.5)),
    });
    out
}
