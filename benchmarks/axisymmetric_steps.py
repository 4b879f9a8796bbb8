"""The quick a = 0.5 column of revolution step by step: each solver's step from one state.

The run of ``verification/granular_column_axisymmetric.py --quick`` (6 particles across
h0, 100 steps, 2 passes: 200 solves) is advanced by ``--base`` (its trajectory); at every
step the same step is also taken from the same state by each solver of ``--compare``:

* ``clarabel``: Clarabel at the library's settings (1e-8),
* ``ipm``: the package's interior point at its defaults (1e-8),
* ``tight``: Clarabel at ``--tight`` with equilibration off (benchmarks/solve_floor.py's
  reference), at most 400 iterations,
* ``ipmtight``: the interior point at ``--tight``.

Each step's particles (all of them: the largest distance, and the axis' top particle's
height) are compared with the two tight references', relative to h0, and the figure that
``verification/granular_column_axisymmetric.py`` checks, h_inf / h0 (the highest particle
of the main body within one spacing of the axis, :func:`~pfem_skfem.pfem.measure.
deposit_at_wall`), is followed along the trajectory (book/performance.md, "The interior
point by the rule", 2026-12-08).

Run: python benchmarks/axisymmetric_steps.py [--base clarabel] [--compare clarabel ipm tight
ipmtight] [--tight 1e-10] [--json PATH]
"""
import argparse
import json
from pathlib import Path
import sys

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from pfem_skfem.drivers.pfem_loop import pfem_step                 # noqa: E402
from pfem_skfem.pfem.measure import deposit_at_wall                # noqa: E402
from pfem_skfem.problems.backends import ENGINES                   # noqa: E402
from verification.granular_column_axisymmetric import ColumnRun    # noqa: E402

MODES = ("clarabel", "ipm", "tight", "ipmtight")
TOLS = ("tol_gap_abs", "tol_gap_rel", "tol_feas")


def dispatcher(tight, solves):
    """Clarabel's engine's solve(P, c, A, b, cones, settings) by the solver named in the
    returned one-item list (every step is stated by the 'clarabel' step solver)."""
    clar, ipm = ENGINES["clarabel"], ENGINES["ipm"]
    mode = ["clarabel"]

    def solve(P, c, A, b, cones, settings):
        m = mode[0]
        if m in ("clarabel", "tight"):
            if m == "tight":
                for k in TOLS:
                    setattr(settings, k, tight)
                settings.equilibrate_enable, settings.max_iter = False, 400
            sol = type(clar).solve(clar, P, c, A, b, cones, settings)
        else:
            sol = ipm.solve(P, c, A, b, cones, ipm.settings(
                dict.fromkeys(TOLS, tight) if m == "ipmtight" else {}))
        solves.append((m, sol.status, int(sol.iterations)))
        return sol

    clar.solve = solve                        # this instance only, removed by the caller
    return mode


def trace(base, compare, tight):
    """(rows, final h_inf / h0, solves): a row a step."""
    solves = []
    mode = dispatcher(tight, solves)
    try:
        p = ColumnRun(0.5, nr=6, steps=100, phi=30.0, settle=4.0, volume_correction=True,
                      alpha_advected=3.0, solver="clarabel")
        state, scene = p.scene()
        h0, alpha, advected = 0.5 * p.r0, p.alpha, p.alpha_advected
        on = np.flatnonzero(state.x[:, 0] == 0.0)
        top = int(on[np.argmax(state.x[on, 1])])          # the axis' top particle
        rows = []
        for step in range(p.steps):
            states = {}
            for m in dict.fromkeys(list(compare) + [base]):
                mode[0] = m
                states[m] = pfem_step(state, scene)[0]
            row = dict(step=step + 1)
            for m, s in states.items():
                row[f"h_{m}"] = deposit_at_wall(s, alpha, advected)[0] / h0
            for ref in ("tight", "ipmtight"):
                for m in states if ref in states else ():
                    n = min(states[m].n, states[ref].n)
                    row[f"ex_{m}_{ref}"] = float(np.max(np.abs(
                        states[m].x[:n] - states[ref].x[:n]))) / h0
                    row[f"ey_{m}_{ref}"] = float(states[m].x[top, 1]
                                                 - states[ref].x[top, 1]) / h0
            rows.append(row)
            state = states[base]
        final = deposit_at_wall(state, alpha, advected)[0] / h0
    finally:
        del ENGINES["clarabel"].solve
    return rows, final, solves


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--base", choices=MODES, default="clarabel")
    p.add_argument("--compare", choices=MODES, nargs="*", default=list(MODES))
    p.add_argument("--tight", type=float, default=1e-10)
    p.add_argument("--json", type=Path, default=None)
    args = p.parse_args(argv)
    rows, final, solves = trace(args.base, args.compare, args.tight)
    print(f"trajectory of {args.base}: h_inf / h0 = {final:.6f}")
    for m in dict.fromkeys(args.compare + [args.base]):
        ends = {}
        for name, status, _ in solves:
            if name == m:
                ends[status] = ends.get(status, 0) + 1
        print(f"  {m}: {ends}")
    for ref in ("tight", "ipmtight"):
        for m in args.compare if ref in args.compare else ():
            if m == ref:
                continue
            ex = np.array([r[f"ex_{m}_{ref}"] for r in rows])
            ey = np.array([r[f"ey_{m}_{ref}"] for r in rows])
            print(f"  {m:9s} from {ref:9s}: particles' largest distance / h0 median "
                  f"{np.median(ex):.2e}, max {ex.max():.2e}; the axis top's height, summed "
                  f"{ey.sum():+.2e}, |.| summed {np.abs(ey).sum():.2e}")
        if {"clarabel", "ipm", ref} <= set(args.compare):
            nearer = sum(r[f"ex_ipm_{ref}"] < r[f"ex_clarabel_{ref}"] for r in rows)
            print(f"  the interior point nearer {ref} than Clarabel in {nearer} of "
                  f"{len(rows)} steps")
    if args.json:
        args.json.write_text(json.dumps(dict(rows=rows, final=final, solves=solves)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
