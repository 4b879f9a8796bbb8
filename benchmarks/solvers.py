"""Clarabel against QOCO (and MOSEK where licensed) on a limit analysis and the bounds.

The strip footing's load-controlled limit analysis (``verification/strip_footing``,
Tresca) and the lower and upper bounds of the vertical cut (Tresca, gamma H / c) with
each solver through cvxpy, round-robin; per case and solver the fastest of ``--repeat``
solves (the solver's own solve time of its last try; the wall time of the call, with
the cvxpy compile and any failed try before a retry), its iterations, its status, the
retry that ended it (QOCO's :data:`~pfem_skfem.problems.conic.QOCO_RETRIES`: '-' for
none) and the relative difference of the load from Clarabel's.

    python benchmarks/solvers.py [--elements 1000] [--size 0.05] [--repeat 3]
"""
import argparse
from pathlib import Path
import sys
import time
import warnings

import numpy as np

from pfem_skfem.discretisation.meshes import triangulate_polygon
from pfem_skfem.materials import Tresca
from pfem_skfem.problems.bounds import LimitProblem, Support, lower_bound, upper_bound
from pfem_skfem.problems.conic import SOLVERS, AlmostSolvedWarning
from pfem_skfem.problems.static import limit_analysis

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))   # run as a file: the root
from verification import strip_footing  # noqa: E402


def cases(n_elements, size):
    model = strip_footing.footing_model(n_elements)
    f = np.zeros(model["disc"].n_u)
    f[model["footing"]] = -1.0
    cut = LimitProblem(triangulate_polygon([(0, 0), (2, 0), (2, 1), (0, 1)], size),
                       Tresca(1.0), supports=(Support(lambda x: x[0] > 2 - 1e-9, "x"),
                                              Support(lambda x: x[1] < 1e-9, "xy")),
                       body_live=(0.0, -1.0))

    def footing(solver):
        res = limit_analysis(model["B"], f, Tresca(1.0), fixed=model["fixed"], solver=solver)
        return res.load_factor, res.info

    def bound(kind):
        def solve(solver):
            res = kind(cut, solver=solver)
            return res.load, res.info
        return solve
    return {f"footing limit analysis ({model['n_elements']} el.)": footing,
            f"cut lower bound ({cut.mesh.t.shape[1]} el.)": bound(lower_bound),
            f"cut upper bound ({cut.mesh.t.shape[1]} el.)": bound(upper_bound)}


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--elements", type=int, default=1000)
    p.add_argument("--size", type=float, default=0.05)
    p.add_argument("--repeat", type=int, default=3)
    args = p.parse_args()
    solvers = [name for name in ("clarabel", "qoco", "mosek")
               if SOLVERS[name].unavailable() is None]
    print("| case | solver | solve s | wall s | iterations | status | retry | load | "
          "rel. diff. |")
    print("|---|---|---|---|---|---|---|---|---|")
    for case, run in cases(args.elements, args.size).items():
        best = {}
        for _ in range(args.repeat):               # round-robin
            for solver in solvers:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", AlmostSolvedWarning)
                    t0 = time.perf_counter()
                    load, info = run(solver)
                    wall = time.perf_counter() - t0
                if solver not in best or info.solve_time < best[solver][1].solve_time:
                    best[solver] = (load, info, wall)
        ref = best["clarabel"][0]
        for solver, (load, info, wall) in best.items():
            retry = info.extra.get("retry")
            retry = "-" if retry is None else f"reg A {retry['kkt_static_reg_A']:.0e}"
            print(f"| {case} | {solver} | {info.solve_time:.3f} | {wall:.3f} | "
                  f"{info.iterations} | {info.status} | {retry} | {load:.6g} | "
                  f"{abs(load / ref - 1):.1e} |", flush=True)


if __name__ == "__main__":
    main()
