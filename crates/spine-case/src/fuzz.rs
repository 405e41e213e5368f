//! The body of the fuzz targets, shared by `fuzz/` (cargo-fuzz, nightly) and the stable fuzz tests
//! (`tests/cases.rs` in process, `crates/spine-cli/tests/adversarial.rs` through the binary), and
//! the seeded generator of mutated case files they use.

/// Parses `data` as a case file and checks it, whatever its kind: any bytes must give a checked
/// case or an error naming a field, never a panic. Returns whether the case was valid.
pub fn check_bytes(data: &[u8]) -> bool {
    let Ok(text) = std::str::from_utf8(data) else { return false };
    match crate::case::Case::from_json(text) {
        Ok(case) => case.check().is_ok(),
        Err(_) => false,
    }
}

use serde_json::{json, Value};

/// Values a mutation puts in place of a field: extremes of every JSON type.
fn extremes() -> [Value; 14] {
    [
        json!(0),
        json!(-1),
        json!(1e300),
        json!(-1e300),
        json!(1e-300),
        json!(1_000_000_000_000_000u64),
        json!(u64::MAX),
        json!("x"),
        Value::Null,
        json!([]),
        json!({}),
        json!(true),
        json!(0.5),
        json!(-0.0),
    ]
}

/// A seeded generator of mutated case files: each call to [`Mutator::mutate`] applies one to three
/// mutations to a copy of a case — a value replaced by an extreme (0, −1, ±1e300, 1e-300, 1e15,
/// u64::MAX, a string, null, an empty array or object, …), a key removed, or an unknown key added.
pub struct Mutator {
    state: u64,
}

impl Mutator {
    pub fn new(seed: u64) -> Self {
        Self { state: seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1 }
    }

    fn next(&mut self) -> u64 {
        self.state ^= self.state << 13;
        self.state ^= self.state >> 7;
        self.state ^= self.state << 17;
        self.state
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    /// A mutated copy of `case`.
    pub fn mutate(&mut self, case: &Value) -> Value {
        let mut paths = Vec::new();
        leaves(case, &mut Vec::new(), &mut paths);
        let mut out = case.clone();
        for _ in 0..1 + self.below(3) {
            let p = paths[self.below(paths.len())].clone();
            if p.is_empty() {
                continue;
            }
            match self.below(4) {
                0 => {
                    let (parent, key) = p.split_at(p.len() - 1);
                    if let Some(Value::Object(m)) = at(&mut out, parent) {
                        m.remove(&key[0]);
                    }
                }
                1 => {
                    if let Some(Value::Object(m)) = at(&mut out, &p) {
                        m.insert("unknown_field".into(), json!(1));
                    }
                }
                _ => {
                    let all = extremes();
                    let v = all[self.below(all.len())].clone();
                    if let Some(slot) = at(&mut out, &p) {
                        *slot = v;
                    }
                }
            }
        }
        out
    }
}

/// Every node of a JSON value with its path.
fn leaves(v: &Value, path: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    out.push(path.clone());
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                path.push(k.clone());
                leaves(x, path, out);
                path.pop();
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                path.push(i.to_string());
                leaves(x, path, out);
                path.pop();
            }
        }
        _ => {}
    }
}

/// The value at `path`, if an earlier mutation left it there.
fn at<'a>(v: &'a mut Value, path: &[String]) -> Option<&'a mut Value> {
    path.iter().try_fold(v, |node, key| match node {
        Value::Array(a) => key.parse::<usize>().ok().and_then(|i| a.get_mut(i)),
        Value::Object(m) => m.get_mut(key),
        _ => None,
    })
}
