//! `results/REPORT.md` and `results/report.html`: every figure's claims with PASS/FAIL and
//! numbers, the figures themselves, the cross-figure C_K check (Figs. 6–8), the errata and the run
//! times, on one page. The HTML page is one self-contained file (figures inline, animations as
//! data URIs, no script, no network).

use crate::claim_text::{measured, passed, split, text_of, verdict};
use crate::counts::Counts;
use serde_json::Value;
use std::fmt::Write as _;

/// A result folder's `result.json`, by case name (`fig3`, `study-ck`, …).
pub struct FolderResult {
    pub name: String,
    pub value: Value,
    /// Files of the folder the HTML report shows, by name (`figure.svg` as SVG text,
    /// `animation.gif` as bytes); the caller reads them, this module writes nothing.
    pub assets: Vec<(String, Vec<u8>)>,
}

impl FolderResult {
    /// The claims of the result (none for a result without claims).
    fn claims(&self) -> &[Value] {
        self.value.get("claims").and_then(Value::as_array).map_or(&[][..], Vec::as_slice)
    }

    fn title(&self) -> &str {
        self.value.get("title").and_then(Value::as_str).unwrap_or("")
    }

    /// The files `result.json` lists that end in `extension`.
    fn files_ending(&self, extension: &str) -> Vec<&str> {
        let files = self.value.get("files").and_then(Value::as_array).into_iter().flatten();
        files.filter_map(Value::as_str).filter(|f| f.ends_with(extension)).collect()
    }
}

/// What a split claim is, where some claims are ([`split`]), else nothing.
fn split_note(results: &[FolderResult]) -> String {
    if results.iter().flat_map(|r| r.claims()).any(split) {
        " A split statement's verdict differs between the optima that starts moved by 1e-6 reach (a knife edge; docs/design.md, \"Knife edges\"): it is counted neither as PASS nor as FAIL.".into()
    } else {
        String::new()
    }
}

fn cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

/// The cross-figure statements of the paper the report decides (the C_K trend over Figs. 6–8),
/// with their verdicts.
fn across(results: &[FolderResult]) -> Vec<(bool, &'static str)> {
    ck_across(results).map_or(vec![], |ck| vec![(ck.spread_up, SPREAD_STATEMENT), (ck.shape_down, SHAPE_STATEMENT)])
}

/// The one count of claims, over every result and the cross-figure statements.
fn counts(results: &[FolderResult]) -> Counts {
    let verdicts: Vec<bool> = across(results).iter().map(|(p, _)| *p).collect();
    Counts::all(results, &verdicts)
}

/// `results/report.json`: the counts the report states and the failing statements with their
/// explanation's anchor in `docs/findings.md` ([`crate::counts::report_json`]).
pub fn report_json(results: &[FolderResult]) -> Value {
    crate::counts::report_json(results, &across(results), &finding)
}

/// The C_K statement on Figs. 6–8 (C_K = 1, 10², 10⁴): rows `(C_K, CV of K, ‖θ0 − θ0_start‖)`,
/// and whether the stiffness spread goes up and the shape change down.
struct CkAcross {
    rows: [(f64, f64, f64); 3],
    spread_up: bool,
    shape_down: bool,
}

const SPREAD_STATEMENT: &str = "\"as the C_K is increased the stiffness variation between the nodes increases\": CV of K strictly increasing over Figs. 6, 7, 8 and up by more than 10 % from Fig. 6 to Fig. 8.";
const SHAPE_STATEMENT: &str = "\"whereas the change in orientation of the links is less apparent\": ‖θ0 − θ0_start‖ strictly decreasing over Figs. 6, 7, 8 and down by more than 10 % from Fig. 6 to Fig. 8.";

/// The C_K statement on Figs. 6–8 (C_K = 1, 10², 10⁴) in Markdown.
fn ck_across_figures(results: &[FolderResult]) -> Option<String> {
    let CkAcross { rows, spread_up, shape_down } = ck_across(results)?;
    let mut text = String::from("| C_K | CV of K | ‖θ0 − θ0_start‖ (rad) |\n|---|---|---|\n");
    for (ck, cv, sh) in rows {
        let _ = writeln!(text, "| {ck} | {cv:.4} | {sh:.4} |");
    }
    let why = |pass: bool| if pass { String::new() } else { format!(" ([why]({FINDINGS}#ck-trend))") };
    let _ = writeln!(
        text,
        "\n- **{}**{} {SPREAD_STATEMENT}\n- **{}**{} {SHAPE_STATEMENT}",
        verdict(spread_up),
        why(spread_up),
        verdict(shape_down),
        why(shape_down)
    );
    Some(text)
}

fn ck_across(results: &[FolderResult]) -> Option<CkAcross> {
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
    let spread_up = rows.windows(2).all(|w| w[1].1 > w[0].1) && rows[2].1 / rows[0].1 - 1.0 > spine_run::study::EFFECT;
    let shape_down =
        rows.windows(2).all(|w| w[1].2 < w[0].2) && rows[2].2 / rows[0].2 - 1.0 < -spine_run::study::EFFECT;
    Some(CkAcross { rows, spread_up, shape_down })
}

/// Writes the report. `order` lists the case names in reading order; `errata` is the text of
/// `docs/errata.md`; `missing` lists cases without a result.
pub fn report(results: &[FolderResult], errata: &str, missing: &[String]) -> String {
    let mut md = String::from("# Reproduction report\n\n");
    md.push_str(
        "Every figure of the paper, computed by `just paper` (one `just case NAME` per figure, then `just study ck`). \
         Each claim is the paper's statement, the test this program holds it to (thresholds fixed in the code, \
         `crates/spine-paper`), the verdict and the measured numbers. A **solver** check is about this program's \
         own computation (converged, δ_d met, T_90 met) or a statement that cannot fail here (it holds by units, or by a \
         target the program enforces or took from its own runs); a **paper** check is a statement of the paper that the \
         computation could contradict, and only those are counted as the paper's. A FAIL is \
         reported, never tuned away. The case files (`paper-cases/NAME.json`) list the paper's values and every \
         assumption with its reason.\n\n",
    );
    md.push_str("## Summary\n\n| case | title | paper statements passed | solver checks passed | run time (s) |\n|---|---|---|---|---|\n");
    for (r, (p, s, t)) in results.iter().zip(crate::counts::rows(results)) {
        let _ = writeln!(md, "| [{}](#{}) | {} | {p} | {s} | {t} |", r.name, r.name, cell(r.title()));
    }
    for m in missing {
        let _ = writeln!(md, "| {m} | **no result** (the case did not run or failed) | — | — | — |");
    }
    let _ = writeln!(md, "\n**{}**{}\n", counts(results).sentence(), split_note(results));

    md.push_str("## Claims\n\n| case | scope | check | statement | test | verdict | measured |\n|---|---|---|---|---|---|---|\n");
    for r in results {
        for c in r.claims() {
            let s = |k: &str| text_of(c, k);
            let verdict = match (passed(c), finding(s("statement"))) {
                _ if split(c) => {
                    "**SPLIT** (a knife edge: the verdict differs between the optima its moved starts reach)"
                        .to_string()
                }
                (true, _) => "PASS".to_string(),
                (false, None) => "**FAIL**".to_string(),
                (false, Some(anchor)) => format!("**FAIL** ([why]({FINDINGS}#{anchor}))"),
            };
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {} | {verdict} | {} |",
                r.name,
                cell(s("scope")),
                s("check"),
                cell(s("statement")),
                cell(s("test")),
                cell(&measured(c))
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
        let _ = writeln!(md, "\n### {}\n\n{}\n", r.name, cell(r.title()));
        for f in r.files_ending(".svg").into_iter().chain(r.files_ending(".gif")) {
            let _ = writeln!(md, "![{} {f}]({}/{f})\n", r.name, r.name);
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
    md.push_str(&errata_table(errata).join("\n"));
    md.push('\n');
    md
}

/// `docs/findings.md` as seen from the results folder (`results/REPORT.md`, `results/report.html`).
pub const FINDINGS: &str = "../docs/findings.md";

/// The paper's statements whose FAIL `docs/findings.md` explains, with the section's anchor: a
/// fragment of the statement as the claims spell it.
const FINDINGS_SECTIONS: [(&str, &str); 11] = [
    ("the time constant of the structure is obtained", "time-constant"),
    ("more sensitive to change in θ0 in comparison to change in K", "sensitivity-ratio"),
    ("∂L/∂K is less than ∂L/∂θ0", "sec3"),
    ("comparing this result with that obtained by genetic algorithm", "fig11-similarity"),
    ("orientation is preferred to change in stiffness", "orientation-vs-stiffness"),
    ("more pronounced near the point of end-point load", "change-near-the-end-load"),
    ("localized stiffening", "localized-stiffening"),
    ("as the C_K is increased", "ck-trend"),
    ("change in orientation of the links is less apparent", "ck-trend"),
    ("reaches the desired δ in 0.5 seconds", "fig10-timings"),
    ("returns to its original state in about 0.25 seconds", "fig10-timings"),
];

/// The anchor in `docs/findings.md` of the section explaining why `statement` fails, if any.
pub fn finding(statement: &str) -> Option<&'static str> {
    FINDINGS_SECTIONS.iter().find(|(fragment, _)| statement.contains(fragment)).map(|(_, anchor)| *anchor)
}

/// The lines of the first Markdown table of `docs/errata.md`.
fn errata_table(errata: &str) -> Vec<&str> {
    errata.lines().skip_while(|l| !l.starts_with('|')).take_while(|l| l.starts_with('|')).collect()
}

/// `text` with `&`, `<`, `>` and `"` escaped for HTML.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    out
}

const STYLE: &str = "body{font-family:'DejaVu Sans',Arial,sans-serif;max-width:1200px;margin:2em auto;padding:0 1em;color:#222;line-height:1.4}\
table{border-collapse:collapse;margin:1em 0;font-size:0.9em}th,td{border:1px solid #bbb;padding:4px 6px;vertical-align:top;text-align:left}\
th{background:#eee}td.pass{background:#c8eac8;font-weight:bold}td.fail{background:#f4c2c2;font-weight:bold}td.split{background:#f4e2a2;font-weight:bold}\
code{background:#f2f2f2;padding:0 2px}figure{margin:1em 0}figure svg,figure img{max-width:100%;height:auto;border:1px solid #ddd}\
.total{font-size:1.1em;font-weight:bold}";

/// `report.html`: the report of [`report`] as one self-contained page: the same summary, claims
/// (verdict cells coloured), C_K check, figures (SVG inline, animations as `data:` URIs), errata
/// and run times. No script and no external resource; the same inputs give the same bytes.
pub fn report_html(results: &[FolderResult], errata: &str, missing: &[String]) -> String {
    let mut h = String::from("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
    let _ = writeln!(h, "<title>Reproduction report</title>\n<style>{STYLE}</style>\n</head>\n<body>");
    h.push_str("<h1>Reproduction report</h1>\n<p>Every figure of the paper, computed by <code>just paper</code>. Each claim is the paper's statement, the test this program holds it to, the verdict and the measured numbers. A <strong>solver</strong> check is about this program's own computation (converged, δ<sub>d</sub> met, T<sub>90</sub> met) or a statement that cannot fail here (it holds by units, or by a target the program enforces or took from its own runs); a <strong>paper</strong> check is a statement of the paper that the computation could contradict, and only those are counted as the paper's. A FAIL is reported, never tuned away. The case files (<code>paper-cases/NAME.json</code>) list the paper's values and every assumption with its reason.</p>\n");
    html_summary(&mut h, results, missing);
    html_claims(&mut h, results);
    html_ck(&mut h, results);
    html_figures(&mut h, results);
    h.push_str("<h2>Errata</h2>\n<p>The slips found in the paper (<code>docs/errata.md</code>), each with the test that proves it.</p>\n");
    h.push_str(&markdown_table_html(&errata_table(errata).join("\n")).replacen("<table>", "<table id=\"errata\">", 1));
    h.push_str("</body>\n</html>\n");
    h
}

/// The report's summary table (one row per case, and one per case with no result) and the total.
fn html_summary(h: &mut String, results: &[FolderResult], missing: &[String]) {
    h.push_str("<h2>Summary</h2>\n<table id=\"summary\">\n<tr><th>case</th><th>title</th><th>paper statements passed</th><th>solver checks passed</th><th>run time (s)</th></tr>\n");
    for (r, (p, s, t)) in results.iter().zip(crate::counts::rows(results)) {
        let _ = writeln!(
            h,
            "<tr><td><a href=\"#{0}\">{0}</a></td><td>{1}</td><td>{p}</td><td>{s}</td><td>{t}</td></tr>",
            escape(&r.name),
            escape(r.title()),
        );
    }
    for m in missing {
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td><strong>no result</strong> (the case did not run or failed)</td><td>—</td><td>—</td><td>—</td></tr>",
            escape(m)
        );
    }
    h.push_str("</table>\n");
    let _ = writeln!(
        h,
        "<p class=\"total\" id=\"total\">{}{}</p>",
        escape(&counts(results).sentence()),
        split_note(results)
    );
}

/// The report's claims table, verdict cells coloured, a failed claim linked to its finding.
fn html_claims(h: &mut String, results: &[FolderResult]) {
    h.push_str("<h2>Claims</h2>\n<table id=\"claims\">\n<tr><th>case</th><th>scope</th><th>check</th><th>statement</th><th>test</th><th>verdict</th><th>measured</th></tr>\n");
    for r in results {
        for c in r.claims() {
            let pass = passed(c);
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"{}\">{}</td><td>{}</td></tr>",
                escape(&r.name),
                escape(text_of(c, "scope")),
                escape(text_of(c, "check")),
                escape(text_of(c, "statement")),
                escape(text_of(c, "test")),
                if split(c) {
                    "split"
                } else if pass {
                    "pass"
                } else {
                    "fail"
                },
                match (pass, finding(text_of(c, "statement"))) {
                    _ if split(c) => "SPLIT".to_string(),
                    (false, Some(anchor)) => format!("FAIL<br><a href=\"{FINDINGS}#{anchor}\">why</a>"),
                    _ => verdict(pass).to_string(),
                },
                escape(&measured(c))
            );
        }
    }
    h.push_str("</table>\n");
}

/// The C_K trend across Figs. 6–8 and the C_K study's conclusion, where the results hold them.
fn html_ck(h: &mut String, results: &[FolderResult]) {
    if let Some(ck) = ck_across(results) {
        h.push_str("<h2>C_K across Figs. 6–8</h2>\n<table id=\"ck\">\n<tr><th>C<sub>K</sub></th><th>CV of K</th><th>‖θ0 − θ0<sub>start</sub>‖ (rad)</th></tr>\n");
        for (c, cv, sh) in ck.rows {
            let _ = writeln!(h, "<tr><td>{c}</td><td>{cv:.4}</td><td>{sh:.4}</td></tr>");
        }
        h.push_str("</table>\n<table>\n");
        for (pass, statement) in [(ck.spread_up, SPREAD_STATEMENT), (ck.shape_down, SHAPE_STATEMENT)] {
            let class = if pass { "pass" } else { "fail" };
            let why = if pass { String::new() } else { format!("<br><a href=\"{FINDINGS}#ck-trend\">why</a>") };
            let _ =
                writeln!(h, "<tr><td class=\"{class}\">{}{why}</td><td>{}</td></tr>", verdict(pass), escape(statement));
        }
        h.push_str("</table>\n");
    }
    if let Some(c) = results.iter().find_map(|r| r.value.get("conclusion").and_then(Value::as_str)) {
        let _ = writeln!(h, "<h2>C_K study: conclusion</h2>\n<p>{}</p>", escape(c));
    }
}

/// Every case's figures: SVG inline, animations as `data:` URIs, with where its data are.
fn html_figures(h: &mut String, results: &[FolderResult]) {
    h.push_str("<h2>Figures</h2>\n");
    for r in results {
        let _ = writeln!(h, "<h3 id=\"{0}\">{0}</h3>\n<p>{1}</p>", escape(&r.name), escape(r.title()));
        for (name, bytes) in &r.assets {
            if name.ends_with(".svg") {
                let svg = String::from_utf8_lossy(bytes);
                let start = svg.find("<svg").unwrap_or(0);
                let _ = writeln!(h, "<figure>{}</figure>", svg[start..].trim_end());
            } else if name.ends_with(".gif") {
                let _ = writeln!(
                    h,
                    "<figure><img alt=\"{} {}\" src=\"data:image/gif;base64,{}\"></figure>",
                    escape(&r.name),
                    escape(name),
                    base64(bytes)
                );
            }
        }
        let _ = writeln!(
            h,
            "<p>Case file <code>paper-cases/{0}.json</code>; data: <code>results/{0}/</code> (<code>result.json</code> and CSV files).</p>",
            escape(&r.name)
        );
    }
}

/// A Markdown table (GitHub's syntax: `code`, **bold**, `\|` for a literal bar) as HTML, by
/// pulldown-cmark; raw HTML in the text is escaped, not passed through.
fn markdown_table_html(table: &str) -> String {
    use pulldown_cmark::{Event, Options, Parser};
    let events = Parser::new_ext(table, Options::ENABLE_TABLES).map(|e| match e {
        Event::Html(t) | Event::InlineHtml(t) => Event::Text(t),
        e => e,
    });
    let mut html = String::new();
    pulldown_cmark::html::push_html(&mut html, events);
    html
}

/// Standard Base64 (RFC 4648, with padding) of `bytes`.
fn base64(bytes: &[u8]) -> String {
    use base64::Engine as _;
    base64::engine::general_purpose::STANDARD.encode(bytes)
}

#[cfg(test)]
mod tests {

    #[test]
    fn every_failing_statement_with_a_finding_links_to_a_section_that_exists() {
        let findings = include_str!("../../../docs/findings.md");
        for (fragment, anchor) in FINDINGS_SECTIONS {
            assert_eq!(finding(&format!("\"{fragment}\" (Sec. 5.1)")), Some(anchor));
            assert!(
                findings.contains(&format!("<a id=\"{anchor}\"></a>")),
                "docs/findings.md has no section `{anchor}`"
            );
        }
        assert!(findings.contains("<a id=\"ck-trend\"></a>"));
        assert_eq!(finding("\"the end point reaches δ_d\""), None);
    }
    use super::*;
    use serde_json::json;

    fn results() -> Vec<FolderResult> {
        let value = json!({
            "title": "Fig. 3 <test>",
            "claims": [
                { "scope": "n5", "check": "solver", "statement": "converges", "test": "Ipopt", "pass": true, "measured": "J = 1" },
                { "scope": "n5", "check": "paper", "statement": "a & b", "test": "t", "pass": false, "measured": "x < y" },
            ],
            "files": ["figure.svg", "animation.gif"],
            "timings": { "total_seconds": 1.25 },
        });
        let svg = br#"<?xml version="1.0"?><svg width="10" height="10" viewBox="0 0 10 10"><text>panel</text></svg>"#;
        vec![FolderResult {
            name: "fig3".into(),
            value,
            assets: vec![("figure.svg".into(), svg.to_vec()), ("animation.gif".into(), b"GIF89a".to_vec())],
        }]
    }

    #[test]
    fn base64_follows_rfc_4648() {
        for (raw, coded) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(raw.as_bytes()), coded);
        }
    }

    #[test]
    fn the_html_report_holds_every_claim_figure_and_erratum_escaped_and_inline() {
        let errata = "# E\n\n| # | Where |\n|---|---|\n| E1 | eq. (3) `a < b` \\| c **d** |\n\nNotes";
        let html = report_html(&results(), errata, &["fig4".into()]);
        assert!(html.starts_with("<!DOCTYPE html>") && html.ends_with("</html>\n"));
        assert!(html.contains("<td class=\"pass\">PASS</td>") && html.contains("<td class=\"fail\">FAIL</td>"));
        assert!(html.contains("Fig. 3 &lt;test&gt;") && html.contains("a &amp; b") && html.contains("x &lt; y"));
        assert!(html.contains("0 of the paper's 1 statements pass, 1 fail; 1 of 1 solver checks pass."), "{html}");
        assert!(html.contains("<td>1.2</td>") || html.contains("<td>1.3</td>"), "run time");
        assert!(html.contains("fig4</td><td><strong>no result</strong>"));
        // The SVG inline without its XML declaration, the GIF as a data URI.
        assert!(html.contains("<figure><svg width=\"10\"") && !html.contains("<?xml"));
        assert!(html.contains("src=\"data:image/gif;base64,R0lGODlh\""));
        // Errata: one header row, one body row, code spans and an escaped bar kept in its cell.
        assert!(html.contains("<table id=\"errata\"><thead><tr><th>#</th><th>Where</th></tr></thead>"), "{html}");
        assert!(
            html.contains("<td>E1</td><td>eq. (3) <code>a &lt; b</code> | c <strong>d</strong></td></tr>"),
            "{html}"
        );
        // Self-contained: nothing fetched, no script.
        for outside in ["<script", "http://", "https://", "<link", "@import"] {
            assert!(!html.contains(outside), "{outside}");
        }
        assert_eq!(html, report_html(&results(), errata, &["fig4".into()]), "same inputs, same bytes");
    }

    #[test]
    fn a_claim_split_by_a_knife_edge_shows_each_branch_in_both_reports() {
        let branch = |b: usize, pass: bool, unmoved: bool, counted: bool| json!({ "branch": b, "objective": 7.27e-3, "starts": 2, "unmoved": unmoved, "counted": counted, "pass": pass, "measured": format!("end {b}") });
        let mut r = results();
        r[0].value["claims"] = json!([
            { "scope": "n10", "check": "paper", "statement": "near the end", "test": "t", "pass": false, "measured": "end 0",
              "split": true, "branches": [branch(0, true, false, true), branch(1, false, false, true), branch(2, false, true, false)] },
        ]);
        let md = report(&r, "", &[]);
        assert!(md.contains("**SPLIT** (a knife edge"), "{md}");
        assert!(md.contains("branch 1 (J = 7.270000e-3 J, 2 starts): FAIL, end 1"), "{md}");
        assert!(
            md.contains("branch 2 (J = 7.270000e-3 J, 2 starts, the unmoved start's only: not counted): FAIL"),
            "{md}"
        );
        assert!(md.contains("0 of the paper's 1 statements pass, 0 fail, 1 is split by a knife edge"), "{md}");
        let html = report_html(&r, "", &[]);
        assert!(html.contains("<td class=\"split\">SPLIT</td>"), "{html}");
        assert!(!report(&results(), "", &[]).contains("split by a knife edge"));
    }
}
