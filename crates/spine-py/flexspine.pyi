"""Flexible spines: planar chains of rigid links joined by torsional springs and dampers, fixed
base, end sliding on X (the paper "Design of a one-dimensional flexible structure for desired
load-bearing capability and axial displacement").

Equilibria with a stability certificate, the static design of eq. (33) with exact AD derivatives
and Ipopt, C_K of eq. (34), dynamics, eqs. (35) and (37): the Rust workspace's own code. A case is
a dictionary in the case-file format (docs/case-format.md), its JSON text, or a file path.
Units: m, rad, N, N·m/rad, N·m·s/rad, kg, s, J.
"""

import os
from typing import Any, Literal, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

CaseLike = Union[Mapping[str, Any], str, os.PathLike[str]]
Array = npt.NDArray[np.float64]
KINDS: list[str]
"""The case kinds this build runs (`"kind"` of a case file), from the one registry in Rust."""

Load = Literal["passive", "loaded"]

def version() -> str:
    """The version of the workspace this module was built from."""

def strain_energy(theta: npt.ArrayLike, theta0: npt.ArrayLike, stiffness: npt.ArrayLike) -> float:
    """Strain energy U = ½ Σ_j K_j (Δθ_j − Δθ0_j)² of eq. (2), J (N angles, N + 1 springs)."""

def design_start(case: CaseLike) -> dict[str, Union[Array, float]]:
    """The full-space start point of eq. (33) for a "design" case: theta0 (rad), k = K / C_K,
    theta1/lambda1 and theta2/lambda2 (both equilibria of the start design, multipliers in N),
    heights (interior node heights, m). The point Ipopt starts from, for a peer model."""

def run_case(
    case: CaseLike,
    *,
    out: Optional[Union[str, os.PathLike[str]]] = None,
    deterministic: bool = False,
    starts: Optional[int] = None,
    seed: Optional[int] = None,
    confidence: Optional[float] = None,
    formulation: Optional[Literal["full", "reduced"]] = None,
    method: Optional[Literal["ga", "pattern", "gradient"]] = None,
    time_limit: Optional[float] = None,
    animate: bool = False,
    frames: Optional[int] = None,
    frame_width: Optional[int] = None,
    magnify: Optional[float] = None,
) -> Result:
    """Runs a case of any kind in `KINDS` (the CLI's `spine case`; docs/case-format.md has a
    section for each).

    A "design" case may choose its criterion and add a budget (`"objective"`: "strain_energy",
    "total_stiffness", {"peak_moment": {...}}, {"compliance": {...}}; `"constraints"`:
    {"strain_energy_max": J}; docs/objectives.md): `result["criterion"]`, `result["measures"]`
    (every criterion's measure of the design) and, for the compliance, `result["probe"]`.

    Overrides as on the command line: `starts`/`seed` (multi-start of eq. (33)), `confidence` (a
    census until P(a better optimum unseen) <= it, `starts` its cap; every reported optimum carries
    `certificate`: strict_minimum / weak_minimum / not_a_minimum), `formulation`,
    `method` (eq. (37)), `time_limit` (s; the result then says stopped="time_limit"), and an
    animation of a dynamic run (`animate`, `frames` 2..=600, `frame_width` 320..=1920 px,
    `magnify`; any of them asks for one; `Result.gif()` returns it). With `out` the result's
    folder is written all or nothing, as the CLI's `--out`.

    Raises ValueError (bad input; the message names the field), TimeoutError (the time limit left
    nothing to report), KeyboardInterrupt (Ctrl-C: the run stops at its next check, nothing
    written), RuntimeError (anything else). The GIL is released while the run works.
    """

def sensitivity(
    case: CaseLike,
    params: Optional[Sequence[str]] = None,
    *,
    out: Optional[Union[str, os.PathLike[str]]] = None,
    deterministic: bool = False,
) -> "Result":
    """Eq. (33) on a design case, then the derivatives of its optimum with respect to `params`
    (the case file's field paths, e.g. "delta_d", "loads.p_y[2]", "loads.scale",
    "chain.length_x"; default: all), as `spine sensitivity`. The result's kind is "sensitivity";
    `result["sensitivity"]["parameters"]` holds, per parameter, `derivative` (or `increase` and
    `decrease` where a bound is weakly active) with `theta0`, `stiffness`, `theta1`, `theta2`,
    `lambda1`, `lambda2`, `objective`; `result["sensitivity"]["conditions"]` the numbers of LICQ,
    strict complementarity and second-order sufficiency. Raises ValueError on a bad case or name."""

def sweep(
    case: CaseLike,
    param: str,
    start: float,
    stop: float,
    points: int = 21,
    *,
    census: Optional[int] = None,
    census_every: int = 5,
    out: Optional[Union[str, os.PathLike[str]]] = None,
    deterministic: bool = False,
) -> "Result":
    """Eq. (33)'s optimum at `param = start` followed to `param = stop` over `points` equally
    spaced values, as `spine sweep`. The result's kind is "sweep"; `result["sweep"]["points"]`
    holds per point `parameter`, `objective` (J*), `design` (`theta0`, `stiffness`), `status`
    ("followed", "jumped", "failed"), `active` (the active bounds) and `tangent`;
    `result["sweep"]["events"]` the events (`kind`, `what`, `parameter`, `bracket`); with
    `census=STARTS`, `result["census"]` the best-known J* at every `census_every`-th point.
    Raises ValueError on a bad case, name or range."""

class Result:
    """A case's typed result: what `result.json` holds, plus its time series as numpy arrays."""

    @property
    def kind(self) -> str:
        """equilibrium, twolink, design, simulate, damping, periodic, figure, study, sensitivity,
        figure_sensitivity or sweep."""
    @property
    def clean(self) -> bool:
        """Converged, stable, every solver check passed, not stopped early (CLI exit code 0)."""
    @property
    def stopped(self) -> Optional[str]:
        """"time_limit" when the time limit cut the run short, else None."""
    @property
    def success(self) -> bool:
        """As scipy's OptimizeResult.success: the same as clean."""
    @property
    def status(self) -> int:
        """As scipy's OptimizeResult.status: the CLI's exit code, 0 (clean) or 3 (not clean)."""
    @property
    def message(self) -> str:
        """As scipy's OptimizeResult.message: "clean", or why not."""
    def keys(self) -> Any:
        """The top-level entries of `result.json`."""
    def __getattr__(self, name: str) -> Any:
        """A top-level entry of `result.json` by attribute (result.objective); AttributeError if absent."""
    def __contains__(self, key: str) -> bool: ...
    @property
    def summary(self) -> str:
        """The summary the CLI prints."""
    @property
    def series(self) -> dict[str, dict[str, Union[Array, list[str]]]]:
        """The tables the CLI writes as CSV (response.csv, …) as {column: values}, straight from
        the typed columns: numbers and counts as float arrays (a missing cell is NaN), labels
        (statuses, run names) as lists of strings."""
    @property
    def derivatives(self) -> Optional[dict[str, Any]]:
        """Sensitivity results: {parameter: {"theta0", "stiffness", "theta1", "theta2": array,
        "lambda1", "lambda2", "objective", "objective_direct": float}} (one-sided:
        {"increase": …, "decrease": …}; None where no derivative is given); keyed by run first for
        a figure case. None for other results."""
    def json(self, deterministic: bool = False) -> str:
        """`result.json`'s text; deterministic=True leaves wall times out (same input, same bytes)."""
    def to_dict(self) -> dict[str, Any]:
        """`result.json` as a dictionary, straight from the typed result: every array of numbers
        a numpy array (int64 for integers, else float64 with null as NaN), rows of numbers of
        equal length a 2-D array, other arrays (strings, objects, empty) lists."""
    def __getitem__(self, key: str) -> Any:
        """One top-level entry of `result.json` (arrays as in to_dict)."""
    def gif(self) -> Optional[bytes]:
        """The animation of the chain's motion as GIF bytes, or None when the run has none."""
    def write(self, out: Union[str, os.PathLike[str]], deterministic: bool = False) -> str:
        """Writes the result's folder (result.json, CSV, SVG, PNG) all or nothing; returns the path
        of result.json."""

class Structure:
    """A chain with its design and loads: the `chain`, `design` and `loads` sections of an
    equilibrium case (kind may be left out). Checked as the CLI checks a case."""

    def __init__(self, case: CaseLike) -> None: ...
    @property
    def n_links(self) -> int:
        """Number of links N."""
    @property
    def spans(self) -> Array:
        """Horizontal spans a_i, m (N)."""
    @property
    def theta0(self) -> Array:
        """Unloaded link angles θ0, rad (N)."""
    @property
    def stiffness(self) -> Array:
        """Springs K_1..K_{N+1}, N·m/rad."""
    def potential(self, theta: npt.ArrayLike, load: Load = "loaded") -> float:
        """Total potential U(θ) + V(θ), J (strain energy of eq. (2), nodal loads, self-weight)."""
    def residual(self, theta: npt.ArrayLike, lam: float, load: Load = "loaded") -> Array:
        """Equilibrium residual of eq. (5): N joint moments ∂(U + V − λΦ)/∂θ_i (N·m) and Φ (m)."""
    def jacobian(
        self, theta: npt.ArrayLike, lam: float, load: Load = "loaded"
    ) -> tuple[tuple[Array, tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]], tuple[int, int]]:
        """Exact AD Jacobian of `residual` in (θ, λ) as ((data, (rows, cols)), shape):
        `scipy.sparse.coo_array(*s.jacobian(theta, lam))`."""
    def equilibria(self) -> Result:
        """θ1 (passive) and θ2 (loaded) by load continuation from θ0, with λ, status and the
        stability certificate: the CLI's `spine equilibrium`."""
