"""Time per PFEM step (Ch 2.2) split into its stages: detect, remesh, map, assemble, solve, move.

The plane granular column (a = 1, thesis 6.4.3) collapsing, at about 500 and 2,000
elements: a few steps after the first (which has no old mesh to map from), the
mean seconds of each stage of :func:`pfem_skfem.drivers.pfem_loop.pfem_step`. Within
'solve', 'compile' is building the conic problem (cvxpy's canonicalisation, or the
direct assembly of pfem_skfem.problems.clarabel_direct) and 'conic' is Clarabel
itself; 'other' is what no stage timer covers (the step record). Each step solves
``--passes`` problems (the fixed-point passes on the lagged mean stress). Goal: the
conic solve at least 85 % of a step (512 elements) and 94 % (2,048) with the direct
backend.

Run: python benchmarks/pfem_step.py [--steps 6] [--nx 17 33] [--passes 2]
     [--backends cvxpy clarabel]
"""
import argparse
from pathlib import Path
import sys

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))       # the verification scripts
from verification.granular_column_plane import granular_column      # noqa: E402
from pfem_skfem.drivers.pfem_loop import run                        # noqa: E402

STAGES = ("detect", "remesh", "map", "assemble", "compile", "conic", "move", "other")


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
        " ".join(f"{s:>8s}" for s in STAGES) + f" {'conic %':>8s} {'iters':>6s}"
    print(head)
    for nx in args.nx:
        for backend in args.backends:
            state, scene = granular_column(1.0, nx, passes=args.passes, backend=backend,
                                           dt=0.02 * np.sqrt(1.0 / 9.8))
            state, _ = run(state, scene, args.steps)
            h = {k: np.asarray(v[1:]) for k, v in state.history.items()
                 if k.startswith("t_") or k in ("seconds", "iterations", "elements")}
            t = {s: h[f"t_{s}"].mean() for s in STAGES[:-1]}
            total = h["seconds"].mean()
            # compile and conic are parts of the solve stage; the rest of it is 'other'
            t["other"] = total - sum(t.values())
            print(f"{backend:>8s} {int(np.median(h['elements'])):8d} {total:7.3f} "
                  + " ".join(f"{t[s]:8.3f}" for s in STAGES)
                  + f" {t['conic'] / total:8.1%} {h['iterations'].mean():6.1f}", flush=True)


if __name__ == "__main__":
    main()
