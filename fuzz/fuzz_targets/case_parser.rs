//! Fuzz the case parser and validation of every case kind: any bytes must give a case or an error,
//! never a panic. The body is `spine_case::fuzz::check_bytes`, which the stable fuzz test in
//! `tests/cases.rs` also runs.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = spine_case::fuzz::check_bytes(data);
});
