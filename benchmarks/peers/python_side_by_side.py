"""Eq. (33) from Python: flexspine (this workspace) beside the `spine` CLI and CasADi + IPOPT.

    crates/spine-py/.venv/bin/python benchmarks/peers/python_side_by_side.py [REPEATS]

(`just python-bench`.) For the paper's 5- and 10-link designs (paper-cases/design5.json,
design10.json), each from the case's own start (no multi-start), in one run:
- flexspine.run_case(case): wall time of the Python call (median of REPEATS), and the Ipopt time
  it reports;
- the CLI, `spine design CASE --out DIR --deterministic`: wall time of the process (start-up, run,
  writing result.json);
- CasADi (SX, its bundled IPOPT 3.14 + MUMPS) through benchmarks/peers/casadi_static.py, started
  from the same point (flexspine.design_start), in its own venv (benchmarks/peers/.venv): the
  solver call's time it reports, and the process wall time (Python start-up, import, graph build).
Prints a Markdown table with J from each, so that the optima can be compared too.
"""

import json
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import flexspine

ROOT = pathlib.Path(__file__).resolve().parents[2]
SPINE = ROOT / "target" / "release" / "spine"
CASADI_PY = ROOT / "benchmarks" / "peers" / ".venv" / "bin" / "python"
repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 5


def median_time(f):
    times, value = [], None
    for _ in range(repeats):
        clock = time.perf_counter()
        value = f()
        times.append(time.perf_counter() - clock)
    return statistics.median(times), value


rows = []
with tempfile.TemporaryDirectory() as tmp:
    tmp = pathlib.Path(tmp)
    for name in ("design5", "design10"):
        case = ROOT / "paper-cases" / f"{name}.json"
        # One start (design10.json asks for a 20-start census; CasADi runs one start).
        py_wall, r = median_time(lambda: flexspine.run_case(case, starts=0))
        assert r.clean, r.summary
        ipopt = r.to_dict()["timings"]["solver.ipopt_seconds"]
        cli_wall, done = median_time(
            lambda: subprocess.run([SPINE, "design", case, "--starts", "0", "--out", tmp / name, "--deterministic"], capture_output=True)
        )
        assert done.returncode == 0, done.stderr
        cli_j = json.loads((tmp / name / "result.json").read_text())["objective"]
        start = {k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in flexspine.design_start(case).items()}
        (tmp / f"{name}-start.json").write_text(json.dumps(start))
        casadi_out = tmp / f"{name}-casadi.json"

        def casadi():
            return subprocess.run(
                [CASADI_PY, ROOT / "benchmarks" / "peers" / "casadi_static.py", case, tmp / f"{name}-start.json", casadi_out],
                capture_output=True,
                text=True,
            )

        casadi_wall, done = median_time(casadi)
        assert done.returncode == 0, done.stderr
        peer = json.loads(casadi_out.read_text())
        rows.append((name, r["objective"], cli_j, peer.get("objective"), py_wall, ipopt, cli_wall,
                     peer.get("wall_seconds"), casadi_wall, peer.get("status")))

print(f"median of {repeats} runs; Debian Ipopt 3.11.9 with the workspace's LDLᵀ (the default) for flexspine and the CLI, CasADi's Ipopt 3.14.19 + MUMPS 5.8.2")
print()
print("| case | J flexspine (J) | J CLI | J CasADi | flexspine call (s) | of it Ipopt (s) | CLI process (s) | CasADi solver call (s) | CasADi process (s) | CasADi status |")
print("|---|---|---|---|---|---|---|---|---|---|")
for name, j_py, j_cli, j_cas, py_wall, ipopt, cli_wall, cas_solve, cas_wall, status in rows:
    print(f"| {name} | {j_py:.10e} | {j_cli:.10e} | {j_cas:.10e} | {py_wall:.4f} | {ipopt:.4f} | {cli_wall:.4f} | {cas_solve:.4f} | {cas_wall:.3f} | {status} |")
