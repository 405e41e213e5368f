//! `results/REPORT.md`: every figure's claims with PASS/FAIL and numbers, the figures themselves,
//! the cross-figure C_K check (Figs. 6–8), the errata and the run times, on one page.

use serde_json::Value;
use std::fmt::Write as _;

/// A result folder's `result.json`, by case name (`fig3`, `study-ck`, …).
pub struct FolderResult {
    pub name: String,
    pub value: Value,
}

fn cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

fn total_seconds(v: &Value) -> Option<f64> {
    v.get("timings")?.get("total_seconds")?.as_f64()
}

/// The C_K statement on Figs. 6–8 (C_K = 1, 10², 10⁴): stiffness spread up, shape change down.
fn ck_across_figures(results: &[FolderResult]) -> Option<String> {
    let pick = |name: &str| -> Option<(f64, f64, f64)> {
        let r = results.iter().find(|r| r.name == name)?;
        let s = r.value.get("summary")?.get("n10")?;
        Some((
            s.get("stiffness_scale")?.as_f64()?,
            s.get("change")?.get("stiffness_variation")?.as_f64()?,
            s.get("change")?.get("theta0_change")?.as_f64()?,
        ))
    };
    let rows = [pick("fig6")?, pick("fig7")?, pick("fig8")?];
    // The study's rule: monotone, and a change of more than 10 % from C_K = 1 to 10⁴.
    let spread_up = rows.windows(2).all(|w| w[1].1 > w[0].1) && rows[2].1 / rows[0].1 - 1.0 > crate::study::EFFECT;
    let shape_down = rows.windows(2).all(|w| w[1].2 < w[0].2) && rows[2].2 / rows[0].2 - 1.0 < -crate::study::EFFECT;
    let mut text = String::from("| C_K | CV of K | ‖θ0 − θ0_start‖ (rad) |\n|---|---|---|\n");
    for (ck, cv, sh) in rows {
        let _ = writeln!(text, "| {ck} | {cv:.4} | {sh:.4} |");
    }
    let _ = writeln!(
        text,
        "\n- **{}** \"as the C_K is increased the stiffness variation between the nodes increases\": CV of K strictly increasing over Figs. 6, 7, 8 and up by more than 10 % from Fig. 6 to Fig. 8.\n- **{}** \"whereas the change in orientation of the links is less apparent\": ‖θ0 − θ0_start‖ strictly decreasing over Figs. 6, 7, 8 and down by more than 10 % from Fig. 6 to Fig. 8.",
        if spread_up { "PASS" } else { "FAIL" },
        if shape_down { "PASS" } else { "FAIL" }
    );
    Some(text)
}

/// Writes the report. `order` lists the case names in reading order; `errata` is the text of
/// `docs/errata.md`; `missing` lists cases without a result.
pub fn report(results: &[FolderResult], errata: &str, missing: &[String]) -> String {
    let mut md = String::from("# Reproduction report\n\n");
    md.push_str(
        "Every figure of the paper, computed by `just paper` (one `just case NAME` per figure, then `just study ck`). \
         Each claim is the paper's statement, the test this program holds it to (thresholds fixed in the code, \
         `crates/spine-paper`), the verdict and the measured numbers. A **solver** check is about this program's \
         own computation (converged, δ_d met, T_90 met); a **paper** check is a statement of the paper. A FAIL is \
         reported, never tuned away. The case files (`paper-cases/NAME.json`) list the paper's values and every \
         assumption with its reason.\n\n",
    );
    let (mut passed, mut total) = (0, 0);
    md.push_str("## Summary\n\n| case | title | claims passed | run time (s) |\n|---|---|---|---|\n");
    for r in results {
        let claims = r.value.get("claims").and_then(Value::as_array).map_or(&[][..], Vec::as_slice);
        let p = claims.iter().filter(|c| c.get("pass") == Some(&Value::Bool(true))).count();
        passed += p;
        total += claims.len();
        let title = r.value.get("title").and_then(Value::as_str).unwrap_or("");
        let t = total_seconds(&r.value).map_or("—".into(), |t| format!("{t:.1}"));
        let _ = writeln!(md, "| [{}](#{}) | {} | {p} / {} | {t} |", r.name, r.name, cell(title), claims.len());
    }
    for m in missing {
        let _ = writeln!(md, "| {m} | **no result** (the case did not run or failed) | — | — |");
    }
    let _ = writeln!(md, "\n**{passed} of {total} claims pass.**\n");

    md.push_str("## Claims\n\n| case | scope | check | statement | test | verdict | measured |\n|---|---|---|---|---|---|---|\n");
    for r in results {
        for c in r.value.get("claims").and_then(Value::as_array).into_iter().flatten() {
            let s = |k: &str| c.get(k).and_then(Value::as_str).unwrap_or("");
            let verdict = if c.get("pass") == Some(&Value::Bool(true)) { "PASS" } else { "**FAIL**" };
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {} | {verdict} | {} |",
                r.name,
                cell(s("scope")),
                s("check"),
                cell(s("statement")),
                cell(s("test")),
                cell(s("measured"))
            );
        }
    }
    if let Some(text) = ck_across_figures(results) {
        md.push_str("\n## C_K across Figs. 6–8\n\n");
        md.push_str(&text);
    }
    if let Some(c) = results.iter().find_map(|r| r.value.get("conclusion").and_then(Value::as_str)) {
        let _ = writeln!(md, "\n## C_K study: conclusion\n\n{c}");
    }
    md.push_str("\n## Figures\n");
    for r in results {
        let title = r.value.get("title").and_then(Value::as_str).unwrap_or("");
        let _ = writeln!(md, "\n### {}\n\n{}\n", r.name, cell(title));
        for f in r.value.get("files").and_then(Value::as_array).into_iter().flatten().filter_map(Value::as_str) {
            if f.ends_with(".svg") {
                let _ = writeln!(md, "![{} {f}]({}/{f})\n", r.name, r.name);
            }
        }
        let _ = writeln!(
            md,
            "Case file `paper-cases/{}.json`; data: `results/{}/` (`result.json` and CSV files).",
            r.name, r.name
        );
    }
    md.push_str(
        "\n## Errata\n\nThe slips found in the paper (`docs/errata.md`), each with the test that proves it.\n\n",
    );
    let table: Vec<&str> =
        errata.lines().skip_while(|l| !l.starts_with('|')).take_while(|l| l.starts_with('|')).collect();
    md.push_str(&table.join("\n"));
    md.push('\n');
    md
}
