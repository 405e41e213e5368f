//! Finds Ipopt and reads its version from the headers, so that the C declarations in `src/ffi.rs`
//! match the library that is linked.
//!
//! * Default: Debian's `coinor-libipopt-dev` (Ipopt 3.11.9): `/usr/lib/libipopt.so`,
//!   headers in `/usr/include/coin` (or wherever `pkg-config ipopt` says).
//! * `IPOPT_DIR=DIR`: an Ipopt installed under `DIR` (`DIR/lib` or `DIR` holds `libipopt.so`,
//!   `DIR/include/coin-or` or `DIR/include/coin` the headers), for example Ipopt 3.14 as the
//!   `casadi` wheel ships it (`just ipopt314` sets this up).
//!
//! The C interface is the same in both versions except for `Bool`: `int` up to 3.13, C99 `bool`
//! from 3.14. The build sets `cfg(ipopt_c99_bool)` from the header itself and exports the
//! version as `SPINE_IPOPT_VERSION`. Builds against an Ipopt with 64-bit indices or single
//! precision are refused.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The first directory of `candidates` that holds `file`.
fn first_with(candidates: &[PathBuf], file: &str) -> Option<PathBuf> {
    candidates.iter().find(|d| d.join(file).exists()).cloned()
}

fn pkg_config(args: &[&str]) -> Option<String> {
    let out = Command::new("pkg-config").args(args).arg("ipopt").output().ok()?;
    out.status.success().then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// `(library directory, header directory)`.
fn locate() -> (PathBuf, PathBuf) {
    if let Some(dir) = std::env::var_os("IPOPT_DIR") {
        let dir = PathBuf::from(dir);
        let lib = first_with(&[dir.join("lib"), dir.clone()], "libipopt.so");
        let include = first_with(
            &[dir.join("include/coin-or"), dir.join("include/coin"), dir.join("include")],
            "IpStdCInterface.h",
        );
        match (lib, include) {
            (Some(lib), Some(include)) => return (lib, include),
            _ => panic!(
                "IPOPT_DIR={}: expected libipopt.so in DIR/lib or DIR and IpStdCInterface.h in DIR/include/coin-or, DIR/include/coin or DIR/include",
                dir.display()
            ),
        }
    }
    let lib = pkg_config(&["--variable=libdir"]).map(PathBuf::from).unwrap_or_else(|| PathBuf::from("/usr/lib"));
    let include = pkg_config(&["--cflags-only-I"])
        .into_iter()
        .flat_map(|flags| flags.split_whitespace().map(|f| PathBuf::from(f.trim_start_matches("-I"))).collect::<Vec<_>>())
        .chain([PathBuf::from("/usr/include/coin"), PathBuf::from("/usr/include/coin-or")])
        .find(|d| d.join("IpStdCInterface.h").exists())
        .unwrap_or_else(|| panic!("Ipopt's C header IpStdCInterface.h not found: install coinor-libipopt-dev (./bootstrap.sh) or set IPOPT_DIR"));
    (lib, include)
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn main() {
    println!("cargo::rerun-if-env-changed=IPOPT_DIR");
    println!("cargo::rustc-check-cfg=cfg(ipopt_c99_bool)");
    let (lib, include) = locate();
    let interface = read(&include.join("IpStdCInterface.h"));
    let config = read(&include.join("IpoptConfig.h"));
    println!("cargo::rerun-if-changed={}", include.join("IpStdCInterface.h").display());

    let version = config
        .lines()
        .find_map(|l| l.trim().strip_prefix("#define IPOPT_VERSION ").map(|v| v.trim().trim_matches('"').to_string()))
        .unwrap_or_else(|| "unknown".into());
    if config
        .lines()
        .any(|l| l.trim().starts_with("#define IPOPT_INT64") || l.trim().starts_with("#define IPOPT_SINGLE"))
    {
        panic!(
            "Ipopt {version} at {} uses 64-bit indices or single precision; this binding needs int indices and double",
            include.display()
        );
    }
    let c99_bool = interface.contains("typedef bool Bool");
    let int_bool = interface.contains("typedef int Bool");
    if c99_bool == int_bool {
        panic!("cannot tell the C type of Bool from {}", include.join("IpStdCInterface.h").display());
    }
    if c99_bool {
        println!("cargo::rustc-cfg=ipopt_c99_bool");
    }
    println!("cargo::rustc-env=SPINE_IPOPT_VERSION={version}");
    println!("cargo::rustc-env=SPINE_IPOPT_LIBDIR={}", lib.display());
    println!("cargo::rustc-link-search=native={}", lib.display());
    println!("cargo::rustc-link-lib=dylib=ipopt");
}
