//! Ipopt's standard C interface (`IpStdCInterface.h`), declared by hand, and the callbacks that
//! connect it to a [`crate::Problem`] through a [`Context`]. Every `unsafe` block of this crate is in
//! this file.
//!
//! The interface is the same in Ipopt 3.11 and 3.14 except for `Bool` (C `int` up to 3.13, C99
//! `bool` from 3.14); `build.rs` reads the header of the library it links and sets
//! `cfg(ipopt_c99_bool)` accordingly, so the declarations always match the library.

use crate::c_bool::{from_c, to_c, Bool};
use crate::clock;
pub(crate) use crate::context::{Context, Finish, Start};
use crate::{IterationInfo, OptionValue, SetupError};
use std::ffi::{c_char, c_int, c_void, CString};

type Index = c_int;
type UserData = *mut c_void;

#[repr(C)]
struct IpoptProblemInfo {
    _private: [u8; 0],
}
type IpoptProblem = *mut IpoptProblemInfo;

type EvalF = extern "C" fn(Index, *mut f64, Bool, *mut f64, UserData) -> Bool;
type EvalGradF = extern "C" fn(Index, *mut f64, Bool, *mut f64, UserData) -> Bool;
type EvalG = extern "C" fn(Index, *mut f64, Bool, Index, *mut f64, UserData) -> Bool;
type EvalJacG = extern "C" fn(Index, *mut f64, Bool, Index, Index, *mut Index, *mut Index, *mut f64, UserData) -> Bool;
type EvalH = extern "C" fn(
    Index,
    *mut f64,
    Bool,
    f64,
    Index,
    *mut f64,
    Bool,
    Index,
    *mut Index,
    *mut Index,
    *mut f64,
    UserData,
) -> Bool;
type IntermediateCb = extern "C" fn(Index, Index, f64, f64, f64, f64, f64, f64, f64, f64, Index, UserData) -> Bool;

extern "C" {
    #[allow(clippy::too_many_arguments)]
    fn CreateIpoptProblem(
        n: Index,
        x_l: *mut f64,
        x_u: *mut f64,
        m: Index,
        g_l: *mut f64,
        g_u: *mut f64,
        nele_jac: Index,
        nele_hess: Index,
        index_style: Index,
        eval_f: Option<EvalF>,
        eval_g: Option<EvalG>,
        eval_grad_f: Option<EvalGradF>,
        eval_jac_g: Option<EvalJacG>,
        eval_h: Option<EvalH>,
    ) -> IpoptProblem;
    fn FreeIpoptProblem(problem: IpoptProblem);
    fn AddIpoptStrOption(problem: IpoptProblem, keyword: *mut c_char, val: *mut c_char) -> Bool;
    fn AddIpoptNumOption(problem: IpoptProblem, keyword: *mut c_char, val: f64) -> Bool;
    fn AddIpoptIntOption(problem: IpoptProblem, keyword: *mut c_char, val: Index) -> Bool;
    fn SetIntermediateCallback(problem: IpoptProblem, cb: Option<IntermediateCb>) -> Bool;
    #[allow(clippy::too_many_arguments)]
    fn IpoptSolve(
        problem: IpoptProblem,
        x: *mut f64,
        g: *mut f64,
        obj_val: *mut f64,
        mult_g: *mut f64,
        mult_x_l: *mut f64,
        mult_x_u: *mut f64,
        user_data: UserData,
    ) -> c_int;
}

/// Owns an `IpoptProblem` and frees it on drop.
struct RawProblem(IpoptProblem);

impl Drop for RawProblem {
    fn drop(&mut self) {
        // SAFETY: created by `CreateIpoptProblem` (non-null) and freed exactly once.
        unsafe { FreeIpoptProblem(self.0) };
    }
}

fn index(value: usize, what: &'static str) -> Result<Index, SetupError> {
    Index::try_from(value).map_err(|_| SetupError::TooLarge(what))
}

/// Creates the problem, sets the options and runs `IpoptSolve` with `context` as user data.
pub(crate) fn run(
    context: &mut Context<'_>,
    mut start: Start,
    options: &[(&str, &OptionValue)],
) -> Result<Finish, SetupError> {
    let n = start.x.len();
    let m = start.g_lower.len();
    let nele_jac = index(context.jacobian.len(), "the Jacobian's number of entries")?;
    let nele_hess = index(context.hessian.as_ref().map_or(0, Vec::len), "the Hessian's number of entries")?;
    // SAFETY: the bound arrays hold n and m values (Ipopt copies them); every callback is an
    // `extern "C"` function of this module with the declared signature.
    let ptr = unsafe {
        CreateIpoptProblem(
            index(n, "the number of variables")?,
            start.x_lower.as_mut_ptr(),
            start.x_upper.as_mut_ptr(),
            index(m, "the number of constraints")?,
            start.g_lower.as_mut_ptr(),
            start.g_upper.as_mut_ptr(),
            nele_jac,
            nele_hess,
            0,
            Some(eval_f),
            Some(eval_g),
            Some(eval_grad_f),
            Some(eval_jac_g),
            Some(eval_h),
        )
    };
    if ptr.is_null() {
        return Err(SetupError::CreateFailed(format!("n = {n}, m = {m}, {nele_jac} Jacobian entries")));
    }
    let raw = RawProblem(ptr);
    // SAFETY: `raw.0` is live and `intermediate` has the declared signature.
    unsafe { SetIntermediateCallback(raw.0, Some(intermediate)) };
    for (name, value) in options {
        let invalid = || SetupError::InvalidOption(format!("{name} = {value}"));
        let key = CString::new(*name).map_err(|_| invalid())?;
        // SAFETY: `raw.0` is live; the strings are NUL-terminated and outlive the calls (Ipopt
        // copies them and never writes through the pointers).
        let accepted = unsafe {
            match value {
                OptionValue::Str(text) => {
                    let text = CString::new(text.as_str()).map_err(|_| invalid())?;
                    AddIpoptStrOption(raw.0, key.as_ptr() as *mut c_char, text.as_ptr() as *mut c_char)
                }
                OptionValue::Num(number) => AddIpoptNumOption(raw.0, key.as_ptr() as *mut c_char, *number),
                OptionValue::Int(integer) => {
                    let integer = Index::try_from(*integer).map_err(|_| invalid())?;
                    AddIpoptIntOption(raw.0, key.as_ptr() as *mut c_char, integer)
                }
            }
        };
        if !from_c(accepted) {
            return Err(invalid());
        }
    }
    let mut g = vec![0.0; m];
    let mut objective = f64::NAN;
    let user_data = context as *mut Context<'_> as *mut c_void;
    // SAFETY: `raw` is live; x, g and the multiplier arrays hold n, m, m, n, n values; `user_data`
    // points to `context`, which outlives the call and is only touched by the callbacks during it.
    let status = unsafe {
        IpoptSolve(
            raw.0,
            start.x.as_mut_ptr(),
            g.as_mut_ptr(),
            &mut objective,
            start.mult_g.as_mut_ptr(),
            start.z_lower.as_mut_ptr(),
            start.z_upper.as_mut_ptr(),
            user_data,
        )
    };
    drop(raw);
    Ok(Finish {
        status,
        x: start.x,
        g,
        objective,
        mult_g: start.mult_g,
        z_lower: start.z_lower,
        z_upper: start.z_upper,
    })
}

/// Recovers the context from Ipopt's `user_data`.
///
/// # Safety
/// `user_data` must be the pointer passed to `IpoptSolve` by [`run`].
unsafe fn context<'a>(user_data: UserData) -> &'a mut Context<'a> {
    // SAFETY: the caller passes the pointer `run` gave Ipopt, which points to a live `Context`.
    unsafe { &mut *(user_data as *mut Context<'a>) }
}

/// A mutable slice over an Ipopt output buffer, empty when Ipopt passes NULL.
///
/// # Safety
/// A non-null `ptr` must be valid for `len` writes for the lifetime `'a`.
unsafe fn out_slice<'a>(ptr: *mut f64, len: Index) -> &'a mut [f64] {
    if ptr.is_null() || len <= 0 {
        &mut []
    } else {
        // SAFETY: non-null and valid for `len` writes (the caller's contract).
        unsafe { std::slice::from_raw_parts_mut(ptr, len as usize) }
    }
}

/// An input slice from Ipopt, empty when Ipopt passes NULL.
///
/// # Safety
/// A non-null `ptr` must be valid for `len` reads for the lifetime `'a`.
unsafe fn in_slice<'a>(ptr: *const f64, len: Index) -> &'a [f64] {
    if ptr.is_null() || len <= 0 {
        &[]
    } else {
        // SAFETY: non-null and valid for `len` reads (the caller's contract).
        unsafe { std::slice::from_raw_parts(ptr, len as usize) }
    }
}

/// Writes a sparsity structure into Ipopt's index arrays.
///
/// # Safety
/// Non-null `rows`/`cols` must be valid for `entries.len()` writes.
unsafe fn write_structure(entries: &[(usize, usize)], rows: *mut Index, cols: *mut Index) -> bool {
    if entries.is_empty() {
        return true;
    }
    if rows.is_null() || cols.is_null() {
        return false;
    }
    // SAFETY: both non-null and valid for `entries.len()` writes (the caller's contract).
    let (rows, cols) = unsafe {
        (std::slice::from_raw_parts_mut(rows, entries.len()), std::slice::from_raw_parts_mut(cols, entries.len()))
    };
    for (k, &(r, c)) in entries.iter().enumerate() {
        rows[k] = r as Index;
        cols[k] = c as Index;
    }
    true
}

extern "C" fn eval_f(n: Index, x: *mut f64, new_x: Bool, obj: *mut f64, user_data: UserData) -> Bool {
    // SAFETY: `user_data` comes from `run`; `x` holds n values and `obj` is a valid scalar.
    let ctx = unsafe { context(user_data) };
    to_c(ctx.guarded(|ctx| unsafe {
        ctx.evaluations.objective += 1;
        match ctx.problem.objective(in_slice(x, n), from_c(new_x)) {
            Some(value) => {
                *obj = value;
                true
            }
            None => false,
        }
    }))
}

extern "C" fn eval_grad_f(n: Index, x: *mut f64, new_x: Bool, grad: *mut f64, user_data: UserData) -> Bool {
    // SAFETY: `user_data` comes from `run`; `x` and `grad` hold n values.
    let ctx = unsafe { context(user_data) };
    to_c(ctx.guarded(|ctx| unsafe {
        ctx.evaluations.gradient += 1;
        ctx.problem.objective_gradient(in_slice(x, n), from_c(new_x), out_slice(grad, n))
    }))
}

extern "C" fn eval_g(n: Index, x: *mut f64, new_x: Bool, m: Index, g: *mut f64, user_data: UserData) -> Bool {
    // SAFETY: `user_data` comes from `run`; `x` holds n values and `g` m values.
    let ctx = unsafe { context(user_data) };
    to_c(ctx.guarded(|ctx| unsafe {
        ctx.evaluations.constraints += 1;
        ctx.problem.constraints(in_slice(x, n), from_c(new_x), out_slice(g, m))
    }))
}

#[allow(clippy::too_many_arguments)]
extern "C" fn eval_jac_g(
    n: Index,
    x: *mut f64,
    new_x: Bool,
    _m: Index,
    nnz: Index,
    rows: *mut Index,
    cols: *mut Index,
    values: *mut f64,
    user_data: UserData,
) -> Bool {
    // SAFETY: `user_data` comes from `run`; Ipopt's buffers hold n and nnz values.
    let ctx = unsafe { context(user_data) };
    to_c(ctx.guarded(|ctx| unsafe {
        if values.is_null() {
            return write_structure(&ctx.jacobian, rows, cols);
        }
        ctx.evaluations.jacobian += 1;
        ctx.problem.jacobian_values(in_slice(x, n), from_c(new_x), out_slice(values, nnz))
    }))
}

#[allow(clippy::too_many_arguments)]
extern "C" fn eval_h(
    n: Index,
    x: *mut f64,
    new_x: Bool,
    sigma: f64,
    m: Index,
    lambda: *mut f64,
    new_lambda: Bool,
    nnz: Index,
    rows: *mut Index,
    cols: *mut Index,
    values: *mut f64,
    user_data: UserData,
) -> Bool {
    // SAFETY: `user_data` comes from `run`; Ipopt's buffers hold n, m and nnz values.
    let ctx = unsafe { context(user_data) };
    to_c(ctx.guarded(|ctx| unsafe {
        let Some(structure) = ctx.hessian.as_ref() else {
            // Limited-memory mode: Ipopt never asks, and must not get a Hessian if it does.
            return false;
        };
        if values.is_null() {
            return write_structure(structure, rows, cols);
        }
        ctx.evaluations.hessian += 1;
        ctx.problem.hessian_values(
            in_slice(x, n),
            from_c(new_x),
            sigma,
            in_slice(lambda, m),
            from_c(new_lambda),
            out_slice(values, nnz),
        )
    }))
}

#[allow(clippy::too_many_arguments)]
extern "C" fn intermediate(
    mode: Index,
    iteration: Index,
    objective: f64,
    inf_pr: f64,
    inf_du: f64,
    mu: f64,
    d_norm: f64,
    regularization: f64,
    alpha_du: f64,
    alpha_pr: f64,
    ls_trials: Index,
    user_data: UserData,
) -> Bool {
    // SAFETY: `user_data` comes from `run`.
    let ctx = unsafe { context(user_data) };
    to_c(ctx.guarded(|ctx| {
        ctx.last = IterationInfo {
            iteration: iteration.max(0) as usize,
            restoration: mode == 1,
            objective,
            primal_infeasibility: inf_pr,
            dual_infeasibility: inf_du,
            barrier: mu,
            step_norm: d_norm,
            regularization,
            alpha_dual: alpha_du,
            alpha_primal: alpha_pr,
            line_search_trials: ls_trials.max(0) as usize,
        };
        let info = ctx.last;
        if let Some(reason) = spine_stop::check() {
            ctx.stopped = Some(reason);
            return false;
        }
        ctx.problem.intermediate(&info)
    }))
}

/// Ipopt's clock of CPU seconds (`Ipopt::CpuTime()`), replaced in this process. Debian's Ipopt
/// 3.11 times every task of every iteration, each start and stop a `getrusage` call: about 140
/// per iteration at 0.6–0.8 µs, a third of a 5-link solve (docs/design.md, "Ipopt's timing").
/// The library calls it through its PLT (`R_X86_64_JUMP_SLOT`), so this definition in the
/// executable interposes it: the monotonic clock (vDSO, about 0.02 µs; with 3.11 read for real at
/// every 16th read, `clock.rs`), seconds since the first read. `max_cpu_time` therefore counts
/// wall-clock seconds, an upper bound of a one-thread solve's CPU time. Where a library binds the
/// call locally this definition is not used.
#[allow(non_snake_case)]
#[no_mangle]
pub extern "C" fn _ZN5Ipopt7CpuTimeEv() -> f64 {
    clock::read(clock::Clock::Cpu)
}

/// Ipopt's wall clock (`Ipopt::WallclockTime()`, a `gettimeofday` read beside the CPU clock:
/// 1.6 % of a design10 census), replaced the same way, on the same clock.
#[allow(non_snake_case)]
#[no_mangle]
pub extern "C" fn _ZN5Ipopt13WallclockTimeEv() -> f64 {
    clock::read(clock::Clock::Wall)
}

/// Ipopt's clock of system CPU seconds (`Ipopt::SysTime()`), replaced with the same reasoning as
/// [`_ZN5Ipopt7CpuTimeEv`]: only Ipopt's timing statistics read it, and they show 0 s of system time.
#[allow(non_snake_case)]
#[no_mangle]
pub extern "C" fn _ZN5Ipopt7SysTimeEv() -> f64 {
    0.0
}
