//! Pardiso's calling convention (the interface Ipopt's `linear_solver pardiso` calls) over
//! [`SymmetricSolver`], in safe Rust: the C entry points of `crate::abi` turn their pointers into
//! these slices and call [`init`] and [`State::call`].
//!
//! What Ipopt 3.11 and 3.14 use of it (`IpPardisoSolverInterface.cpp`): `pardisoinit` once per
//! solver object (matrix type −2, real symmetric indefinite); phase 11 (analysis) with the upper
//! triangle in 1-based compressed rows, phase 22 (factorisation), after which it reads the numbers
//! of positive and negative eigenvalues (`iparm[21]`, `iparm[22]`) and of perturbed pivots
//! (`iparm[13]`, always 0 here: no pivot is perturbed); phase 33 (solve, with `iparm[5] = 1`: the
//! solution overwrites the right-hand side); phase −1 (release). Error −4 (zero pivot) makes Ipopt
//! treat the matrix as singular and perturb it.

use crate::solver::SymmetricSolver;
use crate::symmetric::Structure;
use crate::KktError;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// Length of `iparm` and `dparm`.
pub const PARAMETERS: usize = 64;

/// Pardiso's error codes used here.
pub mod error {
    pub const NONE: i32 = 0;
    /// Input inconsistent.
    pub const INPUT: i32 = -1;
    /// Zero pivot: Ipopt reads it as a singular matrix.
    pub const ZERO_PIVOT: i32 = -4;
    /// Unclassified (internal) error, also a caught panic.
    pub const INTERNAL: i32 = -5;
}

static FACTORIZATIONS: AtomicU64 = AtomicU64::new(0);
static FACTOR_NANOS: AtomicU64 = AtomicU64::new(0);
static SOLVES: AtomicU64 = AtomicU64::new(0);
static SOLVE_NANOS: AtomicU64 = AtomicU64::new(0);
static REPLAYED: AtomicU64 = AtomicU64::new(0);
static PIVOTS: AtomicU64 = AtomicU64::new(0);

/// Process-wide counts of this solver's work (all threads): factorisations, their total time,
/// their pivots and those of them replayed from the factorisation before, solves and their total
/// time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    pub factorizations: u64,
    pub factor_nanos: u64,
    pub pivots: u64,
    pub replayed: u64,
    pub solves: u64,
    pub solve_nanos: u64,
}

/// The counters so far; subtract two readings to measure one run.
pub fn counters() -> Counters {
    Counters {
        factorizations: FACTORIZATIONS.load(Ordering::Relaxed),
        factor_nanos: FACTOR_NANOS.load(Ordering::Relaxed),
        pivots: PIVOTS.load(Ordering::Relaxed),
        replayed: REPLAYED.load(Ordering::Relaxed),
        solves: SOLVES.load(Ordering::Relaxed),
        solve_nanos: SOLVE_NANOS.load(Ordering::Relaxed),
    }
}

/// Whether `SPINE_KKT_TRACE` is set: then every factorisation prints its statistics to stderr,
/// as Ipopt's option `pardiso_msglvl > 0` does.
fn trace() -> bool {
    static TRACE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *TRACE.get_or_init(|| std::env::var_os("SPINE_KKT_TRACE").is_some())
}

/// The file named by a diagnostic environment variable, read once per process (not at every
/// factorisation or solve).
fn dump_path(
    variable: &'static str,
    cell: &'static std::sync::OnceLock<Option<std::ffi::OsString>>,
) -> Option<&'static std::ffi::OsString> {
    cell.get_or_init(|| std::env::var_os(variable)).as_ref()
}
static DUMP: std::sync::OnceLock<Option<std::ffi::OsString>> = std::sync::OnceLock::new();
static DUMP_BAD: std::sync::OnceLock<Option<std::ffi::OsString>> = std::sync::OnceLock::new();

/// `pardisoinit`: default parameters. Only matrix types −2 (symmetric indefinite) and 2 (symmetric
/// positive definite) are served.
pub fn init(mtype: i32, iparm: &mut [i32; PARAMETERS], dparm: &mut [f64; PARAMETERS]) -> i32 {
    iparm.fill(0);
    dparm.fill(0.0);
    iparm[0] = 1;
    iparm[2] = 1;
    if matches!(mtype, -2 | 2) {
        error::NONE
    } else {
        error::INPUT
    }
}

/// The solver state behind Pardiso's handle `pt`.
#[derive(Debug, Default)]
pub struct State {
    solver: Option<SymmetricSolver>,
}

/// One call of `pardiso` with its arrays as slices. `ia`, `ja` and `a` are empty where the phase
/// does not read them; `b` and `x` hold `nrhs` columns of length `n` for a solve.
#[derive(Debug)]
pub struct Call<'a> {
    pub phase: i32,
    pub mtype: i32,
    pub n: usize,
    pub nrhs: usize,
    pub a: &'a [f64],
    pub ia: &'a [i32],
    pub ja: &'a [i32],
    pub iparm: &'a mut [i32; PARAMETERS],
    pub b: &'a mut [f64],
    pub x: &'a mut [f64],
    pub msglvl: i32,
}

impl Call<'_> {
    /// Whether the phase reads the matrix (analysis, factorisation or solve with refinement).
    pub fn reads_matrix(phase: i32) -> bool {
        matches!(phase, 11 | 12 | 13 | 22 | 23 | 33)
    }

    /// Whether the phase solves (reads `b`, writes `x`, and `b` when `iparm[5] ≠ 0`).
    pub fn solves(phase: i32) -> bool {
        matches!(phase, 13 | 23 | 33)
    }
}

impl State {
    /// Runs one call; returns Pardiso's error code.
    pub fn call(&mut self, call: Call<'_>) -> i32 {
        if !matches!(call.mtype, -2 | 2) {
            return error::INPUT;
        }
        match self.run(call) {
            Ok(()) => error::NONE,
            Err(KktError::Singular { .. }) => error::ZERO_PIVOT,
            Err(KktError::Input(_) | KktError::NotFactorized) => error::INPUT,
            Err(KktError::Load(_) | KktError::Internal(_)) => error::INTERNAL,
        }
    }

    fn run(&mut self, mut call: Call<'_>) -> Result<(), KktError> {
        let phase = call.phase;
        if phase == -1 {
            self.solver = None;
            return Ok(());
        }
        if phase == 0 {
            return Ok(());
        }
        let (start, end) = (phase / 10, phase % 10);
        if !(1..=3).contains(&start) || !(start..=3).contains(&end) {
            return Err(KktError::Input(format!("phase {phase}")));
        }
        if start == 1 {
            let structure = Structure::from_one_based(call.n, call.ia, call.ja)?;
            self.solver = Some(SymmetricSolver::new(structure));
        }
        let solver = self.solver.as_mut().ok_or(KktError::NotFactorized)?;
        if solver.analysis().order() != call.n {
            return Err(KktError::Input(format!(
                "order {} after an analysis of order {}",
                call.n,
                solver.analysis().order()
            )));
        }
        if start <= 2 && end >= 2 {
            factorize(solver, &mut call)?;
        }
        if end == 3 {
            solve(solver, &mut call)?;
        }
        Ok(())
    }
}

/// Phase 22: factorises `call.a`; the inertia goes to `iparm[21]`, `iparm[22]` (no perturbed
/// pivots: `iparm[13] = 0`), the factor's size to `iparm[17]`.
fn factorize(solver: &mut SymmetricSolver, call: &mut Call<'_>) -> Result<(), KktError> {
    let clock = Instant::now();
    let inertia = solver.factorize(call.a)?;
    FACTORIZATIONS.fetch_add(1, Ordering::Relaxed);
    FACTOR_NANOS.fetch_add(clock.elapsed().as_nanos() as u64, Ordering::Relaxed);
    call.iparm[13] = 0;
    call.iparm[21] = inertia.positive as i32;
    call.iparm[22] = inertia.negative as i32;
    // Diagnostics: `SPINE_KKT_DUMP=FILE` writes the first matrix whose sweep delayed pivots so
    // front grew past twice the predicted width (order, ia, ja, a; read by
    // `examples/kkt_dump.rs`, parsed by [`crate::Dump`]).
    if let (Some(stats), Some(path)) = (solver.stats(), dump_path("SPINE_KKT_DUMP", &DUMP)) {
        let wide = stats.largest_front > 2 * solver.analysis().predicted_front() + 8;
        if wide && !std::path::Path::new(&path).exists() {
            let _ = std::fs::write(path, recorded(call, None).format());
        }
    }
    if let Some(stats) = solver.stats() {
        REPLAYED.fetch_add(stats.replayed as u64, Ordering::Relaxed);
        PIVOTS.fetch_add(stats.pivots as u64, Ordering::Relaxed);
        call.iparm[17] = (stats.factor_entries + call.n) as i32;
        if call.msglvl > 0 || trace() {
            eprintln!(
                    "spine-kkt: {:.3} ms, order {}, inertia (+{}, -{}), front {} (predicted {}), {} dense rows, {} 2x2 pivots, {} delays, {} entries in L, {} of {} pivots replayed, {} scaling passes",
                    clock.elapsed().as_secs_f64() * 1e3,
                    call.n,
                    inertia.positive,
                    inertia.negative,
                    stats.largest_front,
                    solver.analysis().predicted_front(),
                    solver.analysis().dense_rows(),
                    stats.two_by_two,
                    stats.delayed,
                    stats.factor_entries,
                    stats.replayed,
                    stats.pivots,
                    stats.scaling_passes
                );
        }
    }
    Ok(())
}

/// The system of a call in the text form of [`crate::Dump`].
fn recorded(call: &Call<'_>, rhs: Option<Vec<f64>>) -> crate::Dump {
    crate::Dump { n: call.n, ia: call.ia.to_vec(), ja: call.ja.to_vec(), a: call.a.to_vec(), rhs }
}

/// Phase 33: solves for the `nrhs` right-hand sides in `b` into `x` (and over `b` when `iparm[5]`
/// asks for it); the refinement steps go to `iparm[6]`.
fn solve(solver: &mut SymmetricSolver, call: &mut Call<'_>) -> Result<(), KktError> {
    let clock = Instant::now();
    let n = call.n;
    let (mut steps, mut worst, mut krylov) = (0, 0.0f64, false);
    // The solution goes to `x`, and over `b` too when `iparm[5]` asks for it (Ipopt does).
    let overwrite = call.iparm[5] != 0;
    let dump_bad = dump_path("SPINE_KKT_DUMP_BAD", &DUMP_BAD);
    let rhs_copy = if dump_bad.is_some() { call.b[..n].to_vec() } else { Vec::new() };
    for k in 0..call.nrhs {
        let column = &mut call.x[k * n..(k + 1) * n];
        column.copy_from_slice(&call.b[k * n..(k + 1) * n]);
        let report = solver.solve(column)?;
        steps = steps.max(report.refinement_steps);
        worst = worst.max(report.normwise_error);
        krylov |= report.krylov;
        if overwrite {
            call.b[k * n..(k + 1) * n].copy_from_slice(column);
        }
    }
    SOLVES.fetch_add(call.nrhs as u64, Ordering::Relaxed);
    SOLVE_NANOS.fetch_add(clock.elapsed().as_nanos() as u64, Ordering::Relaxed);
    // Diagnostics: `SPINE_KKT_DUMP_BAD=FILE` writes the first system (matrix and
    // right-hand side) whose solve ends with a normwise backward error above 1e-8.
    if let Some(path) = dump_bad {
        if worst > 1e-8 && !std::path::Path::new(&path).exists() {
            let _ = std::fs::write(path, recorded(call, Some(rhs_copy)).format());
        }
    }
    if trace() {
        eprintln!(
            "spine-kkt: solve {:.3} ms, GMRES {krylov}, {steps} refinement steps, normwise backward error {worst:.1e}",
            clock.elapsed().as_secs_f64() * 1e3
        );
    }
    call.iparm[6] = steps as i32;
    Ok(())
}
