//! Making this solver the `libpardiso.so` of the process, for Ipopt's `linear_solver pardiso`.
//!
//! Ipopt (3.11 and 3.14) opens Pardiso at run time with `dlopen("libpardiso.so")`. The dynamic
//! loader answers such a request with an already loaded library whose SONAME matches, before it
//! looks at the file system. [`install`] writes the shim (a 2 kB C library with that SONAME, built
//! with this crate and embedded in it) to a temporary file, loads it, deletes the file and hands
//! it the two Rust entry points; every later `dlopen("libpardiso.so")` in the process gets it.
//! Without [`install`] nothing changes: Ipopt looks for a real Pardiso as before.

use crate::{abi, KktError, LoadError};
use std::fs::OpenOptions;
use std::io::Write;
use std::path::PathBuf;
use std::sync::OnceLock;

/// Loads the shim once per process; later calls return the first outcome.
pub fn install() -> Result<(), KktError> {
    static INSTALLED: OnceLock<Result<(), Vec<LoadError>>> = OnceLock::new();
    INSTALLED.get_or_init(install_once).clone().map_err(KktError::Load)
}

fn install_once() -> Result<(), Vec<LoadError>> {
    let mut failures = Vec::new();
    // The temporary directory first; an executable's own directory when that is mounted noexec.
    let mut directories = vec![std::env::temp_dir()];
    if let Some(dir) = std::env::current_exe().ok().and_then(|e| e.parent().map(PathBuf::from)) {
        directories.push(dir);
    }
    for dir in directories {
        match write_shim(&dir) {
            Ok(path) => {
                let loaded = abi::load(&path);
                let _ = std::fs::remove_file(&path);
                match loaded {
                    Ok(()) => return Ok(()),
                    Err(e) => failures.push(e),
                }
            }
            Err(e) => failures.push(e),
        }
    }
    Err(failures)
}

/// Writes the shim to a new file in `dir` (never over an existing one).
fn write_shim(dir: &std::path::Path) -> Result<PathBuf, LoadError> {
    let stamp = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map(|d| d.as_nanos()).unwrap_or(0);
    for attempt in 0..8 {
        let path = dir.join(format!("spine-kkt-{}-{stamp}-{attempt}.so", std::process::id()));
        match OpenOptions::new().write(true).create_new(true).open(&path) {
            Ok(mut file) => {
                return file
                    .write_all(abi::SHIM)
                    .map(|()| path.clone())
                    .map_err(|e| LoadError::Write { path: path.display().to_string(), message: e.to_string() });
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(LoadError::Write { path: path.display().to_string(), message: e.to_string() }),
        }
    }
    Err(LoadError::NoFreeName { dir: dir.display().to_string() })
}
