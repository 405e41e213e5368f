#!/usr/bin/env python3
"""Eq. (33) of the flexible-spine paper with CasADi (SX) and its bundled IPOPT: the peer of
`spine design` in `just bench-peers`.

Usage: casadi_static.py CASE.json START.json OUT.json

CASE.json is a `"kind": "design"` case file of this workspace (docs/case-format.md); the script
reads the fields it needs and refuses fields it does not implement. START.json is the full-space
start point that our solver uses for the same case (design, both equilibria of the start design,
node heights), so that both programs start from the same point. The NLP is the same "lifted"
full-space form as `crates/spine-design/src/full_space.rs`, with variables and constraints in the
same order:

  variables   theta0 (N), k = K / C_K (N+1), theta1 (N), lambda1, theta2 (N), lambda2, Y0_2..Y0_N
  objective   J = 1/2 sum_j K_j (D_j - D_{j-1})^2, D = theta1 - theta0, D_{-1} = D_N = 0
  constraints equilibrium rows at theta1 (passive) and theta2 (passive + actuation), eq. (5):
                r_i = K_i (D_i - D_{i-1}) - K_{i+1} (D_{i+1} - D_i)
                      - L_i (cos th_i V_i - sin th_i A_i) - lambda L_i cos th_i,   Phi = sum L_i sin th_i
              node heights Y0_{j+1} - Y0_j - a_j tan theta0_j = 0 (Y0_1 = Y0_{N+1} = 0)
              end position sum L_i cos theta2_i = L_x + delta_d
              relative angles |theta0_i - theta0_{i+1}| <= relative_angle_max
  with L_i = a_i / cos theta0_i and the load resultants V_i, A_i of eq. (48).

Writes J, the design, both states, IPOPT's status and iterations and the wall time of the solver
call (the expression graph is built before the clock starts) as JSON.
"""
import json
import math
import sys
import time

import casadi as ca

KNOWN = {
    "": {"kind", "title", "notes", "chain", "loads", "delta_d", "stiffness_scale", "bounds", "start", "formulation", "multistart", "solver"},
    "chain": {"links", "length_x", "spans", "masses", "gravity"},
    "loads": {"p_y", "p_x", "self_weight"},
    "bounds": {"theta0_max", "relative_angle_max", "stiffness_min", "stiffness_max", "height_min", "height_max"},
    "solver": {"tolerance", "constraint_tolerance", "max_iterations", "scaling", "barrier_strategy", "refine", "ipopt_options"},
}


def fail(message):
    print(f"casadi_static.py: {message}", file=sys.stderr)
    sys.exit(2)


def per_item(value, count, field):
    if isinstance(value, (int, float)):
        return [float(value)] * count
    if isinstance(value, list) and len(value) == count:
        return [float(v) for v in value]
    fail(f"{field}: one number or {count} numbers")


def read_case(path):
    with open(path) as f:
        case = json.load(f)
    for section, fields in KNOWN.items():
        data = case if section == "" else case.get(section, {})
        unknown = set(data) - fields
        if unknown:
            fail(f"{section or 'case'}: fields {sorted(unknown)} are not implemented by the peer script")
    if case.get("kind") != "design":
        fail("kind: only \"design\" cases")
    if case.get("formulation", "full") != "full":
        fail("formulation: the peer solves the full space only")
    chain = case["chain"]
    n = int(chain["links"])
    if "spans" in chain:
        spans = per_item(chain["spans"], n, "chain.spans")
    else:
        spans = [float(chain["length_x"]) / n] * n
    length_x = sum(spans)
    masses = per_item(chain.get("masses", 0.0), n, "chain.masses")
    gravity = float(chain.get("gravity", 9.81))
    loads = case["loads"]
    p_y = per_item(loads["p_y"], n + 1, "loads.p_y")
    p_x = float(loads.get("p_x", 0.0))
    if not loads.get("self_weight", True):
        gravity = 0.0
    b = case.get("bounds", {})
    solver = case.get("solver", {})
    if solver.get("refine", "off") != "off":
        fail("solver.refine: this script solves one chain; only \"off\" is implemented (bench_peers drives the ladder level by level)")
    warm = solver.get("ipopt_options", {})
    if set(warm) - {"mu_init", "bound_push", "bound_frac"}:
        fail("solver.ipopt_options: only mu_init, bound_push and bound_frac (the warm start of a ladder level) are implemented")
    return {
        "n": n,
        "spans": spans,
        "length_x": length_x,
        "masses": masses,
        "gravity": gravity,
        "p_y": p_y,
        "p_x": p_x,
        "delta_d": float(case["delta_d"]),
        "ck": float(case.get("stiffness_scale", 1.0)),
        "theta0_max": float(b.get("theta0_max", math.pi / 6)),
        "relative_max": float(b.get("relative_angle_max", math.pi / 6)),
        "k_min": per_item(b.get("stiffness_min", 100.0), n + 1, "bounds.stiffness_min"),
        "k_max": per_item(b.get("stiffness_max", 1e4), n + 1, "bounds.stiffness_max"),
        "y_min": float(b.get("height_min", 0.01)),
        "y_max": float(b["height_max"]) if b.get("height_max") is not None else 0.25 * length_x,
        "tol": float(solver.get("tolerance", 1e-9)),
        "constr_viol_tol": float(solver.get("constraint_tolerance", 1e-9)),
        "max_iter": int(solver.get("max_iterations", 3000)),
        "scaling": solver.get("scaling", "gradient-based"),
        "mu_strategy": solver.get("barrier_strategy", "monotone"),
        "warm": {k: float(v) for k, v in warm.items()},
    }


def resultants(p, axial_force):
    """Eq. (48): vertical[i] = sum_{j>i} P_Y,j - g (m_i / 2 + sum_{k>i} m_k), axial[i] = sum_{j>i} P_X,j."""
    n = p["n"]
    vertical, axial = [0.0] * n, [0.0] * n
    sum_y, mass_beyond = 0.0, 0.0
    for i in reversed(range(n)):
        sum_y += p["p_y"][i + 1]
        vertical[i] = sum_y - p["gravity"] * (0.5 * p["masses"][i] + mass_beyond)
        axial[i] = axial_force
        mass_beyond += p["masses"][i]
    return vertical, axial


def build(p):
    n, a, ck = p["n"], p["spans"], p["ck"]
    theta0 = ca.SX.sym("theta0", n)
    k = ca.SX.sym("k", n + 1)
    th1, lam1 = ca.SX.sym("theta1", n), ca.SX.sym("lambda1")
    th2, lam2 = ca.SX.sym("theta2", n), ca.SX.sym("lambda2")
    y = ca.SX.sym("Y0", max(n - 1, 0))
    x = ca.vertcat(theta0, k, th1, lam1, th2, lam2, y)
    stiffness = ck * k
    length = [a[i] / ca.cos(theta0[i]) for i in range(n)]

    def delta(th, i):
        return th[i] - theta0[i] if 0 <= i < n else 0

    def equilibrium(th, lam, vertical, axial):
        rows = []
        for i in range(n):
            spring = stiffness[i] * (delta(th, i) - delta(th, i - 1)) - stiffness[i + 1] * (delta(th, i + 1) - delta(th, i))
            c, s = ca.cos(th[i]), ca.sin(th[i])
            rows.append(spring - length[i] * (c * vertical[i] - s * axial[i]) - lam * length[i] * c)
        rows.append(sum(length[i] * ca.sin(th[i]) for i in range(n)))
        return rows

    passive = resultants(p, 0.0)
    total = resultants(p, p["p_x"])
    objective = sum(0.5 * stiffness[j] * (delta(th1, j) - delta(th1, j - 1)) ** 2 for j in range(n + 1))
    heights = [0] + [y[j] for j in range(n - 1)] + [0]
    g = equilibrium(th1, lam1, *passive) + equilibrium(th2, lam2, *total)
    g += [heights[j + 1] - heights[j] - a[j] * ca.tan(theta0[j]) for j in range(n)]
    g += [sum(length[i] * ca.cos(th2[i]) for i in range(n))]
    g += [theta0[i] - theta0[i + 1] for i in range(n - 1)]
    lbg = [0.0] * (2 * (n + 1) + n) + [p["length_x"] + p["delta_d"]] + [-p["relative_max"]] * (n - 1)
    ubg = [0.0] * (2 * (n + 1) + n) + [p["length_x"] + p["delta_d"]] + [p["relative_max"]] * (n - 1)
    inf = ca.inf
    lbx = [-p["theta0_max"]] * n + [v / ck for v in p["k_min"]] + [-inf] * (2 * n + 2) + [p["y_min"]] * (n - 1)
    ubx = [p["theta0_max"]] * n + [v / ck for v in p["k_max"]] + [inf] * (2 * n + 2) + [p["y_max"]] * (n - 1)
    return {"x": x, "f": objective, "g": ca.vertcat(*g)}, lbx, ubx, lbg, ubg


def main():
    if len(sys.argv) != 4:
        fail("usage: casadi_static.py CASE.json START.json OUT.json")
    p = read_case(sys.argv[1])
    with open(sys.argv[2]) as f:
        start = json.load(f)
    n = p["n"]
    x0 = start["theta0"] + start["k"] + start["theta1"] + [start["lambda1"]] + start["theta2"] + [start["lambda2"]] + start["heights"]
    if len(x0) != 5 * n + 2:
        fail(f"START: {len(x0)} values for N = {n}, expected {5 * n + 2}")
    clock = time.perf_counter()
    nlp, lbx, ubx, lbg, ubg = build(p)
    options = {
        "ipopt.tol": p["tol"],
        "ipopt.constr_viol_tol": p["constr_viol_tol"],
        "ipopt.max_iter": p["max_iter"],
        "ipopt.nlp_scaling_method": p["scaling"],
        "ipopt.mu_strategy": p["mu_strategy"],
        "ipopt.print_level": 0,
        **{"ipopt." + k: v for k, v in p["warm"].items()},
        "ipopt.sb": "yes",
        "print_time": False,
    }
    solver = ca.nlpsol("eq33", "ipopt", nlp, options)
    build_seconds = time.perf_counter() - clock
    clock = time.perf_counter()
    sol = solver(x0=x0, lbx=lbx, ubx=ubx, lbg=lbg, ubg=ubg)
    wall = time.perf_counter() - clock
    stats = solver.stats()
    x = [float(v) for v in sol["x"].full().ravel()]
    g = [float(v) for v in sol["g"].full().ravel()]
    violation = max([max(lo - v, v - hi, 0.0) for v, lo, hi in zip(g, lbg, ubg)] + [0.0])
    ck = p["ck"]
    out = {
        "status": stats["return_status"],
        "converged": stats["return_status"] == "Solve_Succeeded",
        "iterations": int(stats["iter_count"]),
        "wall_seconds": wall,
        "build_seconds": build_seconds,
        "objective": float(sol["f"]),
        "constraint_violation": violation,
        "theta0": x[:n],
        "stiffness": [ck * v for v in x[n:2 * n + 1]],
        "theta1": x[2 * n + 1:3 * n + 1],
        "lambda1": x[3 * n + 1],
        "theta2": x[3 * n + 2:4 * n + 2],
        "lambda2": x[4 * n + 2],
        "casadi_version": ca.__version__,
        "ipopt_version": "CasADi " + ca.__version__ + " bundled Ipopt",
    }
    with open(sys.argv[3], "w") as f:
        json.dump(out, f)


if __name__ == "__main__":
    main()
