"""The chain of a `just bench-dynamics` model file, as the Python peers read it (scipy_dynamics.py,
casadi_dynamics.py): link lengths L, the mass matrix's diagonal and coupling coefficients of
uniform rods (M_ii = L_i^2 (m_i/3 + sum_{k>i} m_k), M_ij = C_ij cos(theta_i - theta_j) with
C_ij = L_i L_j (m_j/2 + sum_{k>j} m_k), i < j), and the budget exception the peers stop with.
"""
import json

import numpy as np


class Budget(Exception):
    pass


def model(path):
    with open(path) as f:
        m = json.load(f)
    L = np.array(m["lengths"])
    mass = np.array(m["masses"])
    n = len(L)
    beyond = np.concatenate([np.cumsum(mass[::-1])[::-1][1:], [0.0]])
    coupling = 0.5 * mass + beyond
    diag = L**2 * (mass / 3.0 + beyond)
    idx = np.arange(n)
    mu = coupling[np.maximum.outer(idx, idx)]
    C = L[:, None] * L[None, :] * mu
    np.fill_diagonal(C, 0.0)
    return m, n, L, diag, C
