"""Time per PFEM step (Ch 2.2) split into detect, remesh, map, assemble, compile, solve.

The plane granular column (a = 1, thesis 6.4.3) collapsing, at about 500 and 2,000
elements: a few steps after the first (which has no old mesh to map from), the
mean seconds of each stage. 'compile' is cvxpy building the conic problem,
'solve' Clarabel; 'other' is the rest of the solve stage (the scales, reading
the duals, smoothing the mean stress) and the move. Each step solves ``--passes``
problems (the fixed-point passes on the lagged mean stress). Goal (issue 7): the
conic solve at least 85 % of a step. Both backends of the step are timed: "cvxpy"
(the reference statement; 'compile' is cvxpy's canonicalisation) and "clarabel"
(the direct assembly of pfem_skfem.problems.clarabel_direct; 'compile' is building
its matrices).

Run: PYTHONPATH=. python benchmarks/pfem_step.py [--steps 6] [--nx 17 33] [--passes 2]
     [--backends cvxpy clarabel]
"""
import argparse

import numpy as np

from pfem_skfem.drivers.pfem_loop import granular_column, run

STAGES = ("detect", "remesh", "map", "assemble", "compile", "solve", "other")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--steps", type=int, default=6)
    p.add_argument("--nx", type=int, nargs="+", default=[17, 33],
                   help="particles across the column (17: ~500 elements, 33: ~2,000)")
    p.add_argument("--passes", type=int, default=2)
    p.add_argument("--backends", nargs="+", choices=("cvxpy", "clarabel"),
                   default=["cvxpy", "clarabel"])
    args = p.parse_args(argv)
    head = f"{'backend':>8s} {'elements':>8s} {'s/step':>7s} " + \
        " ".join(f"{s:>8s}" for s in STAGES) + f" {'solve %':>8s} {'iters':>6s}"
    print(head)
    for nx in args.nx:
        for backend in args.backends:
            state, config = granular_column(1.0, nx, passes=args.passes, backend=backend,
                                            dt=0.02 * np.sqrt(1.0 / 9.8))
            state, _ = run(state, config, args.steps)
            h = {k: np.asarray(v[1:]) for k, v in state.history.items()}   # skip step 1
            t = {s: h[f"t_{s}"].mean() for s in STAGES[:-1]}
            total = h["seconds"].mean()
            t["other"] = total - sum(t.values())
            print(f"{backend:>8s} {int(np.median(h['elements'])):8d} {total:7.3f} "
                  + " ".join(f"{t[s]:8.3f}" for s in STAGES)
                  + f" {t['solve'] / total:8.1%} {h['iterations'].mean():6.1f}", flush=True)


if __name__ == "__main__":
    main()
