"""QOCO as an engine of the direct assembly (BSD, PyPI): zero, non-negative and second-order
cones only (no exponential cone: the mu(I) term is refused by name before any work).

QOCO's form is A_eq x = b_eq, G x + s = h, s in R+^l x SOC(q_1) x ...: Clarabel's rows
reordered zero | non-negative | second-order (:func:`row_order`), G = A and h = b; its duals
y (of the equalities) and z (of the cones) put back in Clarabel's row order, with
Clarabel's sign (the displacement increment of a PFEM step agrees with Clarabel's to solver
tolerance, tests/test_solvers.py). After a numerical error it retries with the larger
static regularisations of :data:`~pfem_skfem.problems.conic.QOCO_RETRIES`, as the cvxpy
route does.
"""
from types import SimpleNamespace

import numpy as np
import scipy.sparse as sp

from ..conic import QOCO_RETRIES, _absolute_measures
from .clarabel import check_finite

#: the Clarabel cones QOCO takes, in its order
SELF_DUAL = ("ZeroConeT", "NonnegativeConeT", "SecondOrderConeT")


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
    cones = frozenset({"zero", "nonneg", "soc"})
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
