#!/usr/bin/env python3
"""The scipy peer of `just bench-dynamics`: the step response of one chain by scipy's Radau.

Usage: scipy_dynamics.py MODEL.json BUDGET_SECONDS RTOL [RTOL ...]

MODEL.json is written by `benchmarks/src/bin/dynamics_scaling.rs` for the same chain the workspace
simulates: link lengths L_i (m), masses m_i (kg, uniform rods), unloaded angles theta0 (rad), springs
K_1..K_{N+1} (N m/rad), dampers C_1..C_{N+1} (N m s/rad), the link load resultants (vertical and axial, N)
of the passive load and of the passive load plus the actuation, the start state theta1 (the passive
equilibrium, at rest), the rise target X_target = X1 + 0.9 (X2 - X1) and t_end.

This script builds the equations of motion itself, independently of the Rust code, as a scipy user
would (docs/model.md "Dynamics"): the dense mass matrix
M_ii = L_i^2 (m_i/3 + sum_{k>i} m_k), M_ij = L_i L_j cos(theta_i - theta_j) (m_j/2 + sum_{k>j} m_k) (i < j),
centrifugal terms h_i = sum_j c_ij sin(theta_i - theta_j) omega_j^2, springs and dampers on the
relative angles (the last to the slider, on the last link), generalised loads
P_i = L_i (cos theta_i V_i - sin theta_i A_i), and the slider constraint Phi = sum L_i sin theta_i = 0
in index-1 form with Baumgarte stabilisation (Phi'' + 2 a Phi' + b^2 Phi = 0, a = b = 10 1/s). The
bordered system [M -grad Phi; grad Phi^T 0] is solved densely (numpy), the Jacobian by scipy's finite
differences (its default). T_90 is scipy's event location on X_{N+1}(t) = X_target.

Prints one JSON object per tolerance (atol = rtol / 100): wall time of solve_ivp, T_90, the end
displacement at t_end, the work counts, and status ("ok", "failed" or "budget": the run passed
BUDGET_SECONDS and was stopped).
"""
import json
import sys
import time

import numpy as np
from chain_model import Budget, model
from scipy.integrate import solve_ivp


def joint_moments(c, x):
    # c_i (x_i - x_{i-1}) - c_{i+1} (x_{i+1} - x_i), x_{-1} = x_N = 0.
    xp = np.concatenate([[0.0], x, [0.0]])
    rel = xp[1:] - xp[:-1]  # N+1 relative motions
    return c[:-1] * rel[:-1] - c[1:] * rel[1:]


def main():
    path, budget = sys.argv[1], float(sys.argv[2])
    rtols = [float(a) for a in sys.argv[3:]]
    m, n, L, diag, C = model(path)
    theta0 = np.array(m["theta0"])
    K = np.array(m["stiffness"])
    D = np.array(m["damping"])
    V = np.array(m["loaded"]["vertical"])
    A = np.array(m["loaded"]["axial"])
    a_b, b_b = 10.0, 10.0
    deadline = [0.0]

    def rhs(t, y):
        if time.perf_counter() > deadline[0]:
            raise Budget()
        th, om = y[:n], y[n:]
        s, c = np.sin(th), np.cos(th)
        diff = th[:, None] - th[None, :]
        M = C * np.cos(diff)
        M[idx_d, idx_d] = diag
        h = (C * np.sin(diff)) @ (om**2)
        Q = L * (c * V - s * A) - h - joint_moments(D, om) - joint_moments(K, th - theta0)
        g = L * c
        phi = np.dot(L, s)
        phidot = np.dot(g, om)
        b = np.dot(L * s, om**2) - 2 * a_b * phidot - b_b**2 * phi
        B = np.zeros((n + 1, n + 1))
        B[:n, :n] = M
        B[:n, n] = -g
        B[n, :n] = g
        sol = np.linalg.solve(B, np.concatenate([Q, [b]]))
        return np.concatenate([om, sol[:n]])

    idx_d = np.arange(n)
    target = m["x_target"]

    def rise(t, y):
        return np.dot(L, np.cos(y[:n])) - target

    y0 = np.concatenate([np.array(m["theta1"]), np.zeros(n)])
    for rtol in rtols:
        atol = rtol / 100.0
        deadline[0] = time.perf_counter() + budget
        start = time.perf_counter()
        try:
            sol = solve_ivp(rhs, (0.0, m["t_end"]), y0, method="Radau", rtol=rtol, atol=atol, events=rise)
            elapsed = time.perf_counter() - start
            t90 = float(sol.t_events[0][0]) if len(sol.t_events[0]) else None
            x_end = float(np.dot(L, np.cos(sol.y[:n, -1])))
            out = {
                "rtol": rtol,
                "atol": atol,
                "status": "ok" if sol.success else "failed",
                "time": elapsed,
                "t90": t90,
                "delta_end": x_end - m["x1"],
                "steps": int(sol.t.size - 1),
                "nfev": int(sol.nfev),
                "njev": int(sol.njev),
                "nlu": int(sol.nlu),
            }
        except Budget:
            out = {"rtol": rtol, "atol": atol, "status": "budget", "time": time.perf_counter() - start}
        print(json.dumps(out), flush=True)


if __name__ == "__main__":
    main()
