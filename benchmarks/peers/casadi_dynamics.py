#!/usr/bin/env python3
"""The CasADi peer of `just bench-dynamics`: the step response of one chain by CasADi's SUNDIALS
integrators, IDAS (BDF orders 1-5, the index-1 DAE) and CVODES (BDF, the ODE with the bordered
system solved inside), with exact Jacobians by CasADi's AD.

Usage: casadi_dynamics.py MODEL.json BUDGET_SECONDS PLUGIN RTOL [RTOL ...]   (PLUGIN: idas | cvodes)

MODEL.json is the file `benchmarks/src/bin/dynamics_scaling.rs` writes for the same chain the workspace
and scipy simulate (see scipy_dynamics.py). The equations are those of scipy_dynamics.py, written in
CasADi as a CasADi user would: y = (theta, omega), and the accelerations a and the slider reaction
lambda from the bordered system [M -grad Phi; grad Phi^T 0] [a; lambda] = [Q; b] with Baumgarte's
b (a = b = 10 1/s), M the dense mass matrix, Q springs, dampers, centrifugal terms and loads.
- idas: a semi-explicit index-1 DAE, x = (theta, omega), z = (a, lambda), the bordered system as
  the algebraic equations (SX expressions; IDAS's dense Newton matrices from the exact Jacobian);
- cvodes: an ODE whose right-hand side solves the bordered system (MX with a linear-solver node,
  CasADi's `solve(..., "qr")`), the Jacobian by AD through it.

T_90 is found on the integrator's output by root finding, not on the grid: the run integrates to
t_end = 1 s with outputs every 1 ms (SUNDIALS interpolates them; the steps do not stop there),
takes the first output interval where X_{N+1} - X_target changes sign and solves
X_{N+1}(t) = X_target on the cubic Hermite interpolant of X_{N+1} through that interval's ends
(Illinois method), whose own error (about 1e-12 m) is far below the accuracies compared. The wall
time of a run is the integration and the root finding; the construction of the integrator
(symbolic expressions, code for the Jacobians) is timed apart. IDAS starts from a consistent
state (z and x' from the bordered system at the start).

Prints one JSON object per tolerance (atol = rtol / 100), as scipy_dynamics.py does, plus the
construction time and the plugin.
"""
import json
import signal
import sys
import time

import casadi as ca
import numpy as np
from chain_model import Budget, model

A_B, B_B = 10.0, 10.0
OUTPUT_STEP = 1e-3


def joint_moments(c, x, n):
    # c_i (x_i - x_{i-1}) - c_{i+1} (x_{i+1} - x_i), x_{-1} = x_N = 0.
    xp = ca.vertcat(0, x, 0)
    rel = xp[1:] - xp[:-1]
    return c[:-1] * rel[:-1] - c[1:] * rel[1:]


def bordered(sym, m, n, L, diag, C, th, om):
    """The bordered matrix B and right-hand side [Q; b] of the accelerations, as expressions."""
    theta0 = ca.DM(m["theta0"])
    K = ca.DM(m["stiffness"])
    D = ca.DM(m["damping"])
    V = ca.DM(m["loaded"]["vertical"])
    A = ca.DM(m["loaded"]["axial"])
    Ld = ca.DM(L)
    s, c = ca.sin(th), ca.cos(th)
    ones = ca.DM.ones(1, n)
    diff = ca.mtimes(th, ones) - ca.mtimes(ones.T, th.T)
    Cd = ca.DM(C)
    M = Cd * ca.cos(diff) + ca.diag(ca.DM(diag))
    h = ca.mtimes(Cd * ca.sin(diff), om**2)
    Q = Ld * (c * V - s * A) - h - joint_moments(D, om, n) - joint_moments(K, th - theta0, n)
    g = Ld * c
    phi = ca.dot(Ld, s)
    phidot = ca.dot(g, om)
    b = ca.dot(Ld * s, om**2) - 2 * A_B * phidot - B_B**2 * phi
    B = ca.blockcat([[M, -g], [g.T, sym.zeros(1, 1)]])
    return B, ca.vertcat(Q, b)


def consistent_start(m, n, L, diag, C, y0):
    """The algebraic state z0 = (a, lambda) and the state derivative (omega, a) at y0."""
    x = ca.SX.sym("x", 2 * n)
    B, r = bordered(ca.SX, m, n, L, diag, C, x[:n], x[n:])
    Bv, rv = ca.Function("bordered", [x], [B, r])(y0)
    z0 = np.linalg.solve(np.asarray(Bv), np.asarray(rv)).ravel()
    return z0, np.concatenate([y0[n:], z0[:n]])


def build(plugin, m, n, L, diag, C, rtol, tout, xdot0):
    """The integrator from t = 0 through the output times `tout`."""
    opts = {"abstol": rtol / 100.0, "reltol": rtol, "max_num_steps": 10_000_000}
    if plugin == "idas":
        x = ca.SX.sym("x", 2 * n)
        z = ca.SX.sym("z", n + 1)
        th, om = x[:n], x[n:]
        B, r = bordered(ca.SX, m, n, L, diag, C, th, om)
        dae = {"x": x, "z": z, "ode": ca.vertcat(om, z[:n]), "alg": ca.mtimes(B, z) - r}
        # A consistent start (z0 and x'(0) from the bordered system at y0): IDAS's own
        # initial-condition calculation fails (line search) from N = 10 on, and without x'(0) its
        # first error test fails at tight tolerances.
        opts["calc_ic"] = False
        opts["init_xdot"] = list(xdot0)
        # The accelerations and the reaction are outputs of the bordered system, not states to
        # control: out of the error test (index-1 practice).
        opts["suppress_algebraic"] = True
    else:
        x = ca.MX.sym("x", 2 * n)
        th, om = x[:n], x[n:]
        B, r = bordered(ca.MX, m, n, L, diag, C, th, om)
        acc = ca.solve(B, r, "qr")[:n]
        dae = {"x": x, "ode": ca.vertcat(om, acc)}
    return ca.integrator("full", plugin, dae, 0.0, list(tout), opts)


def end_x(L, y, n):
    return float(np.dot(L, np.cos(np.asarray(y[:n]).ravel())))


def first_rise(L, n, target, t_grid, ys):
    """T_90: the first output interval where X - target changes sign, then the Illinois method on the
    cubic Hermite interpolant of X through the interval's ends (X' = -sum L_i sin(theta_i) omega_i
    from the states; with outputs 1 ms apart its error is of order 1e-12 m here)."""
    X = [end_x(L, ys[:, k], n) - target for k in range(ys.shape[1])]
    V = [float(-np.dot(L * np.sin(ys[:n, k]), ys[n:, k])) for k in range(ys.shape[1])]
    for k in range(1, len(X)):
        if X[k - 1] == 0.0:
            return t_grid[k - 1]
        if X[k - 1] * X[k] < 0.0:
            break
    else:
        return None
    h = t_grid[k] - t_grid[k - 1]
    x0, x1, v0, v1 = X[k - 1], X[k], V[k - 1] * h, V[k] * h

    def hermite(s):
        return ((2 * s**3 - 3 * s**2 + 1) * x0 + (s**3 - 2 * s**2 + s) * v0
                + (-2 * s**3 + 3 * s**2) * x1 + (s**3 - s**2) * v1)

    a, b, fa, fb = 0.0, 1.0, x0, x1
    side = 0
    for _ in range(200):
        c = b - fb * (b - a) / (fb - fa)
        fc = hermite(c)
        if fc * fb < 0.0:
            a, fa = b, fb
            if side == -1:
                fa *= 0.5
            side = -1
        else:
            if side == 1:
                fa *= 0.5
            side = 1
        b, fb = c, fc
        if abs(b - a) * h < 1e-14 or fc == 0.0:
            break
    return t_grid[k - 1] + b * h


# Repeats of one integration: until they take this long together (s), at most this many times.
REPEAT_SECONDS = 0.3
MAX_REPEATS = 30


def main():
    path, budget, plugin = sys.argv[1], float(sys.argv[2]), sys.argv[3]
    rtols = [float(a) for a in sys.argv[4:]]
    m, n, L, diag, C = model(path)
    t_end = m["t_end"]
    count = int(round(t_end / OUTPUT_STEP))
    tout = np.linspace(t_end / count, t_end, count)
    t_grid = np.concatenate([[0.0], tout])
    y0 = np.concatenate([np.array(m["theta1"]), np.zeros(n)])
    target = m["x_target"]
    def stop(signum, frame):
        raise Budget()

    signal.signal(signal.SIGALRM, stop)
    for rtol in rtols:
        atol = rtol / 100.0
        # The budget covers the construction and the integration, enforced by an alarm (SUNDIALS
        # cannot be interrupted from Python otherwise).
        signal.setitimer(signal.ITIMER_REAL, budget)
        begin = time.perf_counter()
        construction = None
        try:
            if plugin == "idas":
                z0, xdot0 = consistent_start(m, n, L, diag, C, y0)
                start_of = {"x0": y0, "z0": z0}
            else:
                xdot0, start_of = None, {"x0": y0}
            full = build(plugin, m, n, L, diag, C, rtol, tout, xdot0)
            construction = time.perf_counter() - begin
            # The fastest of repeated integrations (with the T_90 search), as for the workspace's
            # runs: until they take REPEAT_SECONDS together or MAX_REPEATS times.
            elapsed, total, repeats = float("inf"), 0.0, 0
            while repeats < MAX_REPEATS and total < REPEAT_SECONDS:
                start = time.perf_counter()
                out = full(**start_of)
                ys = np.hstack([y0[:, None], np.asarray(out["xf"])])
                t90 = first_rise(L, n, target, t_grid, ys)
                run = time.perf_counter() - start
                elapsed, total, repeats = min(elapsed, run), total + run, repeats + 1
            signal.setitimer(signal.ITIMER_REAL, 0)
            stats = full.stats()
            line = {
                "rtol": rtol,
                "atol": atol,
                "status": "ok" if stats.get("success", True) else "failed",
                "time": elapsed,
                "construction": construction,
                "plugin": plugin,
                "t90": t90,
                "delta_end": end_x(L, ys[:, -1], n) - m["x1"],
                "steps": int(stats.get("nsteps", 0)),
                "nfev": int(stats.get("nfevals", 0)),
            }
        except Budget:
            line = {"rtol": rtol, "atol": atol, "status": "budget", "time": time.perf_counter() - begin,
                    "construction": construction}
        except RuntimeError as e:
            # A budget alarm inside a SUNDIALS callback comes back as the integrator's error.
            signal.setitimer(signal.ITIMER_REAL, 0)
            total = time.perf_counter() - begin
            line = {"rtol": rtol, "atol": atol, "status": "budget" if total >= budget else "failed",
                    "time": total, "construction": construction, "error": str(e).splitlines()[-1][:200]}
        print(json.dumps(line), flush=True)

if __name__ == "__main__":
    main()
