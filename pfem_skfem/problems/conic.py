"""Shared conic machinery: solving with Clarabel, status checks and scaling.

Clarabel's tolerances are absolute, so every problem of this package is stated in
scaled variables whose data are near order one (see :class:`Scaling`); the
problem functions convert back to physical units.
"""
from dataclasses import dataclass, field
import time
import warnings

import cvxpy as cp
import numpy as np

#: Clarabel settings measured on this project's problems (../shared/NOTES.md):
#: qdldl is faster and more robust than the automatic choice here.
CLARABEL_DEFAULTS = dict(direct_solve_method="qdldl")


class SolverError(RuntimeError):
    """The conic solver did not return an optimal solution; ``status`` says why."""

    def __init__(self, message, status):
        super().__init__(message)
        self.status = status
        self.sigma = None  # the near-solution's stresses, when a problem attaches them

    def __reduce__(self):          # picklable, so a worker process can report it
        return (SolverError, (str(self), self.status))


@dataclass
class SolveInfo:
    """What the solver reported: status, iterations and the time split."""

    status: str
    iterations: int
    compile_time: float
    solve_time: float
    objective: float
    extra: dict = field(default_factory=dict)


#: what a non-optimal status means in this package's problems
STATUS_HINTS = {
    cp.INFEASIBLE: "no admissible stress field equilibrates the loads "
                   "(the load exceeds the collapse load, or a body is unsupported)",
    cp.UNBOUNDED: "the objective is unbounded (a mechanism with no resistance: "
                  "check the supports and the yield criterion)",
    cp.OPTIMAL_INACCURATE: "the solver stopped short of its tolerances",
}


def check_status(status, what, accept_inaccurate=False):
    """Raise :class:`SolverError` naming ``status`` unless it is optimal (or accepted inaccurate)."""
    ok = {cp.OPTIMAL} | ({cp.OPTIMAL_INACCURATE} if accept_inaccurate else set())
    if status not in ok:
        hint = STATUS_HINTS.get(status, "")
        raise SolverError(f"{what}: solver status '{status}'" + (f": {hint}" if hint else ""),
                          status)


def solve(problem, *, what="problem", verbose=False, accept_inaccurate=False, **settings):
    """Solve a cvxpy problem with Clarabel; raise :class:`SolverError` unless optimal.

    Parameters
    ----------
    problem : cvxpy.Problem
    what : str, a name for the problem used in error messages.
    accept_inaccurate : bool, accept cvxpy's 'optimal_inaccurate' (Clarabel's
        'AlmostSolved') instead of raising.
    settings : Clarabel settings, overriding :data:`CLARABEL_DEFAULTS`.
    """
    opts = {**CLARABEL_DEFAULTS, **settings}
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings():
            # the status is checked below and reported as a SolverError
            warnings.filterwarnings("ignore", message="Solution may be inaccurate")
            problem.solve(solver=cp.CLARABEL, verbose=verbose, **opts)
    except cp.error.SolverError as err:
        raise SolverError(f"{what}: Clarabel failed ({err})", "solver_error") from err
    wall = time.perf_counter() - t0
    status = problem.status
    check_status(status, what, accept_inaccurate)
    stats = problem.solver_stats
    solve_time = stats.solve_time if stats.solve_time is not None else wall
    return SolveInfo(status=status, iterations=int(stats.num_iters or 0),
                     compile_time=float(problem.compilation_time or 0.0),
                     solve_time=float(solve_time), objective=float(problem.value))


@dataclass(frozen=True)
class Scaling:
    """Reference magnitudes that make a problem's data order one.

    stress : a stress of the problem (the material strength, say);
    length : a length of the problem (typical |B| entry: an element size);
    compliance : a compliance of the problem (typical C diagonal entry:
        integration weight / E).
    """

    stress: float
    length: float
    compliance: float = 1.0

    def __post_init__(self):
        for name in ("stress", "length", "compliance"):
            value = getattr(self, name)
            if not np.isfinite(value) or value <= 0:
                raise ValueError(f"scaling {name} must be positive, got {value!r}")

    @classmethod
    def from_operators(cls, B, C, stress):
        """Take length and compliance as medians of |B| and of diag(C)."""
        length = float(np.median(np.abs(B.data[B.data != 0])))
        compliance = 1.0 if C is None else float(np.median(np.abs(C.diagonal())))
        return cls(stress=float(stress), length=length, compliance=compliance)


def split_dofs(n_dof, fixed, prescribed):
    """Free dofs, and the prescribed dofs in the order given (their values follow it).

    Raises ValueError for dofs out of range, repeated prescribed dofs, or a dof both
    fixed and prescribed.
    """
    fixed = np.unique(np.asarray(fixed, dtype=int))
    prescribed = np.asarray(prescribed, dtype=int).ravel()
    for name, d in (("fixed", fixed), ("prescribed", prescribed)):
        if d.size and (d.min() < 0 or d.max() >= n_dof):
            raise ValueError(f"{name} dofs out of range [0, {n_dof})")
    if np.unique(prescribed).size != prescribed.size:
        raise ValueError("prescribed dofs must not repeat")
    if np.intersect1d(fixed, prescribed).size:
        raise ValueError("a dof is both fixed and prescribed")
    free = np.setdiff1d(np.arange(n_dof), np.concatenate([fixed, prescribed]))
    return free, prescribed


def prescribed_values(prescribed, values):
    """``values`` as floats, one per prescribed dof (from :func:`split_dofs`), or ValueError."""
    values = np.asarray(values, dtype=float)
    if values.shape != np.shape(prescribed):
        raise ValueError("du_prescribed must give one value per prescribed dof")
    return values
