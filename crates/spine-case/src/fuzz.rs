//! The body of the fuzz targets, shared by `fuzz/` (cargo-fuzz, nightly) and the stable fuzz test
//! in `tests/cases.rs`, so that both exercise the same code.

/// Parses `data` as a case file and checks it, whatever its kind: any bytes must give a checked
/// case or an error naming a field, never a panic. Returns whether the case was valid.
pub fn check_bytes(data: &[u8]) -> bool {
    let Ok(text) = std::str::from_utf8(data) else { return false };
    match crate::Case::from_json(text) {
        Ok(case) => case.validate().is_ok(),
        Err(_) => false,
    }
}
