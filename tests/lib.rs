//! Cross-crate integration tests live beside this file; see `twolink.rs` and `cases.rs`.
#![forbid(unsafe_code)]
