//! `flexspine.Result`: a run's result as scipy's `OptimizeResult` reads (`success`, `status`,
//! `message`, attribute and key access), with its arrays and its folder writer.

use crate::convert::{derivatives_of, series_of, value_to_py};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The typed result of a case: what `result.json` holds, with the time series as numpy arrays.
#[pyclass(name = "Result", module = "flexspine", frozen)]
pub struct CaseResult {
    pub(crate) inner: spine_run::CaseResult,
}

#[pymethods]
impl CaseResult {
    /// The result's kind (`equilibrium`, `twolink`, `design`, `simulate`, `damping`, `periodic`,
    /// `figure`, `study`, `sensitivity`, `figure_sensitivity`, `sweep`): `result.json`'s `"kind"`.
    #[getter]
    fn kind(&self) -> String {
        self.inner.result.kind().to_string()
    }

    /// Every solver converged, every reported equilibrium is stable, every solver check passed and
    /// no time limit cut the run short (the CLI's exit code 0; otherwise 3).
    #[getter]
    fn clean(&self) -> bool {
        self.inner.is_clean()
    }

    /// As scipy's `OptimizeResult.success`: the same as `clean`.
    #[getter]
    fn success(&self) -> bool {
        self.inner.is_clean()
    }

    /// As scipy's `OptimizeResult.status`: the CLI's exit code, 0 (clean) or 3 (not clean: the
    /// result is complete and says why; `message`).
    #[getter]
    fn status(&self) -> u8 {
        if self.inner.is_clean() {
            0
        } else {
            3
        }
    }

    /// As scipy's `OptimizeResult.message`: "clean", or why not (the time limit, the reasons the
    /// result gives in `not_clean`, or a pointer to `summary`).
    #[getter]
    fn message(&self) -> String {
        if self.inner.is_clean() {
            return "clean".into();
        }
        let mut reasons: Vec<String> = self.inner.stopped.iter().map(|r| format!("stopped: {}", r.name())).collect();
        reasons.extend(self.inner.result.not_clean_reasons());
        if reasons.is_empty() {
            reasons.push(
                "not clean: a solver did not converge, an equilibrium is not stable or a check failed (see summary)"
                    .into(),
            );
        }
        reasons.join("; ")
    }

    /// The top-level entries of `result.json`, as a dictionary's keys.
    fn keys<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.to_dict(py)?.call_method0("keys")
    }

    /// A top-level entry of `result.json` by attribute (`result.objective`), as scipy's
    /// `OptimizeResult` gives its fields; `AttributeError` for a name it does not hold.
    fn __getattr__<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        let dict = self.to_dict(py)?;
        match dict.get_item(name) {
            Ok(value) => Ok(value),
            Err(_) => Err(pyo3::exceptions::PyAttributeError::new_err(format!(
                "flexspine.Result of kind {:?} has no entry {name:?} (keys(): result.json's top-level entries)",
                self.kind()
            ))),
        }
    }

    fn __contains__(&self, py: Python<'_>, key: &str) -> PyResult<bool> {
        self.to_dict(py)?.contains(key)
    }

    /// `"time_limit"` when the run's time limit stopped it early (the result holds what it
    /// reached), else `None`.
    #[getter]
    fn stopped(&self) -> Option<&'static str> {
        self.inner.stopped.map(|r| r.name())
    }

    /// `result.json`'s text. `deterministic=True` leaves the wall times out, as the CLI's
    /// `--deterministic` does: then the same input gives the same bytes.
    #[pyo3(signature = (deterministic = false))]
    fn json(&self, deterministic: bool) -> String {
        spine_run::write::result_json(&self.inner, deterministic)
    }

    /// `result.json` as a Python dictionary (wall times under `"timings"`), straight from the typed
    /// result: every array of numbers a numpy array (`int64` for integers, else `float64` with
    /// `null` as NaN), a list of equal-length number rows a 2-D array, other arrays lists.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        value_to_py(py, &self.inner.to_json())
    }

    /// One entry of `result.json` (`result["objective"]`, `result["loaded"]`, …).
    fn __getitem__<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        self.to_dict(py)?.get_item(key)
    }

    /// The tables the CLI writes as CSV beside `result.json` (`response.csv`,
    /// `response_T0.1.csv`, …), each a dictionary keyed by column (`t_s`, `end_displacement_m`,
    /// `theta_1_rad`, …): numpy arrays of numbers and counts, lists of strings for labels.
    #[getter]
    fn series<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        series_of(py, &self.inner)
    }

    /// The derivatives of a sensitivity result as numpy arrays: `{parameter: {"theta0",
    /// "stiffness", "theta1", "theta2": arrays per link or spring (per unit of the parameter),
    /// "lambda1", "lambda2", "objective", "objective_direct": floats}}`; where only one-sided
    /// derivatives exist, `{"increase": …, "decrease": …}`; `None` where none is given. For a
    /// figure case, keyed by run first. `None` for results without sensitivities.
    #[getter]
    fn derivatives<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        derivatives_of(py, &self.inner)
    }

    /// The animation of the chain's motion as GIF bytes (`IPython.display.Image(data=...)` shows
    /// it), or `None` when the run has none (ask with `run_case(..., animate=True)`; figures
    /// fig9–fig11 always have one). Drawn on each call.
    fn gif<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, pyo3::types::PyBytes>>> {
        let animation = self.inner.files().into_iter().find_map(|f| match f.content {
            spine_run::FileContent::Animation(a) => Some(a),
            _ => None,
        });
        let Some(animation) = animation else { return Ok(None) };
        let bytes = py.detach(|| animation.to_gif()).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        Ok(Some(pyo3::types::PyBytes::new(py, &bytes)))
    }

    /// The summary the CLI prints: status, the numbers that show it, warnings.
    #[getter]
    fn summary(&self) -> String {
        self.inner.to_string()
    }

    /// Writes `result.json` and the files beside it (CSV, SVG, PNG) as one new folder in place of
    /// `out`, all or nothing, exactly as the CLI's `--out`. Returns the path of `result.json`.
    #[pyo3(signature = (out, deterministic = false))]
    pub(crate) fn write(&self, py: Python<'_>, out: std::path::PathBuf, deterministic: bool) -> PyResult<String> {
        let written = py.detach(|| spine_run::write::Folder::new(&out, deterministic).write_result(&self.inner));
        match written {
            Ok((path, _)) => Ok(path.display().to_string()),
            Err(e) if e.is_input() => Err(PyValueError::new_err(e.to_string())),
            Err(e) => Err(PyRuntimeError::new_err(e.to_string())),
        }
    }

    fn __repr__(&self) -> String {
        format!(
            "<flexspine.Result kind={:?} clean={}{}>",
            self.kind(),
            self.clean(),
            self.stopped().map_or(String::new(), |s| format!(" stopped={s:?}"))
        )
    }
}
