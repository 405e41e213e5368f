//! `flexspine`: the Python front of the workspace (PyO3, abi3, numpy arrays).
//!
//! Every call goes through the same Rust code as the `spine` CLI — case files are parsed and
//! checked by `spine_case`, runs go through `spine_run::run_case`, folders are written by
//! `spine_run::write` — so a result from Python is the CLI's `result.json`, byte for byte with
//! `deterministic=True`. This crate only converts: Python objects to case text, results to
//! dictionaries and numpy arrays, errors to Python exceptions (`ValueError` naming the field for
//! bad input, `TimeoutError`, `KeyboardInterrupt`, `RuntimeError`).
//!
//! Long calls run on a worker thread with the GIL released; the calling thread polls Python's
//! signal handlers, and Ctrl-C asks the run to stop through `spine_stop` (Ipopt's user-stop hook,
//! the integrator's and the searches' checks), waits for it, and raises `KeyboardInterrupt`.
//! Nothing is written by an interrupted call.
//!
//! Further modules:
//!
//! * `convert`: Python objects to case files, results to arrays, run errors to Python exceptions.
//! * `result`: `flexspine.Result`: a run's result as scipy's `OptimizeResult` reads (`success`,
//!   `status`, `message`, attribute and key access), with its arrays and its folder writer.
//! * `structure`: `flexspine.Structure`: a chain with its design and loads (the sections of an
//!   equilibrium case), its energies, the equilibrium residual of eq. (5) and its exact sparse
//!   Jacobian, and its equilibria with their stability certificate.

#![forbid(unsafe_code)]

mod convert;
mod result;
mod structure;

pub(crate) use result::CaseResult;

use convert::{case_from, run_error};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use spine_run::option_values as values;
use std::time::Duration;

/// A keyword argument checked by the same function as the CLI's option
/// ([`spine_run::option_values`]); a value outside its range is a `ValueError` naming it.
fn checked<T, U>(name: &str, value: Option<T>, check: impl Fn(T) -> Result<U, String>) -> PyResult<Option<U>> {
    value.map(check).transpose().map_err(|why| PyValueError::new_err(format!("{name}: {why}")))
}

/// Runs `work` on a worker thread with the GIL released; Ctrl-C (Python's `KeyboardInterrupt`)
/// stops it at its next check and is raised once it has stopped.
pub(crate) fn interruptible<T: Send>(py: Python<'_>, work: impl FnOnce() -> T + Send) -> PyResult<T> {
    std::thread::scope(|scope| {
        // The worker says when it is done, so the wait ends at once instead of at the next poll
        // (a 10 ms sleep between polls cost 5 ms per call on average, a quarter of a 5-link design).
        let (done, finished) = std::sync::mpsc::channel::<()>();
        let worker = scope.spawn(move || {
            let value = work();
            let _ = done.send(());
            value
        });
        let (mut interrupted, mut finished) = (None, finished);
        loop {
            // The receiver is not `Sync`: it goes into the GIL-free wait and comes back.
            let (outcome, back) = py.detach(move || (finished.recv_timeout(Duration::from_millis(10)), finished));
            finished = back;
            // A panicking worker drops its sender: `Disconnected` ends the wait too.
            match outcome {
                Ok(()) | Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => break,
                Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {}
            }
            if interrupted.is_none() {
                if let Err(e) = py.check_signals() {
                    spine_stop::request_interrupt();
                    interrupted = Some(e);
                }
            }
        }
        let value = worker.join();
        if let Some(e) = interrupted {
            spine_stop::clear_interrupt();
            return Err(e);
        }
        value.map_err(|_| PyRuntimeError::new_err("the run panicked (a bug: please report it with its case)"))
    })
}

/// Runs a case of any kind — the `spine case` command — and returns its [`Result`].
///
/// `case`: a dictionary in the case-file format (docs/case-format.md), its JSON text, or the path
/// of a case file. The optional overrides are the CLI's: `starts` and `seed` (multi-start of
/// eq. (33)), `confidence` (a census until P(a better optimum unseen) ≤ it; `starts` caps it),
/// `formulation` (`"full"` or `"reduced"`), `method` (`"ga"`, `"pattern"` or `"gradient"`, eq. (37)),
/// `time_limit` (s, wall clock; the result then says `stopped="time_limit"`), and the animation
/// of a dynamic run (`animate`, `frames`, `frame_width`, `magnify`, as `--animate`, `--frames`,
/// `--frame-width`, `--magnify`; any of them asks for it; `Result.gif()` gives its bytes). With
/// `out`, the result's folder is written as the CLI writes `--out`.
///
/// Bad input raises `ValueError` with the CLI's one-line message naming the field; a time limit
/// that leaves nothing to report raises `TimeoutError`; Ctrl-C stops the run and raises
/// `KeyboardInterrupt` (nothing written).
#[pyfunction]
#[pyo3(signature = (case, *, out = None, deterministic = false, starts = None, seed = None, confidence = None, formulation = None, method = None, time_limit = None, animate = false, frames = None, frame_width = None, magnify = None))]
#[allow(clippy::too_many_arguments)]
fn run_case(
    py: Python<'_>,
    case: &Bound<'_, PyAny>,
    out: Option<std::path::PathBuf>,
    deterministic: bool,
    starts: Option<usize>,
    seed: Option<u64>,
    confidence: Option<f64>,
    formulation: Option<&str>,
    method: Option<&str>,
    time_limit: Option<f64>,
    animate: bool,
    frames: Option<usize>,
    frame_width: Option<u32>,
    magnify: Option<f64>,
) -> PyResult<CaseResult> {
    let case = case_from(py, case)?;
    let design = spine_run::DesignOverrides {
        starts: checked("starts", starts, values::starts)?,
        seed,
        confidence: checked("confidence", confidence, values::confidence)?,
        formulation: checked("formulation", formulation, values::formulation)?,
        ..Default::default()
    }
    .with_confidence_cap();
    // Animation options are checked by the run itself (`AnimationOptions::validate`, errors named
    // `animation.*`).
    let animation = (animate || frames.is_some() || frame_width.is_some() || magnify.is_some()).then(|| {
        let d = spine_run::AnimationOptions::default();
        spine_run::AnimationOptions {
            frames: frames.unwrap_or(d.frames),
            width: frame_width.unwrap_or(d.width),
            magnification: magnify,
        }
    });
    let overrides = spine_run::Overrides {
        design,
        dynamics: spine_run::DynamicsOverrides { method: checked("method", method, values::method)? },
        time_limit: checked("time_limit", time_limit, values::time_limit)?,
        animation,
        workers: None,
    };
    let result = interruptible(py, || {
        spine_run::run_case(&case, &overrides, &spine_paper::PaperFigures, &mut spine_run::quiet)
    })?
    .map_err(run_error)?;
    let result = CaseResult { inner: result };
    if let Some(out) = out {
        result.write(py, out, deterministic)?;
    }
    Ok(result)
}

/// Eq. (33) on a design case, then the derivatives of its optimum with respect to `params` (the
/// case file's field paths; default all), as `spine sensitivity` does: a result of kind
/// `"sensitivity"` whose `["sensitivity"]` holds the conditions and, per parameter, the
/// derivatives of θ0*, K*, θ1*, θ2*, λ* and J*.
#[pyfunction]
#[pyo3(signature = (case, params = None, *, out = None, deterministic = false))]
fn sensitivity(
    py: Python<'_>,
    case: &Bound<'_, PyAny>,
    params: Option<Vec<String>>,
    out: Option<std::path::PathBuf>,
    deterministic: bool,
) -> PyResult<CaseResult> {
    let case = case_from(py, case)?;
    let names = params.unwrap_or_default();
    let overrides = spine_run::Overrides::default();
    let result = interruptible(py, || spine_run::run_sensitivity(&case, &overrides, &names, &mut spine_run::quiet))?
        .map_err(run_error)?;
    let result = CaseResult { inner: result };
    if let Some(out) = out {
        result.write(py, out, deterministic)?;
    }
    Ok(result)
}

/// Eq. (33)'s optimum at `param = start` followed to `param = stop` over `points` equally spaced
/// values, as `spine sweep` does: a result of kind `"sweep"` whose `["sweep"]["points"]` holds each
/// point (parameter, objective, design, status, active bounds, tangent) and `["sweep"]["events"]`
/// the events located on the way; with `census = STARTS`, a multi-start at every
/// `census_every`-th point (`["census"]`).
#[pyfunction]
#[pyo3(signature = (case, param, start, stop, points = 21, *, census = None, census_every = 5, out = None, deterministic = false))]
#[allow(clippy::too_many_arguments)]
fn sweep(
    py: Python<'_>,
    case: &Bound<'_, PyAny>,
    param: String,
    start: f64,
    stop: f64,
    points: usize,
    census: Option<usize>,
    census_every: usize,
    out: Option<std::path::PathBuf>,
    deterministic: bool,
) -> PyResult<CaseResult> {
    let case = case_from(py, case)?;
    let settings = spine_design::sweep::settings::SweepSettings::new(start, stop, points);
    let plan = census.map(|starts| spine_run::sweep::CensusPlan { starts, every: census_every });
    let overrides = spine_run::Overrides::default();
    let result =
        interruptible(py, || spine_run::run_sweep(&case, &overrides, &param, settings, plan, &mut spine_run::quiet))?
            .map_err(run_error)?;
    let result = CaseResult { inner: result };
    if let Some(out) = out {
        result.write(py, out, deterministic)?;
    }
    Ok(result)
}

/// The strain energy `U = ½ Σ K_j (Δθ_j − Δθ0_j)²` of eq. (2), J, of springs `stiffness`
/// (N·m/rad, `N + 1`) at link angles `theta` from the unloaded angles `theta0` (rad, `N` each).
#[pyfunction]
fn strain_energy(theta: Vec<f64>, theta0: Vec<f64>, stiffness: Vec<f64>) -> PyResult<f64> {
    let n = theta.len();
    if theta0.len() != n || stiffness.len() != n + 1 {
        return Err(PyValueError::new_err(format!(
            "stiffness: N + 1 = {} springs for N = {n} links (theta0 {} values), got {}",
            n + 1,
            theta0.len(),
            stiffness.len()
        )));
    }
    Ok(spine_model::energy::strain_energy(&theta, &theta0, &stiffness))
}

/// The full-space start point of eq. (33) for a `"design"` case: `theta0` (rad), `k = K / C_K`,
/// both equilibria of the start design with their multipliers (`theta1`, `lambda1`, `theta2`,
/// `lambda2`) and the interior node heights (m), as a dictionary of numpy arrays and floats —
/// the point `run_case` hands Ipopt, for a CasADi (or other) model to start from the same point
/// (`benchmarks/peers/casadi_static.py` reads it as its START.json).
#[pyfunction]
fn design_start<'py>(py: Python<'py>, case: &Bound<'_, PyAny>) -> PyResult<Bound<'py, PyDict>> {
    let spine_case::Case::Design(c) = case_from(py, case)? else {
        return Err(PyValueError::new_err("kind: design_start needs a \"design\" case"));
    };
    let valid = c.validate().map_err(|e| PyValueError::new_err(e.to_string()))?;
    let start =
        spine_design::start_point::FullSpaceStart::new(&valid.problem, &valid.start, &valid.settings.continuation);
    let out = PyDict::new(py);
    for (name, values) in [
        ("theta0", start.theta0),
        ("k", start.k),
        ("theta1", start.theta1),
        ("theta2", start.theta2),
        ("heights", start.heights),
    ] {
        out.set_item(name, numpy::PyArray1::from_vec(py, values))?;
    }
    out.set_item("lambda1", start.lambda1)?;
    out.set_item("lambda2", start.lambda2)?;
    Ok(out)
}

/// The version of the workspace this module was built from.
#[pyfunction]
fn version() -> &'static str {
    env!("CARGO_PKG_VERSION")
}

/// Flexible spines: planar chains of rigid links joined by torsional springs and dampers, fixed
/// base, end sliding on X. Equilibria with a stability certificate, the static design of eq. (33)
/// with exact AD derivatives and Ipopt, C_K of eq. (34), dynamics and eqs. (35), (37) — the Rust
/// workspace's own code, called from Python.
#[pymodule]
fn flexspine(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<CaseResult>()?;
    m.add_class::<structure::Structure>()?;
    m.add_function(wrap_pyfunction!(run_case, m)?)?;
    m.add_function(wrap_pyfunction!(sensitivity, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(strain_energy, m)?)?;
    m.add_function(wrap_pyfunction!(design_start, m)?)?;
    m.add_function(wrap_pyfunction!(version, m)?)?;
    // The case kinds, from the one registry (`spine_case::KINDS`).
    m.add("KINDS", spine_case::KINDS.to_vec())?;
    Ok(())
}
