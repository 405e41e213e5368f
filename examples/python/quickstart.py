"""flexspine quickstart: a notebook-style tour that runs in CI (no plotting stack needed).

    python examples/python/quickstart.py OUT_DIR

1. A 10-link arch: its equilibria and their stability certificate, and the exact AD Jacobian at
   the loaded equilibrium checked against finite differences.
2. Eq. (33) for the paper's 10-link design (paper-cases/design10.json) at three target end
   displacements δ_d, from Python dictionaries.
3. The step response of the 5-link design as numpy arrays.
Writes OUT_DIR/delta_d_sweep.csv and OUT_DIR/step5_response.csv (plot them with anything).
"""

import csv
import json
import pathlib
import sys

import numpy as np

import flexspine

ROOT = pathlib.Path(__file__).resolve().parents[2]
out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "results/python-quickstart")
out.mkdir(parents=True, exist_ok=True)

# 1. Equilibria of a 10-link arch.
arch = json.loads((ROOT / "paper-cases" / "arch10.json").read_text())
s = flexspine.Structure({k: arch[k] for k in ("chain", "design", "loads")})
eq = s.equilibria()
loaded = eq["loaded"]
print(f"arch: N = {s.n_links}, θ2 {loaded['status']['kind']}, stable = {loaded['stability']['stable']} "
      f"(smallest eigenvalue {loaded['stability']['min_eigenvalue']:.4g} of the projected Hessian)")
x2 = np.append(loaded["theta"], loaded["lambda"])  # (θ2, λ2)
(data, (rows, cols)), shape = s.jacobian(x2[:-1], x2[-1])  # scipy.sparse.coo_array(*...) builds it
J = np.zeros(shape)
np.add.at(J, (rows, cols), data)
h = 1e-6
fd = np.column_stack([(s.residual((x2 + h * e)[:-1], (x2 + h * e)[-1])
                       - s.residual((x2 - h * e)[:-1], (x2 - h * e)[-1])) / (2 * h)
                      for e in np.eye(len(x2))])
print(f"  AD Jacobian vs central differences: max difference {np.max(np.abs(J - fd)):.2e}")
assert np.max(np.abs(J - fd)) < 1e-5 * np.max(np.abs(J))

# 2. Eq. (33) at three target displacements.
base = json.loads((ROOT / "paper-cases" / "design10.json").read_text())
rows_out = []
for delta_d in (-0.025, -0.05, -0.075):
    case = dict(base, delta_d=delta_d)
    r = flexspine.run_case(case)
    rows_out.append((delta_d, r["objective"], r.clean, r["solver"]["status"], r["solver"]["iterations"]))
    print(f"eq. (33) δ_d = {delta_d:+.3f} m: J = {r['objective']:.6e} J, {r['solver']['status']}, clean = {r.clean}")
with open(out / "delta_d_sweep.csv", "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["delta_d_m", "objective_J", "clean", "status", "iterations"])
    w.writerows(rows_out)

# 3. A step response as arrays.
r = flexspine.run_case(ROOT / "paper-cases" / "step5.json")
series = r.series["response.csv"]
print(f"step response: T_90 = {r['step_response']['rise_time']:.4f} s over {len(series['t_s'])} samples")
np.savetxt(out / "step5_response.csv", np.column_stack([series["t_s"], series["delta_m"]]),
           delimiter=",", header="t_s,delta_m", comments="")
print(f"wrote {out / 'delta_d_sweep.csv'} and {out / 'step5_response.csv'}")
