"""A PFEM step's conic problems on the GPU (issue 40, item 6): captured on the CPU, solved.

Two halves, so that the expensive CPU work (running the column to a step and a tight
reference solve) happens once, and a machine with a GPU only reads files:

``capture`` (CPU) runs the plane granular column (a = 1, thesis 6.4.3) as
``benchmarks/solve_floor.py``'s ``capture_step`` does (``granular_column(1.0, nx,
passes=2, solver="clarabel", dt=0.02 sqrt(1/9.8))``, the direct Clarabel assembly,
primal form, the data as the step hands them to Clarabel's engine,
``ENGINES["clarabel"].solve``, already cleaned) for ``--steps`` steps, keeps the last
``--keep`` of its conic solves and writes each to ``DIR/nx<nx>_solve<k>.npz``:

* P (upper triangle) and A as CSC arrays (``P_data``, ``P_indices``, ``P_indptr``,
  ``P_shape``; the same for A), ``q`` (Clarabel's c), ``b``;
* the cones as two arrays in row order, ``cone_kinds`` (Clarabel's class names:
  ZeroConeT, NonnegativeConeT, SecondOrderConeT, ExponentialConeT) and ``cone_dims``;
* ``elements`` (of the step), ``nx``, ``n_free`` (the free dofs: the first ``n_free``
  rows are the equilibrium rows, and their duals ``z[:n_free]`` are the displacement
  increment du in the solver's scaling, as ``DirectStep.solve`` returns it as
  ``dual_equilibrium``);
* the reference ``x_ref``, ``z_ref``, ``s_ref``, ``du_ref`` from CPU Clarabel at
  ``--ref-tol`` (1e-10: gap abs / rel and feasibility) with equilibration off (the
  reference of ``/work/shared/PERF.md`` and issue 40: with equilibration on Clarabel
  stalls 'AlmostSolved' at 1e-10), with ``ref_status`` and ``ref_iterations``.

``solve`` (any machine) reads every ``*.npz`` of DIR and solves it with each solver of
``--solvers`` that imports there; one that does not is reported 'not installed', not an
error. It prints one row per file and solver: elements, solver, wall seconds (setup +
solve, best of ``--repeat``), iterations, status, the relative error of x and of du
against the reference (2-norms: ||x - x_ref|| / ||x_ref||, ||du - du_ref|| / ||du_ref||,
PERF.md's measure), and with ``--json FILE`` writes the rows. du is the figure to judge
by: it is unique (the dual objective is strongly convex in it), while x is not unique in
every column (a solver at 1e-8 may sit 1e-2 - 4e-1 from the reference in x, measured at
128 elements, and still agree in du to 1e-7).

Solvers (``--solvers``; every one at ``--tol``, default 1e-8 gap abs / rel / feasibility,
their other settings as shipped):

==============  =============================================================================
clarabel        CPU Clarabel (Python API), the same cones, the library's settings.
clarabel-noeq   the same, equilibration off.
clarabel-dual   ``backends.dual_form.solve_dual`` (the displacement form), same data.
qoco            QOCO, ``qoco.QOCO(algebra="builtin")``; rows reordered zero | nonneg | SOC.
qoco-cuda       QOCO's CUDA backend, ``qoco.QOCO(algebra="cuda")`` (cuDSS).
moreau          moreau on the CPU, ``Settings(device="cpu")``.
moreau-cuda     moreau's CUDA backend, ``Settings(device="cuda")`` (cuDSS inside).
==============  =============================================================================

What exists for a GPU (looked up for this script, issue 40 item 6; none of it could be run
here: no device was lent to the session that wrote it):

* **moreau** (Apache-2.0; Clarabel.rs's algorithm, its NOTICE credits Clarabel.rs):
  ``pip install moreau[cuda]`` (CUDA 12) or ``moreau[cuda13]``; the CUDA wheels
  ``moreau-cuda12`` / ``moreau-cuda13`` 0.4.1 are Linux x86_64 / aarch64, **Python 3.12+
  only** (abi3-py312, ~24-28 MB), "GPU (CUDA 12.2+)"; ``python -m moreau check`` verifies
  an install. API: ``moreau.Solver(P, q, A, b, cones, settings)``, ``.solve()`` ->
  solution (x, z, s), ``solver.info`` (status, iterations, timing), ``solver.device``;
  P the full symmetric matrix; ``moreau.Cones(num_zero_cones, num_nonneg_cones,
  so_cone_dims=[...])`` in that row order; ``moreau.Settings(device="cuda", solver="ipm",
  max_iter, ipm_settings=moreau.IPMSettings(tol_gap_abs, tol_gap_rel, tol_feas, ...))``.
  On CUDA its KKT solver is cuDSS. Sources: https://pypi.org/project/moreau-cuda12/0.4.0/,
  https://github.com/moreau-project/moreau/releases (v0.4.1), https://docs.moreau.so/api/core.html,
  https://docs.moreau.so/guide/solver-settings.html,
  https://docs.moreau.so/guide/device-selection.html.
* **QOCO with CUDA** (BSD-3): ``pip install qoco[cuda]`` (pulls ``qoco-cuda`` 0.2.2, wheels
  cp310-cp314 manylinux_2_28 x86_64); "requires CUDA 13 and cuDSS installed on your system"
  (cuDSS from PyPI: ``nvidia-cudss-cu13``, 65-80 MB a wheel). API: ``qoco.QOCO(algebra="cuda")``,
  ``.setup(n, m, p, P, c, A, b, G, h, l, nsoc, q, **settings)``, ``.solve()`` -> x, y, z,
  status, iters, setup_time_sec, solve_time_sec; ``qoco.algebra_available("cuda")``. Its
  equality dual y has Clarabel's sign (PERF.md: du agrees to 4e-8). Sources:
  https://pypi.org/project/qoco-cuda/, https://github.com/qoco-org/qoco-python/releases/tag/v0.2.1
  ("qoco + cuda backend run fully on the GPU"), the qoco docs' python_interface /
  python_installation pages.
* **CuClarabel** (Clarabel.jl, Julia; Chen, Tse, Nobel, Goulart, Boyd, JuMP-dev 2025):
  ``Clarabel.Settings(direct_solve_method=:cudss)`` on CUDA arrays (CUDSS.jl), from Python
  only through ``juliacall`` (and cupy) with a Julia install and the CuClarabel branch; the
  Rust / Python ``clarabel`` wheel has no GPU (Clarabel.rs issue #129 "Using cuDSS for
  direct sparse solves" is open). Not scripted here: a Julia + CUDA.jl install does not fit
  a 10-minute device run. Sources:
  https://jump.dev/assets/jump-dev-workshops/2025/talk-yuwen-chen.pdf,
  https://github.com/oxfordcontrol/Clarabel.jl/issues/210 and /215,
  https://github.com/oxfordcontrol/Clarabel.rs/issues/129.

Sizes: ``--nx`` particles across; nx 17 / 33 / 65 / 129 / 257 give about 512 / 2,048 /
8,192 / 32,768 / 131,072 elements (8,192 elements: n = 197,138 variables, m = 107,805
rows). CPU time of ``capture`` here (2 steps, ``--keep 1``, one core shared with other
work), measured: nx 9 ~1 s, nx 17 ~3 s (step 2.0 s + reference 0.5 s), nx 33 ~15 s
(11.3 s + 3.1 s); extrapolated with the measured growth (~n^1.25-1.3): nx 65 ~1.5 min,
nx 129 ~8 min, nx 257 ~45 min (each further kept solve adds one reference, ~1/4 of the
capture). File sizes (npz, compressed): 0.54 MB at 512 elements, 2.1 MB at 2,048, so
~8.5 / ~35 / ~140 MB at 8k / 32k / 128k.

Measured here (CPU, the last solve of step 2, ``--tol 1e-8``): du error 7.0e-6 / 1.3e-4
(Clarabel as shipped), 6.7e-8 / 7.3e-8 (equilibration off), 3.6e-8 / 1.1e-6 (QOCO, 'solved
inaccurate' at 2,048) at 512 / 2,048 elements: PERF.md's figures, from the files.

On the GPU machine (``run`` of the device tool). It has no network: whatever is not
there must travel with the working tree (``carry``, 64 MiB: ignored paths). Prepare here,
in an ignored folder (``gpu_data/`` is ignored): the 8k and 32k files (``capture --nx 65 129
--keep 1 --out gpu_data/cap``, ~10 min, ~45 MB) and the wheels that fit (``pip download
--only-binary=:all: --python-version 3.12 --no-deps --dest gpu_data/wheels moreau moreau-cpu
moreau-cuda12 qoco qoco-cuda``: ~35 MB, plus numpy, scipy, clarabel, pydantic if the image
lacks them; moreau's CUDA wheel is for Python 3.12+, and cuDSS /
the CUDA runtime, ``nvidia-cudss-cu12`` / ``-cu13`` 65-80 MB, only if the device image
lacks them). Then one call, ``run(command=..., carry=["gpu_data/cap", "gpu_data/wheels"],
timeout_s=600)``, about 5-8 minutes::

    nvidia-smi -L; python3 --version; ls /usr/local/cuda*/lib64 | grep -i cudss
    python3 -m venv --system-site-packages /tmp/v && /tmp/v/bin/pip install -q --no-index \
        --find-links gpu_data/wheels moreau moreau-cpu moreau-cuda12 qoco qoco-cuda; \
        /tmp/v/bin/python -m moreau check     # the script finds pfem_skfem in the tree
    /tmp/v/bin/python benchmarks/gpu_solve.py solve gpu_data/cap --repeat 2 \
        --solvers moreau-cuda qoco-cuda clarabel qoco moreau --json $OUT/gpu_solve.json

Without carried files, capture the 8k step on the device's CPU first (~1.5 min):
``/tmp/v/bin/python benchmarks/gpu_solve.py capture --nx 65 --keep 1 --out $OUT/cap``, and
solve ``$OUT/cap``. The 128k step (nx 257, ~140 MB, ~45 min to capture) does not fit a
carry or one call; a later session with more device time captures it on the device's CPU.

Run here:  python benchmarks/gpu_solve.py capture --nx 17 33 --out /tmp/gpu_cap
           python benchmarks/gpu_solve.py solve /tmp/gpu_cap --solvers clarabel qoco moreau-cuda
"""
import argparse
import json
from pathlib import Path
import sys
import time

import numpy as np
import scipy.sparse as sp

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))       # the verification scripts
import clarabel                                                     # noqa: E402
from pfem_skfem.problems.backends import ENGINES, STEP_SOLVERS      # noqa: E402
from pfem_skfem.problems.backends.dual_form import solve_dual       # noqa: E402

#: the reference: Clarabel at 1e-10 with equilibration off (PERF.md, issue 40)
REF_TOL = 1e-10
SOLVERS = ("clarabel", "clarabel-noeq", "clarabel-dual", "qoco", "qoco-cuda", "moreau",
           "moreau-cuda")
DEFAULT_SOLVERS = ("clarabel", "qoco", "moreau", "moreau-cuda", "qoco-cuda")


class NotInstalled(Exception):
    """The solver's package (or its GPU backend) is not importable here."""


# -- capture (CPU) ------------------------------------------------------------------------
def capture_step(nx, steps=2, passes=2):
    """Every conic solve of ``steps`` steps of the a = 1 column (solve_floor's capture),
    each with its free-dof count: [dict(P, c, A, b, cones, n_free)], and the elements of
    the last step."""
    from verification.granular_column_plane import granular_column
    from pfem_skfem.drivers.pfem_loop import run
    captured = []
    engine, backend = ENGINES["clarabel"], STEP_SOLVERS["clarabel"]    # primal form
    n_free = []

    def recording(P, c, A, b, cones, settings):
        captured.append(dict(P=P.copy(), c=np.array(c), A=A.copy(), b=np.array(b),
                             cones=list(cones), n_free=n_free[-1] if n_free else None))
        return type(engine).solve(engine, P, c, A, b, cones, settings)

    def stepping(step, criterion, terms, **settings):
        n_free.append(int(np.asarray(step.free).size))
        return type(backend).solve(backend, step, criterion, terms, **settings)

    state, scene = granular_column(1.0, nx, passes=passes, solver="clarabel",
                                   dt=0.02 * np.sqrt(1.0 / 9.8))
    engine.solve, backend.solve = recording, stepping     # these instances only
    try:
        state, _ = run(state, scene, steps)
    finally:
        del engine.solve, backend.solve
    return captured, int(state.history["elements"][-1])


def cone_arrays(cones):
    """(kinds, dims) of Clarabel cone objects, in row order."""
    kinds = np.array([type(c).__name__ for c in cones])
    dims = np.array([c.dim for c in cones], dtype=np.int64)
    return kinds, dims


def make_cones(kinds, dims):
    """Clarabel cone objects of (kinds, dims)."""
    out = []
    for kind, dim in zip(kinds, dims):
        kind = str(kind)
        out.append(clarabel.ExponentialConeT() if kind == "ExponentialConeT"
                   else getattr(clarabel, kind)(int(dim)))
    return out


def clarabel_settings(tol, **changes):
    s = clarabel.DefaultSettings()
    s.verbose = False
    s.tol_gap_abs = s.tol_gap_rel = s.tol_feas = tol
    for key, value in changes.items():
        setattr(s, key, value)
    return s


def reference(prob, tol=REF_TOL):
    """Clarabel at ``tol`` with equilibration off: (x, z, s, status, iterations)."""
    settings = clarabel_settings(tol, equilibrate_enable=False, max_iter=500)
    sol = clarabel.DefaultSolver(prob["P"], prob["q"], prob["A"], prob["b"],
                                 make_cones(prob["cone_kinds"], prob["cone_dims"]),
                                 settings).solve()
    return (np.asarray(sol.x), np.asarray(sol.z), np.asarray(sol.s), str(sol.status),
            int(sol.iterations))


def to_file(path, prob):
    """Write a problem dict (P, A CSC; q, b, cone_kinds, cone_dims, scalars, references)."""
    arrays = {}
    for key, value in prob.items():
        if key in ("P", "A"):
            M = sp.csc_matrix(value)
            arrays.update({f"{key}_data": M.data, f"{key}_indices": M.indices,
                           f"{key}_indptr": M.indptr, f"{key}_shape": np.array(M.shape)})
        else:
            arrays[key] = np.asarray(value)
    np.savez_compressed(path, **arrays)


def from_file(path):
    """The problem dict of :func:`to_file` (P, A as scipy CSC; scalars as Python numbers)."""
    with np.load(path, allow_pickle=False) as f:
        d = {k: f[k] for k in f.files}
    prob = {}
    for key in ("P", "A"):
        prob[key] = sp.csc_matrix((d.pop(f"{key}_data"), d.pop(f"{key}_indices"),
                                   d.pop(f"{key}_indptr")), shape=tuple(d.pop(f"{key}_shape")))
    for key, value in d.items():
        prob[key] = value.item() if value.ndim == 0 and value.dtype.kind in "iufb" else value
    prob["ref_status"] = str(d["ref_status"])
    return prob


def capture(nx, out, steps=2, passes=2, keep=None, ref_tol=REF_TOL, log=print):
    """Capture the solves of ``steps`` steps at ``nx``, keep the last ``keep`` (all with
    None), add the reference and write them to ``out``; returns the paths written."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    captured, elements = capture_step(nx, steps, passes)
    log(f"nx {nx}: {len(captured)} solves captured, {elements} elements, "
        f"{time.perf_counter() - t0:.1f} s")
    kept = captured if keep is None else captured[-keep:]
    first = len(captured) - len(kept)
    paths = []
    for k, c in enumerate(kept, start=first):
        kinds, dims = cone_arrays(c["cones"])
        prob = dict(P=sp.csc_matrix(c["P"]), A=sp.csc_matrix(c["A"]), q=c["c"], b=c["b"],
                    cone_kinds=kinds, cone_dims=dims, elements=elements, nx=nx,
                    n_free=c["n_free"], solve_index=k)
        t1 = time.perf_counter()
        x, z, s, status, its = reference(prob, ref_tol)
        prob.update(x_ref=x, z_ref=z, s_ref=s, du_ref=z[:c["n_free"]], ref_status=status,
                    ref_iterations=its, ref_tol=ref_tol)
        path = out / f"nx{nx}_solve{k}.npz"
        to_file(path, prob)
        paths.append(path)
        log(f"  {path.name}: n {prob['P'].shape[0]}, m {prob['A'].shape[0]}, "
            f"reference {status} in {its} iterations, {time.perf_counter() - t1:.1f} s")
    return paths


# -- the solvers ---------------------------------------------------------------------------
def row_order(kinds, dims):
    """Rows reordered zero | nonnegative | second-order (QOCO's and moreau's order):
    (perm, n_zero, n_nonneg, soc_dims); an exponential cone raises NotImplementedError."""
    start = np.concatenate([[0], np.cumsum(dims)])
    groups = {"ZeroConeT": [], "NonnegativeConeT": [], "SecondOrderConeT": []}
    soc = []
    for i, kind in enumerate(map(str, kinds)):
        if kind not in groups:
            raise NotImplementedError(f"cone {kind}")
        groups[kind].append(np.arange(start[i], start[i + 1]))
        if kind == "SecondOrderConeT":
            soc.append(int(dims[i]))
    parts = [np.concatenate(g) if g else np.zeros(0, dtype=int) for g in groups.values()]
    return (np.concatenate(parts), parts[0].size, parts[1].size, soc)


def _clarabel(prob, tol, **changes):
    solver = clarabel.DefaultSolver(prob["P"], prob["q"], prob["A"], prob["b"],
                                    make_cones(prob["cone_kinds"], prob["cone_dims"]),
                                    clarabel_settings(tol, **changes))
    sol = solver.solve()
    return np.asarray(sol.x), np.asarray(sol.z), str(sol.status), int(sol.iterations)


def _clarabel_dual(prob, tol):
    sol = solve_dual(prob["P"], prob["q"], prob["A"], prob["b"],
                     make_cones(prob["cone_kinds"], prob["cone_dims"]), clarabel_settings(tol))
    return np.asarray(sol.x), np.asarray(sol.z), str(sol.status), int(sol.iterations)


def _qoco(prob, tol, algebra="builtin"):
    try:
        import qoco
    except ImportError as e:
        raise NotInstalled("qoco") from e
    available = getattr(qoco, "algebra_available", None)
    if algebra != "builtin" and (available is None or not available(algebra)):
        raise NotInstalled(f"qoco algebra {algebra!r}")
    perm, n_zero, n_nonneg, soc = row_order(prob["cone_kinds"], prob["cone_dims"])
    A, b = prob["A"].tocsr()[perm], prob["b"][perm]
    n = prob["P"].shape[0]
    Aeq, beq = sp.csc_matrix(A[:n_zero]), b[:n_zero]
    G, h = sp.csc_matrix(A[n_zero:]), b[n_zero:]
    solver = qoco.QOCO(algebra=algebra) if available is not None else qoco.QOCO()
    solver.setup(n, G.shape[0], n_zero, sp.triu(prob["P"], format="csc"), prob["q"],
                 Aeq if n_zero else None, beq if n_zero else None,
                 G if G.shape[0] else None, h if G.shape[0] else None,
                 n_nonneg, len(soc), np.array(soc, dtype=int) if soc else None,
                 verbose=0, abstol=tol, reltol=tol)
    res = solver.solve()
    z = np.empty(perm.size)
    z[perm] = np.concatenate([np.asarray(res.y) if n_zero else np.zeros(0),
                              np.asarray(res.z) if G.shape[0] else np.zeros(0)])
    return np.asarray(res.x), z, str(res.status), int(res.iters)


def _moreau(prob, tol, device="cpu"):
    try:
        import moreau
    except ImportError as e:
        raise NotInstalled("moreau") from e
    perm, n_zero, n_nonneg, soc = row_order(prob["cone_kinds"], prob["cone_dims"])
    P = prob["P"]
    P_full = (P + sp.triu(P, 1).T).tocsr()
    cones = moreau.Cones(num_zero_cones=n_zero, num_nonneg_cones=n_nonneg, so_cone_dims=soc)
    ipm = moreau.IPMSettings(tol_gap_abs=tol, tol_gap_rel=tol, tol_feas=tol)
    try:
        settings = moreau.Settings(device=device, solver="ipm", ipm_settings=ipm)
        solver = moreau.Solver(P_full, prob["q"], prob["A"].tocsr()[perm], prob["b"][perm],
                               cones, settings)
    except (RuntimeError, ValueError, ImportError) as e:
        if device != "cpu":
            raise NotInstalled(f"moreau device {device!r}: {e}") from e
        raise
    if getattr(solver, "device", device) != device:
        raise NotInstalled(f"moreau device {device!r} (got {solver.device!r})")
    sol = solver.solve()
    z = np.empty(perm.size)
    z[perm] = np.asarray(sol.z)
    info = solver.info
    its = getattr(info, "iterations", getattr(info, "iter", -1))
    return np.asarray(sol.x), z, str(getattr(info, "status", "?")), int(its)


def solve_with(name, prob, tol):
    """(x, z, status, iterations) of solver ``name`` on ``prob`` (z in the file's row order)."""
    if name == "clarabel":
        return _clarabel(prob, tol)
    if name == "clarabel-noeq":
        return _clarabel(prob, tol, equilibrate_enable=False)
    if name == "clarabel-dual":
        return _clarabel_dual(prob, tol)
    if name == "qoco":
        return _qoco(prob, tol)
    if name == "qoco-cuda":
        return _qoco(prob, tol, algebra="cuda")
    if name == "moreau":
        return _moreau(prob, tol)
    if name == "moreau-cuda":
        return _moreau(prob, tol, device="cuda")
    raise ValueError(f"unknown solver {name!r}; known: {', '.join(SOLVERS)}")


def rel(a, ref):
    den = np.linalg.norm(ref)
    return float(np.linalg.norm(a - ref) / den) if den else float(np.linalg.norm(a))


def solve_file(path, names, tol=1e-8, repeat=1):
    """The table rows of one file: dict(file, elements, solver, seconds, iterations,
    status, x_err, du_err); a solver not installed has status 'not installed'."""
    prob = from_file(path)
    rows = []
    for name in names:
        row = dict(file=Path(path).name, elements=prob["elements"], solver=name)
        try:
            best = None
            for _ in range(repeat):
                t0 = time.perf_counter()
                x, z, status, its = solve_with(name, prob, tol)
                wall = time.perf_counter() - t0
                best = wall if best is None else min(best, wall)
            du = z[:prob["n_free"]]
            row.update(seconds=best, iterations=its, status=status,
                       x_err=rel(x, prob["x_ref"]), du_err=rel(du, prob["du_ref"]))
        except NotInstalled as e:
            row.update(seconds=None, iterations=None, status="not installed", note=str(e))
        except NotImplementedError as e:
            row.update(seconds=None, iterations=None, status=f"unsupported: {e}")
        except Exception as e:                          # a solver's failure is a row
            row.update(seconds=None, iterations=None, status=f"error: {type(e).__name__}: {e}")
        rows.append(row)
    return rows


def print_table(rows, out=print, header=True):
    if header:
        out(f"{'file':>22s} {'elements':>8s} {'solver':>13s} {'seconds':>8s} {'its':>4s} "
            f"{'status':>20s} {'x err':>8s} {'du err':>8s}")
    for r in rows:
        num = (lambda k, f: format(r[k], f) if r.get(k) is not None else "-")
        out(f"{r['file']:>22s} {r['elements']:8d} {r['solver']:>13s} {num('seconds', '8.3f'):>8s} "
            f"{num('iterations', 'd'):>4s} {r['status'][:20]:>20s} {num('x_err', '8.1e'):>8s} "
            f"{num('du_err', '8.1e'):>8s}")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="command", required=True)
    c = sub.add_parser("capture", help="CPU: capture a step's conic problems to DIR/*.npz")
    c.add_argument("--nx", type=int, nargs="+", default=[65, 129, 257],
                   help="particles across (65 / 129 / 257: ~8k / 32k / 128k elements)")
    c.add_argument("--out", required=True)
    c.add_argument("--steps", type=int, default=2)
    c.add_argument("--passes", type=int, default=2)
    c.add_argument("--keep", type=int, default=None, help="keep the last KEEP solves (all)")
    c.add_argument("--ref-tol", type=float, default=REF_TOL)
    s = sub.add_parser("solve", help="solve every DIR/*.npz with each solver, print a table")
    s.add_argument("dir")
    s.add_argument("--solvers", nargs="+", default=list(DEFAULT_SOLVERS))
    s.add_argument("--tol", type=float, default=1e-8)
    s.add_argument("--repeat", type=int, default=1)
    s.add_argument("--json", default=None)
    args = p.parse_args(argv)
    if args.command == "capture":
        for nx in args.nx:
            capture(nx, args.out, args.steps, args.passes, args.keep, args.ref_tol)
        return 0
    unknown = set(args.solvers) - set(SOLVERS)
    if unknown:
        p.error(f"unknown solvers {sorted(unknown)}; known: {', '.join(SOLVERS)}")
    files = sorted(Path(args.dir).glob("*.npz"),
                   key=lambda f: (from_file_elements(f), f.name))
    if not files:
        p.error(f"no .npz files in {args.dir}")
    rows = []
    print_table([])
    for f in files:
        new = solve_file(f, args.solvers, args.tol, args.repeat)
        print_table(new, out=lambda line: print(line, flush=True), header=False)
        rows += new
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))
    return 0


def from_file_elements(path):
    with np.load(path, allow_pickle=False) as f:
        return int(f["elements"])


if __name__ == "__main__":
    sys.exit(main())
