"""The interior point reached through cvxpy, for every problem the package states in cvxpy
(the static step, the limit analyses, the bounds): cvxpy's Clarabel interface prepares the
data in Clarabel's form (P, c, A, b and its cones), and this subclass hands them to
:func:`~pfem_skfem.problems.ipm.solver.solve` instead (cvxpy takes a solver object for
``solver=``), then reads the answer back as Clarabel's.
"""
import time
from types import SimpleNamespace

import scipy.sparse as sp
import cvxpy.settings as cps
from cvxpy.reductions.solvers.conic_solvers.clarabel_conif import (CLARABEL,
                                                                    dims_to_solver_cones)
from cvxpy.reductions.solvers.conic_solvers.conic_solver import ConicSolver

from .solver import DEFAULTS, solve


class IPMCvxpy(CLARABEL):
    """cvxpy's Clarabel interface with the package's interior point behind it."""

    #: the settings it takes (:data:`~pfem_skfem.problems.ipm.solver.DEFAULTS`)
    SETTINGS = frozenset(DEFAULTS)

    def name(self):
        return "PFEM_IPM"

    def import_solver(self):
        import cvxopt.cholmod  # noqa: F401  (the factorisation)

    def solve_via_data(self, data, warm_start, verbose, solver_opts, solver_cache=None):
        settings = {k: v for k, v in solver_opts.items() if k in self.SETTINGS}
        unknown = set(solver_opts) - self.SETTINGS - {"accept_unknown"}
        if unknown:
            raise ValueError(f"the interior point has no setting(s) {sorted(unknown)}; "
                             f"it takes {sorted(self.SETTINGS)}")
        q = data[cps.C]
        P = data[cps.P] if cps.P in data else sp.csc_array((q.size, q.size))
        cones = dims_to_solver_cones(data[ConicSolver.DIMS])
        t0 = time.perf_counter()
        sol = solve(sp.triu(P).tocsc(), q, sp.csc_matrix(data[cps.A]), data[cps.B], cones,
                    {**settings, "verbose": verbose})
        if solver_cache is not None:         # the measures, read by IPMBackend.measures
            solver_cache[self.name()] = sol
        return SimpleNamespace(x=sol.x, z=sol.z, s=sol.s, status=sol.status,
                               iterations=sol.iterations, obj_val=sol.obj_val,
                               solve_time=time.perf_counter() - t0)
