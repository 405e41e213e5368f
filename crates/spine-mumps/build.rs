//! Compiles `shim/mumps_shim.c` (the few calls of MUMPS's C interface this crate needs, with the
//! settings Ipopt uses) into a static library and links Debian's sequential MUMPS
//! (`libdmumps_seq`, installed with `coinor-libipopt-dev`).

use std::path::PathBuf;
use std::process::Command;

fn main() {
    println!("cargo::rerun-if-changed=shim/mumps_shim.c");
    println!("cargo::rerun-if-env-changed=CC");
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let compiler = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    let object = out.join("mumps_shim.o");
    let status = Command::new(&compiler)
        .args(["-c", "-fPIC", "-O2", "-Wall", "-I/usr/include/mumps_seq", "-o"])
        .arg(&object)
        .arg("shim/mumps_shim.c")
        .status()
        .unwrap_or_else(|e| panic!("running the C compiler `{compiler}` (set CC to choose one): {e}"));
    assert!(status.success(), "`{compiler}` failed to build shim/mumps_shim.c (is libmumps-seq-dev installed?)");
    let status = Command::new("ar")
        .arg("crs")
        .arg(out.join("libspine_mumps_shim.a"))
        .arg(&object)
        .status()
        .unwrap_or_else(|e| panic!("running ar: {e}"));
    assert!(status.success(), "ar failed to archive the MUMPS shim");
    println!("cargo::rustc-link-search=native={}", out.display());
    println!("cargo::rustc-link-lib=static=spine_mumps_shim");
    println!("cargo::rustc-link-lib=dylib=dmumps_seq");
    println!("cargo::rustc-link-lib=dylib=mumps_common_seq");
    println!("cargo::rustc-link-lib=dylib=mpiseq_seq");
}
