"""The package's own interior point (:mod:`pfem_skfem.problems.ipm`) as an engine of the
direct assembly: zero, non-negative and second-order cones (the mu(I) term's exponential
cones are refused by name before any work, as QOCO's are); its Newton system reduced to
the displacements and factorised by CHOLMOD once an iteration (book, "How a step is
solved").
"""
from ..conic import SolverError
from ..ipm import DEFAULTS, solve
from ..ipm.structure import NotStructured
from .clarabel import check_finite


class IPMEngine:
    """The interior point on the standard form as given; its settings a dict over
    :data:`~pfem_skfem.problems.ipm.solver.DEFAULTS` (Clarabel's tolerance names)."""

    name = "ipm"
    cones = frozenset({"zero", "nonneg", "soc"})
    defaults = {}
    retries = ()

    def settings(self, changes):
        unknown = set(changes) - set(DEFAULTS)
        if unknown:
            raise ValueError(f"the interior point has no setting(s) {sorted(unknown)}; it "
                             f"takes {sorted(DEFAULTS)}")
        return {**self.defaults, **changes}

    def solve(self, P, c, A, b, cones, settings):
        """SimpleNamespace(x, z, s, status, iterations, obj_val, measures, ...)."""
        check_finite(P, c, A, b)
        try:
            return solve(P, c, A, b, cones, settings)
        except NotStructured as err:
            raise SolverError(f"the interior point cannot reduce this problem: {err} (use "
                              "solver 'clarabel')", "NotStructured") from None
