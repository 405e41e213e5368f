"""Global bounds on eq. (33) with SCIP (spatial branch-and-bound), an optional certifier.

Builds the simultaneous form of eq. (33) for a design case with uniform spans (docs/case-format.md,
the defaults of docs/design.md's bounds) and asks SCIP 10 (the `pyscipopt` wheel ships libscip) for
the global optimum: its best point, its dual (lower) bound and the gap, against a time limit.

    python scip_global.py CASE.json [--time 600] [--check RESULT.json] [--naive] [--faces]

The formulation (module `formulate`): the spring moments `m_j = K_j (Δθ_j − Δθ_{j−1})` are
variables, so the equilibrium rows are linear in them and `J = ½ Σ m_j² / K_j` is a sum of rotated
second-order cones (convex); `sin`/`cos` of every angle are variables tied by their
identity (`s² + c² = 1`, and `s = sin θ`, `c = cos θ`), the link lengths `L_i = a / cos θ0_i` are
variables with `L_i cos θ0_i = a`, and the bounds that make branch-and-bound close are derived
from the problem, not guessed:

* `|θ0_i| ≤ θ0_max` (the case's bound) gives `cos θ0_i ≥ cos θ0_max` and `L_i ≤ a / cos θ0_max`;
* the loaded states are bounded by `|θ_i| ≤ π/2` (a link past vertical is off the load path the
  workspace certifies) unless `--naive` keeps only that;
* `|λ1| ≤ 1e4` N (an assumption, as in the naive formulation: the passive end's X is free); for
  `λ2`, the end constraint's row `i` reads `(K_m Δθ)_i − P_i − λ L_i cos θ_i = 0`;
  summing the rows with weights `L_i cos θ_i` bounds `|λ|` by the stiffness and load terms
  (computed in `lambda_bound`);
* the mirror symmetry of a uniform load (θ0 → −reversed θ0, K → reversed K, with the same J) is
  broken by `θ0_1 ≥ −θ0_N` (the first link at least as steep upward as the last is downward),
  which keeps one of each mirror pair.

With `--check RESULT.json` (a `spine design` result of the same case) the workspace's reported
optimum is evaluated in this model first: every constraint's residual and `J`, so that the two
formulations are known to be the same problem before SCIP's numbers are compared.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time


def per_node(value, n):
    """A case's load field: one number for every node, or a list of N + 1."""
    if isinstance(value, list):
        return [float(v) for v in value]
    return [float(value)] * (n + 1)


def read_case(path):
    case = json.load(open(path))
    if case.get("kind") != "design":
        sys.exit(f"{path}: a design case is needed")
    n = int(case["chain"]["links"])
    lx = float(case["chain"].get("length_x", 1.0))
    loads = case["loads"]
    p_y = per_node(loads.get("p_y", 0.0), n)
    p_x_end = loads.get("p_x", 0.0)
    p_x = [0.0] * (n + 1)
    if isinstance(p_x_end, list):
        p_x = [float(v) for v in p_x_end]
    else:
        p_x[n] = float(p_x_end)
    bounds = case.get("bounds", {})
    return {
        "n": n,
        "lx": lx,
        "a": lx / n,
        "p_y": p_y,
        "p_x": p_x,
        "delta_d": float(case["delta_d"]),
        "theta0_max": float(bounds.get("theta0_max", math.pi / 6)),
        "relative_max": float(bounds.get("relative_angle_max", math.pi / 6)),
        "k_min": float(bounds.get("stiffness_min", 100.0)),
        "k_max": float(bounds.get("stiffness_max", 1e4)),
        "y_min": float(bounds.get("height_min", 0.01)),
        "y_max": float(bounds.get("height_max", 0.25 * lx)),
    }


def lambda_bound(p):
    """A bound on the loaded state's slider reaction |λ2|. Row i of the equilibrium, times
    L_i cos θ_i and summed: the spring moments and the loads' moments are bounded by the largest
    stiffness times the largest relative deflection (π for |θ| ≤ π/2, θ0 within θ0_max) and the
    loads times the chain's length, while Σ L_i² cos² θ_i is at least the span squared over N
    (the end meets Y = 0 with X near L_x)."""
    n, a = p["n"], p["a"]
    l_max = a / math.cos(p["theta0_max"])
    moment = 2 * p["k_max"] * (math.pi / 2 + p["theta0_max"]) * 2
    load = sum(abs(v) for v in p["p_y"]) + sum(abs(v) for v in p["p_x"])
    per_row = moment + load * n * l_max
    reach = sum(l_max for _ in range(n))
    denominator = (p["lx"] + p["delta_d"]) ** 2 / n
    return per_row * reach / denominator


def flat_faces(p):
    """The faces of the K box that together hold a global optimum of the two-link problem.

    With N = 2, Φ(θ0) = a (tan θ0_1 + tan θ0_2) = 0 gives θ0_2 = −θ0_1 (equal lengths), each
    state's closure gives θ_2 = −θ_1, the relative rotations are φ (1, −2, 1) and every row and
    J = ½ φ² (K_1 + 4 K_2 + K_3) depend on K only through K_1 + 2 K_2 and 2 K_2 + K_3. Moving an
    optimum along the flat direction (2, −1, 2) keeps it optimal until K_2 reaches its lower
    bound or K_1 or K_3 their upper bound: the three faces below cover the global optimum, and
    none of them has the flat direction (which keeps branch-and-bound's bound open along it)."""
    if p["n"] != 2:
        sys.exit("--faces: the flat direction is derived for N = 2 only")
    return [(1, p["k_min"]), (0, p["k_max"]), (2, p["k_max"])]


def formulate(p, naive=False, fixed=None):
    import pyscipopt as scip

    n, a = p["n"], p["a"]
    m = scip.Model()
    m.hideOutput()
    t0 = [m.addVar(f"theta0_{i}", lb=-p["theta0_max"], ub=p["theta0_max"]) for i in range(n)]
    k = [m.addVar(f"K_{j}", lb=p["k_min"], ub=p["k_max"]) for j in range(n + 1)]
    if fixed is not None:
        j, value = fixed
        m.chgVarLb(k[j], value)
        m.chgVarUb(k[j], value)
    c0 = [m.addVar(f"c0_{i}", lb=math.cos(p["theta0_max"]), ub=1.0) for i in range(n)]
    s0 = [m.addVar(f"s0_{i}", lb=-math.sin(p["theta0_max"]), ub=math.sin(p["theta0_max"])) for i in range(n)]
    length = [m.addVar(f"L_{i}", lb=a, ub=a / math.cos(p["theta0_max"])) for i in range(n)]
    for i in range(n):
        m.addCons(c0[i] == scip.cos(t0[i]))
        m.addCons(s0[i] == scip.sin(t0[i]))
        m.addCons(s0[i] * s0[i] + c0[i] * c0[i] == 1)
        m.addCons(length[i] * c0[i] == a)
    # Φ(θ0) = Σ L_i sin θ0_i = 0; interior node heights; relative angles.
    m.addCons(scip.quicksum(length[i] * s0[i] for i in range(n)) == 0)
    for j in range(1, n):
        height = scip.quicksum(length[i] * s0[i] for i in range(j))
        m.addCons(height >= p["y_min"])
        m.addCons(height <= p["y_max"])
    for i in range(n - 1):
        m.addCons(t0[i] - t0[i + 1] <= p["relative_max"])
        m.addCons(t0[i + 1] - t0[i] <= p["relative_max"])
    if not naive and n > 1:
        m.addCons(t0[0] >= -t0[n - 1])
    # λ2: derived (the loaded end sits at X = L_x + δ_d); λ1: the naive formulation's 1e4 N, an
    # assumption (the passive end's X is not fixed, so no bound follows from the rows alone).
    lam_max = 1e4 if naive else lambda_bound(p)
    states = []
    for name, p_x in (("1", [0.0] * (n + 1)), ("2", p["p_x"])):
        lam_max_state = 1e4 if name == "1" else lam_max
        th = [m.addVar(f"theta{name}_{i}", lb=-math.pi / 2, ub=math.pi / 2) for i in range(n)]
        s = [m.addVar(f"s{name}_{i}", lb=-1.0, ub=1.0) for i in range(n)]
        c = [m.addVar(f"c{name}_{i}", lb=0.0, ub=1.0) for i in range(n)]
        lam = m.addVar(f"lambda{name}", lb=-lam_max_state, ub=lam_max_state)
        for i in range(n):
            m.addCons(s[i] == scip.sin(th[i]))
            m.addCons(c[i] == scip.cos(th[i]))
            m.addCons(s[i] * s[i] + c[i] * c[i] == 1)
        d = [th[i] - t0[i] for i in range(n)]
        # Spring moments m_j = K_j (Δθ_j − Δθ_{j−1}) (N·m): the rows are linear in them, and the
        # energy ½ Σ K_j r_j² is ½ Σ m_j² / K_j, convex in (m, K).
        moment = [m.addVar(f"m{name}_{j}", lb=None, ub=None) for j in range(n + 1)]
        for j in range(n + 1):
            rel = (d[j] if j < n else 0) - (d[j - 1] if j > 0 else 0)
            m.addCons(moment[j] == k[j] * rel)
        for i in range(n):
            sum_y = sum(p["p_y"][j] for j in range(i + 1, n + 1))
            sum_x = sum(p_x[j] for j in range(i + 1, n + 1))
            load = length[i] * c[i] * sum_y - length[i] * s[i] * sum_x
            m.addCons(moment[i] - moment[i + 1] - load - lam * length[i] * c[i] == 0)
        m.addCons(scip.quicksum(length[i] * s[i] for i in range(n)) == 0)
        states.append((th, s, c, lam, moment))
    # End displacement under the loaded state.
    c2 = states[1][2]
    m.addCons(scip.quicksum(length[i] * c2[i] for i in range(n)) - p["lx"] == p["delta_d"])
    # J = U(θ1) = ½ Σ m_j² / K_j: one epigraph variable per spring, 2 e_j K_j ≥ m_j² (a rotated
    # second-order cone, convex: SCIP's relaxation bounds J from below through the moments the
    # loads force, where ½ Σ K_j r_j² with K and r relaxed separately gives 0).
    moments = states[0][4]
    parts = [m.addVar(f"e_{j}", lb=0.0, ub=None) for j in range(n + 1)]
    for j in range(n + 1):
        m.addCons(2 * parts[j] * k[j] >= moments[j] * moments[j])
    objective = m.addVar("J", lb=0.0, ub=None)
    m.addCons(objective == scip.quicksum(parts))
    m.setObjective(objective, "minimize")
    return m, {"theta0": t0, "K": k, "states": states, "J": objective, "lambda_max": lam_max}


def check_point(p, result_path):
    """The workspace's reported optimum in this model's equations: residuals and J."""
    r = json.load(open(result_path))
    n, a = p["n"], p["a"]
    t0 = r["design"]["theta0"]
    k = r["design"]["stiffness"]
    length = [a / math.cos(t) for t in t0]
    worst = abs(sum(length[i] * math.sin(t0[i]) for i in range(n)))
    energy = None
    for key, p_x in (("passive", [0.0] * (n + 1)), ("loaded", p["p_x"])):
        th = r[key]["theta"]
        lam = r[key]["lambda"]
        d = [th[i] - t0[i] for i in range(n)]
        for i in range(n):
            left = d[i] - (d[i - 1] if i > 0 else 0)
            right = (d[i + 1] if i + 1 < n else 0) - d[i]
            sum_y = sum(p["p_y"][j] for j in range(i + 1, n + 1))
            sum_x = sum(p_x[j] for j in range(i + 1, n + 1))
            row = k[i] * left - k[i + 1] * right - (length[i] * math.cos(th[i]) * sum_y - length[i] * math.sin(th[i]) * sum_x) - lam * length[i] * math.cos(th[i])
            worst = max(worst, abs(row))
        worst = max(worst, abs(sum(length[i] * math.sin(th[i]) for i in range(n))))
        if key == "passive":
            energy = sum(0.5 * k[j] * (((d[j] if j < n else 0) - (d[j - 1] if j > 0 else 0)) ** 2) for j in range(n + 1))
        else:
            end = sum(length[i] * math.cos(th[i]) for i in range(n)) - p["lx"]
            worst = max(worst, abs(end - p["delta_d"]))
    lam_ok = abs(r["passive"]["lambda"]) <= 1e4 and abs(r["loaded"]["lambda"]) <= lambda_bound(p)
    return {"largest_residual": worst, "J": energy, "J_reported": r["objective"], "lambda_within_bound": lam_ok}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("case")
    ap.add_argument("--time", type=float, default=600.0, help="SCIP's time limit, s")
    ap.add_argument("--check", help="a spine design result.json of the same case, evaluated in this model first")
    ap.add_argument("--naive", action="store_true", help="the naive bounds (|λ| ≤ 1e4, no symmetry breaking)")
    ap.add_argument("--gap", type=float, default=1e-4, help="relative gap at which SCIP stops")
    ap.add_argument("--faces", action="store_true", help="N = 2: solve the three faces of the K box that hold the global optimum (flat_faces), each with --time")
    args = ap.parse_args()
    p = read_case(args.case)
    out = {"case": args.case, "links": p["n"], "naive": args.naive}
    if args.check:
        out["check"] = check_point(p, args.check)
    faces = flat_faces(p) if args.faces else [None]
    runs = []
    for fixed in faces:
        model, v = formulate(p, naive=args.naive, fixed=fixed)
        model.setParam("limits/time", args.time)
        model.setParam("limits/gap", args.gap)
        model.setParam("randomization/randomseedshift", 0)
        clock = time.time()
        model.optimize()
        run = {
            "face": None if fixed is None else {"spring": fixed[0] + 1, "K": fixed[1]},
            "status": model.getStatus(),
            "seconds": round(time.time() - clock, 2),
            "best_J": model.getObjVal() if model.getNSols() > 0 else None,
            "dual_bound": model.getDualbound(),
            "gap": model.getGap(),
            "nodes": model.getNNodes(),
        }
        if model.getNSols() > 0:
            run["theta0"] = [model.getVal(t) for t in v["theta0"]]
            run["K"] = [model.getVal(x) for x in v["K"]]
        runs.append(run)
    out.update({"lambda_bound": v["lambda_max"], "scip": model.version()})
    if args.faces:
        # The global optimum lies on one of the faces: its lower bound is the smallest face bound
        # (an infeasible face bounds nothing), its best point the best face's.
        found = [r for r in runs if r["best_J"] is not None]
        bounds = [r["dual_bound"] for r in runs if r["status"] != "infeasible"]
        best = min((r["best_J"] for r in found), default=None)
        lower = min(bounds, default=None)
        gap = None if best is None or lower is None else (best - lower) / abs(best)
        out.update({"faces": runs, "best_J": best, "dual_bound": lower, "gap": gap,
                    "seconds": round(sum(r["seconds"] for r in runs), 2)})
    else:
        out.update(runs[0])
        out.pop("face")
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
