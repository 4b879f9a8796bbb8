"""How close the interior-point solve of a PFEM step comes to its floor: iterations x one LDL.

The conic data of a step of the plane granular column (a = 1, thesis 6.4.3, built as
benchmarks/pfem_step.py builds it, the step solver 'clarabel': the direct assembly) are
captured as the step hands them to Clarabel (``ENGINES["clarabel"].solve``; the last pass
of the last step run). On them are timed

* the full Clarabel solve with qdldl (setup, equilibration and every iteration), as the
  step runs it;
* one sparse LDL^T factorisation of its KKT matrix [[P + eps I, A^T], [A, -(H + eps I)]]
  (H: a dense block per second-order cone, a diagonal for the other cones: the pattern
  Clarabel factorises; nnz(K) and nnz(L) are printed beside Clarabel's own) by the
  ``qdldl`` package with its approximate-minimum-degree ordering: once with the ordering
  and symbolic analysis ('first') and as a numerical refactorisation on the same pattern
  ('refactor', what an interior-point iteration needs), and, for reference, scipy's
  SuperLU LU (symmetric mode) of the full matrix;

and the table gives the ratio solve / (iterations x refactorisation): the cost of one
iteration in bare factorisations. One solve and one factorisation use one core. The
machine's load average is printed in the header: the timings are noisy when other work
shares the cores, the ratios less so.

With ``--qoco`` the same captured problem is also solved by QOCO (handed Clarabel's data
as the direct assembly hands it, :class:`pfem_skfem.problems.backends.qoco.QOCOEngine`):
its KKT matrix has Clarabel's pattern, so its ratio is to the same refactorisation.

Run: python benchmarks/solve_floor.py [--nx 17 33 65] [--steps 2] [--repeat 3] [--qoco]
     (17: ~500 elements, 33: ~2,000, 65: ~8,000)
"""
import argparse
import os
from pathlib import Path
import re
import sys
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))       # the verification scripts
from verification.granular_column_plane import granular_column      # noqa: E402
from pfem_skfem.drivers.pfem_loop import run                        # noqa: E402
import clarabel                                                     # noqa: E402
from pfem_skfem.problems.backends import ENGINES                    # noqa: E402

REGULARISATION = 1e-8            # Clarabel's static regularisation (its default)


def capture_step(nx, steps=2, passes=2):
    """The conic data (P, c, A, b, cones, settings) of every solve of ``steps`` steps of the
    a = 1 column with ``nx`` particles across (the passes of each step, in order), and the
    element count of the last step."""
    captured = []
    engine = ENGINES["clarabel"]

    def recording(P, c, A, b, cones, settings):
        captured.append(dict(P=P.copy(), c=np.array(c), A=A.copy(), b=np.array(b),
                             cones=list(cones), settings=settings))
        return type(engine).solve(engine, P, c, A, b, cones, settings)

    state, scene = granular_column(1.0, nx, passes=passes, solver="clarabel",
                                   dt=0.02 * np.sqrt(1.0 / 9.8))
    engine.solve = recording                    # this instance only, removed after
    try:
        state, _ = run(state, scene, steps)
    finally:
        del engine.solve
    return captured, int(state.history["elements"][-1])


def cone_dims(cones):
    """[(kind, dim)] of Clarabel cone objects (their repr is 'SecondOrderConeT(3)')."""
    out = []
    for cone in cones:
        kind, dim = re.fullmatch(r"(\w+)\((\d+)\)", repr(cone)).groups()
        out.append((kind, int(dim)))
    return out


def kkt_matrix(P, A, cones, eps=REGULARISATION):
    """The upper triangle of the quasi-definite KKT matrix of Clarabel's linear systems:
    P + eps I over the variables, -(H + eps I) over the constraints, with H the cones'
    scaling blocks (dense m x m per second-order cone, diagonal otherwise) at an interior
    point; the values are representative, the pattern is Clarabel's."""
    blocks = []
    for kind, m in cone_dims(cones):
        if kind == "SecondOrderConeT":
            blocks.append(np.eye(m) + 0.25 * np.ones((m, m)))   # W^T W: dense, SPD
        elif kind == "ZeroConeT":
            blocks.append(sp.csr_matrix((m, m)))
        else:
            blocks.append(sp.identity(m))
    H = sp.block_diag(blocks, format="csc")
    n, m = P.shape[0], A.shape[0]
    P_full = P + sp.triu(P, 1).T
    K = sp.bmat([[P_full + eps * sp.identity(n), A.T],
                 [A, -(H + eps * sp.identity(m))]], format="csc")
    return sp.triu(K, format="csc"), K


class Clock:
    """Wall-clock and CPU seconds of a block (CPU time: this process only, so less
    disturbed by other work on a shared machine; every timed call here is one thread)."""

    def __enter__(self):
        self.wall, self.cpu = time.perf_counter(), time.process_time()
        return self

    def __exit__(self, *exc):
        self.wall = time.perf_counter() - self.wall
        self.cpu = time.process_time() - self.cpu
        return False


def best(clocks):
    """(least wall seconds, least CPU seconds) of several timings."""
    return min(c.wall for c in clocks), min(c.cpu for c in clocks)


def time_solve(problem, repeat):
    """((wall, CPU) seconds of the best fresh solve, iterations, status, Clarabel's
    nnz(KKT) and nnz(L))."""
    clocks = []
    for _ in range(repeat):
        with Clock() as clock:
            solver = clarabel.DefaultSolver(problem["P"], problem["c"], problem["A"],
                                            problem["b"], problem["cones"], problem["settings"])
            sol = solver.solve()
        clocks.append(clock)
    info = solver.get_info().linsolver
    return best(clocks), int(sol.iterations), str(sol.status), int(info.nnzA), int(info.nnzL)


def time_qoco(problem, repeat):
    """((wall, CPU) seconds of the best fresh QOCO solve (setup and iterations), iterations,
    status) of the captured problem (pfem_skfem.problems.backends.qoco.QOCOEngine)."""
    engine, clocks = ENGINES["qoco"], []
    for _ in range(repeat):
        with Clock() as clock:
            sol = engine.solve(problem["P"], problem["c"], problem["A"], problem["b"],
                               problem["cones"], engine.settings({}))
        clocks.append(clock)
    return best(clocks), sol.iterations, sol.status


VARIANTS = {                      # Clarabel settings changed from the step's own
    "no iterative refinement": dict(iterative_refinement_enable=False),
    "explicit zeros dropped": dict(input_sparse_dropzeros=True),
    "no equilibration": dict(equilibrate_enable=False),
    "zeros dropped, no equilibr.": dict(input_sparse_dropzeros=True, equilibrate_enable=False),
    "tolerances 1e-6": dict(tol_gap_abs=1e-6, tol_gap_rel=1e-6, tol_feas=1e-6),
}


def with_settings(problem, **changes):
    """``problem`` with a copy of its Clarabel settings, ``changes`` applied."""
    settings = clarabel.DefaultSettings()
    for name in dir(problem["settings"]):
        if not name.startswith("_") and not callable(getattr(problem["settings"], name)):
            try:
                setattr(settings, name, getattr(problem["settings"], name))
            except (AttributeError, TypeError):
                pass
    for name, value in changes.items():
        setattr(settings, name, value)
    return dict(problem, settings=settings)


def time_ldl(K_upper, repeat):
    """((wall, CPU) of the first factorisation with its ordering, (wall, CPU) of a
    numerical refactorisation, nnz(L))."""
    import qdldl
    first, refactor = [], []
    for _ in range(repeat):
        with Clock() as clock:
            factor = qdldl.Solver(K_upper, upper=True)
        first.append(clock)
        with Clock() as clock:
            factor.update(K_upper, upper=True)
        refactor.append(clock)
    L = factor.factors()[0]
    return best(first), best(refactor), int(L.nnz)


def time_lu(K, repeat):
    """(wall, CPU) seconds of one scipy SuperLU factorisation of the full KKT matrix in its
    symmetric mode: minimum degree on A^T + A, diagonal pivots (a quasi-definite matrix
    needs no pivoting; COLAMD with partial pivoting fills 50x more and is 25x slower here)."""
    clocks = []
    for _ in range(repeat):
        with Clock() as clock:
            spla.splu(K.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                      options=dict(SymmetricMode=True))
        clocks.append(clock)
    return best(clocks)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--nx", type=int, nargs="+", default=[17, 33, 65],
                   help="particles across the column (17: ~500 elements, 33: ~2,000, 65: ~8,000)")
    p.add_argument("--steps", type=int, default=2, help="steps run before the capture")
    p.add_argument("--repeat", type=int, default=3,
                   help="best of this many timings (solves above 2,000 elements: once)")
    p.add_argument("--no-lu", action="store_true", help="skip scipy's LU")
    p.add_argument("--qoco", action="store_true",
                   help="also solve the captured problem with QOCO (backends.ENGINES, its own "
                        "defaults) and give its ratio to the same LDL refactorisation (QOCO's "
                        "KKT matrix has Clarabel's pattern)")
    p.add_argument("--variants", nargs="*", choices=tuple(VARIANTS), default=None,
                   help="also solve every captured problem with these settings of VARIANTS "
                        "(all when none is named): where the time of an iteration goes")
    args = p.parse_args(argv)
    load = os.getloadavg()
    print(f"conic data of the a = 1 column step (last pass of step {args.steps}); "
          f"load average {load[0]:.2f} / {load[1]:.2f} / {load[2]:.2f} on "
          f"{os.cpu_count()} cores")
    head = (f"{'elements':>8s} {'n_x':>6s} {'rows':>6s} {'nnz(K)':>8s} {'nnz(L)':>8s} "
            f"{'Cl nnzL':>8s} {'iters':>5s} {'status':>12s} {'solve':>7s} {'cpu':>7s} "
            f"{'LDL1':>6s} {'LDL':>6s} {'LU':>6s} {'ratio':>6s} {'wall':>6s}")
    print(head)
    print("-" * len(head))
    variants = []
    for nx in args.nx:
        problems, elements = capture_step(nx, args.steps)
        problem = problems[-1]
        n, m = problem["P"].shape[0], problem["A"].shape[0]
        repeat = args.repeat if elements <= 2500 else 1
        solve, iters, status, nnz_kkt, nnz_l_clarabel = time_solve(problem, repeat)
        K_upper, K = kkt_matrix(problem["P"], problem["A"], problem["cones"])
        assert K_upper.nnz == nnz_kkt, "not the pattern Clarabel factorises"
        first, refactor, nnz_l = time_ldl(K_upper, max(args.repeat, 5))
        lu = (np.nan, np.nan) if args.no_lu else time_lu(K, repeat)
        print(f"{elements:8d} {n:6d} {m:6d} {K_upper.nnz:8d} {nnz_l:8d} {nnz_l_clarabel:8d} "
              f"{iters:5d} {status:>12s} {solve[0]:7.3f} {solve[1]:7.3f} {first[1]:6.3f} "
              f"{refactor[1]:6.3f} {lu[1]:6.3f} {solve[1] / (iters * refactor[1]):6.2f} "
              f"{solve[0] / (iters * refactor[0]):6.2f}", flush=True)
        if args.qoco:
            (wall, cpu), q_iters, q_status = time_qoco(problem, repeat)
            print(f"{'':8s} {'QOCO':>6s} {'':6s} {'':8s} {'':8s} {'':8s} {q_iters:5d} "
                  f"{q_status:>12s} {wall:7.3f} {cpu:7.3f} {'':6s} {'':6s} {'':6s} "
                  f"{cpu / (q_iters * refactor[1]):6.2f} {wall / (q_iters * refactor[0]):6.2f}",
                  flush=True)
        if args.variants is not None:
            variants.append((elements, refactor[1], problems))
    print("seconds: solve = Clarabel's setup and iterations (wall, then CPU); LDL1 = qdldl "
          "with its AMD ordering and symbolic analysis, LDL = its numerical refactorisation, "
          "LU = scipy SuperLU (CPU)\nratio = solve / (iterations x LDL) in CPU time, wall: "
          "the same in wall-clock time; nnz(K) is Clarabel's KKT pattern (checked), Cl nnzL "
          "its factor's")
    if variants:
        print_variants(variants, args.variants or list(VARIANTS))


def print_variants(variants, names):
    """Every captured solve (all passes of all steps) with the step's settings and with
    each of VARIANTS: iterations, statuses, CPU seconds and the floor ratio."""
    print("\nsettings variants on every solve of the run (all passes of all steps): mean "
          "iterations, solves 'Solved' / all, mean CPU seconds, ratio to the step's settings")
    head = (f"{'elements':>8s} {'settings':28s} {'nnz(L)':>8s} {'iters':>6s} {'solved':>7s} "
            f"{'cpu s':>7s} {'x step':>7s} {'floor':>6s}")
    print(head)
    print("-" * len(head))
    for elements, refactor, problems in variants:
        base = None
        chosen = {name: VARIANTS[name] for name in names}
        for name, changes in {"the step's": {}, **chosen}.items():
            runs = [time_solve(with_settings(p, **changes), 1) for p in problems]
            iters = np.mean([r[1] for r in runs])
            cpu = np.mean([r[0][1] for r in runs])
            solved = sum(r[2] == "Solved" for r in runs)
            base = cpu if base is None else base
            print(f"{elements:8d} {name:28s} {runs[-1][4]:8d} {iters:6.1f} "
                  f"{solved:3d}/{len(runs):<3d} {cpu:7.3f} {cpu / base:7.2f} "
                  f"{cpu / (iters * refactor):6.2f}", flush=True)


if __name__ == "__main__":
    main()
