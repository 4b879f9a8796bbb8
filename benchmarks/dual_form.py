"""The dual (displacement) form of a PFEM step's conic problem against the primal (issue 19 item 3).

``pfem_skfem.problems.backends.direct.DirectStep`` states the step (4.23)+(5.12) in
Clarabel's form, min 1/2 x^T P x + c^T x s.t. A x + s = b, s in K (form "primal", the step
solver 'clarabel'), or hands Clarabel its Lagrangian dual (form "dual", 'clarabel-dual',
:func:`~pfem_skfem.problems.backends.dual_form.solve_dual`)

    min 1/2 z^T A_r P_r^-1 A_r^T z + (A_r P_r^-1 c_r + b)^T z
    s.t. A_0^T z = -c_0  (the columns without P: stresses, contact forces),  z_K in K,

with P_r^-1 block-diagonal (each element's 12 x 12 inverse-mass block inverted): the
variables are the displacement increment (z on the equilibrium rows) and the cones'
multipliers. The calls of ``DirectStep.solve(step, criterion, terms, **settings)`` (the
scaled step, :class:`~pfem_skfem.problems.step_scaling.ScaledStep`) of ``--steps`` steps
of the a = 1 column (built as benchmarks/pfem_step.py builds it, solver 'clarabel', every
pass of every step) are captured and each is solved in both forms through
``DirectStep(ENGINES["clarabel"], form).solve`` (the library's settings:
qdldl, 1e-8, clean data); the table gives Clarabel's KKT dimension and nnz of its KKT
matrix and factor (of the last solve), the iterations and CPU seconds of the call
(assembly, the dual's statement and recovery included; the mean over the solves), the
solves that ended 'Solved', and the displacement increment's relative difference
(the dual's against the primal's, the largest).

Run: python benchmarks/dual_form.py [--nx 17 33] [--steps 2] [--repeat 1]
"""
import argparse
import copy
import os
from pathlib import Path
import sys
import time

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))       # the verification scripts
from verification.granular_column_plane import granular_column      # noqa: E402
from pfem_skfem.drivers.pfem_loop import run                        # noqa: E402
import clarabel                                                     # noqa: E402
from pfem_skfem.problems.backends import ENGINES, STEP_SOLVERS, DirectStep   # noqa: E402

#: the direct assembly handed to Clarabel in each form
FORMS = {form: DirectStep(ENGINES["clarabel"], form) for form in ("primal", "dual")}


def capture_calls(nx, steps=2, passes=2):
    """(step, criterion, terms, settings) of every DirectStep.solve call of ``steps`` steps
    of the a = 1 column with ``nx`` particles across (solver 'clarabel'), and the element
    count of the last step."""
    calls, backend = [], STEP_SOLVERS["clarabel"]

    def recording(step, criterion, terms, **settings):
        calls.append(copy.deepcopy((step, criterion, terms, settings)))
        return DirectStep.solve(backend, step, criterion, terms, **settings)

    state, scene = granular_column(1.0, nx, passes=passes, solver="clarabel",
                                   dt=0.02 * np.sqrt(1.0 / 9.8))
    backend.solve = recording                   # this instance only, removed after
    try:
        state, _ = run(state, scene, steps)
    finally:
        del backend.solve
    return calls, int(state.history["elements"][-1])


def solve(call, form, repeat):
    """(KKT dimension, nnz(KKT), nnz(L), iterations, Clarabel's status, least CPU seconds,
    equilibrium dual) of one call in ``form``."""
    step, criterion, terms, settings = call
    original, seen = clarabel.DefaultSolver, []

    class Recording:
        def __init__(self, P, q, A, b, cones, settings):
            self.solver = original(P, q, A, b, cones, settings)
            seen.append((self, P.shape[0] + A.shape[0]))

        def solve(self):
            self.solution = self.solver.solve()
            return self.solution

    cpu = []
    clarabel.DefaultSolver = Recording
    try:
        for _ in range(repeat):
            t0 = time.process_time()
            out = FORMS[form].solve(step, criterion, terms, **settings)
            cpu.append(time.process_time() - t0)
    finally:
        clarabel.DefaultSolver = original
    rec, dim = seen[-1]
    info = rec.solver.get_info().linsolver
    return (dim, int(info.nnzA), int(info.nnzL), out.info.iterations,
            str(rec.solution.status), min(cpu), out.dual_equilibrium)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--nx", type=int, nargs="+", default=[17, 33])
    p.add_argument("--steps", type=int, default=2)
    p.add_argument("--repeat", type=int, default=1, help="timings of each call (least kept)")
    args = p.parse_args(argv)
    load = os.getloadavg()
    print(f"load average {load[0]:.2f} / {load[1]:.2f} / {load[2]:.2f} on {os.cpu_count()} "
          f"cores; every solve of {args.steps} steps of the a = 1 column; CPU seconds")
    head = (f"{'elements':>8s} {'form':>6s} {'KKT dim':>8s} {'nnz(K)':>8s} {'nnz(L)':>8s} "
            f"{'iters':>6s} {'solved':>7s} {'cpu':>7s} {'x primal':>8s} {'du diff':>8s}")
    print(head)
    print("-" * len(head))
    for nx in args.nx:
        calls, elements = capture_calls(nx, args.steps)
        rows = {"primal": [], "dual": []}
        for call in calls:
            for form in rows:                       # alternated: the load falls on both
                rows[form].append(solve(call, form, args.repeat))
        base = np.mean([r[5] for r in rows["primal"]])
        for form, rs in rows.items():
            diff = max(np.linalg.norm(r[6] - q[6]) / np.linalg.norm(q[6])
                       for r, q in zip(rs, rows["primal"]))
            print(f"{elements:8d} {form:>6s} {rs[-1][0]:8d} {rs[-1][1]:8d} {rs[-1][2]:8d} "
                  f"{np.mean([r[3] for r in rs]):6.1f} "
                  f"{sum(r[4] == 'Solved' for r in rs):3d}/{len(rs):<3d} "
                  f"{np.mean([r[5] for r in rs]):7.3f} "
                  f"{np.mean([r[5] for r in rs]) / base:8.2f} {diff:8.1e}", flush=True)
    print("KKT dim, nnz(K), nnz(L): of the last solve (Clarabel's); iterations, CPU: mean over "
          "the solves (CPU: the whole DirectStep.solve call); du diff: the dual's "
          "displacement increment against the primal's, largest")


if __name__ == "__main__":
    main()
