"""The solvers of the direct assembly: one class a solver, handed the same standard form.

:mod:`~pfem_skfem.problems.clarabel_direct` writes the dynamic step (4.23)+(5.12) in
Clarabel's standard form

    minimise  1/2 x^T P x + c^T x   subject to  A x + s = b,  s in K

(or its Lagrangian dual in the same form). An engine solves that data and answers in
Clarabel's terms (x, z, s, Clarabel's status names, its measures), so that the step reads
every solver's answer alike:

* :class:`ClarabelEngine`: Clarabel itself (every cone of the step);
* :class:`QOCOEngine`: QOCO (BSD, PyPI), zero, non-negative and second-order cones only
  (no exponential cone: the mu(I) term is refused by name before any work, in
  :func:`~pfem_skfem.problems.conic.solver_backend`). QOCO's form is
  A_eq x = b_eq, G x + s = h, s in R+^l x SOC(q_1) x ...: Clarabel's rows reordered zero |
  non-negative | second-order (:func:`row_order`), G = A and h = b; its duals y (of the
  equalities) and z (of the cones) put back in Clarabel's row order, with Clarabel's sign
  (measured: the displacement increment of a PFEM step agrees with Clarabel's to
  solver tolerance, tests/test_solvers.py). After a numerical error it retries with the
  larger static regularisations of :data:`~pfem_skfem.problems.conic.QOCO_RETRIES`, as
  the cvxpy route does.
"""
from types import SimpleNamespace

import clarabel
import numpy as np
import scipy.sparse as sp

from .conic import CLARABEL_DEFAULTS, QOCO_RETRIES, _absolute_measures, clarabel_measures

#: the cones of Clarabel's standard form the direct assembly writes
SELF_DUAL = ("ZeroConeT", "NonnegativeConeT", "SecondOrderConeT")


def check_finite(P, c, A, b):
    """Refuse conic data holding NaN or infinity (ValueError naming the block) before any
    solve: Clarabel answers such data with a 'NumericalError' that names no cause (and
    the step retries), QOCO in the test with no error at all."""
    for name, values in (("P", P.data), ("c", c), ("A", A.data), ("b", b)):
        bad = ~np.isfinite(np.asarray(values, dtype=float))
        if bad.any():
            raise ValueError(f"the conic problem's {name} holds {int(bad.sum())} non-finite "
                             f"value(s): the step's data (positions, velocities, stresses) "
                             f"went non-finite before the solve")


class ClarabelEngine:
    """Clarabel on the data as given (its settings: ``clarabel.DefaultSettings`` made from
    :data:`~pfem_skfem.problems.conic.CLARABEL_DEFAULTS` and the caller's changes)."""

    name = "clarabel"
    cones = SELF_DUAL + ("ExponentialConeT",)
    defaults = CLARABEL_DEFAULTS
    retries = ()                   # clarabel_direct.RETRY (equilibration off) is the step's

    def settings(self, changes):
        opts = clarabel.DefaultSettings()
        opts.verbose = False
        for key, value in {**self.defaults, **changes}.items():
            setattr(opts, key, value)
        return opts

    def solve(self, P, c, A, b, cones, settings):
        """SimpleNamespace(x, z, s, status, iterations, obj_val, measures) of one solve."""
        check_finite(P, c, A, b)
        solver = clarabel.DefaultSolver(P, c, A, b, cones, settings)
        sol = solver.solve()
        return SimpleNamespace(x=np.asarray(sol.x), z=np.asarray(sol.z), s=np.asarray(sol.s),
                               status=str(sol.status), iterations=int(sol.iterations),
                               obj_val=float(sol.obj_val), measures=clarabel_measures(solver))


#: QOCO's status names read as Clarabel's
QOCO_STATUS = {"QOCO_SOLVED": "Solved", "QOCO_SOLVED_INACCURATE": "AlmostSolved",
               "QOCO_NUMERICAL_ERROR": "NumericalError", "QOCO_MAX_ITER": "MaxIterations",
               "QOCO_UNSOLVED": "Unsolved"}


def row_order(cones):
    """(perm, n_zero, n_nonneg, soc_dims): the rows of ``cones`` (Clarabel's) reordered
    zero | non-negative | second-order, QOCO's order; another cone raises ValueError."""
    groups = {kind: [] for kind in SELF_DUAL}
    soc, start = [], 0
    for cone in cones:
        kind = type(cone).__name__
        if kind not in groups:
            raise ValueError(f"QOCO takes zero, non-negative and second-order cones, not {kind}")
        groups[kind].append(np.arange(start, start + cone.dim))
        if kind == "SecondOrderConeT":
            soc.append(int(cone.dim))
        start += cone.dim
    parts = [np.concatenate(g) if g else np.zeros(0, dtype=int) for g in groups.values()]
    return np.concatenate(parts), parts[0].size, parts[1].size, soc


class QOCOEngine:
    """QOCO on Clarabel's data, rows reordered (module docstring); its settings a dict
    (``abstol``, ``reltol``, ``max_iters``, ``kkt_static_reg_*``, ...) over QOCO's
    defaults; its measures absolute (``conic._absolute_measures``)."""

    name = "qoco"
    cones = SELF_DUAL
    defaults = {}
    retries = QOCO_RETRIES

    def settings(self, changes):
        return {**self.defaults, **changes}

    def solve(self, P, c, A, b, cones, settings):
        import qoco
        check_finite(P, c, A, b)
        perm, n_zero, n_nonneg, soc = row_order(cones)
        A = sp.csr_matrix(A)[perm]
        b = np.asarray(b, dtype=float)[perm]
        n = P.shape[0]
        Aeq, beq = sp.csc_matrix(A[:n_zero]), b[:n_zero]
        G, h = sp.csc_matrix(A[n_zero:]), b[n_zero:]
        iterations = 0
        for attempt in ({},) + tuple(self.retries):
            solver = qoco.QOCO()
            solver.setup(n, G.shape[0], n_zero, sp.triu(P, format="csc"),
                         np.asarray(c, dtype=float), Aeq if n_zero else None,
                         beq if n_zero else None, G if G.shape[0] else None,
                         h if G.shape[0] else None, n_nonneg, len(soc),
                         np.array(soc, dtype=int) if soc else None,
                         **{"verbose": 0, **settings, **attempt})
            res = solver.solve()
            iterations += int(res.iters)
            status = QOCO_STATUS.get(str(res.status), str(res.status))
            if status != "NumericalError":
                break
        z = np.empty(perm.size)
        z[perm] = np.concatenate([np.asarray(res.y) if n_zero else np.zeros(0),
                                  np.asarray(res.z) if G.shape[0] else np.zeros(0)])
        s = np.zeros(perm.size)
        s[perm[n_zero:]] = np.asarray(res.s) if G.shape[0] else np.zeros(0)
        return SimpleNamespace(
            x=np.asarray(res.x), z=z, s=s, status=status, iterations=iterations,
            obj_val=float(res.obj),
            measures=_absolute_measures("QOCO", res.status, res.pres, res.dres, res.gap,
                                        res.obj))


#: the direct assembly's solvers by name (a solver of conic.SOLVERS not here is reached
#: through the cvxpy statement)
ENGINES = {engine.name: engine for engine in (ClarabelEngine(), QOCOEngine())}
