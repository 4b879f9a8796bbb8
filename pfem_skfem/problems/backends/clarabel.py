"""Clarabel as an engine of the direct assembly: the standard form handed to it as it is.

An engine solves the data of :class:`~pfem_skfem.problems.backends.standard_form.StandardForm`
(or of its dual) and answers in Clarabel's terms (x, z, s, Clarabel's status names, its
measures), so that the step reads every engine's answer alike. It declares the cones it
takes (:data:`~pfem_skfem.problems.conic.CONE_KINDS`), its default settings and its
retries.
"""
from types import SimpleNamespace

import clarabel
import numpy as np

from ..conic import CLARABEL_DEFAULTS, NonFiniteDataError, clarabel_measures

#: Clarabel settings of the direct assembly (over Clarabel's defaults; a caller's
#: ``settings`` override them): the package's (qdldl). Iterative refinement, the
#: regularisations and the step fraction stay Clarabel's: none makes the solve faster
#: without moving the figures (benchmarks/iteration_cost.py, book/performance.md).
SETTINGS = dict(CLARABEL_DEFAULTS)


def check_finite(P, c, A, b):
    """Refuse conic data holding NaN or infinity before any solve
    (:class:`~pfem_skfem.problems.conic.NonFiniteDataError`, a ValueError and a SolverError,
    naming the block, so that a run stops on it as on a failed solve): Clarabel answers
    such data with a 'NumericalError' that names no cause (and the step retries), QOCO in
    the test with no error at all."""
    for name, values in (("P", P.data), ("c", c), ("A", A.data), ("b", b)):
        bad = ~np.isfinite(np.asarray(values, dtype=float))
        if bad.any():
            raise NonFiniteDataError(
                f"the conic problem's {name} holds {int(bad.sum())} non-finite value(s): the "
                "step's data (positions, velocities, stresses) went non-finite before the "
                "solve, or a value of the scene is too large for floating point (a density "
                "or load near 1e300 overflows the step's scaling)")


class ClarabelEngine:
    """Clarabel on the data as given (its settings: ``clarabel.DefaultSettings`` made from
    :data:`~pfem_skfem.problems.conic.CLARABEL_DEFAULTS` and the caller's changes)."""

    name = "clarabel"
    cones = frozenset({"zero", "nonneg", "soc", "exp"})
    defaults = SETTINGS
    retries = ()                   # direct.RETRY (equilibration off) is the step's

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
