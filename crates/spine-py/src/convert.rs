//! Python objects to case files, results to arrays, run errors to Python exceptions.

use numpy::PyArray1;
use pyo3::exceptions::{PyKeyboardInterrupt, PyRuntimeError, PyTimeoutError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use spine_run::{Cells, FileContent};

/// The case `obj` describes: a dictionary (case-file format), JSON text (starts with `{`), or the
/// path of a case file (`str` or `os.PathLike`). Parsed and checked as the CLI does; bad input is
/// a `ValueError` with the CLI's message naming the field.
pub fn case_from(py: Python<'_>, obj: &Bound<'_, PyAny>) -> PyResult<spine_case::Case> {
    let text = case_text(py, obj)?;
    spine_case::Case::from_json(&text).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// The JSON text of a case given as a dictionary, JSON text or a path.
pub fn case_text(py: Python<'_>, obj: &Bound<'_, PyAny>) -> PyResult<String> {
    let path = if obj.is_instance_of::<PyString>() {
        let s: String = obj.extract()?;
        if s.trim_start().starts_with('{') {
            return Ok(s);
        }
        Some(std::path::PathBuf::from(s))
    } else if obj.hasattr("__fspath__")? {
        Some(obj.extract::<std::path::PathBuf>()?)
    } else {
        None
    };
    match path {
        Some(path) => spine_case::read_text(&path, "case file", spine_case::MAX_CASE_BYTES)
            .map_err(|e| PyValueError::new_err(e.to_string())),
        // `allow_nan=False`: a NaN or infinity is not JSON, and the case format refuses it.
        None => {
            let kwargs = PyDict::new(py);
            kwargs.set_item("allow_nan", false)?;
            py.import("json")?
                .call_method("dumps", (obj,), Some(&kwargs))
                .map_err(|e| PyValueError::new_err(format!("case: not a JSON-like dictionary: {e}")))?
                .extract()
        }
    }
}

/// A run error as a Python exception: bad input `ValueError`, a time limit that left nothing to
/// report `TimeoutError`, an outside stop `KeyboardInterrupt`, anything else `RuntimeError`.
pub fn run_error(e: spine_run::RunError) -> PyErr {
    let message = e.to_string();
    if e.is_interrupted() {
        PyKeyboardInterrupt::new_err(message)
    } else if e.is_time_limit() {
        PyTimeoutError::new_err(message)
    } else if e.is_input() {
        PyValueError::new_err(message)
    } else {
        PyRuntimeError::new_err(message)
    }
}

/// The tables of a result as `{file name: {column: values}}`, straight from the typed columns:
/// numbers and counts as numpy float arrays (a missing cell is NaN), labels as lists of strings.
pub fn series_of<'py>(py: Python<'py>, result: &spine_run::CaseResult) -> PyResult<Bound<'py, PyDict>> {
    let all = PyDict::new(py);
    for file in result.files() {
        let FileContent::Table(table) = &file.content else { continue };
        let columns = PyDict::new(py);
        for column in &table.columns {
            match &column.cells {
                Cells::Numbers(v) => {
                    let values = v.iter().map(|x| x.unwrap_or(f64::NAN)).collect();
                    columns.set_item(&column.name, PyArray1::from_vec(py, values))?
                }
                Cells::Counts(v) => {
                    columns.set_item(&column.name, PyArray1::from_vec(py, v.iter().map(|&n| n as f64).collect()))?
                }
                Cells::Labels(v) => columns.set_item(&column.name, v.clone())?,
            }
        }
        all.set_item(&file.name, columns)?;
    }
    Ok(all)
}

/// One derivative as `{theta0, stiffness, theta1, theta2: numpy arrays; lambda1, lambda2,
/// objective, objective_direct: floats}`.
fn derivative_dict<'py>(py: Python<'py>, d: &spine_design::sensitivity::Derivative) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    for (name, values) in
        [("theta0", &d.theta0), ("stiffness", &d.stiffness), ("theta1", &d.theta1), ("theta2", &d.theta2)]
    {
        out.set_item(name, PyArray1::from_vec(py, values.clone()))?;
    }
    for (name, value) in [
        ("lambda1", d.lambda1),
        ("lambda2", d.lambda2),
        ("objective", d.objective),
        ("objective_direct", d.objective_direct),
    ] {
        out.set_item(name, value)?;
    }
    Ok(out)
}

/// A sensitivity report's derivatives by parameter: the two-sided derivative's dictionary, or
/// `{"increase": …, "decrease": …}` where only one-sided ones exist, or `None`.
fn report_dict<'py>(
    py: Python<'py>,
    report: &spine_design::sensitivity::SensitivityReport,
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    for p in &report.parameters {
        match (&p.derivative, &p.increase, &p.decrease) {
            (Some(d), _, _) => out.set_item(&p.name, derivative_dict(py, d)?)?,
            (None, None, None) => out.set_item(&p.name, py.None())?,
            (None, up, down) => {
                let sides = PyDict::new(py);
                for (side, d) in [("increase", up), ("decrease", down)] {
                    match d {
                        Some(d) => sides.set_item(side, derivative_dict(py, d)?)?,
                        None => sides.set_item(side, py.None())?,
                    }
                }
                out.set_item(&p.name, sides)?;
            }
        }
    }
    Ok(out)
}

/// The derivatives of a sensitivity result as numpy arrays (see `Result.derivatives`).
pub fn derivatives_of<'py>(py: Python<'py>, result: &spine_run::CaseResult) -> PyResult<Option<Bound<'py, PyDict>>> {
    match &result.result {
        spine_run::KindResult::Sensitivity(r) => r.sensitivity.as_ref().map(|s| report_dict(py, s)).transpose(),
        spine_run::KindResult::FigureSensitivity(r) => {
            let out = PyDict::new(py);
            for run in &r.runs {
                match &run.result.sensitivity {
                    Some(s) => out.set_item(&run.name, report_dict(py, s)?)?,
                    None => out.set_item(&run.name, py.None())?,
                }
            }
            Ok(Some(out))
        }
        spine_run::KindResult::Design(r) => r.sensitivity.as_ref().map(|s| report_dict(py, s)).transpose(),
        _ => Ok(None),
    }
}

/// A JSON value of `result.json` as Python: objects as dictionaries, scalars as Python scalars,
/// and arrays as numpy arrays where they hold numbers (integers as `int64`, others as `float64`
/// with `null` as NaN), a list of equal-length number lists as a 2-D array; other arrays (of
/// strings, of objects, ragged, empty) as lists of converted values.
pub fn value_to_py<'py>(py: Python<'py>, value: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    use serde_json::Value;
    Ok(match value {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => pyo3::types::PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(n) => match n.as_i64() {
            Some(i) => i.into_pyobject(py)?.into_any(),
            None => n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any(),
        },
        Value::String(s) => PyString::new(py, s).into_any(),
        Value::Object(map) => {
            let dict = PyDict::new(py);
            for (k, v) in map {
                dict.set_item(k, value_to_py(py, v)?)?;
            }
            dict.into_any()
        }
        Value::Array(items) => match numeric_array(py, items)? {
            Some(array) => array,
            None => {
                let list = pyo3::types::PyList::empty(py);
                for v in items {
                    list.append(value_to_py(py, v)?)?;
                }
                list.into_any()
            }
        },
    })
}

/// The numbers of a JSON array, `None` unless every item is a number or `null` (at least one a
/// number); integers stay integers when every item is one.
fn numbers(items: &[serde_json::Value]) -> Option<Result<Vec<i64>, Vec<f64>>> {
    if items.is_empty() || !items.iter().all(|v| v.is_number() || v.is_null()) || items.iter().all(|v| v.is_null()) {
        return None;
    }
    if items.iter().all(|v| v.as_i64().is_some()) {
        return Some(Ok(items.iter().filter_map(|v| v.as_i64()).collect()));
    }
    Some(Err(items.iter().map(|v| v.as_f64().unwrap_or(f64::NAN)).collect()))
}

/// A JSON array as a numpy array: 1-D of numbers, or 2-D from rows of numbers of equal length.
fn numeric_array<'py>(py: Python<'py>, items: &[serde_json::Value]) -> PyResult<Option<Bound<'py, PyAny>>> {
    use numpy::PyArrayMethods;
    if let Some(values) = numbers(items) {
        return Ok(Some(match values {
            Ok(ints) => PyArray1::from_vec(py, ints).into_any(),
            Err(floats) => PyArray1::from_vec(py, floats).into_any(),
        }));
    }
    let rows: Option<Vec<_>> = items.iter().map(|v| v.as_array().and_then(|r| numbers(r))).collect();
    let Some(rows) = rows.filter(|r| !r.is_empty()) else { return Ok(None) };
    let width = items[0].as_array().map_or(0, Vec::len);
    if items.iter().any(|v| v.as_array().map_or(0, Vec::len) != width) {
        return Ok(None);
    }
    let floats: Vec<f64> = rows
        .into_iter()
        .flat_map(|r| match r {
            Ok(ints) => ints.into_iter().map(|i| i as f64).collect::<Vec<_>>(),
            Err(floats) => floats,
        })
        .collect();
    Ok(Some(PyArray1::from_vec(py, floats).reshape([items.len(), width])?.into_any()))
}
