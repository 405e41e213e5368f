"""Global bounds on eq. (33) with SCIP (spatial branch-and-bound), an optional certifier.

Builds eq. (33) for a design case with uniform spans (docs/case-format.md, the defaults of
docs/design.md's bounds) in a form SCIP 10 can bound (the `pyscipopt` wheel ships libscip), and
asks SCIP for the global optimum below the census's: its best point, its dual (lower) bound and
the gap, against a time limit.

    python scip_global.py CASE.json CENSUS_RESULT.json [--time 600] [--gap 1e-4] [--incumbent]

CENSUS_RESULT.json is a `spine design` result of the same case (best of a census). Its `J` is the
cutoff `J_u` that the derived bounds below use, and its point is first evaluated in this problem's
equations (`check_point`: every residual and `J`), so the two are known to be one problem. With
`--incumbent` its point is also handed to SCIP as the first solution; without it SCIP finds its
own best point, and agreement with the census is a separate result. The report (JSON on stdout)
has `gap_to_census = (J_census − dual bound) / J_census` (no design has `J` below the dual bound)
and `dual_bound_trace`, the dual bound against time.

The formulation (`formulate`), in the scaled deflection form:

* the design shape by the tangents `t_i = tan θ0_i`: `Φ(θ0) = a Σ t_i = 0` and the node heights
  `a Σ_{i<j} t_i` are linear, the relative-angle bound is `|t_i − t_{i+1}| ≤ tan ρ (1 + t_i t_{i+1})`
  (exact while `θ0_max < π/4`, so that `1 + t_i t_{i+1} > 0`);
* each state by its deflections `d_i = θ_i − θ0_i` from the design shape, with `sin d` and
  `1 − cos d` as variables: the link vectors are `a (cos d − t sin d, t cos d + sin d)`, so the
  lengths `a / cos θ0` never appear and the state's closure is `Σ (sin d_i − t_i (1 − cos d_i)) = 0`;
* the spring moments `m_j = K_j r_j` (`r_j` the relative rotations) as variables, so the rows are
  linear in them, and `J = ½ Σ e_j` with `2 e_j K_j ≥ m_j²` (a rotated cone, convex) and the
  identity `2 e_j = m_j r_j` (its own relaxation closes the bound where the cone alone leaves it);
* every quantity in a unit where it is of order one (deflections in mrad or crad, link-vector
  changes in mm, `K` in 100 N·m/rad, `J` in mJ). SCIP's feasibility tolerance is absolute for
  small values: in SI units a passive deflection of 3e-3 rad held to 1e-6 is a relative 3e-4, `J`
  (quadratic in it) 7e-4, and the bound cannot close to 1e-4. Scaled, N = 2 closes in seconds
  where the same form in SI units did not in minutes (benchmarks/analysis.md).

Bounds derived from the problem, not assumed (with the cutoff `J ≤ J_u`):

* passive relative rotations: `½ Σ K_j r_j² ≤ J_u` and `K_j ≥ K_min` give `Σ r_j² ≤ 2 J_u / K_min`,
  so `|d_i| ≤ sqrt(min(i + 1, N − i) · 2 J_u / K_min)` (Cauchy–Schwarz on `d_i = Σ_{j≤i} r_j =
  −Σ_{j>i} r_j`);
* passive end reaction: the last link's row gives `λ1 = (m_{N−1} − m_N)/u_{N−1} − S_{N−1}`, and
  `|m_{N−1}| + |m_N| ≤ 2 sqrt(K_max J_u)`, so `|λ1| ≤ 2 sqrt(K_max J_u) / u_min + |S_{N−1}|`;
* loaded end reaction `|λ2|` from the rows weighted by `u_i` (`lambda_bound`);
* the mirror symmetry of a uniform load (θ0 → −reversed θ0, K → reversed K, the same J) broken by
  `t_1 ≥ −t_N`.

One assumption remains: every link points forward in both states, `|θ_i| ≤ π/2` (the load path
the workspace certifies); a certified optimum is global within it.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time

K_UNIT = 100.0  # N·m/rad: K = K_UNIT · k
# Deflections in units of 1/SCALE rad: mrad in the passive state (deflections ~1e-3 rad), crad in
# the loaded one (~1e-1 rad).
SCALE = {"passive": 1000.0, "loaded": 100.0}


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
    p = {
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
    if not p["theta0_max"] < math.pi / 4:
        sys.exit(f"{path}: bounds.theta0_max must be below pi/4 for the tangent form")
    return p


def beyond(values, i):
    """The sum of a per-node load over the nodes past link i (0-based): the row's lever."""
    return sum(values[j] for j in range(i + 1, len(values)))


def relative_rotations(d):
    """The N + 1 springs' relative rotations `r_j = d_j − d_{j−1}` from the N links' deflections
    (the base and the end held: `d_{−1} = d_N = 0`); numbers or SCIP expressions alike."""
    n = len(d)
    return [(d[j] if j < n else 0) - (d[j - 1] if j > 0 else 0) for j in range(n + 1)]


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


def passive_bounds(p, cutoff):
    """Bounds on the passive state under `J ≤ cutoff` (module docstring): |d_i| (rad) and |λ1| (N)."""
    n = p["n"]
    rotations = 2 * cutoff / p["k_min"]
    d_max = [math.sqrt(min(i + 1, n - i) * rotations) for i in range(n)]
    t_max = math.tan(p["theta0_max"])
    worst = max(d_max)
    u_min = p["a"] * (math.cos(worst) - t_max * math.sin(worst))
    lam_max = 2 * math.sqrt(p["k_max"] * cutoff) / u_min + abs(beyond(p["p_y"], n - 1))
    return d_max, lam_max


def formulate(p, cutoff):
    """Eq. (33) in the scaled deflection form (module docstring), with `J ≤ cutoff`."""
    import pyscipopt as scip

    n, a = p["n"], p["a"]
    m = scip.Model()
    m.hideOutput()
    t_max = math.tan(p["theta0_max"])
    t = [m.addVar(f"t_{i}", lb=-t_max, ub=t_max) for i in range(n)]
    k = [m.addVar(f"k_{j}", lb=p["k_min"] / K_UNIT, ub=p["k_max"] / K_UNIT) for j in range(n + 1)]
    m.addCons(scip.quicksum(t) == 0)
    for j in range(1, n):
        height = a * scip.quicksum(t[i] for i in range(j))
        m.addCons(height >= p["y_min"])
        m.addCons(height <= p["y_max"])
    tan_rho = math.tan(p["relative_max"])
    for i in range(n - 1):
        m.addCons(t[i] - t[i + 1] <= tan_rho * (1 + t[i] * t[i + 1]))
        m.addCons(t[i + 1] - t[i] <= tan_rho * (1 + t[i] * t[i + 1]))
    if n > 1:
        m.addCons(t[0] >= -t[n - 1])
    d_passive, lam_passive = passive_bounds(p, cutoff)
    states = {}
    for key, p_x in (("passive", [0.0] * (n + 1)), ("loaded", p["p_x"])):
        s = SCALE[key]
        if key == "passive":
            d_max, lam_max = [s * x for x in d_passive], lam_passive
        else:
            d_max, lam_max = [s * (math.pi / 2 + p["theta0_max"])] * n, lambda_bound(p)
        # D = s d, S = s sin d, C = s² (1 − cos d), U = 1000 (u − a) in mm (u the link's X extent).
        d = [m.addVar(f"D_{key}_{i}", lb=-d_max[i], ub=d_max[i]) for i in range(n)]
        sin_d = [m.addVar(f"S_{key}_{i}", lb=-s, ub=s) for i in range(n)]
        vers_d = [m.addVar(f"C_{key}_{i}", lb=0.0, ub=2 * s * s) for i in range(n)]
        du = [m.addVar(f"U_{key}_{i}", lb=-1000 * a, ub=None) for i in range(n)]  # u ≥ 0: |θ| ≤ π/2
        lam = m.addVar(f"lambda_{key}", lb=-lam_max, ub=lam_max)
        for i in range(n):
            m.addCons(sin_d[i] == s * scip.sin(d[i] * (1.0 / s)))
            m.addCons(vers_d[i] == s * s * (1 - scip.cos(d[i] * (1.0 / s))))
            m.addCons(sin_d[i] * sin_d[i] == 2 * vers_d[i] - vers_d[i] * vers_d[i] * (1.0 / (s * s)))
            m.addCons(du[i] == -1000 * a * (vers_d[i] * (1.0 / (s * s)) + t[i] * sin_d[i] * (1.0 / s)))
        m.addCons(scip.quicksum(sin_d[i] - t[i] * vers_d[i] * (1.0 / s) for i in range(n)) == 0)
        rotation = relative_rotations(d)
        moment = [m.addVar(f"M_{key}_{j}", lb=None, ub=None) for j in range(n + 1)]  # s m / K_UNIT
        for j in range(n + 1):
            m.addCons(moment[j] == k[j] * rotation[j])
        for i in range(n):
            u = a + du[i] * 0.001
            v = a * (t[i] * (1 - vers_d[i] * (1.0 / (s * s))) + sin_d[i] * (1.0 / s))
            spring = (K_UNIT / s) * (moment[i] - moment[i + 1])
            m.addCons(spring - u * beyond(p["p_y"], i) + v * beyond(p_x, i) - lam * u == 0)
        states[key] = {"d": d, "sin": sin_d, "vers": vers_d, "du": du, "lambda": lam,
                       "moment": moment, "rotation": rotation}
    m.addCons(scip.quicksum(states["loaded"]["du"]) == 1000 * p["delta_d"])
    # e_j in mJ: 1000 · ½ K r² = c · M R with M = s m / K_UNIT, R = s r and c = 500 K_UNIT / s².
    passive, s = states["passive"], SCALE["passive"]
    c = 500 * K_UNIT / (s * s)
    parts = [m.addVar(f"e_{j}", lb=0.0) for j in range(n + 1)]
    for j in range(n + 1):
        m.addCons(parts[j] * k[j] >= c * passive["moment"][j] * passive["moment"][j])
        m.addCons(parts[j] == c * passive["moment"][j] * passive["rotation"][j])
    objective = m.addVar("J_mJ", lb=0.0, ub=1000 * cutoff)
    m.addCons(objective == scip.quicksum(parts))
    m.setObjective(objective, "minimize")
    return m, {"t": t, "k": k, "states": states, "parts": parts, "J": objective,
               "lambda_max": {"passive": lam_passive, "loaded": lambda_bound(p)}}


def mirrored(p, r):
    """The census's point, or its mirror image where it falls on the side the symmetry cut removes."""
    n = p["n"]
    t0, k = r["design"]["theta0"], r["design"]["stiffness"]
    point = {"theta0": list(t0), "K": list(k),
             "passive": list(r["passive"]["theta"]), "loaded": list(r["loaded"]["theta"])}
    if math.tan(t0[0]) >= -math.tan(t0[n - 1]):
        return point
    flip = lambda xs: [-x for x in reversed(xs)]  # noqa: E731
    return {"theta0": flip(t0), "K": list(reversed(k)),
            "passive": flip(point["passive"]), "loaded": flip(point["loaded"])}


def incumbent(model, v, p, r):
    """Hands the census's point (or its mirror image) to SCIP as a first solution; `λ` of each
    state from its last row, so that the point is complete."""
    n, a = p["n"], p["a"]
    point = mirrored(p, r)
    tan0 = [math.tan(x) for x in point["theta0"]]
    sol = model.createSol()
    for i in range(n):
        model.setSolVal(sol, v["t"][i], tan0[i])
    for j in range(n + 1):
        model.setSolVal(sol, v["k"][j], point["K"][j] / K_UNIT)
    energy = 0.0
    for key, p_x in (("passive", [0.0] * (n + 1)), ("loaded", p["p_x"])):
        st, s = v["states"][key], SCALE[key]
        d = [point[key][i] - point["theta0"][i] for i in range(n)]
        rot = relative_rotations(d)
        for i in range(n):
            model.setSolVal(sol, st["d"][i], s * d[i])
            model.setSolVal(sol, st["sin"][i], s * math.sin(d[i]))
            model.setSolVal(sol, st["vers"][i], s * s * (1 - math.cos(d[i])))
            model.setSolVal(sol, st["du"][i], -1000 * a * (1 - math.cos(d[i]) + tan0[i] * math.sin(d[i])))
        for j in range(n + 1):
            model.setSolVal(sol, st["moment"][j], s * point["K"][j] * rot[j] / K_UNIT)
            if key == "passive":
                part = 500 * point["K"][j] * rot[j] ** 2
                model.setSolVal(sol, v["parts"][j], part)
                energy += part
        last = n - 1
        u = a * (math.cos(d[last]) - tan0[last] * math.sin(d[last]))
        w = a * (tan0[last] * math.cos(d[last]) + math.sin(d[last]))
        spring = point["K"][last] * rot[last] - point["K"][n] * rot[n]
        lam = (spring + w * beyond(p_x, last)) / u - beyond(p["p_y"], last)
        model.setSolVal(sol, st["lambda"], lam)
    model.setSolVal(sol, v["J"], energy)
    return model.addSol(sol, free=True)


def check_point(p, r):
    """The census's optimum in eq. (33)'s own equations (angles, lengths a / cos θ0): residuals and J."""
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
        rot = relative_rotations(d)
        for i in range(n):
            load = length[i] * math.cos(th[i]) * beyond(p["p_y"], i) - length[i] * math.sin(th[i]) * beyond(p_x, i)
            row = k[i] * rot[i] - k[i + 1] * rot[i + 1] - load - lam * length[i] * math.cos(th[i])
            worst = max(worst, abs(row))
        worst = max(worst, abs(sum(length[i] * math.sin(th[i]) for i in range(n))))
        if key == "passive":
            energy = sum(0.5 * k[j] * rot[j] ** 2 for j in range(n + 1))
        else:
            end = sum(length[i] * math.cos(th[i]) for i in range(n)) - p["lx"]
            worst = max(worst, abs(end - p["delta_d"]))
    return {"largest_residual": worst, "J": energy, "J_reported": r["objective"]}


def dual_bound_trace(model):
    """Records SCIP's dual bound against time (`[seconds, J]`, J in J) whenever a node is solved and
    the bound has risen by 1e-4 relative since the last record: the gap against time in one run."""
    import pyscipopt as scip

    class Trace(scip.Eventhdlr):
        def __init__(self):
            self.points = []
            self.clock = time.time()

        def eventinit(self):
            self.model.catchEvent(scip.SCIP_EVENTTYPE.NODESOLVED, self)

        def eventexit(self):
            self.model.dropEvent(scip.SCIP_EVENTTYPE.NODESOLVED, self)

        def eventexec(self, event):
            bound = self.model.getDualbound() / 1000
            if not self.points or bound > self.points[-1][1] + 1e-4 * abs(self.points[-1][1]):
                self.points.append([round(time.time() - self.clock, 2), bound])
            return {}

    trace = Trace()
    model.includeEventhdlr(trace, "dual_bound_trace", "the dual bound against time")
    return trace


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("case")
    ap.add_argument("census", help="a spine design result.json of the same case: the cutoff J_u and the point checked")
    ap.add_argument("--time", type=float, default=600.0, help="SCIP's time limit, s")
    ap.add_argument("--gap", type=float, default=1e-4, help="relative gap at which SCIP stops")
    ap.add_argument("--incumbent", action="store_true", help="hand the census's point to SCIP as its first solution")
    ap.add_argument("--seed", type=int, default=0, help="SCIP's random seed shift")
    args = ap.parse_args()
    p = read_case(args.case)
    census = json.load(open(args.census))
    check = check_point(p, census)
    # The cutoff a hair above the census's J, so that its own point stays inside the model.
    cutoff = census["objective"] * (1 + 1e-7)
    model, v = formulate(p, cutoff)
    model.setParam("limits/time", args.time)
    model.setParam("limits/gap", args.gap)
    model.setParam("randomization/randomseedshift", args.seed)
    accepted = incumbent(model, v, p, census) if args.incumbent else None
    trace = dual_bound_trace(model)
    clock = time.time()
    model.optimize()
    seconds = time.time() - clock
    found = model.getNSols() > 0
    best = model.getObjVal() / 1000 if found else None
    lower = model.getDualbound() / 1000
    out = {
        "case": args.case,
        "links": p["n"],
        "scip": model.version(),
        "check": check,
        "census_J": census["objective"],
        "incumbent_given": args.incumbent,
        "incumbent_accepted": accepted,
        "status": model.getStatus(),
        "seconds": round(seconds, 2),
        "nodes": model.getNNodes(),
        "best_J": best,
        "dual_bound": lower,
        "gap": model.getGap() if found else None,
        # What the certificate says about the census's optimum: no design has J below the dual bound.
        "gap_to_census": (census["objective"] - lower) / census["objective"],
        "best_vs_census": None if best is None else (best - census["objective"]) / census["objective"],
        "dual_bound_trace": trace.points,
        "bounds": {"lambda_passive": v["lambda_max"]["passive"], "lambda_loaded": v["lambda_max"]["loaded"]},
    }
    if found:
        out["theta0"] = [math.atan(model.getVal(x)) for x in v["t"]]
        out["K"] = [K_UNIT * model.getVal(x) for x in v["k"]]
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
