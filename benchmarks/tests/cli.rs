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
    assert!(String::from_utf8_lossy(&out.stdout).contains("Usage: design_scaling [OPTIONS] [SIZES]..."));
}

/// Every benchmark program parses its command line with clap: a bad value names the argument
/// and what is allowed, exit code 2, before any work (the dynamics benchmark panicked on a bad
/// `--budget` before).
#[test]
fn every_benchmark_program_refuses_a_bad_argument_with_exit_code_2() {
    let cases: [(&str, &[&str], &str); 6] = [
        (env!("CARGO_BIN_EXE_first_solve"), &["1"], "at least 2"),
        (env!("CARGO_BIN_EXE_first_solve"), &["5", "0"], "at least 1"),
        (env!("CARGO_BIN_EXE_dynamics_scaling"), &["--budget", "x"], "positive number of seconds"),
        (env!("CARGO_BIN_EXE_dynamic_gradients"), &["--gradient-sizes=7,1"], "at least 2"),
        (env!("CARGO_BIN_EXE_bench_peers"), &[], "<PYTHON>"),
        (env!("CARGO_BIN_EXE_bench_ad_peers"), &["python3", "ten"], "\"ten\""),
    ];
    for (program, args, expected) in cases {
        let out = Command::new(program).args(args).output().expect("the program runs");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{program} {args:?}: {stderr}");
        assert!(stderr.starts_with("error: ") && stderr.contains(expected), "{program} {args:?}: {stderr}");
        assert!(!stderr.contains("panicked") && out.stdout.is_empty(), "{program} {args:?}: {stderr}");
    }
}
