//! The benchmark programs' command lines: a bad argument is a usage error (exit code 2, the
//! argument and what is allowed on stderr, nothing on stdout), never a panic.

use std::process::Command;

fn design_scaling(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_design_scaling")).args(args).output().expect("design_scaling runs")
}

#[test]
fn design_scaling_rejects_bad_arguments_with_exit_code_2() {
    let cases: [(&[&str], &str); 7] = [
        (&["1"], "at least 2"),
        (&["ten"], "\"ten\""),
        (&["--repeats=x"], "--repeats"),
        (&["--repeats=0"], "at least 1"),
        (&["--ipopt=tol"], "NAME=VALUE"),
        (&["--warm=no_such_field=1"], "allowed"),
        (&["--springs=cubic", "10"], "auto, log or linear"),
    ];
    for (args, expected) in cases {
        let out = design_scaling(args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.starts_with("error: ") && stderr.contains(expected), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(out.stdout.is_empty(), "{args:?} printed a table");
    }
}

#[test]
fn design_scaling_prints_its_usage_on_help() {
    let out = design_scaling(&["--help"]);
    assert_eq!(out.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("usage: design_scaling"));
}
