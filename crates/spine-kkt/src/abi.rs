//! The C boundary of the linear solver, and every `unsafe` block of this crate: Pardiso's two
//! entry points as `extern "C"` functions, and the loading of the shim library that forwards
//! Ipopt's calls to them.
//!
//! Each entry point checks its pointers, builds slices of the lengths Pardiso's interface gives
//! them (`iparm`/`dparm`: 64 entries; `ia`: `n + 1`; `ja`, `a`: `ia[n] − 1`; `b`, `x`: `n · nrhs`),
//! runs the safe [`crate::pardiso`] code inside `catch_unwind` (a panic becomes error −5, never an
//! unwind into C), and writes the error code. The solver state lives in a `Box` whose pointer is
//! the first entry of Pardiso's handle array `pt`, which Ipopt owns, zeroes through `pardisoinit`
//! and releases with phase −1.

use crate::pardiso::{self, error, Call, State, PARAMETERS};
use crate::LoadError;
use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::os::unix::ffi::OsStrExt;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

/// The shim library built by `build.rs`.
pub(crate) const SHIM: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/libpardiso.so"));

const RTLD_NOW: c_int = 2;
const RTLD_NODELETE: c_int = 0x1000;

extern "C" {
    fn dlopen(filename: *const c_char, flags: c_int) -> *mut c_void;
    fn dlsym(handle: *mut c_void, symbol: *const c_char) -> *mut c_void;
    fn dlerror() -> *mut c_char;
}

type InitFn = extern "C" fn(*mut c_void, *const c_int, *const c_int, *mut c_int, *mut f64, *mut c_int);
type PardisoFn = extern "C" fn(
    *mut *mut c_void,
    *const c_int,
    *const c_int,
    *const c_int,
    *const c_int,
    *const c_int,
    *const f64,
    *const c_int,
    *const c_int,
    *const c_int,
    *const c_int,
    *mut c_int,
    *const c_int,
    *mut f64,
    *mut f64,
    *mut c_int,
    *mut f64,
);
type RegisterFn = unsafe extern "C" fn(InitFn, PardisoFn);

fn last_dl_error() -> String {
    // SAFETY: dlerror returns NULL or a NUL-terminated string owned by the C library, valid until
    // the next dl* call on this thread; it is copied out at once.
    let message = unsafe { dlerror() };
    if message.is_null() {
        "unknown error".into()
    } else {
        // SAFETY: non-null, NUL-terminated (see above).
        unsafe { CStr::from_ptr(message) }.to_string_lossy().into_owned()
    }
}

/// Loads the shim at `path` for the life of the process and registers the entry points with it.
pub(crate) fn load(path: &Path) -> Result<(), LoadError> {
    let shown = || path.display().to_string();
    let c_path = CString::new(path.as_os_str().as_bytes()).map_err(|_| LoadError::NulInPath { path: shown() })?;
    // SAFETY: a valid NUL-terminated path; the shim has no constructors. RTLD_NODELETE keeps it
    // mapped after the file is removed and for the rest of the process.
    let handle = unsafe { dlopen(c_path.as_ptr(), RTLD_NOW | RTLD_NODELETE) };
    if handle.is_null() {
        return Err(LoadError::Open { path: shown(), message: last_dl_error() });
    }
    // SAFETY: a live handle and a NUL-terminated symbol name.
    let symbol = unsafe { dlsym(handle, c"spine_kkt_register".as_ptr()) };
    if symbol.is_null() {
        return Err(LoadError::NoRegister { path: shown(), message: last_dl_error() });
    }
    // SAFETY: the symbol is the shim's `void spine_kkt_register(init_fn, pardiso_fn)`, whose C
    // signature is `RegisterFn`; a data pointer and a function pointer have the same size here.
    let register: RegisterFn = unsafe { std::mem::transmute::<*mut c_void, RegisterFn>(symbol) };
    // SAFETY: both functions match the shim's typedefs; it stores them in two statics.
    unsafe { register(pardisoinit, pardiso) };
    Ok(())
}

/// `pardisoinit(pt, mtype, solver, iparm, dparm, error)`.
extern "C" fn pardisoinit(
    pt: *mut c_void,
    mtype: *const c_int,
    _solver: *const c_int,
    iparm: *mut c_int,
    dparm: *mut f64,
    error: *mut c_int,
) {
    let code = catch_unwind(AssertUnwindSafe(|| {
        if pt.is_null() || mtype.is_null() || iparm.is_null() || dparm.is_null() {
            return error::INPUT;
        }
        let pt = pt.cast::<*mut c_void>();
        // SAFETY: Pardiso's interface: `pt` is an array of 64 pointers (possibly uninitialised:
        // written, never read, here), `iparm` and `dparm` arrays of 64, `mtype` one integer.
        unsafe {
            for i in 0..PARAMETERS {
                pt.add(i).write(std::ptr::null_mut());
            }
            let iparm = &mut *iparm.cast::<[i32; PARAMETERS]>();
            let dparm = &mut *dparm.cast::<[f64; PARAMETERS]>();
            pardiso::init(*mtype, iparm, dparm)
        }
    }))
    .unwrap_or(error::INTERNAL);
    report(error, code);
}

/// `pardiso(pt, maxfct, mnum, mtype, phase, n, a, ia, ja, perm, nrhs, iparm, msglvl, b, x, error,
/// dparm)`.
#[allow(clippy::too_many_arguments)]
extern "C" fn pardiso(
    pt: *mut *mut c_void,
    _maxfct: *const c_int,
    mnum: *const c_int,
    mtype: *const c_int,
    phase: *const c_int,
    n: *const c_int,
    a: *const f64,
    ia: *const c_int,
    ja: *const c_int,
    _perm: *const c_int,
    nrhs: *const c_int,
    iparm: *mut c_int,
    msglvl: *const c_int,
    b: *mut f64,
    x: *mut f64,
    error: *mut c_int,
    _dparm: *mut f64,
) {
    let code = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the pointers are those of one Pardiso call (see `call`).
        unsafe { call(pt, mnum, mtype, phase, n, a, ia, ja, nrhs, iparm, msglvl, b, x) }
    }))
    .unwrap_or(error::INTERNAL);
    report(error, code);
}

/// Writes Pardiso's error code where the caller asked for it (nowhere for a null pointer).
fn report(error: *mut c_int, code: i32) {
    if !error.is_null() {
        // SAFETY: a non-null pointer to one integer (Pardiso's interface).
        unsafe { error.write(code) };
    }
}

/// A slice of `len` values at `ptr`, or `None` for a null pointer.
///
/// # Safety
/// A non-null `ptr` must point to `len` initialised values that outlive the slice.
unsafe fn slice<'a, T>(ptr: *const T, len: usize) -> Option<&'a [T]> {
    // SAFETY: the caller's promise.
    (!ptr.is_null()).then(|| unsafe { std::slice::from_raw_parts(ptr, len) })
}

/// # Safety
/// Pointers as Pardiso's interface defines them: `pt` an array of 64 pointers whose first entry is
/// null or this crate's `State`, the scalars single integers, the arrays of the lengths in the
/// module docs for the phase given.
#[allow(clippy::too_many_arguments)]
unsafe fn call(
    pt: *mut *mut c_void,
    mnum: *const c_int,
    mtype: *const c_int,
    phase: *const c_int,
    n: *const c_int,
    a: *const f64,
    ia: *const c_int,
    ja: *const c_int,
    nrhs: *const c_int,
    iparm: *mut c_int,
    msglvl: *const c_int,
    b: *mut f64,
    x: *mut f64,
) -> i32 {
    if pt.is_null() || phase.is_null() || mtype.is_null() || n.is_null() || iparm.is_null() {
        return error::INPUT;
    }
    // SAFETY: non-null pointers to single integers and the handle array (caller's promise).
    let (phase, mtype, n, handle) = unsafe { (*phase, *mtype, *n, &mut *pt) };
    if phase == -1 {
        if !handle.is_null() {
            // SAFETY: a non-null first entry of `pt` is a `Box<State>` made below.
            drop(unsafe { Box::from_raw(handle.cast::<State>()) });
            *handle = std::ptr::null_mut();
        }
        return error::NONE;
    }
    // SAFETY: single integer when non-null.
    if mnum.is_null() || unsafe { *mnum } != 1 {
        return error::INPUT;
    }
    let Ok(order) = usize::try_from(n) else { return error::INPUT };
    if handle.is_null() {
        if !(11..=13).contains(&phase) {
            return error::INPUT;
        }
        *handle = Box::into_raw(Box::<State>::default()).cast::<c_void>();
    }
    // SAFETY: the first entry of `pt` is our `Box<State>`; Ipopt serialises calls on one handle.
    let state = unsafe { &mut *handle.cast::<State>() };
    let (mut ia_s, mut ja_s, mut a_s): (&[i32], &[i32], &[f64]) = (&[], &[], &[]);
    if Call::reads_matrix(phase) {
        // SAFETY: `ia` has n + 1 entries.
        let Some(rows) = (unsafe { slice(ia, order + 1) }) else { return error::INPUT };
        let Ok(stored) = usize::try_from(rows[order] - 1) else { return error::INPUT };
        // SAFETY: `ja` and `a` have ia[n] − 1 entries.
        let (Some(cols), Some(values)) = (unsafe { slice(ja, stored) }, unsafe { slice(a, stored) }) else {
            return error::INPUT;
        };
        (ia_s, ja_s, a_s) = (rows, cols, values);
    }
    let mut columns = 0;
    let (mut b_s, mut x_s): (&mut [f64], &mut [f64]) = (&mut [], &mut []);
    if Call::solves(phase) {
        // SAFETY: single integer when non-null.
        let Some(k) = (!nrhs.is_null()).then(|| unsafe { *nrhs }).and_then(|k| usize::try_from(k).ok()) else {
            return error::INPUT;
        };
        if b.is_null() || x.is_null() {
            return error::INPUT;
        }
        columns = k;
        // SAFETY: `b` and `x` hold n · nrhs values each, distinct arrays (Pardiso's interface).
        (b_s, x_s) =
            unsafe { (std::slice::from_raw_parts_mut(b, order * k), std::slice::from_raw_parts_mut(x, order * k)) };
    }
    // SAFETY: `iparm` has 64 entries.
    let iparm = unsafe { &mut *iparm.cast::<[i32; PARAMETERS]>() };
    // SAFETY: single integer when non-null.
    let msglvl = if msglvl.is_null() { 0 } else { unsafe { *msglvl } };
    state.call(Call {
        phase,
        mtype,
        n: order,
        nrhs: columns,
        a: a_s,
        ia: ia_s,
        ja: ja_s,
        iparm,
        b: b_s,
        x: x_s,
        msglvl,
    })
}
