//! Fuzz the case parser and validation: any bytes must give a case or an error, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(case) = spine_case::Case::from_json(text) {
            match case {
                spine_case::Case::Equilibrium(c) => {
                    let _ = c.validate();
                }
                spine_case::Case::Twolink(c) => {
                    let _ = c.validate();
                }
            }
        }
    }
});
