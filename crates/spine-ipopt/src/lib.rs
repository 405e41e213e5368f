//! A thin safe wrapper over Ipopt's C interface (the `cnlp` shim of `ipopt-sys`).
//!
//! Ipopt solves
//!
//! ```text
//! min f(x)   subject to   g_l ≤ g(x) ≤ g_u,   x_l ≤ x ≤ x_u
//! ```
//!
//! with an interior-point method. A problem implements [`Problem`]: sizes, bounds, a start point,
//! `f`, `∇f`, `g`, the sparse Jacobian of `g` and (optionally) the sparse Hessian of the Lagrangian
//! `σ∇²f + Σ λ_i ∇²g_i`, lower triangle only. [`solve`] runs Ipopt and returns a [`Solution`] whose
//! [`Status`] names every Ipopt return code.
//!
//! This is the only crate of the workspace with `unsafe` code. Every callback runs inside
//! `catch_unwind`: a panic in user code is caught, Ipopt is told the evaluation failed and is
//! stopped at its next iteration, and the panic resumes after Ipopt has returned, so no Rust panic
//! ever unwinds through C frames.
//!
//! Debian's Ipopt 3.11.9 uses MUMPS, which is not thread-safe: [`solve`] holds a process-wide lock
//! so two solves never run at the same time.
//!
//! ```
//! use spine_ipopt::{solve, Options, Problem};
//!
//! /// min (x − 3)²  subject to  x ≥ 0 (no constraints): the optimum is x = 3.
//! struct Parabola;
//! impl Problem for Parabola {
//!     fn num_variables(&self) -> usize { 1 }
//!     fn num_constraints(&self) -> usize { 0 }
//!     fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
//!         lower[0] = 0.0;
//!         upper[0] = f64::INFINITY;
//!     }
//!     fn constraint_bounds(&self, _: &mut [f64], _: &mut [f64]) {}
//!     fn initial_point(&self, x: &mut [f64]) { x[0] = 1.0; }
//!     fn objective(&mut self, x: &[f64], _new_x: bool) -> Option<f64> { Some((x[0] - 3.0).powi(2)) }
//!     fn objective_gradient(&mut self, x: &[f64], _new_x: bool, grad: &mut [f64]) -> bool {
//!         grad[0] = 2.0 * (x[0] - 3.0);
//!         true
//!     }
//!     fn constraints(&mut self, _: &[f64], _: bool, _: &mut [f64]) -> bool { true }
//!     fn jacobian_structure(&self) -> Vec<(usize, usize)> { Vec::new() }
//!     fn jacobian_values(&mut self, _: &[f64], _: bool, _: &mut [f64]) -> bool { true }
//!     fn hessian_structure(&self) -> Option<Vec<(usize, usize)>> { Some(vec![(0, 0)]) }
//!     fn hessian_values(&mut self, _: &[f64], _: bool, sigma: f64, _: &[f64], _: bool, h: &mut [f64]) -> bool {
//!         h[0] = 2.0 * sigma;
//!         true
//!     }
//! }
//!
//! let solution = solve(&mut Parabola, &Options::new()).unwrap();
//! assert!(solution.status.is_optimal());
//! assert!((solution.x[0] - 3.0).abs() < 1e-8);
//! ```

mod options;
mod status;

pub use options::{OptionValue, Options};
pub use status::Status;

use ipopt_sys as sys;
use std::any::Any;
use std::ffi::{c_void, CString};
use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// A nonlinear program for Ipopt. Indices are zero-based. Every evaluation returns `false` (or
/// `None`) when it cannot evaluate at `x` (for example an equilibrium solve failed); Ipopt then
/// shortens its step.
///
/// `new_x` is `false` when `x` is the same as in the previous call of any evaluation, so a problem
/// may cache work shared between `f`, `g` and their derivatives.
pub trait Problem {
    /// Number of variables `n`.
    fn num_variables(&self) -> usize;
    /// Number of constraints `m`.
    fn num_constraints(&self) -> usize;
    /// Variable bounds; `±f64::INFINITY` (or beyond ±1e19) means unbounded.
    fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]);
    /// Constraint bounds; equal bounds make an equality constraint.
    fn constraint_bounds(&self, lower: &mut [f64], upper: &mut [f64]);
    /// The start point.
    fn initial_point(&self, x: &mut [f64]);
    /// Start values of the bound multipliers and the constraint multipliers, asked for only with the
    /// option `warm_start_init_point = yes`. Return `false` when there are none.
    fn initial_multipliers(&self, _z_lower: &mut [f64], _z_upper: &mut [f64], _lambda: &mut [f64]) -> bool {
        false
    }
    /// The objective `f(x)`.
    fn objective(&mut self, x: &[f64], new_x: bool) -> Option<f64>;
    /// The gradient `∇f(x)`.
    fn objective_gradient(&mut self, x: &[f64], new_x: bool, gradient: &mut [f64]) -> bool;
    /// The constraint values `g(x)`.
    fn constraints(&mut self, x: &[f64], new_x: bool, g: &mut [f64]) -> bool;
    /// The sparsity pattern of `∂g/∂x` as `(row, column)` pairs. Called once per solve.
    fn jacobian_structure(&self) -> Vec<(usize, usize)>;
    /// The Jacobian values, in the order of [`Problem::jacobian_structure`].
    fn jacobian_values(&mut self, x: &[f64], new_x: bool, values: &mut [f64]) -> bool;
    /// The sparsity pattern of the Hessian of the Lagrangian, lower triangle (`row ≥ column`), or
    /// `None` to let Ipopt build a limited-memory quasi-Newton approximation instead.
    fn hessian_structure(&self) -> Option<Vec<(usize, usize)>>;
    /// The values of `σ∇²f(x) + Σ λ_i ∇²g_i(x)`, in the order of [`Problem::hessian_structure`].
    fn hessian_values(
        &mut self,
        x: &[f64],
        new_x: bool,
        sigma: f64,
        lambda: &[f64],
        new_lambda: bool,
        values: &mut [f64],
    ) -> bool;
    /// Called once per iteration; return `false` to stop Ipopt (status [`Status::UserRequestedStop`]).
    fn intermediate(&mut self, _info: &IterationInfo) -> bool {
        true
    }
}

/// What Ipopt reports at the end of one iteration.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct IterationInfo {
    /// Iteration number (0 is the start point).
    pub iteration: usize,
    /// Whether Ipopt is in its feasibility restoration phase.
    pub restoration: bool,
    /// Objective value (of the original problem, unscaled).
    pub objective: f64,
    /// Primal infeasibility (largest constraint violation, scaled).
    pub primal_infeasibility: f64,
    /// Dual infeasibility (scaled).
    pub dual_infeasibility: f64,
    /// Barrier parameter μ.
    pub barrier: f64,
    /// Size of the step, ∞-norm.
    pub step_norm: f64,
    /// Hessian regularisation added in this iteration.
    pub regularization: f64,
    /// Dual and primal step lengths.
    pub alpha_dual: f64,
    pub alpha_primal: f64,
    /// Line-search trials.
    pub line_search_trials: usize,
}

/// What Ipopt returned, copied out of the solver.
#[derive(Clone, Debug)]
pub struct Solution {
    pub status: Status,
    /// The final iterate.
    pub x: Vec<f64>,
    /// Objective at `x`.
    pub objective: f64,
    /// Constraint values `g(x)`.
    pub g: Vec<f64>,
    /// Constraint multipliers (Ipopt's sign convention: `∇f + ∇gᵀλ − z_L + z_U = 0`).
    pub lambda: Vec<f64>,
    /// Lower and upper bound multipliers.
    pub z_lower: Vec<f64>,
    pub z_upper: Vec<f64>,
    /// Iterations Ipopt ran (the last iteration number reported).
    pub iterations: usize,
    /// The last iteration's report.
    pub last_iteration: IterationInfo,
    /// Evaluations of f, ∇f, g, ∂g and ∇²L.
    pub evaluations: EvaluationCounts,
    /// Wall time of the whole solve, and the part of it spent inside the problem's callbacks.
    pub wall_time: Duration,
    pub callback_time: Duration,
}

/// How often Ipopt called each evaluation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EvaluationCounts {
    pub objective: usize,
    pub gradient: usize,
    pub constraints: usize,
    pub jacobian: usize,
    pub hessian: usize,
}

/// Why a problem could not be handed to Ipopt at all.
#[derive(Debug, Clone, PartialEq)]
pub enum SetupError {
    /// Sizes too large for Ipopt's 32-bit indices.
    TooLarge(&'static str),
    /// A sparsity entry outside the matrix, or in the upper triangle of the Hessian.
    BadStructure(String),
    /// Ipopt refused an option (unknown name or wrong type).
    InvalidOption(String),
    /// `cnlp_create_problem` failed with this code.
    CreateFailed(u32),
}

impl std::fmt::Display for SetupError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SetupError::TooLarge(what) => write!(f, "{what} exceeds Ipopt's 32-bit index range"),
            SetupError::BadStructure(what) => write!(f, "bad sparsity structure: {what}"),
            SetupError::InvalidOption(what) => write!(f, "Ipopt rejected the option {what}"),
            SetupError::CreateFailed(code) => write!(f, "Ipopt could not create the problem (code {code})"),
        }
    }
}

impl std::error::Error for SetupError {}

/// MUMPS in Ipopt 3.11 is not thread-safe: one solve at a time per process.
static SOLVE_LOCK: Mutex<()> = Mutex::new(());

/// Everything a callback needs, behind the `user_data` pointer.
struct Context<'a> {
    problem: &'a mut dyn Problem,
    n: usize,
    m: usize,
    jacobian: Vec<(usize, usize)>,
    hessian: Option<Vec<(usize, usize)>>,
    panic: Option<Box<dyn Any + Send>>,
    last: IterationInfo,
    evaluations: EvaluationCounts,
    callback_time: Duration,
}

impl Context<'_> {
    /// Runs `f` with panics caught and time recorded; a panic is stored and reported as failure.
    fn guarded(&mut self, f: impl FnOnce(&mut Self) -> bool) -> sys::CNLP_Bool {
        if self.panic.is_some() {
            return 0;
        }
        let start = Instant::now();
        let outcome = catch_unwind(AssertUnwindSafe(|| f(self)));
        self.callback_time += start.elapsed();
        match outcome {
            Ok(ok) => ok as sys::CNLP_Bool,
            Err(payload) => {
                self.panic = Some(payload);
                0
            }
        }
    }
}

/// Solves `problem` with Ipopt.
///
/// The options are passed to Ipopt as given, after two defaults that keep the terminal quiet
/// (`print_level = 0`, `sb = yes`) and, when [`Problem::hessian_structure`] is `None`,
/// `hessian_approximation = limited-memory`; any of them can be overridden in `options`.
///
/// # Panics
/// Resumes a panic raised inside one of the problem's callbacks, after Ipopt has returned.
pub fn solve(problem: &mut dyn Problem, options: &Options) -> Result<Solution, SetupError> {
    let n = problem.num_variables();
    let m = problem.num_constraints();
    let jacobian = problem.jacobian_structure();
    let hessian = problem.hessian_structure();
    check_sizes(n, m, &jacobian, hessian.as_deref())?;

    let mut all_options = Options::new().string("sb", "yes").integer("print_level", 0);
    if hessian.is_none() {
        all_options = all_options.string("hessian_approximation", "limited-memory");
    }
    all_options.extend(options);

    let _guard = SOLVE_LOCK.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    let mut context = Context {
        problem,
        n,
        m,
        jacobian,
        hessian,
        panic: None,
        last: IterationInfo::default(),
        evaluations: EvaluationCounts::default(),
        callback_time: Duration::ZERO,
    };
    let raw = RawProblem::create()?;
    for (name, value) in all_options.iter() {
        raw.add_option(name, value)?;
    }
    let start = Instant::now();
    let user_data = &mut context as *mut Context as *mut c_void;
    // SAFETY: `raw` is a live problem; `user_data` points to `context`, which outlives the call and
    // is only touched by the callbacks during it.
    let result = unsafe { sys::cnlp_solve(raw.0, user_data) };
    let wall_time = start.elapsed();
    let copy = |ptr: *const f64, len: usize| -> Vec<f64> {
        if ptr.is_null() || len == 0 {
            vec![0.0; len]
        } else {
            // SAFETY: the solver data vectors belong to `raw` (still alive) and hold `len` values.
            unsafe { std::slice::from_raw_parts(ptr, len) }.to_vec()
        }
    };
    let solution = Solution {
        status: Status::from_code(result.status),
        x: copy(result.data.x, n),
        objective: result.obj_val,
        g: copy(result.g, m),
        lambda: copy(result.data.mult_g, m),
        z_lower: copy(result.data.mult_x_L, n),
        z_upper: copy(result.data.mult_x_U, n),
        iterations: context.last.iteration,
        last_iteration: context.last,
        evaluations: context.evaluations,
        wall_time,
        callback_time: context.callback_time,
    };
    drop(raw);
    if let Some(payload) = context.panic.take() {
        resume_unwind(payload);
    }
    Ok(solution)
}

fn check_sizes(
    n: usize,
    m: usize,
    jacobian: &[(usize, usize)],
    hessian: Option<&[(usize, usize)]>,
) -> Result<(), SetupError> {
    let limit = i32::MAX as usize;
    if n > limit {
        return Err(SetupError::TooLarge("the number of variables"));
    }
    if m > limit {
        return Err(SetupError::TooLarge("the number of constraints"));
    }
    if jacobian.len() > limit {
        return Err(SetupError::TooLarge("the Jacobian's number of entries"));
    }
    if let Some(&(r, c)) = jacobian.iter().find(|&&(r, c)| r >= m || c >= n) {
        return Err(SetupError::BadStructure(format!("Jacobian entry ({r}, {c}) outside {m}×{n}")));
    }
    if let Some(hessian) = hessian {
        if hessian.len() > limit {
            return Err(SetupError::TooLarge("the Hessian's number of entries"));
        }
        if let Some(&(r, c)) = hessian.iter().find(|&&(r, c)| r >= n || c > r) {
            return Err(SetupError::BadStructure(format!(
                "Hessian entry ({r}, {c}) is not in the lower triangle of {n}×{n}"
            )));
        }
    }
    Ok(())
}

/// Owns a `CNLP_ProblemPtr` and frees it on drop.
struct RawProblem(sys::CNLP_ProblemPtr);

impl RawProblem {
    fn create() -> Result<Self, SetupError> {
        let mut ptr: sys::CNLP_ProblemPtr = std::ptr::null_mut();
        // SAFETY: every callback is an `extern "C"` function of this module with the expected
        // signature; `ptr` receives the new problem.
        let code = unsafe {
            sys::cnlp_create_problem(
                &mut ptr,
                0,
                Some(sizes),
                Some(init),
                Some(bounds),
                Some(eval_f),
                Some(eval_g),
                Some(eval_grad_f),
                Some(eval_jac_g),
                Some(eval_h),
                None,
            )
        };
        if code != sys::CNLP_CreateProblemStatus_CNLP_SUCCESS || ptr.is_null() {
            return Err(SetupError::CreateFailed(code));
        }
        // SAFETY: `ptr` is a live problem and `intermediate` has the expected signature.
        unsafe { sys::cnlp_set_intermediate_callback(ptr, Some(intermediate)) };
        Ok(RawProblem(ptr))
    }

    fn add_option(&self, name: &str, value: &OptionValue) -> Result<(), SetupError> {
        let invalid = || SetupError::InvalidOption(format!("{name} = {value}"));
        let key = CString::new(name).map_err(|_| invalid())?;
        // SAFETY: `self.0` is live; the strings are NUL-terminated and outlive the calls.
        let accepted = unsafe {
            match value {
                OptionValue::Str(text) => {
                    let text = CString::new(text.as_str()).map_err(|_| invalid())?;
                    sys::cnlp_add_str_option(self.0, key.as_ptr(), text.as_ptr())
                }
                OptionValue::Num(number) => sys::cnlp_add_num_option(self.0, key.as_ptr(), *number),
                OptionValue::Int(integer) => {
                    let integer = i32::try_from(*integer).map_err(|_| invalid())?;
                    sys::cnlp_add_int_option(self.0, key.as_ptr(), integer)
                }
            }
        };
        if accepted == 0 {
            Err(invalid())
        } else {
            Ok(())
        }
    }
}

impl Drop for RawProblem {
    fn drop(&mut self) {
        // SAFETY: created by `cnlp_create_problem` and freed exactly once.
        unsafe { sys::cnlp_free_problem(self.0) };
    }
}

/// Recovers the context from Ipopt's `user_data`.
///
/// # Safety
/// `user_data` must be the pointer passed to `cnlp_solve` by [`solve`].
unsafe fn context<'a>(user_data: sys::CNLP_UserDataPtr) -> &'a mut Context<'a> {
    &mut *(user_data as *mut Context)
}

/// A mutable slice over an Ipopt output buffer, empty when Ipopt passes NULL.
///
/// # Safety
/// A non-null `ptr` must be valid for `len` writes for the lifetime `'a`.
unsafe fn out_slice<'a>(ptr: *mut f64, len: usize) -> &'a mut [f64] {
    if ptr.is_null() || len == 0 {
        &mut []
    } else {
        std::slice::from_raw_parts_mut(ptr, len)
    }
}

/// An input slice from Ipopt, empty when Ipopt passes NULL.
///
/// # Safety
/// A non-null `ptr` must be valid for `len` reads for the lifetime `'a`.
unsafe fn in_slice<'a>(ptr: *const f64, len: usize) -> &'a [f64] {
    if ptr.is_null() || len == 0 {
        &[]
    } else {
        std::slice::from_raw_parts(ptr, len)
    }
}

/// Writes a sparsity structure into Ipopt's index arrays.
///
/// # Safety
/// Non-null `rows`/`cols` must be valid for `entries.len()` writes.
unsafe fn write_structure(entries: &[(usize, usize)], rows: *mut sys::CNLP_Index, cols: *mut sys::CNLP_Index) -> bool {
    if entries.is_empty() {
        return true;
    }
    if rows.is_null() || cols.is_null() {
        return false;
    }
    let rows = std::slice::from_raw_parts_mut(rows, entries.len());
    let cols = std::slice::from_raw_parts_mut(cols, entries.len());
    for (k, &(r, c)) in entries.iter().enumerate() {
        rows[k] = r as sys::CNLP_Index;
        cols[k] = c as sys::CNLP_Index;
    }
    true
}

extern "C" fn sizes(
    n: *mut sys::CNLP_Index,
    m: *mut sys::CNLP_Index,
    nnz_jac: *mut sys::CNLP_Index,
    nnz_hess: *mut sys::CNLP_Index,
    user_data: sys::CNLP_UserDataPtr,
) -> sys::CNLP_Bool {
    // SAFETY: `user_data` comes from `solve`; the out-pointers are valid Ipopt scalars.
    let ctx = unsafe { context(user_data) };
    ctx.guarded(|ctx| {
        let hessian_len = ctx.hessian.as_ref().map_or(0, Vec::len);
        unsafe {
            *n = ctx.n as sys::CNLP_Index;
            *m = ctx.m as sys::CNLP_Index;
            *nnz_jac = ctx.jacobian.len() as sys::CNLP_Index;
            *nnz_hess = hessian_len as sys::CNLP_Index;
        }
        true
    })
}

#[allow(clippy::too_many_arguments)]
extern "C" fn init(
    n: sys::CNLP_Index,
    init_x: sys::CNLP_Bool,
    x: *mut f64,
    init_z: sys::CNLP_Bool,
    z_l: *mut f64,
    z_u: *mut f64,
    m: sys::CNLP_Index,
    init_lambda: sys::CNLP_Bool,
    lambda: *mut f64,
    user_data: sys::CNLP_UserDataPtr,
) -> sys::CNLP_Bool {
    // SAFETY: `user_data` comes from `solve`; Ipopt's buffers hold n and m values.
    let ctx = unsafe { context(user_data) };
    ctx.guarded(|ctx| unsafe {
        let (n, m) = (n as usize, m as usize);
        if init_x != 0 {
            ctx.problem.initial_point(out_slice(x, n));
        }
        if init_z != 0 || init_lambda != 0 {
            let (mut zl, mut zu, mut lam) = (vec![0.0; n], vec![0.0; n], vec![0.0; m]);
            if !ctx.problem.initial_multipliers(&mut zl, &mut zu, &mut lam) {
                return false;
            }
            if init_z != 0 {
                out_slice(z_l, n).copy_from_slice(&zl);
                out_slice(z_u, n).copy_from_slice(&zu);
            }
            if init_lambda != 0 {
                out_slice(lambda, m).copy_from_slice(&lam);
            }
        }
        true
    })
}

extern "C" fn bounds(
    n: sys::CNLP_Index,
    x_l: *mut f64,
    x_u: *mut f64,
    m: sys::CNLP_Index,
    g_l: *mut f64,
    g_u: *mut f64,
    user_data: sys::CNLP_UserDataPtr,
) -> sys::CNLP_Bool {
    // SAFETY: `user_data` comes from `solve`; Ipopt's buffers hold n and m values.
    let ctx = unsafe { context(user_data) };
    ctx.guarded(|ctx| unsafe {
        let (n, m) = (n as usize, m as usize);
        let (lower, upper) = (out_slice(x_l, n), out_slice(x_u, n));
        lower.fill(f64::NEG_INFINITY);
        upper.fill(f64::INFINITY);
        ctx.problem.variable_bounds(lower, upper);
        let (lower, upper) = (out_slice(g_l, m), out_slice(g_u, m));
        lower.fill(f64::NEG_INFINITY);
        upper.fill(f64::INFINITY);
        ctx.problem.constraint_bounds(lower, upper);
        // Ipopt reads ±1e19 as infinite; Rust's infinities map onto that.
        for value in [out_slice(x_l, n), out_slice(x_u, n), out_slice(g_l, m), out_slice(g_u, m)]
            .into_iter()
            .flat_map(|s| s.iter_mut())
        {
            *value = value.clamp(-1e20, 1e20);
        }
        true
    })
}

extern "C" fn eval_f(
    n: sys::CNLP_Index,
    x: *const f64,
    new_x: sys::CNLP_Bool,
    obj: *mut f64,
    user_data: sys::CNLP_UserDataPtr,
) -> sys::CNLP_Bool {
    // SAFETY: `user_data` comes from `solve`; `x` holds n values and `obj` is a valid scalar.
    let ctx = unsafe { context(user_data) };
    ctx.guarded(|ctx| unsafe {
        ctx.evaluations.objective += 1;
        match ctx.problem.objective(in_slice(x, n as usize), new_x != 0) {
            Some(value) => {
                *obj = value;
                true
            }
            None => false,
        }
    })
}

extern "C" fn eval_grad_f(
    n: sys::CNLP_Index,
    x: *const f64,
    new_x: sys::CNLP_Bool,
    grad: *mut f64,
    user_data: sys::CNLP_UserDataPtr,
) -> sys::CNLP_Bool {
    // SAFETY: `user_data` comes from `solve`; `x` and `grad` hold n values.
    let ctx = unsafe { context(user_data) };
    ctx.guarded(|ctx| unsafe {
        ctx.evaluations.gradient += 1;
        let n = n as usize;
        ctx.problem.objective_gradient(in_slice(x, n), new_x != 0, out_slice(grad, n))
    })
}

extern "C" fn eval_g(
    n: sys::CNLP_Index,
    x: *const f64,
    new_x: sys::CNLP_Bool,
    m: sys::CNLP_Index,
    g: *mut f64,
    user_data: sys::CNLP_UserDataPtr,
) -> sys::CNLP_Bool {
    // SAFETY: `user_data` comes from `solve`; `x` holds n values and `g` m values.
    let ctx = unsafe { context(user_data) };
    ctx.guarded(|ctx| unsafe {
        ctx.evaluations.constraints += 1;
        ctx.problem.constraints(in_slice(x, n as usize), new_x != 0, out_slice(g, m as usize))
    })
}

#[allow(clippy::too_many_arguments)]
extern "C" fn eval_jac_g(
    n: sys::CNLP_Index,
    x: *const f64,
    new_x: sys::CNLP_Bool,
    _m: sys::CNLP_Index,
    nnz: sys::CNLP_Index,
    rows: *mut sys::CNLP_Index,
    cols: *mut sys::CNLP_Index,
    values: *mut f64,
    user_data: sys::CNLP_UserDataPtr,
) -> sys::CNLP_Bool {
    // SAFETY: `user_data` comes from `solve`; Ipopt's buffers hold n and nnz values.
    let ctx = unsafe { context(user_data) };
    ctx.guarded(|ctx| unsafe {
        if values.is_null() {
            return write_structure(&ctx.jacobian, rows, cols);
        }
        ctx.evaluations.jacobian += 1;
        ctx.problem.jacobian_values(in_slice(x, n as usize), new_x != 0, out_slice(values, nnz as usize))
    })
}

#[allow(clippy::too_many_arguments)]
extern "C" fn eval_h(
    n: sys::CNLP_Index,
    x: *const f64,
    new_x: sys::CNLP_Bool,
    sigma: f64,
    m: sys::CNLP_Index,
    lambda: *const f64,
    new_lambda: sys::CNLP_Bool,
    nnz: sys::CNLP_Index,
    rows: *mut sys::CNLP_Index,
    cols: *mut sys::CNLP_Index,
    values: *mut f64,
    user_data: sys::CNLP_UserDataPtr,
) -> sys::CNLP_Bool {
    // SAFETY: `user_data` comes from `solve`; Ipopt's buffers hold n, m and nnz values.
    let ctx = unsafe { context(user_data) };
    ctx.guarded(|ctx| unsafe {
        let Some(structure) = ctx.hessian.as_ref() else {
            // Limited-memory mode: Ipopt never asks, and must not get a Hessian if it does.
            return false;
        };
        if values.is_null() {
            return write_structure(structure, rows, cols);
        }
        ctx.evaluations.hessian += 1;
        ctx.problem.hessian_values(
            in_slice(x, n as usize),
            new_x != 0,
            sigma,
            in_slice(lambda, m as usize),
            new_lambda != 0,
            out_slice(values, nnz as usize),
        )
    })
}

#[allow(clippy::too_many_arguments)]
extern "C" fn intermediate(
    mode: sys::CNLP_AlgorithmMode,
    iteration: sys::CNLP_Index,
    objective: f64,
    inf_pr: f64,
    inf_du: f64,
    mu: f64,
    d_norm: f64,
    regularization: f64,
    alpha_du: f64,
    alpha_pr: f64,
    ls_trials: sys::CNLP_Index,
    user_data: sys::CNLP_UserDataPtr,
) -> sys::CNLP_Bool {
    // SAFETY: `user_data` comes from `solve`.
    let ctx = unsafe { context(user_data) };
    ctx.guarded(|ctx| {
        ctx.last = IterationInfo {
            iteration: iteration.max(0) as usize,
            restoration: mode == sys::CNLP_AlgorithmMode_CNLP_RESTORATION_PHASE_MODE,
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
        ctx.problem.intermediate(&info)
    })
}
