//! Numbers the docs quote from the paper cases' runs, written from the runs.
//!
//! A quoted number sits between two HTML comments, invisible where the markdown is rendered:
//!
//! ```text
//! J = <!--q fig6 knife_edge/branches/0/objective | .6e-->7.270441e-3<!--/q--> from the moved starts
//! ```
//!
//! - the **source** (`fig6`) is a result folder: `RESULTS/fig6/result.json`; `report` is
//!   `RESULTS/report.json`, the counts `spine report` writes;
//! - the **path** (`knife_edge/branches/0/objective`) walks the JSON: an object key, an array index,
//!   `*` (every element: the quote is then a list), or `key=value` (the first element of an array
//!   whose `key` is `value`; `key~text`: whose `key` contains `text`; several joined by `&` must
//!   all hold);
//! - the **format**, after `|`, is applied in order: `*F` multiplies by `F`, `abs`, `len` (the
//!   length of an array), `.Nf` (N decimals), `.Ne` (N decimals, scientific), `.Ng` (N
//!   significant digits), `d` (an integer), `umin` (a negative number with the sign `−`), `verdict` (`true`/`false` as PASS/FAIL),
//!   `join=TEXT` (the separator of a list, `, ` unless given; `_` is a space; an empty list reads
//!   `none`), and `~R`: the
//!   quote stands while it is within the relative tolerance `R` of the run (else its text must
//!   equal the run's, as formatted).
//!
//! In a markdown table row, write the `|` before the format as `\|` (the table would take a bare
//! `|` for a cell's end, even inside the comment).
//!
//! [`rewrite`] puts each run's number in; a quote within its tolerance is kept as written, so
//! rewriting after a run that agrees changes nothing. [`Drift`]s are the quotes that differ.

use serde_json::Value;
use std::fmt::Write as _;
use std::ops::Range;

const OPEN: &str = "<!--q ";
const CLOSE: &str = "<!--/q-->";

/// A quote that cannot be read or resolved, with where it is.
#[derive(Debug, thiserror::Error)]
#[error("{file}:{line}: {message}")]
pub struct QuoteError {
    pub file: String,
    pub line: usize,
    pub message: String,
}

/// One quoted number: where it is, what it reads, and the text the doc has now.
#[derive(Debug, Clone, PartialEq)]
pub struct Quote {
    /// Line of the opening comment (1-based).
    pub line: usize,
    /// Result folder (`fig6`, `study-ck`) or `report`.
    pub source: String,
    pub path: String,
    pub format: Vec<String>,
    /// The quoted text as the doc has it.
    pub text: String,
    /// Byte range of the text in the doc.
    span: Range<usize>,
}

/// A quote whose text differs from the run beyond its tolerance.
#[derive(Debug, Clone, PartialEq)]
pub struct Drift {
    pub file: String,
    pub line: usize,
    pub source: String,
    pub path: String,
    pub quoted: String,
    pub computed: String,
}

/// The quotes of one doc, in order.
pub fn quotes(file: &str, doc: &str) -> Result<Vec<Quote>, QuoteError> {
    let error = |at: usize, message: String| QuoteError { file: file.into(), line: line_of(doc, at), message };
    let mut found = Vec::new();
    let mut from = 0;
    while let Some(start) = doc[from..].find(OPEN).map(|i| from + i) {
        let head_end = doc[start..]
            .find("-->")
            .map(|i| start + i)
            .ok_or_else(|| error(start, "a quote's opening comment is not closed".into()))?;
        let head = &doc[start + OPEN.len()..head_end];
        let text_start = head_end + 3;
        let text_end = doc[text_start..]
            .find(CLOSE)
            .map(|i| text_start + i)
            .ok_or_else(|| error(start, format!("no {CLOSE} after the quote")))?;
        let text = &doc[text_start..text_end];
        if text.contains(OPEN) || text.contains('\n') {
            return Err(error(start, format!("the quoted text runs into the next quote or line before {CLOSE}")));
        }
        let (spec, format) = head.split_once('|').unwrap_or((head, ""));
        let (source, path) = spec.trim().trim_end_matches('\\').trim_end().split_once(' ').ok_or_else(|| {
            error(
                start,
                format!("\"{}\": a quote names a source and a path, e.g. <!--q fig6 summary/J | .4g-->", head.trim()),
            )
        })?;
        found.push(Quote {
            line: line_of(doc, start),
            source: source.into(),
            path: path.trim().into(),
            format: format.split_whitespace().map(String::from).collect(),
            text: text.into(),
            span: text_start..text_end,
        });
        from = text_end + CLOSE.len();
    }
    Ok(found)
}

fn line_of(doc: &str, at: usize) -> usize {
    doc[..at].matches('\n').count() + 1
}

/// The doc with every quote set to its run's text (kept where it is within tolerance), and the
/// quotes that drifted. `source` gives the JSON of a source, `None` where it is missing.
pub fn rewrite<'a>(
    file: &str,
    doc: &str,
    source: &dyn Fn(&str) -> Option<&'a Value>,
) -> Result<(String, Vec<Drift>), QuoteError> {
    let mut out = String::with_capacity(doc.len());
    let mut drifts = Vec::new();
    let mut last = 0;
    for q in quotes(file, doc)? {
        let error = |message: String| QuoteError { file: file.into(), line: q.line, message };
        let json = source(&q.source)
            .ok_or_else(|| error(format!("no result for \"{}\" (run `just paper` first)", q.source)))?;
        let value = resolve(json, &q.path).map_err(|m| error(format!("{} {}: {m}", q.source, q.path)))?;
        let computed = render(&value, &q.format).map_err(|m| error(format!("{} {}: {m}", q.source, q.path)))?;
        let keep = q.text == computed || within(&q.text, &computed, tolerance(&q.format));
        if !keep {
            drifts.push(Drift {
                file: file.into(),
                line: q.line,
                source: q.source.clone(),
                path: q.path.clone(),
                quoted: q.text.clone(),
                computed: computed.clone(),
            });
        }
        out.push_str(&doc[last..q.span.start]);
        out.push_str(if keep { &q.text } else { &computed });
        last = q.span.end;
    }
    out.push_str(&doc[last..]);
    Ok((out, drifts))
}

fn tolerance(format: &[String]) -> Option<f64> {
    format.iter().find_map(|f| f.strip_prefix('~')).and_then(|r| r.parse().ok())
}

/// Whether every number of `quoted` is within `tol` (relative) of the same number of `computed`.
fn within(quoted: &str, computed: &str, tol: Option<f64>) -> bool {
    let Some(tol) = tol else { return false };
    let (a, b) = (numbers(quoted), numbers(computed));
    a.len() == b.len()
        && !a.is_empty()
        && a.iter().zip(&b).all(|(x, y)| (x - y).abs() <= tol * y.abs().max(f64::MIN_POSITIVE))
}

/// The numbers of a quoted text (`−` read as a minus sign).
fn numbers(text: &str) -> Vec<f64> {
    let text = text.replace('−', "-");
    let mut out = Vec::new();
    for token in text.split(|c: char| !(c.is_ascii_digit() || matches!(c, '.' | '-' | '+' | 'e' | 'E'))) {
        if let Ok(x) = token.trim_matches(|c| c == '.' || c == 'e' || c == 'E').parse::<f64>() {
            out.push(x);
        }
    }
    out
}

/// The value at `path` in `json`.
pub fn resolve(json: &Value, path: &str) -> Result<Value, String> {
    let mut current = vec![json.clone()];
    let mut listed = false;
    for segment in path.split('/').map(str::trim).filter(|s| !s.is_empty()) {
        let mut next = Vec::new();
        for value in &current {
            if segment == "*" {
                let items = value.as_array().ok_or_else(|| format!("\"*\" needs a list, found {}", kind(value)))?;
                next.extend(items.iter().cloned());
                listed = true;
            } else {
                next.push(step(value, segment)?);
            }
        }
        current = next;
    }
    Ok(if listed { Value::Array(current) } else { current.pop().unwrap_or(Value::Null) })
}

fn step(value: &Value, segment: &str) -> Result<Value, String> {
    if segment.contains(['=', '~']) {
        let conditions: Vec<_> = segment.split('&').map(filter).collect::<Option<_>>().ok_or_else(|| {
            format!("\"{segment}\": each condition of a filter is key=value or key~text, joined by &")
        })?;
        let items = value.as_array().ok_or_else(|| format!("\"{segment}\" needs a list, found {}", kind(value)))?;
        let text = |v: &Value, key: &str| v.get(key).map(|f| f.as_str().map_or_else(|| f.to_string(), String::from));
        let holds = |item: &Value, (key, wanted, contains): &(&str, &str, bool)| {
            text(item, key).is_some_and(|t| if *contains { t.contains(wanted) } else { t == *wanted })
        };
        return items
            .iter()
            .find(|item| conditions.iter().all(|c| holds(item, c)))
            .cloned()
            .ok_or_else(|| format!("no element with {segment}"));
    }
    match value {
        Value::Array(items) => {
            let i: usize = segment.parse().map_err(|_| format!("\"{segment}\": a list is indexed by a number"))?;
            items.get(i).cloned().ok_or_else(|| format!("index {i} past the list's {} elements", items.len()))
        }
        Value::Object(map) => map.get(segment).cloned().ok_or_else(|| format!("no key \"{segment}\"")),
        other => Err(format!("\"{segment}\" in {}", kind(other))),
    }
}

/// `key=value` or `key~text`.
fn filter(condition: &str) -> Option<(&str, &str, bool)> {
    let at = condition.find(['=', '~'])?;
    Some((&condition[..at], &condition[at + 1..], condition[at..].starts_with('~')))
}

fn kind(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "a list",
        Value::Object(_) => "an object",
    }
}

/// The text of `value` after the format steps.
pub fn render(value: &Value, format: &[String]) -> Result<String, String> {
    let mut value = value.clone();
    let mut separator = ", ".to_string();
    let mut text_steps = Vec::new();
    for step in format {
        if step == "len" {
            let n =
                value.as_array().map(Vec::len).ok_or_else(|| format!("len needs a list, found {}", kind(&value)))?;
            value = Value::from(n);
        } else if let Some(sep) = step.strip_prefix("join=") {
            separator = sep.replace('_', " ");
        } else if let Some(f) = step.strip_prefix('*') {
            let factor: f64 = f.parse().map_err(|_| format!("\"{step}\": *F needs a number F"))?;
            value = map_numbers(&value, &|x| x * factor)?;
        } else if step == "abs" {
            value = map_numbers(&value, &f64::abs)?;
        } else if !step.starts_with('~') {
            text_steps.push(step.as_str());
        }
    }
    match &value {
        Value::Array(items) if items.is_empty() => Ok("none".into()),
        Value::Array(items) => {
            let parts: Result<Vec<String>, String> = items.iter().map(|v| scalar(v, &text_steps)).collect();
            Ok(parts?.join(&separator))
        }
        v => scalar(v, &text_steps),
    }
}

fn map_numbers(value: &Value, f: &dyn Fn(f64) -> f64) -> Result<Value, String> {
    match value {
        Value::Array(items) => Ok(Value::Array(items.iter().map(|v| map_numbers(v, f)).collect::<Result<_, _>>()?)),
        Value::Number(n) => Ok(Value::from(f(n.as_f64().unwrap_or(f64::NAN)))),
        other => Err(format!("arithmetic on {}", kind(other))),
    }
}

fn scalar(value: &Value, steps: &[&str]) -> Result<String, String> {
    let x = match value {
        Value::Number(n) => n.as_f64().unwrap_or(f64::NAN),
        Value::String(s) if steps.is_empty() => return Ok(s.clone()),
        Value::Bool(b) if steps.is_empty() => return Ok(b.to_string()),
        Value::Bool(b) if steps == ["verdict"] => return Ok(if *b { "PASS" } else { "FAIL" }.into()),
        other if steps.is_empty() => return Ok(other.to_string()),
        other => return Err(format!("a number format on {}", kind(other))),
    };
    let mut text = x.to_string();
    let mut unicode_minus = false;
    for step in steps {
        if *step == "umin" {
            unicode_minus = true;
            continue;
        }
        text = number(x, step)?;
    }
    Ok(match text.strip_prefix('-') {
        Some(rest) if unicode_minus => format!("−{rest}"),
        _ => text,
    })
}

fn number(x: f64, step: &str) -> Result<String, String> {
    let digits = |s: &str| s.parse::<usize>().ok().filter(|d| *d <= 17);
    let bad = || format!("\"{step}\": a format is *F, abs, len, .Nf, .Ne, .Ng, d, umin, join=TEXT or ~R");
    if step == "d" {
        return Ok(format!("{}", x.round() as i64));
    }
    let body = step.strip_prefix('.').ok_or_else(bad)?;
    let (n, kind) = body.split_at(body.len().saturating_sub(1));
    let n = digits(n).ok_or_else(bad)?;
    let mut s = String::new();
    match kind {
        "f" => write!(s, "{x:.n$}"),
        "e" => write!(s, "{x:.n$e}"),
        "g" => return Ok(significant(x, n.max(1))),
        _ => return Err(bad()),
    }
    .map_err(|e| e.to_string())?;
    Ok(s)
}

/// `x` to `n` significant digits: plain where 1e-3 ≤ |x| < 10ⁿ (zero too), else scientific.
fn significant(x: f64, n: usize) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let exponent = x.abs().log10().floor() as i32;
    // Rounding can carry into the next decade (9.996 to 3 digits is 10.0).
    let rounded: f64 = format!("{x:.p$e}", p = n - 1).parse().unwrap_or(x);
    let exponent = if rounded.abs() >= 10f64.powi(exponent + 1) { exponent + 1 } else { exponent };
    if (-3..n as i32).contains(&exponent) {
        let decimals = (n as i32 - 1 - exponent).max(0) as usize;
        format!("{rounded:.decimals$}")
    } else {
        format!("{rounded:.p$e}", p = n - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn run() -> Value {
        json!({"summary": {"J": 7.270441e-3, "runs": [{"name": "n10", "J": 0.0072704}, {"name": "n5", "J": -0.0076031}]},
               "knife_edge": {"branches": [{"objective": 7.270441e-3}, {"objective": 7.2704392e-3}]},
               "claims": [{"scope": "n10", "statement": "near the end", "pass": false},
                          {"scope": "n10 best", "statement": "near the end", "pass": true},
                          {"scope": "n10 best", "statement": "R > 1", "pass": false}],
               "verdict": "FAIL"})
    }

    fn redo(doc: &str) -> (String, Vec<Drift>) {
        let json = run();
        rewrite("doc.md", doc, &|s| (s == "fig6").then_some(&json)).unwrap()
    }

    #[test]
    fn a_quote_that_agrees_is_kept_and_one_that_drifted_is_rewritten_and_reported() {
        let doc = "J = <!--q fig6 summary/J | *1e3 .3f-->7.270<!--/q--> mJ, and <!--q fig6 summary/runs/name=n5/J | .4g umin-->−7.6e-3<!--/q-->.\n";
        let (out, drifts) = redo(doc);
        assert_eq!(out, "J = <!--q fig6 summary/J | *1e3 .3f-->7.270<!--/q--> mJ, and <!--q fig6 summary/runs/name=n5/J | .4g umin-->−0.007603<!--/q-->.\n");
        assert_eq!(drifts.len(), 1);
        assert_eq!(
            (drifts[0].line, drifts[0].quoted.as_str(), drifts[0].computed.as_str()),
            (1, "−7.6e-3", "−0.007603")
        );
        assert_eq!(redo(&out), (out.clone(), vec![]));
    }

    #[test]
    fn a_tolerance_keeps_a_quote_close_enough_and_lists_are_joined() {
        let doc = "<!--q fig6 knife_edge/branches/*/objective | .7e ~1e-6-->7.2704410e-3, 7.2704390e-3<!--/q-->";
        let (out, drifts) = redo(doc);
        assert!(drifts.is_empty());
        assert_eq!(out, doc);
        let far = doc.replace("7.2704390e-3", "7.2804390e-3");
        assert_eq!(redo(&far).1.len(), 1);
        let (count, _) =
            redo("<!--q fig6 knife_edge/branches | len d-->3<!--/q--> and <!--q fig6 verdict-->PASS<!--/q-->");
        assert_eq!(count, "<!--q fig6 knife_edge/branches | len d-->2<!--/q--> and <!--q fig6 verdict-->FAIL<!--/q-->");
    }

    #[test]
    fn filters_joined_by_and_pick_the_element_where_all_hold_and_verdicts_read_pass_or_fail() {
        let doc = "<!--q fig6 claims/scope=n10 best&statement~end/pass | verdict-->FAIL<!--/q-->, \
                   <!--q fig6 claims/scope=n10 best&statement~R/pass | verdict-->FAIL<!--/q-->";
        let (out, drifts) = redo(doc);
        assert_eq!(drifts.len(), 1, "{out}");
        assert!(out.starts_with("<!--q fig6 claims/scope=n10 best&statement~end/pass | verdict-->PASS<!--/q-->"));
        let row = "| a | <!--q fig6 summary/J \\| *1e3 .3f-->7.270<!--/q--> |";
        assert_eq!(redo(row), (row.to_string(), vec![]), "a table row escapes the bar");
        let json = run();
        let source = |s: &str| (s == "fig6").then_some(&json);
        let err = rewrite("f.md", "<!--q fig6 claims/scope=n5&pass=true/pass-->x<!--/q-->", &source).unwrap_err();
        assert!(err.to_string().contains("no element with scope=n5&pass=true"), "{err}");
        assert!(rewrite("f.md", "<!--q fig6 claims/scope=n10&x/pass-->x<!--/q-->", &source).is_err());
    }

    #[test]
    fn significant_digits_write_plain_or_scientific_numbers() {
        assert_eq!(significant(7.270441e-3, 6), "0.00727044");
        assert_eq!(significant(7.270441e-4, 4), "7.270e-4");
        assert_eq!(significant(9.9996, 3), "10.0");
        assert_eq!(significant(128.612, 4), "128.6");
        assert_eq!(significant(-23.84, 3), "-23.8");
        assert_eq!(significant(26890.0, 3), "2.69e4");
        let umin = |x: f64| scalar(&Value::from(x), &[".3e", "umin"]).unwrap();
        assert_eq!((umin(7.162e-7), umin(-8.494e-7)), ("7.162e-7".to_string(), "−8.494e-7".to_string()));
    }

    #[test]
    fn bad_quotes_name_the_line_and_what_is_wrong() {
        let json = run();
        let source = |s: &str| (s == "fig6").then_some(&json);
        let err = |doc: &str| rewrite("f.md", doc, &source).unwrap_err().to_string();
        assert!(err("a\n<!--q fig6 summary/K-->1<!--/q-->").contains("f.md:2: fig6 summary/K: no key \"K\""));
        assert!(err("<!--q fig9 summary/J-->1<!--/q-->").contains("no result for \"fig9\""));
        assert!(err("<!--q fig6-->1<!--/q-->").contains("names a source and a path"));
        assert!(err("<!--q fig6 summary/J-->1").contains("no <!--/q-->"));
        assert!(err("<!--q fig6 summary/J | .4x-->1<!--/q-->").contains("a format is"));
        assert!(err("<!--q fig6 summary/runs/9/J-->1<!--/q-->").contains("index 9 past the list's 2"));
    }
}
