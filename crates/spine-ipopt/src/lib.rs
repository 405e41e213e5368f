//! A thin safe wrapper over Ipopt's standard C interface (`IpStdCInterface.h`), for Debian's
//! Ipopt 3.11.9 (the default build) or an Ipopt 3.14 named by `IPOPT_DIR` at build time
//! ([`IPOPT_VERSION`] says which one is linked).
//!
//! Ipopt solves
//!
//! Further modules:
//!
//! * `context`: What the Ipopt callbacks share with the solve that started them (behind Ipopt's
//!   `user_data`), and the arrays that go into and come out of `IpoptSolve`.
//! * `options`: Ipopt options as an ordered list of `name = value` pairs.
//! * `barrier`: The barrier strategy, Ipopt's `mu_strategy`, as a typed setting.
//! * `c_bool`: Ipopt's C `Bool`: a C `int` up to 3.13, C99 `bool` from 3.14 (read by `build.rs`).
//! * `clock`: The clock behind this crate's replacements of Ipopt's `CpuTime()` and
//!   `WallclockTime()` (`ffi.rs`, where the C symbols are defined), and how often Ipopt read each.
//! * `status`: Ipopt's return codes, one named variant each.
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
//! This is the only crate of the workspace with `unsafe` code, all of it in the `ffi` module. Every callback runs inside
//! `catch_unwind`: a panic in user code is caught, Ipopt is told the evaluation failed and is
//! stopped at its next iteration, and the panic resumes after Ipopt has returned, so no Rust panic
//! ever unwinds through C frames.
//!
//! Ipopt factorises its KKT matrices with the MUMPS it ships (option `linear_solver = "mumps"`,
//! this crate's default) or through its Pardiso interface (`"pardiso"`), where the workspace's own
//! sparse `LDLᵀ` (`spine-kkt`) answers once its caller has installed it (spine-design does, for
//! eq. (33)'s design solves; this crate knows no client). MUMPS is not thread-safe (Debian's Ipopt
//! 3.11.9 aborts when two MUMPS solves overlap): [`solve`] holds a process-wide lock for MUMPS
//! solves only.
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
#![deny(unsafe_code)]

mod barrier;
mod c_bool;
mod clock;
mod context;
#[allow(unsafe_code)]
mod ffi;
mod options;
mod status;

pub use barrier::BarrierStrategy;
pub use options::{OptionValue, Options};
pub use status::Status;

use std::panic::resume_unwind;
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

impl Solution {
    /// Counts an earlier run of the same problem that this one continued from (a restart): its
    /// iterations, evaluations and times are added to this run's.
    pub fn continues(&mut self, earlier: &Solution) {
        self.iterations += earlier.iterations;
        let (e, a) = (&mut self.evaluations, &earlier.evaluations);
        e.objective += a.objective;
        e.gradient += a.gradient;
        e.constraints += a.constraints;
        e.jacobian += a.jacobian;
        e.hessian += a.hessian;
        self.wall_time += earlier.wall_time;
        self.callback_time += earlier.callback_time;
    }
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
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SetupError {
    /// Sizes too large for Ipopt's 32-bit indices.
    #[error("{0} exceeds Ipopt's 32-bit index range")]
    TooLarge(&'static str),
    /// A sparsity entry outside the matrix, or in the upper triangle of the Hessian.
    #[error("bad sparsity structure: {0}")]
    BadStructure(String),
    /// Ipopt refused an option (unknown name or wrong type).
    #[error("Ipopt rejected the option {0}")]
    InvalidOption(String),
    /// `CreateIpoptProblem` refused the sizes (for example no variable, or constraints without
    /// Jacobian entries).
    #[error("Ipopt could not create the problem ({0})")]
    CreateFailed(String),
}

/// The sparse symmetric indefinite solver Ipopt factorises its KKT matrices with (the option
/// `linear_solver`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LinearSolver {
    /// Ipopt's Pardiso interface, which loads a Pardiso library at run time (`dlopen` of
    /// `libpardiso.so`). The caller makes one loadable first: the workspace's own frontal `LDLᵀ`
    /// with exact inertia installs itself as that library (`spine_kkt::install`, called by
    /// spine-design before its solves; docs/design.md, "Linear solver"). Solves run in several
    /// threads at once.
    Pardiso,
    /// MUMPS, as the Ipopt library ships it (not thread-safe: one solve at a time): this crate's
    /// default.
    Mumps,
}

impl LinearSolver {
    /// Ipopt's option value: `"pardiso"` or `"mumps"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Pardiso => "pardiso",
            Self::Mumps => "mumps",
        }
    }

    /// The solver of an option value, if it is one of the two.
    pub fn from_name(name: &str) -> Option<Self> {
        [Self::Pardiso, Self::Mumps].into_iter().find(|s| s.name() == name)
    }
}

/// The version of the Ipopt this crate was built against (read from its headers), e.g. "3.11.9".
pub const IPOPT_VERSION: &str = env!("SPINE_IPOPT_VERSION");

/// MUMPS is not thread-safe (Ipopt 3.11 aborts when two solves overlap): one MUMPS solve at a time
/// per process.
static SOLVE_LOCK: Mutex<()> = Mutex::new(());

/// How many times Ipopt has read its CPU clock through this crate's replacement of
/// `Ipopt::CpuTime()` in this process (see `ffi.rs`: Debian's Ipopt 3.11 reads it about 70 times
/// per iteration, each read a `getrusage` system call in the library's own clock). Zero when the
/// library does not call the replacement.
pub fn replaced_clock_reads() -> usize {
    clock::reads(clock::Clock::Cpu)
}

/// How many times Ipopt has read its wall clock through this crate's replacement of
/// `Ipopt::WallclockTime()` (`ffi.rs`) in this process; zero when the library does not call it.
pub fn replaced_wall_clock_reads() -> usize {
    clock::reads(clock::Clock::Wall)
}

/// Solves `problem` with Ipopt.
///
/// The options are passed to Ipopt as given, after defaults that keep the terminal quiet
/// (`print_level = 0`, `sb = yes`), keep Ipopt from reading an options file (`option_file_name`
/// empty: otherwise an `ipopt.opt` in the working directory would silently change every solve)
/// and, when [`Problem::hessian_structure`] is `None`, `hessian_approximation = limited-memory`;
/// any of them can be overridden in `options`.
///
/// # Panics
/// Resumes a panic raised inside one of the problem's callbacks, after Ipopt has returned.
pub fn solve(problem: &mut dyn Problem, options: &Options) -> Result<Solution, SetupError> {
    let n = problem.num_variables();
    let m = problem.num_constraints();
    let jacobian = problem.jacobian_structure();
    let hessian = problem.hessian_structure();
    check_sizes(n, m, &jacobian, hessian.as_deref())?;

    let (all_options, linear_solver) = session_options(options, hessian.is_some())?;
    let start = ffi::Start::from_problem(problem, n, m);

    // MUMPS needs the lock; the workspace's solver keeps its state in Ipopt's handle, so solves
    // with it run concurrently.
    let _guard = (linear_solver == LinearSolver::Mumps).then(|| SOLVE_LOCK.lock().unwrap_or_else(|p| p.into_inner()));
    let mut context = ffi::Context {
        problem,
        jacobian,
        hessian,
        panic: None,
        last: IterationInfo::default(),
        evaluations: EvaluationCounts::default(),
        callback_time: Duration::ZERO,
        stopped: None,
    };
    let clock = Instant::now();
    // Ipopt's first clock reads of this solve see this solve's time, not this thread's last
    // reading from before it.
    clock::refresh();
    let finish = ffi::run(&mut context, start, &all_options.iter().collect::<Vec<_>>())?;
    let wall_time = clock.elapsed();
    if let Some(payload) = context.panic.take() {
        resume_unwind(payload);
    }
    Ok(Solution {
        status: match (Status::from_code(finish.status), context.stopped) {
            (Status::UserRequestedStop, Some(spine_stop::StopReason::TimeLimit)) => Status::TimeLimit,
            (Status::UserRequestedStop, Some(spine_stop::StopReason::Interrupted)) => Status::Interrupted,
            (status, _) => status,
        },
        x: finish.x,
        objective: finish.objective,
        g: finish.g,
        lambda: finish.mult_g,
        z_lower: finish.z_lower,
        z_upper: finish.z_upper,
        iterations: context.last.iteration,
        last_iteration: context.last,
        evaluations: context.evaluations,
        wall_time,
        callback_time: context.callback_time,
    })
}

/// Our defaults (see [`solve`]), then `options`; the linear solver they name.
fn session_options(options: &Options, has_hessian: bool) -> Result<(Options, LinearSolver), SetupError> {
    let mut all_options = Options::new()
        .string("sb", "yes")
        .integer("print_level", 0)
        .string("option_file_name", "")
        .string("linear_solver", LinearSolver::Mumps.name());
    if !has_hessian {
        all_options = all_options.string("hessian_approximation", "limited-memory");
    }
    all_options.extend(options);
    let linear_solver = match all_options.get("linear_solver") {
        Some(OptionValue::Str(name)) => LinearSolver::from_name(name),
        _ => None,
    }
    .ok_or_else(|| SetupError::InvalidOption("linear_solver (allowed: pardiso, mumps)".into()))?;
    Ok((all_options, linear_solver))
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
