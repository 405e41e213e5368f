//! `flexspine.Structure`: a chain with its design and loads (the sections of an equilibrium
//! case), its energies, the equilibrium residual of eq. (5) and its exact sparse Jacobian, and
//! its equilibria with their stability certificate.

use crate::convert::{case_text, run_error};
use crate::{interruptible, CaseResult};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use spine_case::{Case, EquilibriumCase, ValidEquilibrium};
use spine_model::{LinkLoads, NodalLoads, State};

/// A flexible spine: `chain` (links, spans or `length_x`, masses, gravity), `design` (`theta0`,
/// rad; `stiffness`, N·m/rad) and `loads` (`p_y`, `p_x`, N; self-weight), given as a dictionary
/// in the case-file format (kind `"equilibrium"`, which may be left out), its JSON text or a
/// path. Checked as the CLI checks a case: `ValueError` names the field.
#[pyclass(module = "flexspine", frozen)]
pub struct Structure {
    case: EquilibriumCase,
    valid: ValidEquilibrium,
}

/// Which load: `"passive"` (θ1: the passive nodal load with self-weight) or `"loaded"` (θ2: the
/// passive load plus the actuation).
fn nodal(valid: &ValidEquilibrium, load: &str) -> PyResult<NodalLoads> {
    let s = &valid.problem.structure;
    match load {
        "passive" => Ok(s.passive.clone()),
        "loaded" => Ok(s.passive.plus(&s.actuation)),
        other => Err(PyValueError::new_err(format!("load: \"passive\" or \"loaded\", got {other:?}"))),
    }
}

impl Structure {
    fn link_loads(&self, load: &str) -> PyResult<LinkLoads> {
        Ok(LinkLoads::from_nodal(&self.valid.problem.structure.chain, &nodal(&self.valid, load)?, true))
    }

    fn state(&self, theta: PyReadonlyArray1<'_, f64>, lam: f64) -> PyResult<State> {
        Ok(State { theta: self.angles(theta)?, lambda: lam })
    }

    fn angles(&self, theta: PyReadonlyArray1<'_, f64>) -> PyResult<Vec<f64>> {
        let theta = theta.as_slice().map_err(|e| PyValueError::new_err(format!("theta: {e}")))?.to_vec();
        let n = self.valid.problem.structure.n_links();
        if theta.len() != n {
            return Err(PyValueError::new_err(format!("theta: one angle per link, N = {n}, got {}", theta.len())));
        }
        if let Some(i) = theta.iter().position(|v| !v.is_finite()) {
            return Err(PyValueError::new_err(format!("theta[{i}]: must be finite, got {}", theta[i])));
        }
        Ok(theta)
    }
}

#[pymethods]
impl Structure {
    #[new]
    fn new(py: Python<'_>, case: &Bound<'_, PyAny>) -> PyResult<Self> {
        let text = case_text(py, case)?;
        let mut value: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| PyValueError::new_err(format!("case: not JSON: {e}")))?;
        if let Some(map) = value.as_object_mut() {
            map.entry("kind").or_insert_with(|| "equilibrium".into());
        }
        let case = match Case::from_json(&value.to_string()).map_err(|e| PyValueError::new_err(e.to_string()))? {
            Case::Equilibrium(c) => c,
            other => {
                return Err(PyValueError::new_err(format!(
                    "kind: a Structure is an \"equilibrium\" case (chain, design, loads), got \"{}\"",
                    other.kind()
                )))
            }
        };
        let valid = case.validate().map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(Self { case, valid })
    }

    /// Number of links `N`.
    #[getter]
    fn n_links(&self) -> usize {
        self.valid.problem.structure.n_links()
    }

    /// Horizontal spans `a_i` of the links, m (`N`).
    #[getter]
    fn spans<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.valid.problem.structure.chain.spans)
    }

    /// Unloaded link angles `θ0`, rad (`N`).
    #[getter]
    fn theta0<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.valid.problem.design.theta0)
    }

    /// Spring stiffnesses `K_1..K_{N+1}`, N·m/rad (`N + 1`; the first at the base, the last at the
    /// sliding end).
    #[getter]
    fn stiffness<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.valid.problem.design.stiffness)
    }

    /// Total potential `U(θ) + V(θ)`, J: strain energy of eq. (2) plus the potential of the nodal
    /// loads and self-weight (`load`: `"passive"` or `"loaded"`), at link angles `theta` (rad).
    #[pyo3(signature = (theta, load = "loaded"))]
    fn potential(&self, theta: PyReadonlyArray1<'_, f64>, load: &str) -> PyResult<f64> {
        let theta = self.angles(theta)?;
        let p = &self.valid.problem;
        let u = spine_model::energy::strain_energy(&theta, &p.design.theta0, &p.design.stiffness);
        let v = spine_model::energy::load_potential(
            &p.structure.chain,
            &nodal(&self.valid, load)?,
            true,
            &p.design.theta0,
            &theta,
        );
        Ok(u + v)
    }

    /// The equilibrium residual of eq. (5) at `(theta, lam)`: `N` joint moments `∂(U + V − λΦ)/∂θ_i`
    /// (N·m) and the end constraint `Φ = Σ L_i sin θ_i` (m), `N + 1` values.
    #[pyo3(signature = (theta, lam, load = "loaded"))]
    fn residual<'py>(
        &self,
        py: Python<'py>,
        theta: PyReadonlyArray1<'_, f64>,
        lam: f64,
        load: &str,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let state = self.state(theta, lam)?;
        let p = &self.valid.problem;
        let r = spine_model::residual::equilibrium_residual(
            &p.structure.chain.spans,
            &p.design,
            &self.link_loads(load)?,
            &state,
        );
        Ok(PyArray1::from_vec(py, r))
    }

    /// The exact Jacobian of [`Structure.residual`] with respect to `(θ, λ)` (forward-mode AD,
    /// bordered tridiagonal, `(N + 1) × (N + 1)`) as `((data, (rows, cols)), shape)`:
    /// `scipy.sparse.coo_array(*s.jacobian(theta, lam))` builds it.
    #[pyo3(signature = (theta, lam, load = "loaded"))]
    #[allow(clippy::type_complexity)]
    fn jacobian<'py>(
        &self,
        py: Python<'py>,
        theta: PyReadonlyArray1<'_, f64>,
        lam: f64,
        load: &str,
    ) -> PyResult<((Bound<'py, PyArray1<f64>>, (Bound<'py, PyArray1<i64>>, Bound<'py, PyArray1<i64>>)), (usize, usize))>
    {
        let state = self.state(theta, lam)?;
        let p = &self.valid.problem;
        let (_, jac) = spine_model::jacobian::residual_and_state_jacobian(
            &p.structure.chain.spans,
            &p.design,
            &self.link_loads(load)?,
            &state,
        );
        let sparse = jac.to_sparse();
        let rows = sparse.entries.iter().map(|e| e.0 as i64).collect();
        let cols = sparse.entries.iter().map(|e| e.1 as i64).collect();
        let data = sparse.entries.iter().map(|e| e.2).collect();
        Ok((
            (PyArray1::from_vec(py, data), (PyArray1::from_vec(py, rows), PyArray1::from_vec(py, cols))),
            (sparse.nrows, sparse.ncols),
        ))
    }

    /// The passive equilibrium `θ1` and the loaded one `θ2` by load continuation from `θ0`, each
    /// with `λ`, its status and its stability certificate (the smallest eigenvalue of the
    /// projected Hessian): the CLI's `spine equilibrium`, as a [`Result`] (`result["loaded"]`).
    fn equilibria(&self, py: Python<'_>) -> PyResult<CaseResult> {
        let case = Case::Equilibrium(self.case.clone());
        let inner = interruptible(py, || {
            spine_run::run_case(&case, &Default::default(), &spine_run::NoRecipes, &mut spine_run::quiet)
        })?
        .map_err(run_error)?;
        Ok(CaseResult { inner })
    }

    fn __repr__(&self) -> String {
        format!("<flexspine.Structure N={}>", self.n_links())
    }
}
