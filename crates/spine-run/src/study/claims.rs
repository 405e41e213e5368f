//! The paper's C_K statement (Sec. 5.1) read on the study's rows, per solver.

use super::{CkRow, CkSolver, CkStudy, SOLVERS};
use crate::claims::Claim;

/// Values closer than this, relative to the larger, are ties for [`kendall`] (a trend must be more
/// than solver tolerance).
const TIE: f64 = 1e-3;
/// The smallest relative change between the first and the last C_K that counts as an effect.
pub const EFFECT: f64 = 0.10;

fn differ(a: f64, b: f64) -> f64 {
    if (a - b).abs() <= TIE * a.abs().max(b.abs()) {
        0.0
    } else {
        (b - a).signum()
    }
}

/// Kendall's rank correlation of `y` against `x` (near ties count zero): +1 for a monotone increase.
fn kendall(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len();
    let mut s = 0.0;
    let mut pairs = 0.0;
    for i in 0..n {
        for j in i + 1..n {
            s += differ(x[i], x[j]) * differ(y[i], y[j]);
            pairs += 1.0;
        }
    }
    if pairs > 0.0 {
        s / pairs
    } else {
        0.0
    }
}

impl CkStudy {
    /// The rows a solver's claims are read on: the clean solves of the exact solver; for the
    /// fmincon-like one every design it returned that meets the constraints, converged or stopped
    /// at its iteration limit (fmincon returns its last iterate with exit flag 0, and the paper's
    /// designs are what it returned).
    pub(super) fn of(&self, solver: CkSolver) -> Vec<&CkRow> {
        self.rows
            .iter()
            .filter(|r| r.solver == solver && if solver.fmincon_like() { r.feasible } else { r.clean })
            .collect()
    }

    /// The paper's statement, checked for each solver on its rows (`CkStudy::of`): Kendall's τ
    /// of the stiffness coefficient of variation against C_K must be positive and that of
    /// `‖θ0 − θ0_s‖` negative, and each must change by more than 10 % from the smallest to the
    /// largest C_K.
    pub fn claims(&self) -> Vec<Claim> {
        let mut claims = Vec::new();
        for solver in SOLVERS {
            let rows = self.of(solver);
            let all = self.rows.iter().filter(|r| r.solver == solver).count();
            let x: Vec<f64> = rows.iter().map(|r| r.stiffness_scale).collect();
            let cv: Vec<f64> = rows.iter().map(|r| r.change.stiffness_variation).collect();
            let shape: Vec<f64> = rows.iter().map(|r| r.change.theta0_change).collect();
            let (tk, ts) = (kendall(&x, &cv), kendall(&x, &shape));
            let ends = |v: &[f64]| match (v.first(), v.last()) {
                (Some(a), Some(b)) => format!("{a:.4} → {b:.4} ({:+.1} %)", 100.0 * (b / a - 1.0)),
                _ => "—".into(),
            };
            let change = |v: &[f64]| match (v.first(), v.last()) {
                (Some(a), Some(b)) => b / a - 1.0,
                _ => 0.0,
            };
            let scope = solver.name();
            let scope = scope.as_str();
            let rows_read =
                if solver.fmincon_like() { "designs returned within the constraints" } else { "clean solves" };
            // The fmincon-like solver stopping short is a finding about the paper's optimiser, not
            // a failure of this program: its count is in the claims' numbers, not a check.
            let converged = self.rows.iter().filter(|r| r.solver == solver && r.clean).count();
            let counted = if solver.fmincon_like() {
                format!(" ({converged} of {all} converged, {} of {all} within the constraints)", rows.len())
            } else {
                claims.push(Claim::solver(
                    scope,
                    "eq. (33) solves cleanly at every C_K of the sweep",
                    "Ipopt converged, constraints met, both equilibria stable, on the load path",
                    rows.len() == all,
                    format!("{} of {all} solves clean", rows.len()),
                ));
                String::new()
            };
            claims.push(Claim::new(
                scope,
                "\"as the C_K is increased the stiffness variation between the nodes increases\" (Sec. 5.1)",
                format!("Kendall's τ of the coefficient of variation (CV) of K against C_K > 0 and CV up by more than {:.0} % from the smallest to the largest C_K ({rows_read})", 100.0 * EFFECT),
                rows.len() >= 2 && tk > 0.0 && change(&cv) > EFFECT,
                format!("τ = {tk:.3}; CV of K from C_K = 1 to 10⁴: {}{counted}", ends(&cv)),
            ));
            claims.push(Claim::new(
                scope,
                "\"whereas the change in orientation of the links is less apparent\" (Sec. 5.1)",
                format!("Kendall's τ of ‖θ0 − θ0_start‖ against C_K < 0 and ‖θ0 − θ0_start‖ down by more than {:.0} % from the smallest to the largest C_K ({rows_read})", 100.0 * EFFECT),
                rows.len() >= 2 && ts < 0.0 && change(&shape) < -EFFECT,
                format!("τ = {ts:.3}; ‖θ0 − θ0_start‖ from C_K = 1 to 10⁴: {} rad{counted}", ends(&shape)),
            ));
        }
        claims
    }
}

#[cfg(test)]
mod tests {
    use super::super::half_decades;
    use super::*;

    #[test]
    fn kendall_and_half_decades() {
        assert_eq!(kendall(&[1.0, 2.0, 3.0], &[1.0, 5.0, 9.0]), 1.0);
        assert_eq!(kendall(&[1.0, 2.0, 3.0], &[3.0, 2.0, 1.0]), -1.0);
        assert!((kendall(&[1.0, 2.0, 3.0], &[1.0, 3.0, 2.0]) - 1.0 / 3.0).abs() < 1e-15);
        // Differences below the tie tolerance are no trend.
        assert_eq!(kendall(&[1.0, 2.0, 3.0], &[1.0, 1.0001, 1.0002]), 0.0);
        let v = half_decades();
        assert_eq!(v.len(), 9);
        assert_eq!(v[0], 1.0);
        assert!((v[8] - 1e4).abs() < 1e-9);
    }
}
