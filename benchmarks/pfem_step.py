"""Time per PFEM step (Ch 2.2) split into its stages, and how it grows with the mesh.

The plane granular column (a = 1, thesis 6.4.3) collapsing, at about 500, 2,000 and
8,000 elements (``--nx`` 17, 33, 65 particles across): ``--steps`` steps after the
first (which has no old mesh to map from), the mean seconds of each stage of
:func:`pfem_skfem.drivers.pfem_loop.pfem_step` (detect, remesh, map, assemble, solve,
move). Within 'solve', 'compile' is building the conic problem (cvxpy's
canonicalisation, or the direct assembly of pfem_skfem.problems.clarabel_direct) and
'conic' is Clarabel itself; 'other' is what no stage timer covers (the rest of the
solve stage and the step record). Each step solves one problem per fixed-point pass on
the lagged mean stress (``--passes`` at most; with a pass tolerance,
``PFEMConfig.pass_tolerance``, fewer where a pass changed the mean stress by less than
it): passes and interior-point iterations per step are given, and for each backend and
tolerance the growth exponent b of the step time (and of the conic solve) with the
element count n, t ~ n^b, a least-squares fit over the sizes run. Stage times are
wall-clock seconds ('cpu': the CPU seconds of the whole step, all its threads) of a
machine whose load average is printed: other work on its cores inflates the wall-clock
times (the shares and the CPU times less).

``--solver before after`` runs the direct backend with the solver configuration of
before issue 19's iteration study (qdldl, Clarabel's other defaults, the data as
assembled) and with today's (``clarabel_direct.SETTINGS`` and ``CLEAN_DATA``), in
the same process, alternating ``--repeat`` times (least times kept), and prints the
ratio after / before of the step's CPU time and of the conic solve; ``--solver after
dual`` compares today's primal form with the dual form (``clarabel_direct.FORM``).

Run: python benchmarks/pfem_step.py [--steps 6] [--nx 17 33 65] [--passes 2]
     [--pass-tolerances 0 0.05] [--backends clarabel cvxpy] [--solver before after]
     [--repeat 1] [--json PATH]
"""
import argparse
import json
import os
from pathlib import Path
import sys
import time

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))       # the verification scripts
from verification.granular_column_plane import granular_column      # noqa: E402
from pfem_skfem.drivers.pfem_loop import run                        # noqa: E402
from pfem_skfem.problems import clarabel_direct                     # noqa: E402

STAGES = ("detect", "remesh", "map", "assemble", "compile", "conic", "move", "other")


def time_steps(nx, steps, passes, pass_tolerance, backend):
    """Mean seconds per stage, the step, passes and iterations over steps 2..steps+1."""
    state, scene = granular_column(1.0, nx, passes=passes, backend=backend,
                                   pass_tolerance=pass_tolerance,
                                   dt=0.02 * np.sqrt(1.0 / 9.8))
    state, _ = run(state, scene, 1)
    cpu = []
    for _ in range(steps):                  # CPU seconds of each step (all its threads)
        t0 = time.process_time()
        state, _ = run(state, scene, 1)
        cpu.append(time.process_time() - t0)
    h = {k: np.asarray(v[1:], dtype=float) for k, v in state.history.items()
         if k.startswith("t_") or k in ("seconds", "iterations", "elements", "passes")}
    t = {s: float(h[f"t_{s}"].mean()) for s in STAGES[:-1]}
    total = float(h["seconds"].mean())
    t["other"] = total - sum(t.values())     # compile and conic are parts of the solve
    return dict(nx=nx, backend=backend, pass_tolerance=pass_tolerance,
                elements=int(np.median(h["elements"])), seconds=total,
                cpu=float(np.mean(cpu)), stages=t,
                conic_share=t["conic"] / total,
                solve_share=float(h["t_solve"].mean()) / total,
                passes=float(h["passes"].mean()), iterations=float(h["iterations"].mean()))


# the direct backend's solver configuration: (Clarabel settings, clean the data, form)
SOLVERS = {"before": (dict(direct_solve_method="qdldl"), False, "primal"),
           "after": (dict(clarabel_direct.SETTINGS), clarabel_direct.CLEAN_DATA, "primal"),
           "dual": (dict(clarabel_direct.SETTINGS), clarabel_direct.CLEAN_DATA, "dual")}


def with_solver(name, *args):
    """time_steps(*args) with the direct backend configured as SOLVERS[name]."""
    saved = clarabel_direct.SETTINGS, clarabel_direct.CLEAN_DATA, clarabel_direct.FORM
    (clarabel_direct.SETTINGS, clarabel_direct.CLEAN_DATA,
     clarabel_direct.FORM) = SOLVERS[name]
    try:
        return dict(time_steps(*args), solver=name)
    finally:
        clarabel_direct.SETTINGS, clarabel_direct.CLEAN_DATA, clarabel_direct.FORM = saved


def least(runs):
    """The run with the least CPU time, its stage times the least of each."""
    best = dict(min(runs, key=lambda r: r["cpu"]))
    best["stages"] = {s: min(r["stages"][s] for r in runs) for s in STAGES}
    best["seconds"] = min(r["seconds"] for r in runs)
    return best


def growth(rows, key):
    """b of key ~ elements^b, least squares in log-log (nan with fewer than two sizes)."""
    n = np.array([r["elements"] for r in rows], dtype=float)
    y = np.array([r[key] if key in r else r["stages"][key.split(":")[1]] for r in rows])
    if len(n) < 2:
        return float("nan")
    return float(np.polyfit(np.log(n), np.log(y), 1)[0])


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--steps", type=int, default=6)
    p.add_argument("--nx", type=int, nargs="+", default=[17, 33, 65],
                   help="particles across the column (17: ~500 elements, 33: ~2,000, "
                        "65: ~8,000)")
    p.add_argument("--passes", type=int, default=2)
    p.add_argument("--pass-tolerances", type=float, nargs="+", default=[0.0],
                   help="PFEMConfig.pass_tolerance of the runs (0: every pass, today's)")
    p.add_argument("--backends", nargs="+", choices=("cvxpy", "clarabel"),
                   default=["clarabel"])
    p.add_argument("--solver", nargs="+", choices=tuple(SOLVERS), default=["after"],
                   help="the direct backend's solver configuration (before / after the "
                        "iteration study; dual: after, in the dual form); several: "
                        "alternated in this process")
    p.add_argument("--repeat", type=int, default=1,
                   help="runs of each configuration (least CPU time kept)")
    p.add_argument("--json", type=Path, default=None, help="write the rows here")
    args = p.parse_args(argv)
    if args.steps < 1 or args.passes < 1 or min(args.nx) < 2:
        p.error("--steps and --passes must be >= 1 and --nx >= 2")
    if any(not t >= 0 for t in args.pass_tolerances):
        p.error(f"--pass-tolerances must be >= 0, got {args.pass_tolerances}")
    load = os.getloadavg()
    print(f"load average {load[0]:.2f} / {load[1]:.2f} / {load[2]:.2f} on {os.cpu_count()} "
          f"cores; mean seconds per step over steps 2-{args.steps + 1}, at most "
          f"{args.passes} passes")
    head = (f"{'backend':>8s} {'solver':>6s} {'tol':>6s} {'elements':>8s} {'s/step':>7s} "
            f"{'cpu':>7s} "
            + " ".join(f"{s:>8s}" for s in STAGES)
            + f" {'solve %':>8s} {'conic %':>8s} {'passes':>6s} {'iters':>6s}")
    print(head)
    rows = []
    for nx in args.nx:
        for backend in args.backends:
            for tol in args.pass_tolerances:
                solvers = args.solver if backend == "clarabel" else args.solver[:1]
                runs = {name: [] for name in solvers}
                for _ in range(args.repeat):            # alternated: a load change hits all
                    for name in solvers:
                        runs[name].append(with_solver(name, nx, args.steps, args.passes,
                                                      tol, backend))
                for name in solvers:
                    r = least(runs[name])
                    rows.append(r)
                    print(f"{backend:>8s} {name:>6s} {tol:6g} {r['elements']:8d} "
                          f"{r['seconds']:7.3f} {r['cpu']:7.3f} "
                          + " ".join(f"{r['stages'][s]:8.3f}" for s in STAGES)
                          + f" {r['solve_share']:8.1%} {r['conic_share']:8.1%}"
                          f" {r['passes']:6.2f} {r['iterations']:6.1f}", flush=True)
                if len(solvers) > 1:
                    a, b = least(runs[solvers[-1]]), least(runs[solvers[0]])
                    print(f"{'':8s} {solvers[-1]} / {solvers[0]}: step CPU "
                          f"{a['cpu'] / b['cpu']:.2f}, step wall "
                          f"{a['seconds'] / b['seconds']:.2f}, conic "
                          f"{a['stages']['conic'] / b['stages']['conic']:.2f}, "
                          f"iterations {a['iterations'] / b['iterations']:.2f}", flush=True)
                if args.json is not None:
                    args.json.write_text(json.dumps(rows, indent=1))
    print("\ngrowth with the element count n, t ~ n^b:")
    for backend in args.backends:
        for tol, name in ((t, n) for t in args.pass_tolerances for n in args.solver):
            mine = [r for r in rows if r["backend"] == backend and r["pass_tolerance"] == tol
                    and r["solver"] == name]
            if not mine:
                continue
            print(f"  {backend}, {name}, tol {tol:g}: step b = {growth(mine, 'seconds'):.2f} "
                  f"(CPU "
                  f"{growth(mine, 'cpu'):.2f}), conic b = {growth(mine, 'stage:conic'):.2f}, "
                  "iterations "
                  + " / ".join(f"{r['iterations']:.1f}" for r in mine))


if __name__ == "__main__":
    main()
