"""Time per PFEM step (Ch 2.2) split into its stages, and how it grows with the mesh.

The plane granular column (a = 1, thesis 6.4.3) collapsing, at about 500, 2,000 and
8,000 elements (``--nx`` 17, 33, 65 particles across): ``--steps`` steps after the
first (which has no old mesh to map from), the mean seconds of each stage of
:func:`pfem_skfem.drivers.pfem_loop.pfem_step` (detect, remesh, map, assemble, solve,
move). Within 'solve', 'compile' is building the conic problem (cvxpy's
canonicalisation, or the direct assembly of pfem_skfem.problems.backends.direct) and
'conic' is the conic solver itself; 'other' is what no stage timer covers (the rest of
the solve stage and the step record). Each step solves one problem per fixed-point pass
on the lagged mean stress (``--passes`` at most; with a pass tolerance,
``PFEMConfig.pass_tolerance``, fewer where a pass changed the mean stress by less than
it): passes and interior-point iterations per step are given, with the passes that
ended 'inaccurate' (accepted, counted in the step record) and the statuses of the
steps; and for each backend, solver and tolerance the growth exponent b of the step
time (and of the conic solve) with the element count n, t ~ n^b, a least-squares fit
over the sizes run. 'conic' is the time the solver reports for its solve: QOCO's
setup (its KKT matrix and ordering) is outside it, in 'other' with the rest of the solve
stage (so compare solvers by the step, its CPU time and the solve share). Stage times
are wall-clock seconds ('cpu': the CPU seconds of the whole step, all its threads) of a
machine whose load average is printed: other work on its cores inflates the wall-clock
times (the shares and the CPU times less).

``--solvers clarabel qoco`` runs the same steps with each conic solver
(:data:`pfem_skfem.problems.conic.SOLVERS`). A solver with an engine of the direct
assembly (:data:`pfem_skfem.problems.backends.ENGINES`: Clarabel, QOCO) runs on each of
``--backends`` (the direct assembly 'clarabel', the cvxpy statement 'cvxpy'); another
solves the cvxpy statement only. Each run's (backend, conic solver, form) is one step
solver, ``PFEMConfig.solver`` (:data:`pfem_skfem.problems.backends.STEP_SOLVERS`):
clarabel on 'clarabel' is 'clarabel' (its 'dual' settings 'clarabel-dual'), qoco on
'clarabel' 'qoco' / 'qoco-dual', scs on 'clarabel' 'scs', clarabel on 'cvxpy' 'cvxpy',
qoco on 'cvxpy' 'cvxpy-qoco', mosek 'mosek'. The ratios of every
run to the first (Clarabel's, direct, the first ``--settings``) of the step's CPU time,
its wall time, the conic solve and the iterations are printed at each size.

``--settings`` are configurations of the direct backend: 'before' (Clarabel as before
issue 19's iteration study: qdldl, Clarabel's other defaults, the data as assembled),
'after' (today's: ``backends.direct.SETTINGS`` and ``CLEAN_DATA``, the primal form),
'dual' (today's in the dual form: the step solver '<solver>-dual'), 'noref' and 'dual-noref'
(those with Clarabel's iterative refinement off). QOCO takes the form of each ('before'
and 'noref' are Clarabel's: QOCO runs 'after' and 'dual' only); the cvxpy backend runs
the first.

All the configurations of one size run in the same process, alternating ``--repeat``
times (least times kept), so that a change of load hits them all.

Run: python benchmarks/pfem_step.py [--steps 6] [--nx 17 33 65] [--passes 2]
     [--pass-tolerances 0 0.05] [--backends clarabel cvxpy] [--solvers clarabel qoco]
     [--settings before after] [--repeat 1] [--json PATH]
"""
import argparse
from collections import Counter
import json
import os
from pathlib import Path
import sys
import time

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))       # the verification scripts
from verification.granular_column_plane import granular_column      # noqa: E402
from pfem_skfem.drivers.pfem_loop import run                        # noqa: E402
from pfem_skfem.problems.backends import ENGINES, cvxpy_solver, direct   # noqa: E402
from pfem_skfem.problems.conic import SOLVERS as CONIC_SOLVERS      # noqa: E402

STAGES = ("detect", "remesh", "map", "assemble", "compile", "conic", "move", "other")


def step_solver(backend, solver, form="primal"):
    """The step's solver (``PFEMConfig.solver``) of a run: the conic ``solver`` on
    ``backend`` ('clarabel': the direct assembly in ``form``; 'cvxpy': the statement)."""
    if backend == "cvxpy" or solver not in ENGINES:
        return cvxpy_solver(solver)
    return solver + ("-dual" if form == "dual" else "")


def time_steps(nx, steps, passes, pass_tolerance, backend, solver="clarabel", form="primal"):
    """Mean seconds per stage, the step, passes and iterations over steps 2..steps+1."""
    name = step_solver(backend, solver, form)
    state, scene = granular_column(1.0, nx, passes=passes, pass_tolerance=pass_tolerance,
                                   solver=name, dt=0.02 * np.sqrt(1.0 / 9.8))
    state, _ = run(state, scene, 1)
    cpu = []
    for _ in range(steps):                  # CPU seconds of each step (all its threads)
        t0 = time.process_time()
        state, _ = run(state, scene, 1)
        cpu.append(time.process_time() - t0)
    h = {k: np.asarray(v[1:], dtype=float) for k, v in state.history.items()
         if k.startswith("t_") or k in ("seconds", "iterations", "elements", "passes",
                                        "inaccurate")}
    t = {s: float(h[f"t_{s}"].mean()) for s in STAGES[:-1]}
    total = float(h["seconds"].mean())
    t["other"] = total - sum(t.values())     # compile and conic are parts of the solve
    return dict(nx=nx, backend=backend, solver=solver, step_solver=name,
                pass_tolerance=pass_tolerance,
                elements=int(np.median(h["elements"])), seconds=total,
                cpu=float(np.mean(cpu)), stages=t,
                solve=float(h["t_solve"].mean()), conic_share=t["conic"] / total,
                solve_share=float(h["t_solve"].mean()) / total,
                passes=float(h["passes"].mean()), iterations=float(h["iterations"].mean()),
                inaccurate=int(h["inaccurate"].sum()),
                total_passes=int(h["passes"].sum()),
                statuses=dict(Counter(str(s) for s in state.history["status"][1:])))


# the direct backend's Clarabel configuration: (Clarabel settings, clean the data, form)
NO_REFINEMENT = dict(direct.SETTINGS, iterative_refinement_enable=False)
SETTINGS = {"before": (dict(direct_solve_method="qdldl"), False, "primal"),
            "after": (dict(direct.SETTINGS), direct.CLEAN_DATA, "primal"),
            "dual": (dict(direct.SETTINGS), direct.CLEAN_DATA, "dual"),
            "noref": (NO_REFINEMENT, direct.CLEAN_DATA, "primal"),
            "dual-noref": (NO_REFINEMENT, direct.CLEAN_DATA, "dual")}
#: the configurations that mean something to another engine than Clarabel (the form)
FORM_ONLY = ("after", "dual")


def with_settings(name, *args):
    """time_steps(*args) with the direct backend configured as SETTINGS[name] (its Clarabel
    settings and clean-up: ``backends.direct.SETTINGS``, ``CLEAN_DATA``; its form: the step
    solver's name)."""
    saved = direct.SETTINGS, direct.CLEAN_DATA
    direct.SETTINGS, direct.CLEAN_DATA, form = SETTINGS[name]
    try:
        return dict(time_steps(*args, form=form), settings=name)
    finally:
        direct.SETTINGS, direct.CLEAN_DATA = saved


def configurations(backends, solvers, settings):
    """The (backend, solver, settings) runs of one size and tolerance: a solver with a
    direct engine on each backend (the settings variants on the direct one: all for
    Clarabel, the forms for another), any other once, on cvxpy."""
    runs = []
    for solver in solvers:
        for backend in (backends if solver in ENGINES else ["cvxpy"]):
            names = settings if backend == "clarabel" else settings[:1]
            if solver != "clarabel" and backend == "clarabel":
                names = [name for name in names if name in FORM_ONLY] or ["after"]
            for name in names:
                if (backend, solver, name) not in runs:
                    runs.append((backend, solver, name))
    return runs


def least(runs):
    """The run with the least CPU time, its stage times the least of each."""
    best = dict(min(runs, key=lambda r: r["cpu"]))
    best["stages"] = {s: min(r["stages"][s] for r in runs) for s in STAGES}
    best["seconds"] = min(r["seconds"] for r in runs)
    best["solve"] = min(r["solve"] for r in runs)
    return best


def growth(rows, key):
    """b of key ~ elements^b, least squares in log-log (nan with fewer than two sizes)."""
    n = np.array([r["elements"] for r in rows], dtype=float)
    y = np.array([r[key] if key in r else r["stages"][key.split(":")[1]] for r in rows])
    if len(n) < 2:
        return float("nan")
    return float(np.polyfit(np.log(n), np.log(y), 1)[0])


def ratio_line(a, b):
    """a / b of the step CPU, the step wall time, the solve stage, the conic solve and
    the iterations."""
    return (f"{label(a)} / {label(b)}: step CPU {a['cpu'] / b['cpu']:.2f}, step wall "
            f"{a['seconds'] / b['seconds']:.2f}, solve {a['solve'] / b['solve']:.2f}, conic "
            f"{a['stages']['conic'] / b['stages']['conic']:.2f}, iterations "
            f"{a['iterations'] / b['iterations']:.2f}")


def label(r):
    return f"{r['solver']}-{r['backend']}" + ("" if r["settings"] == "after"
                                              else f"-{r['settings']}")


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
                   default=["clarabel"],
                   help="the backends of a solver with a direct engine (another runs on "
                        "cvxpy)")
    p.add_argument("--solvers", nargs="+", choices=tuple(CONIC_SOLVERS),
                   default=["clarabel"],
                   help="the conic solvers (PFEMConfig.solver); several: alternated in "
                        "this process, the ratios to Clarabel printed")
    p.add_argument("--settings", nargs="+", choices=tuple(SETTINGS), default=["after"],
                   help="the direct backend's configuration (before / after the "
                        "iteration study; dual: after, in the dual form; noref, dual-noref: "
                        "Clarabel's iterative refinement off); several: alternated in "
                        "this process")
    p.add_argument("--repeat", type=int, default=1,
                   help="runs of each configuration (least CPU time kept)")
    p.add_argument("--json", type=Path, default=None, help="write the rows here")
    args = p.parse_args(argv)
    if args.steps < 1 or args.passes < 1 or min(args.nx) < 2:
        p.error("--steps and --passes must be >= 1 and --nx >= 2")
    if any(not t >= 0 for t in args.pass_tolerances):
        p.error(f"--pass-tolerances must be >= 0, got {args.pass_tolerances}")
    if "clarabel" not in args.backends and args.settings != ["after"]:
        p.error("--settings before / dual need the direct backend (--backends clarabel)")
    load = os.getloadavg()
    print(f"load average {load[0]:.2f} / {load[1]:.2f} / {load[2]:.2f} on {os.cpu_count()} "
          f"cores; mean seconds per step over steps 2-{args.steps + 1}, at most "
          f"{args.passes} passes")
    head = (f"{'solver':>8s} {'backend':>8s} {'set':>6s} {'tol':>6s} {'elements':>8s} "
            f"{'s/step':>7s} {'cpu':>7s} "
            + " ".join(f"{s:>8s}" for s in STAGES)
            + f" {'solve %':>8s} {'conic %':>8s} {'passes':>6s} {'iters':>6s} "
              f"{'inacc':>7s}  statuses")
    print(head)
    configs = configurations(args.backends, args.solvers, args.settings)
    rows = []
    for nx in args.nx:
        for tol in args.pass_tolerances:
            runs = {c: [] for c in configs}
            for _ in range(args.repeat):                # alternated: a load change hits all
                for c in configs:
                    backend, solver, name = c
                    runs[c].append(with_settings(name, nx, args.steps, args.passes, tol,
                                                 backend, solver))
            best = {}
            for c in configs:
                r = best[c] = least(runs[c])
                rows.append(r)
                print(f"{r['solver']:>8s} {r['backend']:>8s} {r['settings']:>6s} {tol:6g} "
                      f"{r['elements']:8d} {r['seconds']:7.3f} {r['cpu']:7.3f} "
                      + " ".join(f"{r['stages'][s]:8.3f}" for s in STAGES)
                      + f" {r['solve_share']:8.1%} {r['conic_share']:8.1%}"
                      f" {r['passes']:6.2f} {r['iterations']:6.1f} "
                      f"{r['inaccurate']:3d}/{r['total_passes']:<3d}  "
                      + ", ".join(f"{k} {v}" for k, v in r["statuses"].items()),
                      flush=True)
            for c in configs[1:]:               # every run against the first
                print(f"{'':8s} {ratio_line(best[c], best[configs[0]])}", flush=True)
            if args.json is not None:
                args.json.write_text(json.dumps(rows, indent=1))
    print("\ngrowth with the element count n, t ~ n^b:")
    for tol in args.pass_tolerances:
        for backend, solver, name in configs:
            mine = [r for r in rows if r["backend"] == backend and r["solver"] == solver
                    and r["pass_tolerance"] == tol and r["settings"] == name]
            print(f"  {solver}, {backend}, {name}, tol {tol:g}: step b = "
                  f"{growth(mine, 'seconds'):.2f} (CPU {growth(mine, 'cpu'):.2f}), conic b = "
                  f"{growth(mine, 'stage:conic'):.2f}, iterations "
                  + " / ".join(f"{r['iterations']:.1f}" for r in mine))


if __name__ == "__main__":
    main()
