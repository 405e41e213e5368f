//! Ipopt's C `Bool`: a C `int` up to Ipopt 3.13, C99 `bool` from 3.14 (`build.rs` reads the
//! linked library's header and sets `cfg(ipopt_c99_bool)`), and its conversions.

#[cfg(not(ipopt_c99_bool))]
use std::ffi::c_int;

#[cfg(ipopt_c99_bool)]
pub(crate) type Bool = bool;
#[cfg(not(ipopt_c99_bool))]
pub(crate) type Bool = c_int;

#[cfg(ipopt_c99_bool)]
pub(crate) fn to_c(b: bool) -> Bool {
    b
}
#[cfg(not(ipopt_c99_bool))]
pub(crate) fn to_c(b: bool) -> Bool {
    b as c_int
}
#[cfg(ipopt_c99_bool)]
pub(crate) fn from_c(b: Bool) -> bool {
    b
}
#[cfg(not(ipopt_c99_bool))]
pub(crate) fn from_c(b: Bool) -> bool {
    b != 0
}
