//! `spine twolink`: Sec. 3 closed forms against the exact solution.

use crate::output::Output;
use crate::{Failure, Outcome};
use serde_json::json;
use spine_case::{TwoLinkCase, ValidTwoLink};

fn fmt_opt(v: Option<f64>, digits: usize) -> String {
    v.map_or("—".into(), |x| format!("{x:.digits$e}"))
}

pub fn run(case: &TwoLinkCase, valid: &ValidTwoLink, out: &Output) -> Result<Outcome, Failure> {
    let clock = std::time::Instant::now();
    let study = spine_solve::twolink::study(&valid.twolink, valid.stiffness, &valid.deltas, &valid.options);
    let seconds = clock.elapsed().as_secs_f64();
    let tl = &valid.twolink;
    let result = json!({
        "kind": "twolink",
        "title": case.title,
        "length": tl.length, "stiffness": valid.stiffness, "p_y": tl.p_y, "p_x": tl.p_x,
        "study": study,
        "timings": { "total_seconds": seconds },
    });
    let path = out.write_json("result.json", result)?;
    println!(
        "two-link analysis (Sec. 3): L = {} m, K = {} N·m/rad, P_Y = {} N, P_X = {} N; zero-moment angle θ* = {:.9} rad",
        tl.length, valid.stiffness, tl.p_y, tl.p_x, study.zero_moment_angle
    );
    println!("θ0 for each δ: exact (general N = 2 solver) vs eq. (10) as printed, on the right branch, and made first-order consistent");
    println!(
        "{:>11} {:>16} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12}",
        "δ (m)", "θ0 exact", "err (10) pr.", "err (10)", "err (10′)", "K(11)/K−1", "R (17) pr.", "R corrected"
    );
    let mut all_found = true;
    for r in &study.rows {
        let err = |v: f64| r.theta0_exact.map(|t| (v - t).abs());
        all_found &= r.theta0_exact.is_some();
        println!(
            "{:>11.3e} {:>16} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12}",
            r.delta,
            r.theta0_exact.map_or("not found".into(), |t| format!("{t:.12}")),
            fmt_opt(err(r.theta0_eq10_printed), 3),
            fmt_opt(err(r.theta0_eq10), 3),
            fmt_opt(err(r.theta0_first_order), 3),
            fmt_opt(r.stiffness_eq11.map(|k| k / valid.stiffness - 1.0), 3),
            fmt_opt(r.ratio_eq17_printed, 5),
            fmt_opt(r.ratio, 5),
        );
    }
    let o = &study.orders;
    println!(
        "observed orders in δ: eq. (10) θ0 error {}, first-order-consistent θ0 error {}, eq. (11) relative K error {}",
        fmt_opt(o.eq10, 3),
        fmt_opt(o.first_order, 3),
        fmt_opt(o.eq11_relative, 3)
    );
    println!("see docs/errata.md E2–E5 for the slips these columns show");
    println!("wrote {}", path.display());
    Ok(if all_found { Outcome::Success } else { Outcome::NotConverged })
}
