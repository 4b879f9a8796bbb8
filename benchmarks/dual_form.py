"""A prototype of issue 19 item 3: the Lagrangian dual of a PFEM step's conic problem.

Not the library's statement: a measurement of what the dual (displacement) form would
cost, built here from the captured conic data of the a = 1 column step
(``benchmarks/solve_floor.py``'s capture; rigid-plastic, so P is nonzero only on the
r block, 12 x 12 per element). The step's problem (Clarabel's form)

    min 1/2 x^T P x + c^T x   s.t.  A x + s = b,  s in K

has the dual (z in K*, the cones here self-dual; free on the zero-cone rows)

    min 1/2 z^T A_r P_r^-1 A_r^T z + (A_r P_r^-1 c_r + b)^T z
    s.t. A_0^T z = -c_0  (the columns without P: stresses, contact forces),  z_K in K,

with P_r^-1 block-diagonal (each element's inverse-mass block inverted): the variables
are the displacement increment (z on the equilibrium rows) and the cones' multipliers.
Both are solved by Clarabel (qdldl, 1e-8) on every captured solve; the table gives the
KKT size and its factor's, iterations, status, CPU seconds, and the displacement
increment's relative difference (the dual's z_eq against the step's).

Run: python benchmarks/dual_form.py [--nx 17 33] [--steps 2]
"""
import argparse
import os
from pathlib import Path
import re
import sys

import numpy as np
import scipy.sparse as sp

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from benchmarks.solve_floor import Clock, capture_step                     # noqa: E402
from pfem_skfem.problems import clarabel_direct                           # noqa: E402

BLOCK = 12            # r' per element (P2 velocity, 6 nodes x 2)


def dual_problem(problem):
    """(P, c, A, b, cones, settings, n_eq) of the dual of a captured step problem."""
    clarabel = clarabel_direct.clarabel
    P = sp.csc_matrix(problem["P"])
    P = P + sp.triu(P, 1).T
    A, b, c = sp.csc_matrix(problem["A"]), problem["b"], problem["c"]
    with_p = np.flatnonzero(np.asarray(abs(P).sum(axis=0)).ravel() > 0)
    start, count = with_p[0], with_p.size
    if count % BLOCK or not np.array_equal(with_p, np.arange(start, start + count)):
        raise ValueError("P is not one contiguous block of 12 x 12 element blocks")
    Pr = P[start:start + count][:, start:start + count].toarray()
    blocks = Pr.reshape(count // BLOCK, BLOCK, count // BLOCK, BLOCK)
    diag = np.einsum("eiej->eij", blocks)
    off = np.abs(Pr).sum() - np.abs(diag).sum()
    if off != 0.0:
        raise ValueError("P_r is not block-diagonal")
    inv = np.linalg.inv(diag)
    e = np.arange(count // BLOCK)
    rows = (e[:, None, None] * BLOCK + np.arange(BLOCK)[None, :, None]).repeat(BLOCK, 2)
    cols = (e[:, None, None] * BLOCK + np.arange(BLOCK)[None, None, :]).repeat(BLOCK, 1)
    Pr_inv = sp.csc_matrix((inv.ravel(), (rows.ravel(), cols.ravel())), shape=(count, count))
    rest = np.setdiff1d(np.arange(P.shape[0]), with_p)
    Ar, A0 = A[:, start:start + count], A[:, rest]
    Pd = sp.triu(Ar @ Pr_inv @ Ar.T, format="csc")
    cd = Ar @ (Pr_inv @ c[start:start + count]) + b
    kinds = [re.fullmatch(r"(\w+)\((\d+)\)", repr(k)).groups() for k in problem["cones"]]
    if kinds[0][0] != "ZeroConeT" or any(k == "ZeroConeT" for k, _ in kinds[1:]):
        raise ValueError("expected one zero cone, first")
    n_eq, m = int(kinds[0][1]), A.shape[0]
    cone_rows = sp.hstack([sp.csc_matrix((m - n_eq, n_eq)), -sp.identity(m - n_eq)])
    Ad = sp.vstack([A0.T, cone_rows], format="csc")
    bd = np.concatenate([-c[rest], np.zeros(m - n_eq)])
    cones = [clarabel.ZeroConeT(rest.size)] + list(problem["cones"][1:])
    return Pd, cd, Ad, bd, cones, problem["settings"], n_eq


def solve(P, c, A, b, cones, settings):
    clarabel = clarabel_direct.clarabel
    with Clock() as clock:
        solver = clarabel.DefaultSolver(P, c, A, b, cones, settings)
        sol = solver.solve()
    info = solver.get_info().linsolver
    return sol, clock.cpu, int(info.nnzA), int(info.nnzL), P.shape[0] + A.shape[0]


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--nx", type=int, nargs="+", default=[17, 33])
    p.add_argument("--steps", type=int, default=2)
    args = p.parse_args(argv)
    load = os.getloadavg()
    print(f"load average {load[0]:.2f} / {load[1]:.2f} / {load[2]:.2f} on {os.cpu_count()} "
          f"cores; every solve of {args.steps} steps of the a = 1 column; CPU seconds")
    head = (f"{'elements':>8s} {'form':>6s} {'KKT dim':>8s} {'nnz(K)':>8s} {'nnz(L)':>8s} "
            f"{'iters':>6s} {'solved':>7s} {'cpu':>7s} {'x step':>7s} {'du diff':>8s}")
    print(head)
    print("-" * len(head))
    for nx in args.nx:
        problems, elements = capture_step(nx, args.steps)
        rows = {"step": [], "dual": []}
        for q in problems:
            sol, cpu, nnz_k, nnz_l, dim = solve(q["P"], q["c"], q["A"], q["b"], q["cones"],
                                                q["settings"])
            Pd, cd, Ad, bd, cones, settings, n_eq = dual_problem(q)
            dsol, dcpu, dnnz_k, dnnz_l, ddim = solve(Pd, cd, Ad, bd, cones, settings)
            z, zd = np.asarray(sol.z)[:n_eq], np.asarray(dsol.x)[:n_eq]
            rows["step"].append((dim, nnz_k, nnz_l, sol.iterations, str(sol.status), cpu, 0.0))
            rows["dual"].append((ddim, dnnz_k, dnnz_l, dsol.iterations, str(dsol.status), dcpu,
                                 np.linalg.norm(zd - z) / np.linalg.norm(z)))
        base = np.mean([r[5] for r in rows["step"]])
        for form, rs in rows.items():
            print(f"{elements:8d} {form:>6s} {rs[-1][0]:8d} {rs[-1][1]:8d} {rs[-1][2]:8d} "
                  f"{np.mean([r[3] for r in rs]):6.1f} "
                  f"{sum(r[4] == 'Solved' for r in rs):3d}/{len(rs):<3d} "
                  f"{np.mean([r[5] for r in rs]):7.3f} {np.mean([r[5] for r in rs]) / base:7.2f} "
                  f"{max(r[6] for r in rs):8.1e}", flush=True)
    print("KKT dim, nnz(K), nnz(L): of the last solve (Clarabel's); iterations, CPU: mean over "
          "the solves; du diff: the dual's displacement increment against the step's, largest")


if __name__ == "__main__":
    main()
