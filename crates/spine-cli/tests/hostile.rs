//! Issue 49: the corpus of hostile and careless command lines in `tests/hostile/corpus.json`, each
//! with its expectation (exit codes, a text the error must contain). Every entry must end within
//! its time with no panic, abort or signal; nothing that was in its folder before may be removed
//! or changed; a refusal (exit 2) writes nothing; an error is one line a person can read.

mod common;
use common::{tmpdir, workspace};
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// RFC 7396: `patch` merged into `target` (null removes a key).
fn merge_patch(target: &mut Value, patch: &Value) {
    match patch {
        Value::Object(p) => {
            if !target.is_object() {
                *target = Value::Object(Default::default());
            }
            let t = target.as_object_mut().unwrap();
            for (k, v) in p {
                if v.is_null() {
                    t.remove(k);
                } else {
                    merge_patch(t.entry(k.clone()).or_insert(Value::Null), v);
                }
            }
        }
        other => *target = other.clone(),
    }
}

/// Every file under `dir` (links not followed) with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let e = e.unwrap();
            let path = e.path();
            let meta = std::fs::symlink_metadata(&path).unwrap();
            let name = path.strip_prefix(dir).unwrap().display().to_string();
            if meta.is_dir() {
                out.insert(format!("{name}/"), Vec::new());
                stack.push(path);
            } else if meta.file_type().is_symlink() {
                out.insert(name, std::fs::read_link(&path).unwrap().display().to_string().into_bytes());
            } else {
                out.insert(name, std::fs::read(&path).unwrap());
            }
        }
    }
    out
}

fn run(work: &Path, args: &[String], seconds: u64) -> (Option<i32>, String, Duration) {
    let stderr_file = work.with_extension("stderr");
    let stderr = std::fs::File::create(&stderr_file).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_spine"))
        .args(args)
        .current_dir(work)
        .stdout(Stdio::null())
        .stderr(stderr)
        .spawn()
        .unwrap();
    let clock = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if clock.elapsed() > Duration::from_secs(seconds) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("hang: {args:?} ran over {seconds} s");
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let text = String::from_utf8_lossy(&std::fs::read(&stderr_file).unwrap()).into_owned();
    (status.code(), text, clock.elapsed())
}

#[test]
fn hostile_command_lines_end_as_the_corpus_expects() {
    let corpus: Value =
        serde_json::from_str(&std::fs::read_to_string(workspace().join("tests/hostile/corpus.json")).unwrap()).unwrap();
    let ws = workspace().canonicalize().unwrap();
    let root = tmpdir("hostile");
    let entries = corpus["entries"].as_array().unwrap();
    assert!(entries.len() >= 60, "{} entries", entries.len());
    let mut failures = Vec::new();
    for (k, e) in entries.iter().enumerate() {
        let name = e["name"].as_str().unwrap();
        let work = root.join(format!("{k:03}"));
        std::fs::create_dir_all(&work).unwrap();
        let work = work.canonicalize().unwrap();
        let subst = |a: &Value| {
            a.as_str()
                .unwrap()
                .replace("{work}", &work.display().to_string())
                .replace("{ws}", &ws.display().to_string())
        };
        // The case file.
        let case_at = work.join(e["case_at"].as_str().unwrap_or("case.json"));
        std::fs::create_dir_all(case_at.parent().unwrap()).unwrap();
        let text = if let Some(t) = e["text"].as_str() {
            t.to_string()
        } else if let Some(n) = e["text_key_chars"].as_u64() {
            format!("{{\"kind\": \"design\", \"{}\": 1}}", "k".repeat(n as usize))
        } else {
            let base = e["base"].as_str().unwrap_or("design5");
            let mut value: Value =
                serde_json::from_str(&std::fs::read_to_string(ws.join(format!("paper-cases/{base}.json"))).unwrap())
                    .unwrap();
            if !e["patch"].is_null() {
                merge_patch(&mut value, &e["patch"]);
            }
            value.to_string()
        };
        std::fs::write(&case_at, text).unwrap();
        for d in e["dirs"].as_array().into_iter().flatten() {
            std::fs::create_dir_all(work.join(d.as_str().unwrap())).unwrap();
        }
        let latin1: Vec<&str> = e["raw_latin1"].as_array().into_iter().flatten().map(|v| v.as_str().unwrap()).collect();
        for (path, content) in e["files"].as_object().into_iter().flatten() {
            let file = work.join(path);
            std::fs::create_dir_all(file.parent().unwrap()).unwrap();
            let content = content.as_str().unwrap();
            if latin1.contains(&path.as_str()) {
                std::fs::write(&file, content.chars().map(|c| c as u8).collect::<Vec<u8>>()).unwrap();
            } else {
                std::fs::write(&file, content).unwrap();
            }
        }
        for (link, to) in e["symlinks"].as_object().into_iter().flatten() {
            std::os::unix::fs::symlink(to.as_str().unwrap(), work.join(link)).unwrap();
        }
        for setup in e["setup"].as_array().into_iter().flatten() {
            let args: Vec<String> = setup.as_array().unwrap().iter().map(subst).collect();
            let (code, stderr, _) = run(&work, &args, 120);
            assert_eq!(code, Some(0), "{name}: setup {args:?}: {stderr}");
        }
        for edit in e["edits"].as_array().into_iter().flatten() {
            let file = work.join(edit[0].as_str().unwrap());
            let mut value: Value = serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
            *value.pointer_mut(edit[1].as_str().unwrap()).unwrap_or_else(|| panic!("{name}: {}", edit[1])) =
                edit[2].clone();
            std::fs::write(&file, value.to_string()).unwrap();
        }
        let before = snapshot(&work);
        let args: Vec<String> = e["args"].as_array().unwrap().iter().map(subst).collect();
        let seconds = e["seconds"].as_u64().unwrap_or(60);
        let (code, stderr, took) = run(&work, &args, seconds);
        let after = snapshot(&work);
        let mut fail = |why: String| failures.push(format!("{name} ({args:?}): {why}\n  stderr: {stderr}"));
        let Some(code) = code else {
            fail("killed by a signal".into());
            continue;
        };
        let allowed: Vec<i64> = e["exit"].as_array().unwrap().iter().map(|v| v.as_i64().unwrap()).collect();
        if !allowed.contains(&(code as i64)) {
            fail(format!("exit {code}, expected one of {allowed:?}"));
        }
        if let Some(text) = e["stderr"].as_str() {
            if !stderr.contains(text) {
                fail(format!("stderr lacks {text:?}"));
            }
        }
        if let Some(piece) = common::debug_text(&stderr) {
            fail(format!("Rust debug text in what it says: {piece:?}"));
        }
        if stderr.contains("panicked") || stderr.contains("RUST_BACKTRACE") {
            fail("a panic".into());
        }
        for (path, bytes) in &before {
            if after.get(path) != Some(bytes) {
                fail(format!("{path} was removed or changed"));
            }
        }
        if code == 2 && after.len() != before.len() {
            let new: Vec<&String> = after.keys().filter(|p| !before.contains_key(*p)).collect();
            fail(format!("a refusal wrote {new:?}"));
        }
        if code != 0 {
            let error: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error")).collect();
            if code == 2 && error.len() != 1 {
                fail(format!("{} error lines", error.len()));
            }
            for line in error {
                if line.chars().count() > 1000 || line.chars().any(|c| c.is_control()) {
                    fail("an error line too long or with control characters".into());
                }
                if line.contains("Some(") || line.contains("None") || line.contains("invalid type: null") {
                    fail("Rust debug text or serde's wording".into());
                }
            }
        }
        if let Some(pointer) = e["result_has"].as_str() {
            let result: Option<Value> =
                std::fs::read_to_string(work.join("out/result.json")).ok().and_then(|t| serde_json::from_str(&t).ok());
            if result.as_ref().and_then(|r| r.pointer(pointer)).is_none() {
                fail(format!("out/result.json lacks {pointer}"));
            }
        }
        eprintln!("{k:3} exit {code} in {:.2} s: {name}", took.as_secs_f64());
    }
    assert!(failures.is_empty(), "{} of {} entries failed:\n{}", failures.len(), entries.len(), failures.join("\n"));
    let _ = std::fs::remove_dir_all(&root);
}
