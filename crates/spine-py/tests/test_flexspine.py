"""The Python front (`flexspine`) against the Rust CLI and against numpy finite differences.

Run by `just python` (inside `just test`): `crates/spine-py/.venv/bin/python -m pytest crates/spine-py/tests`.
The CLI binary is `target/release/spine` unless SPINE_BIN says otherwise.
"""

import json
import os
import pathlib
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import flexspine

ROOT = pathlib.Path(__file__).resolve().parents[3]
CASES = ROOT / "paper-cases"
SPINE = os.environ.get("SPINE_BIN", str(ROOT / "target" / "release" / "spine"))

ARCH = {
    "chain": {"links": 4, "length_x": 1.0, "masses": 0.5},
    "design": {"theta0": [0.3, 0.1, -0.1, -0.3], "stiffness": [200, 150, 120, 150, 200]},
    "loads": {"p_y": [0, -5, -5, -5, 0], "p_x": -20},
}


def cli(*args):
    return subprocess.run([SPINE, *args], capture_output=True, text=True)


def central(f, x, h):
    """Central differences of a vector function, column by column."""
    columns = []
    for i in range(len(x)):
        e = np.zeros_like(x)
        e[i] = h
        columns.append((np.asarray(f(x + e)) - np.asarray(f(x - e))) / (2 * h))
    return np.array(columns).T


def test_residual_is_the_gradient_of_the_potential_and_the_jacobian_is_exact():
    s = flexspine.Structure(ARCH)
    rng = np.random.default_rng(7)
    for load in ("passive", "loaded"):
        theta = s.theta0 + 0.05 * rng.standard_normal(s.n_links)
        # With λ = 0 the joint rows are ∂(U + V)/∂θ.
        r = s.residual(theta, 0.0, load=load)
        grad = central(lambda t: [s.potential(t, load=load)], theta, 1e-6)[0]
        assert np.max(np.abs(r[:-1] - grad)) < 1e-6 * max(1.0, np.max(np.abs(grad)))
        # The AD Jacobian against central differences of the residual in (θ, λ).
        lam = 3.7
        x = np.append(theta, lam)
        (data, (rows, cols)), shape = s.jacobian(theta, lam, load=load)
        dense = np.zeros(shape)
        np.add.at(dense, (rows, cols), data)
        fd = central(lambda v: s.residual(v[:-1], v[-1], load=load), x, 1e-6)
        assert shape == (s.n_links + 1, s.n_links + 1)
        assert np.max(np.abs(dense - fd)) < 1e-6 * np.max(np.abs(fd)), np.max(np.abs(dense - fd))
        # Bordered tridiagonal: no entry off the three diagonals except the border.
        for i, j in zip(rows, cols):
            assert abs(i - j) <= 1 or i == s.n_links or j == s.n_links


def test_strain_energy_matches_the_structure_potential_without_loads():
    theta0 = np.array([0.3, 0.1, -0.1, -0.3])
    k = np.array([200.0, 150, 120, 150, 200])
    theta = theta0 + np.array([0.01, -0.02, 0.03, 0.0])
    u = flexspine.strain_energy(theta, theta0, k)
    d = np.concatenate([[0.0], theta - theta0, [0.0]])
    assert u == pytest.approx(0.5 * np.sum(k * np.diff(d) ** 2), rel=1e-14)


def test_equilibrium_from_python_equals_the_cli_result_byte_for_byte(tmp_path):
    case = CASES / "arch10.json"
    r = flexspine.run_case(case)
    out = tmp_path / "cli"
    done = cli("equilibrium", str(case), "--out", str(out), "--deterministic")
    assert done.returncode == 0, done.stderr
    assert r.json(deterministic=True) == (out / "result.json").read_text()
    assert r.kind == "equilibrium" and r.clean and r.stopped is None
    assert r["loaded"]["stability"]["stable"] is True
    # The Structure's own equilibria are the same run.
    text = json.loads(case.read_text())
    s = flexspine.Structure({k: text[k] for k in ("chain", "design", "loads")})
    eq = s.equilibria()
    assert np.array_equal(eq["loaded"]["theta"], r["loaded"]["theta"])
    # Arrays of numbers come as numpy arrays straight from the typed result, nested ones too.
    assert isinstance(r["loaded"]["theta"], np.ndarray) and r["loaded"]["theta"].dtype == np.float64
    assert r["loaded"]["theta"].shape == (len(text["design"]["theta0"]),)
    assert isinstance(r.loaded["stability"]["stable"], bool)
    nodes = r["loaded"]["nodes"]  # (x, y) of every node, m: a 2-D array
    assert nodes.shape == (len(text["design"]["theta0"]) + 1, 2) and nodes[0, 0] == 0.0
    # At θ2 the residual vanishes.
    theta2, lam2 = eq["loaded"]["theta"], eq["loaded"]["lambda"]
    assert np.max(np.abs(s.residual(theta2, lam2))) < 1e-8


def test_fig3_five_link_design_reaches_the_checked_optimum():
    r = flexspine.run_case(CASES / "design5.json")
    assert r.clean, r.summary
    assert r["objective"] == pytest.approx(7.6031253e-3, abs=1e-10)
    assert r["solver"]["status"] == "solve_succeeded"
    assert r["loaded"]["stability"]["stable"]
    assert r["certificate"]["status"] in ("strict_minimum", "weak_minimum")
    # As scipy's OptimizeResult: success, status, message, attribute access, keys().
    assert r.success and r.status == 0 and r.message == "clean"
    assert r.objective == r["objective"] and "objective" in r.keys() and "objective" in r
    with pytest.raises(AttributeError, match="no entry"):
        r.no_such_entry


def test_a_result_that_is_not_clean_says_why_as_scipy_would():
    # design5's optimum has bounds whose rows are dependent: no derivative for them, exit 3.
    r = flexspine.sensitivity(CASES / "design5.json")
    assert not r.success and r.status == 3
    assert "no derivative with respect to bounds.theta0_max" in r.message, r.message
    assert any(n["reason"] == "no_derivative" for n in r.not_clean)


def test_a_census_to_a_stated_confidence_from_python_reports_its_best_certified():
    r = flexspine.run_case(CASES / "design5.json", confidence=0.05, deterministic=True)
    census = r["multistart"]["census"]
    assert r["multistart"]["confidence"]["reached"] and census["probability_better_unseen"] <= 0.05
    assert r["objective"] <= 7.6031253e-3
    assert all(o["certificate"]["status"] != "not_a_minimum" for o in r["multistart"]["optima"])


def test_write_gives_the_cli_folder_and_series_are_the_csv_columns(tmp_path):
    case = CASES / "step5.json"
    r = flexspine.run_case(case, out=tmp_path / "py", deterministic=True)
    done = cli("simulate", str(case), "--out", str(tmp_path / "cli"), "--deterministic")
    assert done.returncode == 0, done.stderr
    for name in ("result.json", "response.csv"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    t = r.series["response.csv"]["t_s"]
    delta = r.series["response.csv"]["delta_m"]
    assert t.dtype == np.float64 and np.all(np.diff(t) > 0) and len(t) == len(delta)
    # T_90 from the arrays (first sample with Δ ≥ 0.9 Δ∞) agrees with the reported rise time to
    # the sampling step.
    reached = t[np.argmax(delta / r["step_response"]["delta_inf"] >= 0.9)]
    assert 0 <= reached - r["step_response"]["rise_time"] <= t[1] - t[0] + 1e-12


def test_write_never_removes_a_users_files(tmp_path):
    """Issue 49: Result.write follows the CLI's --out rule: a folder holding files the program did
    not write is refused (ValueError) and left as it was; a folder it wrote is replaced."""
    r = flexspine.run_case(CASES / "arch10.json")
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("a user's notes")
    with pytest.raises(ValueError, match="did not write"):
        r.write(mine)
    assert sorted(p.name for p in mine.iterdir()) == ["notes.txt"]
    out = tmp_path / "out"
    r.write(out)
    r.write(out)
    assert sorted(p.name for p in out.iterdir()) == [".spine-output", "result.json"]


@pytest.mark.parametrize(
    "edit, field",
    [
        (lambda c: c["chain"].update(links=0), "chain.links"),
        (lambda c: c["chain"].update(length_x=-1.0), "chain.length_x"),
        (lambda c: c["design"].update(stiffness=[1, 2]), "stiffness"),
        (lambda c: c["loads"].update(p_y=[0, 1]), "loads.p_y"),
        (lambda c: c.update(extra=1), "unknown field `extra`"),
    ],
)
def test_bad_input_raises_value_error_naming_the_field(edit, field):
    case = json.loads(json.dumps(ARCH))
    edit(case)
    with pytest.raises(ValueError, match=field.replace("[", r"\[").replace(".", r"\.")):
        flexspine.Structure(case)


def test_bad_arguments_raise_value_error_naming_them():
    s = flexspine.Structure(ARCH)
    with pytest.raises(ValueError, match="theta"):
        s.residual(np.zeros(3), 0.0)
    with pytest.raises(ValueError, match="load"):
        s.potential(s.theta0, load="both")
    with pytest.raises(ValueError, match="time_limit"):
        flexspine.run_case(CASES / "design5.json", time_limit=-1)
    with pytest.raises(ValueError, match="formulation"):
        flexspine.run_case(CASES / "design5.json", formulation="half")
    with pytest.raises(ValueError, match="confidence"):
        flexspine.run_case(CASES / "design5.json", confidence=1.0)
    with pytest.raises(ValueError, match="method"):
        flexspine.run_case(CASES / "periodic7.json", method="newton")
    with pytest.raises(ValueError, match="cannot read"):
        flexspine.run_case(str(CASES / "no-such-case.json"))


def test_a_time_limit_returns_what_was_reached_marked():
    r = flexspine.run_case(CASES / "periodic7.json", time_limit=0.3)
    assert r.stopped == "time_limit" and not r.clean
    assert r["stopped"] == "time_limit"
    assert r["periodic_design"]["search"]["status"] == "time_limit"


def test_eq37_by_gradient_from_python_reports_ipopt_and_meets_delta_d():
    r = flexspine.run_case(CASES / "periodic7.json", method="gradient")
    d = r["periodic_design"]
    assert d["method"] == "gradient" and d["search"] is None
    assert d["gradient"]["status"] == "solve_succeeded" and d["feasible"]
    assert abs(d["min_end_displacement"] - d["delta_d"]) <= 1e-6 * abs(d["delta_d"])
    assert d["simulations"] == 1 + d["gradient"]["root_search_simulations"] + d["gradient"]["gradient_simulations"]


def test_long_calls_release_the_gil():
    ticks = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(1)
            time.sleep(0.001)

    t = threading.Thread(target=tick)
    t.start()
    clock = time.perf_counter()
    flexspine.run_case(CASES / "design10.json", starts=4)
    took = time.perf_counter() - clock
    stop.set()
    t.join()
    # A thread that never got the GIL would tick once or not at all.
    assert len(ticks) > 0.2 * took / 0.001 * 0.1, (len(ticks), took)


def test_ctrl_c_stops_a_long_multistart_and_raises_keyboard_interrupt(tmp_path):
    out = tmp_path / "out"
    code = (
        "import flexspine, sys\n"
        "try:\n"
        f"    flexspine.run_case({str(CASES / 'design10.json')!r}, starts=400, out={str(out)!r})\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted', flush=True)\n"
        "    sys.exit(130)\n"
    )
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(2.0)
    p.send_signal(signal.SIGINT)
    clock = time.perf_counter()
    stdout, stderr = p.communicate(timeout=30)
    assert time.perf_counter() - clock < 2.5, "the run stops at Ipopt's next iteration"
    assert p.returncode == 130, stderr
    assert "interrupted" in stdout
    assert not out.exists(), "an interrupted call writes nothing"


def test_design_start_is_the_point_handed_to_ipopt():
    start = flexspine.design_start(CASES / "design5.json")
    assert set(start) == {"theta0", "k", "theta1", "lambda1", "theta2", "lambda2", "heights"}
    assert start["theta0"].shape == (5,) and start["k"].shape == (6,) and start["heights"].shape == (4,)
    # The heights are those of the unloaded shape θ0.
    text = json.loads((CASES / "design5.json").read_text())
    s = flexspine.Structure(
        {
            "chain": text["chain"],
            "design": {"theta0": list(start["theta0"]), "stiffness": list(start["k"])},
            "loads": text["loads"],
        }
    )
    heights = np.cumsum(s.spans * np.tan(start["theta0"]))[:-1]
    assert np.max(np.abs(heights - start["heights"])) < 1e-12


def test_figure_pdf_opens_in_a_pdf_reader_with_its_text(tmp_path):
    import pypdf  # installed by crates/spine-py/setup.sh
    case = json.loads((CASES / "fig3.json").read_text())
    flexspine.run_case(case, out=tmp_path / "fig3", deterministic=True)
    reader = pypdf.PdfReader(str(tmp_path / "fig3" / "figure.pdf"))
    assert len(reader.pages) == 1
    page = reader.pages[0]
    assert float(page.mediabox.width) == pytest.approx(504.0, abs=0.5)  # 7 in: a two-column figure
    text = page.extract_text()
    assert "nodal stiffness" in text and "node j" in text and "Kⱼ (N·m/rad)" in text


def test_animation_bytes_from_python_equal_the_cli_file(tmp_path):
    case = CASES / "step5.json"
    plain = flexspine.run_case(case)
    assert plain.gif() is None  # no animation unless asked
    r = flexspine.run_case(case, animate=True, frames=8, frame_width=400, out=tmp_path / "py", deterministic=True)
    gif = r.gif()
    assert gif[:6] == b"GIF89a"
    assert int.from_bytes(gif[6:8], "little") == 400  # logical screen width
    assert (tmp_path / "py" / "animation.gif").read_bytes() == gif
    done = cli("simulate", str(case), "--out", str(tmp_path / "cli"), "--frames", "8", "--frame-width", "400")
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "cli" / "animation.gif").read_bytes() == gif
    with pytest.raises(ValueError, match=r"animation\.frames"):
        flexspine.run_case(case, frames=1)
    with pytest.raises(ValueError, match="no motion to animate"):
        flexspine.run_case(CASES / "design5.json", animate=True)


def test_kinds_come_from_the_registry_and_each_has_a_paper_case():
    kinds = flexspine.KINDS
    assert len(set(kinds)) == len(kinds) and {"equilibrium", "design", "figure"} <= set(kinds)
    root = pathlib.Path(__file__).resolve().parents[3]
    found = {json.loads(p.read_text())["kind"] for p in (root / "paper-cases").glob("*.json")}
    assert found <= set(kinds)


def test_sensitivity_from_python_matches_the_cli_and_re_solves(tmp_path):
    """flexspine.sensitivity gives the CLI's result, and dJ*/dδ_d matches a central difference of
    two solves of the case at δ_d ± h (the optimum's vertex does not move for this small h)."""
    case = json.loads((CASES / "design5.json").read_text())
    result = flexspine.sensitivity(case, ["delta_d"], out=tmp_path / "py", deterministic=True)
    assert result.kind == "sensitivity" and result.clean
    cli = subprocess.run(
        [SPINE, "sensitivity", str(CASES / "design5.json"), "--param", "delta_d", "--out", str(tmp_path / "cli"), "--deterministic"],
        capture_output=True,
    )
    assert cli.returncode == 0, cli.stderr
    assert (tmp_path / "py" / "result.json").read_bytes() == (tmp_path / "cli" / "result.json").read_bytes()
    derivative = result["sensitivity"]["parameters"][0]["derivative"]
    h = 1e-4
    objective = []
    for sign in (1, -1):
        changed = dict(case, delta_d=case["delta_d"] + sign * h)
        objective.append(flexspine.run_case(changed)["objective"])
    assert abs(derivative["objective"] - (objective[0] - objective[1]) / (2 * h)) < 1e-4 * abs(derivative["objective"])
    assert np.asarray(derivative["stiffness"]).shape == (6,)
    # The same numbers as numpy arrays.
    arrays = result.derivatives["delta_d"]
    assert isinstance(arrays["stiffness"], np.ndarray) and arrays["stiffness"].shape == (6,)
    assert np.array_equal(arrays["stiffness"], np.asarray(derivative["stiffness"]))
    assert arrays["objective"] == derivative["objective"]


def test_sensitivity_of_a_figure_case_gives_arrays_per_run():
    """A figure case (Fig. 3): each design run's derivatives, keyed by run, as numpy arrays."""
    result = flexspine.sensitivity(str(CASES / "fig3.json"), ["delta_d"])
    assert result.kind == "figure_sensitivity"
    runs = result.derivatives
    # The paper's two runs, and Fig. 3's two under the text's stiffness bound 1000 where present.
    assert {"n10", "n5"} <= set(runs) <= {"n10", "n5", "n10-k1000", "n5-k1000"}
    assert runs["n10"]["delta_d"]["theta0"].shape == (10,) and runs["n5"]["delta_d"]["theta0"].shape == (5,)
    assert runs["n10"]["delta_d"]["objective"] < 0  # a larger |δ_d| costs more energy


def test_sweep_from_python_matches_the_cli_and_follows_one_optimum(tmp_path):
    """flexspine.sweep gives the CLI's result byte for byte, one point per value, and every
    followed point's J* grows with the load's magnitude as its tangent says (dJ*/dp < 0 for p < 0)."""
    case = json.loads((CASES / "fig5-base.json").read_text())
    result = flexspine.sweep(case, "loads.p_y", -1.0, -3.0, 5, out=tmp_path / "py", deterministic=True)
    assert result.kind == "sweep" and result.clean
    cli = subprocess.run(
        [SPINE, "sweep", str(CASES / "fig5-base.json"), "--param", "loads.p_y", "--from", "-1", "--to", "-3",
         "--points", "5", "--out", str(tmp_path / "cli"), "--deterministic"],
        capture_output=True,
    )
    assert cli.returncode == 0, cli.stderr
    assert (tmp_path / "py" / "result.json").read_bytes() == (tmp_path / "cli" / "result.json").read_bytes()
    assert (tmp_path / "py" / "sweep.csv").read_bytes() == (tmp_path / "cli" / "sweep.csv").read_bytes()
    points = result["sweep"]["points"]
    assert [p["parameter"] for p in points] == [-1.0, -1.5, -2.0, -2.5, -3.0]
    objective = np.array([p["objective"] for p in points])
    assert np.all(np.diff(objective) > 0)
    assert all(p["tangent"]["objective"] < 0 for p in points)
    with pytest.raises(ValueError, match="--points"):
        flexspine.sweep(case, "loads.p_y", -1.0, -3.0, 1)


def _moments(theta0, stiffness, theta):
    """M_j = K_j ((θ_j − θ0_j) − (θ_{j−1} − θ0_{j−1})), zero deflection beyond the ends."""
    u = np.concatenate([[0.0], np.asarray(theta) - np.asarray(theta0), [0.0]])
    return np.asarray(stiffness) * np.diff(u)


@pytest.mark.parametrize(
    "objective",
    [
        "total_stiffness",
        {"peak_moment": {"exponent": 8}},
        {"compliance": {"p_y": [0, 0, -30, 0, 0, 0]}},
    ],
)
def test_each_built_in_objective_runs_from_python_and_is_its_criterion_recomputed(objective, tmp_path):
    """Issue 51: `objective` in a case dictionary; the reported objective recomputed here with
    numpy from the design and the states, and the Python result equal to the CLI's bytes."""
    case = json.loads((CASES / "design5.json").read_text())
    case.pop("multistart", None)
    case["objective"] = objective
    r = flexspine.run_case(case, out=tmp_path / "py", deterministic=True)
    assert r["solver"]["status"] == "solve_succeeded", r.summary
    assert r["certificate"]["status"] in ("strict_minimum", "weak_minimum", "not_a_minimum")
    name = objective if isinstance(objective, str) else next(iter(objective))
    assert r["criterion"]["name"] == name
    d, p, l = r["design"], r["passive"], r["loaded"]
    if name == "total_stiffness":
        expected = np.sum(d["stiffness"])
    elif name == "peak_moment":
        m = np.concatenate([_moments(d["theta0"], d["stiffness"], s["theta"]) for s in (p, l)])
        expected = np.sum((m / r["criterion"]["reference"]) ** 8)
        assert r["measures"]["peak_moment"] == pytest.approx(np.max(np.abs(m)), rel=1e-12)
    else:
        moved = np.asarray(r["probe"]["nodes"]) - np.asarray(r["unloaded_nodes"])
        expected = np.sum(moved[:, 1] * np.asarray(objective["compliance"]["p_y"]))
        assert r["measures"]["compliance"] == r["objective"]
        assert r["probe"]["stability"]["stable"] and r["probe"]["residual"] < 1e-8
    assert r["objective"] == pytest.approx(expected, rel=1e-10)
    path = tmp_path / "case.json"
    path.write_text(json.dumps(case))
    done = cli("design", str(path), "--out", str(tmp_path / "cli"), "--deterministic")
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "py" / "result.json").read_bytes() == (tmp_path / "cli" / "result.json").read_bytes()


def test_the_reduced_space_refuses_another_objective_naming_the_field():
    case = json.loads((CASES / "design5.json").read_text())
    case["objective"] = "total_stiffness"
    case["formulation"] = "reduced"
    with pytest.raises(ValueError, match="formulation"):
        flexspine.run_case(case)
    case["formulation"] = "full"
    with pytest.raises(ValueError, match="formulation"):
        flexspine.run_case(case, formulation="reduced")
