"""The package's interior point beside Clarabel (and QOCO) on the conic data of PFEM steps.

The data: the direct assembly's standard form of the last solves of the a = 1 plane
column (thesis 6.4.3), captured as ``benchmarks/solve_floor.py`` captures them
(:func:`~benchmarks.solve_floor.capture_step`: 2 steps, 2 passes, the solves of the last
step), at ``--nx`` particles across (17 / 33 / 65 / 129: 512 / 2,048 / 8,192 / 32,768
elements). On each problem, in one process, alternated ``--repeat`` times (the least CPU
time kept, ``time.process_time``: one core), are timed

* Clarabel with the library's settings (qdldl; :data:`~pfem_skfem.problems.conic.CLARABEL_DEFAULTS`),
* the interior point (:mod:`pfem_skfem.problems.ipm`: one CHOLMOD Cholesky of the
  displacement-sized matrix an iteration),
* QOCO at its defaults (``--qoco``),

and the table gives for each: the status, the iterations, CPU seconds, seconds per
iteration, factorisations per iteration (the interior point's count; Clarabel's and
QOCO's: one an iteration plus their refinements' solves), and the du error
||du - du_ref|| / ||du_ref|| against a reference: Clarabel at 1e-10 with equilibration off
(book/performance.md says why), du the equilibrium rows' dual.

Run: python benchmarks/interior_point.py [--nx 17 33 65] [--repeat 2] [--qoco] [--json PATH]
"""
import argparse
import json
from pathlib import Path
import sys
import time

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from benchmarks.solve_floor import capture_step, cone_dims        # noqa: E402
from pfem_skfem.problems.backends import ENGINES                   # noqa: E402
from pfem_skfem.problems.ipm import solve as ipm_solve             # noqa: E402
from pfem_skfem.harness.report import Report                       # noqa: E402

REFERENCE = dict(equilibrate_enable=False, tol_gap_abs=1e-10, tol_gap_rel=1e-10,
                 tol_feas=1e-10, max_iter=400)


def cpu(fn):
    """(result, CPU seconds) of fn()."""
    t = time.process_time()
    out = fn()
    return out, time.process_time() - t


def solvers(with_qoco):
    """name -> fn(problem) answering SimpleNamespace(z, status, iterations[,
    factorisations])."""
    clar, qoco = ENGINES["clarabel"], ENGINES["qoco"]
    out = {"clarabel": lambda p: clar.solve(p["P"], p["c"], p["A"], p["b"], p["cones"],
                                            clar.settings({})),
           "ipm": lambda p: ipm_solve(p["P"], p["c"], p["A"], p["b"], p["cones"])}
    if with_qoco:
        out["qoco"] = lambda p: qoco.solve(p["P"], p["c"], p["A"], p["b"], p["cones"],
                                           qoco.settings({}))
    return out


def measure(nx, repeat, with_qoco):
    """The rows of one size: per captured solve of the last step, per solver."""
    captured, elements = capture_step(nx)
    clar = ENGINES["clarabel"]
    rows = []
    for k, problem in enumerate(captured[-2:]):               # the last step's passes
        n_eq = cone_dims(problem["cones"])[0][1]
        ref = clar.solve(problem["P"], problem["c"], problem["A"], problem["b"],
                         problem["cones"], clar.settings(REFERENCE))
        du_ref = ref.z[:n_eq]
        best = {}
        for _ in range(repeat):
            for name, fn in solvers(with_qoco).items():
                sol, seconds = cpu(lambda: fn(problem))
                if name not in best or seconds < best[name][1]:
                    best[name] = (sol, seconds)
        for name, (sol, seconds) in best.items():
            its = max(int(sol.iterations), 1)
            facts = getattr(sol, "factorisations", None)
            rows.append(dict(elements=elements, solve=k, solver=name, status=sol.status,
                             iterations=int(sol.iterations), cpu=seconds,
                             per_iteration=seconds / its,
                             factorisations=(facts / its) if facts else np.nan,
                             du_error=float(np.linalg.norm(sol.z[:n_eq] - du_ref)
                                            / np.linalg.norm(du_ref)),
                             reference=ref.status))
    return rows


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--nx", type=int, nargs="+", default=[17, 33, 65])
    p.add_argument("--repeat", type=int, default=2)
    p.add_argument("--qoco", action="store_true")
    p.add_argument("--json", type=Path, default=None)
    args = p.parse_args(argv)
    rows = []
    for nx in args.nx:
        rows += measure(nx, args.repeat, args.qoco)
    report = Report("interior_point")
    report.add_table(
        "solves", ["elements", "solve", "solver", "status", "iterations", "CPU s",
                   "s / iteration", "factorisations / iteration", "du error"],
        [[r["elements"], r["solve"], r["solver"], r["status"], r["iterations"], r["cpu"],
          r["per_iteration"], r["factorisations"], r["du_error"]] for r in rows],
        formats={"CPU s": ".3f", "s / iteration": ".4f", "factorisations / iteration": ".2f",
                 "du error": ".1e"},
        title="each solve of the last step (least CPU time of the repeats, one core)")
    ratios = []
    for elements in sorted({r["elements"] for r in rows}):
        for k in sorted({r["solve"] for r in rows}):
            sel = {r["solver"]: r for r in rows
                   if r["elements"] == elements and r["solve"] == k}
            if "ipm" in sel and "clarabel" in sel:
                ratios.append([elements, k, sel["ipm"]["cpu"] / sel["clarabel"]["cpu"],
                               sel["ipm"]["du_error"], sel["clarabel"]["du_error"]])
    report.add_table("ratios", ["elements", "solve", "CPU ipm / Clarabel", "du error ipm",
                                "du error Clarabel"], ratios,
                     formats={"CPU ipm / Clarabel": ".2f", "du error ipm": ".1e",
                              "du error Clarabel": ".1e"},
                     title="the interior point against Clarabel, solve by solve")
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1, default=float))
    return 0


if __name__ == "__main__":
    sys.exit(main())
