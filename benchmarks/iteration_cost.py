"""What a Clarabel iteration costs beyond one factorisation, and the settings that change it.

One question: on the conic data of a PFEM step (the a = 1 column, captured as
``benchmarks/solve_floor.py`` captures them: every solve of ``--steps`` steps, two
passes a step), how does the time of an interior-point iteration split, and which of
Clarabel's settings, or which clean-up of the data, makes it cheaper without changing
the solution?

A Clarabel iteration (Clarabel.rs, ``DirectLDLKKTSolver``; qdldl here):

* updates the cone scalings and writes them, with the static regularisation
  (``static_regularization_constant``, 1e-8), into the KKT matrix (its own copy and
  qdldl's permuted one), and refactors it numerically (the one factorisation);
* solves the KKT system three times: the constant part of the homogeneous embedding,
  the affine (predictor) and the combined (corrector) direction;
* refines every one of the three solves (``iterative_refinement_enable``): residual
  e = b - K x with the unregularised K (one product with K), a correction by one more
  pair of triangular solves, repeated while ||e|| > abstol + reltol ||b|| (1e-12, 1e-13:
  in practice never) and each step still cuts ||e|| by ``iterative_refinement_stop_ratio``
  (5), at most ``iterative_refinement_max_iter`` (10) times;
* the residuals, the step length to the cone boundaries (``max_step_fraction`` 0.99 of
  it) and the termination tests: O(nnz(A)), small.

The header prints the floor pieces of the last captured problem: one numerical
refactorisation, one pair of triangular solves and one product with K (the python
``qdldl`` package, Clarabel's pattern and AMD ordering), so the table's 'floor' (CPU per
iteration / one refactorisation) can be read as 1 (the factorisation) + the KKT update
+ 3 x (1 + refinement steps) x (solve + product).

Per variant: mean iterations over the captured solves, how many ended 'Solved', the mean
CPU seconds of setup (``DefaultSolver(...)``: equilibration, ordering, symbolic
factorisation) and of ``solve()``, the CPU per iteration, 'floor', the time against the
first row (the data as assembled), and the solution's change: the largest over the
solves of ||du - du_0|| / ||du_0|| (du: the dual of the equilibrium rows, the
displacement increment in the solver's scaling) and of the objective's relative change.

Data clean-ups (not settings; what ``problems/backends/direct.py`` does before the call
since this study, ``CLEAN_DATA``; the data are captured here as assembled, without it,
so the first row is the solver as it was and 'A0 + P0' today's): 'A0' drops the stored
zeros of A (the same as ``input_sparse_dropzeros``), 'P0' the entries of P below 1e-12
sqrt(|P_ii P_jj|), a relative rule (round-off of the assembly, ~1e-15 relative; the real
couplings are >= 0.1): invariant under a scaling of the data, so the c = 0 density
invariance stays bit-identical.

Run: python benchmarks/iteration_cost.py [--nx 17 33] [--steps 2] [--repeat 3]
     [--variants NAME ...] [--extra 'label:key=value,key=value[,clean=A0+P0]']
"""
import argparse
import os
from pathlib import Path
import sys

import numpy as np
import scipy.sparse as sp

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from benchmarks.solve_floor import (Clock, capture_step, kkt_matrix,       # noqa: E402
                                    with_settings)
import clarabel                                                           # noqa: E402
from pfem_skfem.problems.backends import direct                           # noqa: E402
from pfem_skfem.problems.backends.standard_form import drop_roundoff      # noqa: E402


# name: (Clarabel settings changed from Clarabel's defaults + qdldl, data clean-ups)
VARIANTS = {
    "as assembled (qdldl, 1e-8)": ({}, ()),
    "refinement off": (dict(iterative_refinement_enable=False), ()),
    "refinement max_iter 3": (dict(iterative_refinement_max_iter=3), ()),
    "refinement max_iter 1": (dict(iterative_refinement_max_iter=1), ()),
    "refinement tol 1e-10": (dict(iterative_refinement_reltol=1e-10,
                                  iterative_refinement_abstol=1e-10), ()),
    "refinement tol 1e-8": (dict(iterative_refinement_reltol=1e-8,
                                 iterative_refinement_abstol=1e-8), ()),
    "refinement stop_ratio 2": (dict(iterative_refinement_stop_ratio=2.0), ()),
    "refinement stop_ratio 50": (dict(iterative_refinement_stop_ratio=50.0), ()),
    "static reg 1e-7": (dict(static_regularization_constant=1e-7), ()),
    "static reg 1e-10": (dict(static_regularization_constant=1e-10), ()),
    "dynamic reg off": (dict(dynamic_regularization_enable=False), ()),
    "max_step_fraction 0.995": (dict(max_step_fraction=0.995), ()),
    "max_step_fraction 0.95": (dict(max_step_fraction=0.95), ()),
    "A zeros dropped (A0)": ({}, ("A0",)),
    "P round-off dropped (P0)": ({}, ("P0",)),
    "A0 + P0 (today's)": ({}, ("A0", "P0")),
}


def drop_zeros(A):
    """A without its stored zeros (a copy)."""
    A = sp.csc_matrix(A, copy=True)
    A.eliminate_zeros()
    return A


def cleaned(problem, clean):
    out = dict(problem)
    if "A0" in clean:
        out["A"] = drop_zeros(problem["A"])
    if "P0" in clean:
        out["P"] = drop_roundoff(problem["P"])
    return out


def solve_once(problem):
    """(setup, solve) CPU seconds of a fresh solve; iterations, status, the equilibrium
    duals, objective, Clarabel's nnz(L)."""
    with Clock() as setup:
        solver = clarabel.DefaultSolver(problem["P"], problem["c"], problem["A"],
                                        problem["b"], problem["cones"], problem["settings"])
    with Clock() as run:
        sol = solver.solve()
    n_eq = int(repr(problem["cones"][0]).split("(")[1].rstrip(")"))
    return dict(setup=setup.cpu, solve=run.cpu, iterations=int(sol.iterations),
                status=str(sol.status), z=np.asarray(sol.z)[:n_eq].copy(),
                objective=float(sol.obj_val), nnz_l=int(solver.get_info().linsolver.nnzL))


def floor_pieces(problem, repeat=5):
    """CPU seconds of one numerical refactorisation of the KKT matrix, one pair of
    triangular solves, one product with the full K (python qdldl, scipy)."""
    import qdldl
    K_upper, K = kkt_matrix(problem["P"], problem["A"], problem["cones"])
    factor = qdldl.Solver(K_upper, upper=True)
    rhs = np.random.default_rng(0).standard_normal(K.shape[0])
    K = K.tocsr()
    refactor, solve, product = [], [], []
    for _ in range(repeat):
        with Clock() as c:
            factor.update(K_upper, upper=True)
        refactor.append(c.cpu)
        with Clock() as c:
            factor.solve(rhs)
        solve.append(c.cpu)
        with Clock() as c:
            K @ rhs
        product.append(c.cpu)
    return min(refactor), min(solve), min(product)


def parse_extra(text):
    """'label:key=value,...' (values bool, int, float; clean=A0+P0) -> (label, (settings,
    clean))."""
    label, _, body = text.partition(":")
    settings, clean = {}, ()
    for item in filter(None, body.split(",")):
        key, value = item.split("=", 1)
        if key == "clean":
            clean = tuple(value.split("+"))
            continue
        if value in ("True", "False"):
            settings[key] = value == "True"
        else:
            settings[key] = float(value) if any(ch in value for ch in ".e") else int(value)
    return label, (settings, clean)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--nx", type=int, nargs="+", default=[17, 33],
                   help="particles across the column (17: ~500 elements, 33: ~2,000, "
                        "65: ~8,000)")
    p.add_argument("--steps", type=int, default=2, help="steps run (every solve captured)")
    p.add_argument("--repeat", type=int, default=3,
                   help="least CPU of this many rounds (each round solves every variant)")
    p.add_argument("--variants", nargs="*", choices=tuple(VARIANTS), default=list(VARIANTS))
    p.add_argument("--extra", nargs="*", default=[],
                   help="more variants, 'label:key=value,...[,clean=A0+P0]'")
    args = p.parse_args(argv)
    variants = {name: VARIANTS[name] for name in args.variants}
    variants.update(parse_extra(e) for e in args.extra)
    base_name = "as assembled (qdldl, 1e-8)"
    variants = {base_name: VARIANTS[base_name], **variants}
    load = os.getloadavg()
    print(f"load average {load[0]:.2f} / {load[1]:.2f} / {load[2]:.2f} on {os.cpu_count()} "
          f"cores; every solve of {args.steps} steps of the a = 1 column (2 passes a step); "
          f"CPU seconds, least of {args.repeat} rounds")
    for nx in args.nx:
        saved, direct.CLEAN_DATA = direct.CLEAN_DATA, False
        try:                                        # the data as assembled
            problems, elements = capture_step(nx, args.steps)
        finally:
            direct.CLEAN_DATA = saved
        refactor, tri, product = floor_pieces(problems[-1])
        print(f"\n{elements} elements, {len(problems)} solves; floor pieces (last solve): "
              f"refactorisation {refactor * 1e3:.2f} ms, triangular solves {tri * 1e3:.2f} ms "
              f"({tri / refactor:.3f} refact.), product with K {product * 1e3:.2f} ms "
              f"({product / refactor:.3f})")
        head = (f"{'variant':28s} {'nnz(L)':>8s} {'iters':>6s} {'solved':>7s} {'setup':>7s} "
                f"{'solve':>7s} {'ms/iter':>8s} {'floor':>6s} {'x step':>7s} {'du chg':>8s} "
                f"{'obj chg':>8s}")
        print(head)
        print("-" * len(head))
        names = list(variants)
        data = {name: [cleaned(with_settings(q, **variants[name][0]), variants[name][1])
                       for q in problems] for name in names}
        rounds = []                    # round-robin: a load change hits every variant alike
        for _ in range(args.repeat):
            rounds.append({name: [solve_once(q) for q in data[name]] for name in names})
        reference = None
        for name in names:
            runs = [dict(r, setup=min(rd[name][i]["setup"] for rd in rounds),
                         solve=min(rd[name][i]["solve"] for rd in rounds))
                    for i, r in enumerate(rounds[0][name])]
            if reference is None:
                reference = runs
            iters = np.mean([r["iterations"] for r in runs])
            setup = np.mean([r["setup"] for r in runs])
            solve = np.mean([r["solve"] for r in runs])
            per_iter = np.mean([r["solve"] / max(r["iterations"], 1) for r in runs])
            du = max(np.linalg.norm(r["z"] - r0["z"]) / np.linalg.norm(r0["z"])
                     for r, r0 in zip(runs, reference))
            obj = max(abs(r["objective"] - r0["objective"]) / abs(r0["objective"])
                      for r, r0 in zip(runs, reference))
            base = np.mean([r["setup"] + r["solve"] for r in reference])
            solved = sum(r["status"] == "Solved" for r in runs)
            print(f"{name:28s} {runs[-1]['nnz_l']:8d} {iters:6.1f} {solved:3d}/{len(runs):<3d} "
                  f"{setup:7.3f} {solve:7.3f} {per_iter * 1e3:8.2f} "
                  f"{per_iter / refactor:6.2f} {(setup + solve) / base:7.2f} {du:8.1e} "
                  f"{obj:8.1e}", flush=True)
    print("\nsetup / solve: mean CPU seconds of DefaultSolver(...) and of solve(); ms/iter: "
          "solve() / iterations; floor: that / one refactorisation (python qdldl); x step: "
          "(setup + solve) against the first row; du chg, obj chg: largest relative "
          "change from the first row over the solves")


if __name__ == "__main__":
    main()
