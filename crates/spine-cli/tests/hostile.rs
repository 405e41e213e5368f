//! Issues 49 and 75: the corpus of hostile and careless command lines in `tests/hostile/corpus.json`, each
//! with its expectation (exit codes, a text the error must contain). Every entry must end within
//! its time with no panic, abort or signal; nothing that was in its folder before may be removed
//! or changed; a refusal (exit 2) writes nothing; an error is one line a person can read.

mod common;
use common::{tmpdir, workspace};
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;
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

/// How an entry is run: the program, its arguments, an address-space limit, extra environment.
struct Invocation<'a> {
    args: &'a [String],
    /// `census.sh` (scripts/slurm/census.sh, with `SPINE` set and a stand-in `sbatch`), else `spine`.
    census_script: bool,
    /// `prlimit --as=BYTES`: the run must end as it would with less memory, never abort.
    address_space: Option<u64>,
    /// A folder of stand-in Slurm commands (first on `PATH`) and the log they append to.
    slurm: &'a Path,
}

fn run(work: &Path, how: &Invocation<'_>, seconds: u64) -> (Option<i32>, String, String, Duration) {
    let stderr_file = work.with_extension("stderr");
    let stdout_file = work.with_extension("stdout");
    let stderr = std::fs::File::create(&stderr_file).unwrap();
    let stdout = std::fs::File::create(&stdout_file).unwrap();
    let spine = env!("CARGO_BIN_EXE_spine");
    let mut line: Vec<String> = Vec::new();
    if let Some(bytes) = how.address_space {
        line.extend(["prlimit".to_string(), format!("--as={bytes}"), "--".into()]);
    }
    if how.census_script {
        line.extend(["bash".into(), workspace().join("scripts/slurm/census.sh").display().to_string()]);
    } else {
        line.push(spine.into());
    }
    line.extend(how.args.iter().cloned());
    let path = format!("{}:{}", how.slurm.display(), std::env::var("PATH").unwrap_or_default());
    let mut child = Command::new(&line[0])
        .args(&line[1..])
        .current_dir(work)
        .env("SPINE", spine)
        .env("PATH", path)
        .stdout(stdout)
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
            panic!("hang: {:?} ran over {seconds} s", how.args);
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let text = String::from_utf8_lossy(&std::fs::read(&stderr_file).unwrap()).into_owned();
    let out = String::from_utf8_lossy(&std::fs::read(&stdout_file).unwrap()).into_owned();
    (status.code(), text, out, clock.elapsed())
}

/// Stand-ins for `sbatch` and `squeue` in `dir`: `sbatch` appends its arguments to `dir/submitted`
/// and answers a job number; `squeue` lists nothing. Returns the log's path.
fn slurm_stand_ins(dir: &Path) -> std::path::PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let log = dir.join("submitted");
    let sbatch = format!("#!/bin/sh\necho \"$@\" >>'{}'\necho 4242\n", log.display());
    for (name, text) in [("sbatch", sbatch.as_str()), ("squeue", "#!/bin/sh\nexit 0\n")] {
        let file = dir.join(name);
        std::fs::write(&file, text).unwrap();
        std::process::Command::new("chmod").arg("+x").arg(&file).status().unwrap();
    }
    log
}

/// The first number in `text` longer than 20 characters (a value printed in full), if any.
fn long_number(text: &str) -> Option<String> {
    let mut run = String::new();
    for c in text.chars().chain(std::iter::once(' ')) {
        if c.is_ascii_digit() || (c == '.' && !run.is_empty()) {
            run.push(c);
        } else {
            if run.len() > 20 {
                return Some(run);
            }
            run.clear();
        }
    }
    None
}

#[test]
fn hostile_command_lines_end_as_the_corpus_expects() {
    let corpus: Value =
        serde_json::from_str(&std::fs::read_to_string(workspace().join("tests/hostile/corpus.json")).unwrap()).unwrap();
    let ws = workspace().canonicalize().unwrap();
    let root = tmpdir("hostile");
    let slurm = root.join("slurm-bin");
    let submitted = slurm_stand_ins(&slurm);
    let entries = corpus["entries"].as_array().unwrap();
    assert!(entries.len() >= 120, "{} entries", entries.len());
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
            let how = Invocation { args: &args, census_script: false, address_space: None, slurm: &slurm };
            let (code, stderr, _, _) = run(&work, &how, 120);
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
        let _ = std::fs::remove_file(&submitted);
        let how = Invocation {
            args: &args,
            census_script: e["program"].as_str() == Some("census.sh"),
            address_space: e["address_space_bytes"].as_u64(),
            slurm: &slurm,
        };
        let (code, stderr, stdout, took) = run(&work, &how, seconds);
        let after = snapshot(&work);
        let mut fail = |why: String| failures.push(format!("{name} ({args:?}): {why}\n  stderr: {stderr}"));
        if let Some(most) = e["within_seconds"].as_f64() {
            if took.as_secs_f64() > most {
                fail(format!("took {:.1} s, more than {most} s", took.as_secs_f64()));
            }
        }
        if let Some(text) = e["stdout"].as_str() {
            if !stdout.contains(text) {
                fail(format!("stdout lacks {text:?}; stdout: {}", stdout.chars().take(2000).collect::<String>()));
            }
        }
        for text in e["stdout_lacks"].as_array().into_iter().flatten().map(|t| t.as_str().unwrap()) {
            if stdout.contains(text) {
                fail(format!("stdout says {text:?}"));
            }
        }
        for text in e["stderr_lacks"].as_array().into_iter().flatten().map(|t| t.as_str().unwrap()) {
            if stderr.contains(text) {
                fail(format!("stderr says {text:?}"));
            }
        }
        if e["submits"].as_bool() == Some(true) && !submitted.exists() {
            fail("it submitted nothing".into());
        }
        if let Some(number) = long_number(&stdout) {
            fail(format!("stdout prints a number in full: {number}"));
        }
        if stdout.chars().any(|c| (c.is_control() && c != '\n' && c != '\t') || spine_check::is_bidi_control(c)) {
            fail("stdout holds control or bidirectional characters".into());
        }
        if e["submits"].as_bool() == Some(false) && submitted.exists() {
            fail(format!("it submitted jobs: {}", std::fs::read_to_string(&submitted).unwrap_or_default()));
        }
        for path in e["absent"].as_array().into_iter().flatten() {
            let path = subst(path);
            if Path::new(&path).exists() {
                fail(format!("{path} exists"));
            }
        }
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
                if line.chars().count() > 1000
                    || line.chars().any(|c| c.is_control() || spine_check::is_bidi_control(c))
                {
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
