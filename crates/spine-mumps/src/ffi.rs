//! The C boundary: the shim's functions (`shim/mumps_shim.c`) and the only `unsafe` code of the
//! crate. MUMPS does not call back into Rust, so no Rust panic can unwind through it.

use std::ffi::{c_double, c_int, c_longlong};
use std::ptr::NonNull;

/// The shim's opaque handle (MUMPS's `DMUMPS_STRUC_C` inside).
#[repr(C)]
pub(crate) struct Handle {
    _private: [u8; 0],
}

extern "C" {
    fn spine_mumps_analyse(
        n: c_int,
        nnz: c_longlong,
        irn: *mut c_int,
        jcn: *mut c_int,
        a: *mut c_double,
        info: *mut c_int,
    ) -> *mut Handle;
    fn spine_mumps_factor(m: *mut Handle) -> c_int;
    fn spine_mumps_negative(m: *const Handle) -> c_int;
    fn spine_mumps_solve(m: *mut Handle, rhs: *mut c_double) -> c_int;
    fn spine_mumps_free(m: *mut Handle);
}

/// Initialises MUMPS and analyses the matrix whose coordinates and values are in the three
/// arrays; returns the handle, or `INFOG(1)` on failure.
///
/// The arrays must have equal lengths and stay alive and unmoved (their heap buffers) for as long
/// as the handle: MUMPS keeps the pointers.
pub(crate) fn analyse(n: i32, irn: &mut [i32], jcn: &mut [i32], a: &mut [f64]) -> Result<NonNull<Handle>, i32> {
    assert!(irn.len() == jcn.len() && jcn.len() == a.len(), "coordinate arrays of equal length");
    let mut info: c_int = 0;
    // SAFETY: the three pointers address `nnz` valid elements each (checked above); the caller
    // keeps the buffers alive for the handle's life (see `crate::Mumps`, which owns them); `info`
    // is a valid out-pointer.
    let handle = unsafe {
        spine_mumps_analyse(n, a.len() as c_longlong, irn.as_mut_ptr(), jcn.as_mut_ptr(), a.as_mut_ptr(), &mut info)
    };
    match NonNull::new(handle) {
        Some(h) if info >= 0 => Ok(h),
        Some(h) => {
            free(h);
            Err(info)
        }
        None => Err(info),
    }
}

/// Factorises the current values (`JOB = 2`); returns `INFOG(1)`.
pub(crate) fn factor(handle: NonNull<Handle>) -> i32 {
    // SAFETY: `handle` came from `analyse` and has not been freed (`crate::Mumps` frees it once,
    // in `Drop`); the value array it points to is alive.
    unsafe { spine_mumps_factor(handle.as_ptr()) }
}

/// `INFOG(12)`: the negative pivots of the last factorisation.
pub(crate) fn negative(handle: NonNull<Handle>) -> i32 {
    // SAFETY: as in `factor`; reads one field.
    unsafe { spine_mumps_negative(handle.as_ptr()) }
}

/// Overwrites `rhs` (length `n`) with the solution (`JOB = 3`); returns `INFOG(1)`.
pub(crate) fn solve(handle: NonNull<Handle>, rhs: &mut [f64]) -> i32 {
    // SAFETY: as in `factor`; `rhs` holds `n` values (checked by the caller), which MUMPS reads
    // and overwrites during the call only.
    unsafe { spine_mumps_solve(handle.as_ptr(), rhs.as_mut_ptr()) }
}

/// Frees MUMPS's storage and the handle.
pub(crate) fn free(handle: NonNull<Handle>) {
    // SAFETY: `handle` came from `analyse`; callers free it exactly once.
    unsafe { spine_mumps_free(handle.as_ptr()) }
}
