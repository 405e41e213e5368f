//! Compiles `shim/pardiso_shim.c` into `$OUT_DIR/libpardiso.so` (SONAME `libpardiso.so`), the small
//! library through which Ipopt's Pardiso loader reaches this crate's factorisation; `src/abi.rs`
//! embeds its bytes.

use std::path::PathBuf;
use std::process::Command;

fn main() {
    println!("cargo::rerun-if-changed=shim/pardiso_shim.c");
    println!("cargo::rerun-if-env-changed=CC");
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let compiler = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    let status = Command::new(&compiler)
        .args(["-shared", "-fPIC", "-O2", "-Wall", "-Wl,-soname,libpardiso.so", "-o"])
        .arg(out.join("libpardiso.so"))
        .arg("shim/pardiso_shim.c")
        .status()
        .unwrap_or_else(|e| panic!("running the C compiler `{compiler}` (set CC to choose one): {e}"));
    assert!(status.success(), "`{compiler}` failed to build shim/pardiso_shim.c");
}
