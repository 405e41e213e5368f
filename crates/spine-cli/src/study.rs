//! `spine study ck CASE`: the C_K study of eq. (34) on a design case.

use crate::output::Output;
use crate::{Failure, Outcome};
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::{json, Map};
use spine_case::{DesignCase, ValidDesign};
use spine_paper::study::ck_study;
use spine_paper::Check;

pub fn run(case: &DesignCase, valid: &ValidDesign, values: &[f64], out: &Output) -> Result<Outcome, Failure> {
    let title = format!("C_K study, eq. (34): {}", if case.title.is_empty() { "design case" } else { &case.title });
    println!("{title}: C_K = {values:?}, Ipopt scaling gradient-based and none");
    let bar = ProgressBar::new((2 * values.len()) as u64);
    bar.set_style(
        ProgressStyle::with_template("  eq. (33) solves {bar:40} {pos}/{len} [{elapsed_precise}]")
            .expect("valid template"),
    );
    let clock = std::time::Instant::now();
    let study = ck_study(valid, values, &mut |done, _| bar.set_position(done as u64))
        .map_err(|e| Failure::Input(e.to_string()))?;
    bar.finish_and_clear();
    let claims = study.claims();
    out.write_text("ck_study.csv", &study.csv())?;
    out.write_figure("figure", &study.figure(&title))?;
    let mut value = serde_json::to_value(&study).expect("serialises");
    let mut timings = Map::new();
    crate::figure::split_timings(&mut value, "", &mut timings);
    timings.insert("total_seconds".into(), json!(clock.elapsed().as_secs_f64()));
    let passed = claims.iter().filter(|c| c.pass).count();
    let result = json!({
        "kind": "study",
        "study": "ck",
        "title": title,
        "stiffness_scales": values,
        "claims": claims,
        "claims_passed": passed,
        "claims_total": claims.len(),
        "conclusion": study.conclusion(),
        "files": ["ck_study.csv", "figure.svg", "figure.png"],
        "study_rows": value["rows"],
        "timings": timings,
    });
    let path = out.write_json("result.json", result)?;
    println!(
        "{:>10} {:>15} {:>22} {:>5} {:>12} {:>8} {:>10} {:>10}",
        "C_K", "scaling", "status", "iter", "J (J)", "CV(K)", "maxK/minK", "‖Δθ0‖"
    );
    for r in &study.rows {
        println!(
            "{:>10.4e} {:>15} {:>22} {:>5} {:>12.5e} {:>8.4} {:>10.2} {:>10.4}",
            r.stiffness_scale,
            format!("{:?}", r.scaling),
            if r.clean { r.status.clone() } else { format!("{} (NOT clean)", r.status) },
            r.iterations,
            r.objective,
            r.change.stiffness_variation,
            r.change.stiffness_max_over_min,
            r.change.theta0_change
        );
    }
    println!("claims ({passed} of {} PASS):", claims.len());
    for c in &claims {
        println!("  {c}");
    }
    println!("conclusion: {}", study.conclusion());
    println!("wrote {}", path.display());
    let solver_ok = claims.iter().all(|c| c.pass || c.check != Check::Solver);
    Ok(if solver_ok { Outcome::Success } else { Outcome::NotConverged })
}
