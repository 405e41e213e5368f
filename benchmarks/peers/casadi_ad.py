#!/usr/bin/env python3
"""CasADi's automatic differentiation beside the workspace's: the peer of `just bench-ad-peers`.

Usage: casadi_ad.py CASE.json POINT.json OUT.json

CASE.json is a `"kind": "design"` case (the scaled family); the NLP of eq. (33) is built in CasADi
SX exactly as `casadi_static.py` builds it (the same lifted full-space form, variables and
constraints in the workspace's order). POINT.json holds the full-space point `x`, the constraint
multipliers `lambda`, the objective factor `sigma` and `batch` (how many evaluations one timed
call makes). Two functions are built and timed:

  jacobian   the passive equilibrium rows [r; Phi] at (theta1, lambda1) and their Jacobian with
             respect to (theta1, lambda1): the workspace's `residual_and_state_jacobian`
  hessian    the lower triangle of the Hessian of sigma f + lambda' g with respect to x: the
             workspace's Lagrangian Hessian (Ipopt's convention)

each evaluated inside CasADi in two ways, so that Python's call overhead does not count:
  vm         CasADi's SX virtual machine, `F.map(batch)` over `batch` copies of the point
  c          its generated C code compiled with `gcc -O3` and loaded back (`casadi.external`), the
             same map; skipped (null) where no C compiler is found

Each time is the best of 5 timed calls divided by `batch`: seconds per evaluation. The values at
the point are written too (triplets), so that the caller checks both programs computed the same
derivatives. The expression graphs are built before any clock starts.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import casadi as ca

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from casadi_static import build, fail, read_case  # noqa: E402

REPEATS = 5


def functions(p):
    nlp, _, _, _, _ = build(p)
    n = p["n"]
    x, f, g = nlp["x"], nlp["f"], nlp["g"]
    # Passive equilibrium rows and their state variables (theta1, lambda1).
    r = g[0 : n + 1]
    u = x[2 * n + 1 : 3 * n + 2]
    jacobian = ca.Function("spine_jacobian", [x], [r, ca.jacobian(r, u)])
    lam = ca.SX.sym("lambda", g.numel())
    sigma = ca.SX.sym("sigma")
    lagrangian = sigma * f + ca.dot(lam, g)
    hessian = ca.Function("spine_hessian", [x, lam, sigma], [ca.tril(ca.hessian(lagrangian, x)[0])])
    return jacobian, hessian


def compiled(function, directory):
    """`function` through its generated C code, compiled with gcc -O3; None without a compiler."""
    compiler = shutil.which("gcc") or shutil.which("cc")
    if compiler is None:
        return None
    name = function.name()
    source = os.path.join(directory, name + ".c")
    library = os.path.join(directory, name + ".so")
    cwd = os.getcwd()
    try:
        os.chdir(directory)
        function.generate(name + ".c")
    finally:
        os.chdir(cwd)
    subprocess.run([compiler, "-O3", "-march=x86-64", "-fPIC", "-shared", source, "-o", library], check=True)
    return ca.external(name, library)


def per_evaluation(function, args, batch):
    """Best of REPEATS calls of `function.map(batch)` over `batch` copies of `args`, per evaluation."""
    mapped = function.map(batch, "serial")
    copies = [ca.repmat(ca.DM(a), 1, batch) for a in args]
    mapped(*copies)  # warm-up
    best = float("inf")
    for _ in range(REPEATS):
        clock = time.perf_counter()
        mapped(*copies)
        best = min(best, time.perf_counter() - clock)
    return best / batch


def triplets(matrix):
    matrix = ca.DM(matrix)
    sparsity = matrix.sparsity()
    rows, cols = sparsity.get_triplet()
    values = [float(v) for v in matrix.nonzeros()]
    return [[int(r), int(c), v] for r, c, v in zip(rows, cols, values)]


def main():
    if len(sys.argv) != 4:
        fail("usage: casadi_ad.py CASE.json POINT.json OUT.json")
    p = read_case(sys.argv[1])
    with open(sys.argv[2]) as f:
        point = json.load(f)
    x0, lam0, sigma0, batch = point["x"], point["lambda"], float(point["sigma"]), int(point["batch"])
    jacobian, hessian = functions(p)
    if len(x0) != jacobian.size1_in(0) or len(lam0) != hessian.size1_in(1):
        fail(f"POINT: {len(x0)} variables and {len(lam0)} multipliers do not fit N = {p['n']}")
    out = {"n": p["n"], "batch": batch}
    residual, jac = jacobian(x0)
    out["residual"] = [float(v) for v in ca.DM(residual).full().ravel()]
    out["jacobian"] = triplets(jac)
    out["hessian"] = triplets(hessian(x0, lam0, sigma0))
    out["jacobian_vm_seconds"] = per_evaluation(jacobian, [x0], batch)
    out["hessian_vm_seconds"] = per_evaluation(hessian, [x0, lam0, sigma0], batch)
    with tempfile.TemporaryDirectory() as directory:
        clock = time.perf_counter()
        compiled_jacobian = compiled(jacobian, directory)
        compiled_hessian = compiled(hessian, directory)
        out["compile_seconds"] = time.perf_counter() - clock
        out["jacobian_c_seconds"] = (
            per_evaluation(compiled_jacobian, [x0], batch) if compiled_jacobian is not None else None
        )
        out["hessian_c_seconds"] = (
            per_evaluation(compiled_hessian, [x0, lam0, sigma0], batch) if compiled_hessian is not None else None
        )
    out["casadi"] = ca.__version__
    with open(sys.argv[3], "w") as f:
        json.dump(out, f)


if __name__ == "__main__":
    main()
