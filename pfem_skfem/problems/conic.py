"""Shared conic machinery: solving with Clarabel, status checks and scaling.

Clarabel's tolerances are absolute, so every problem of this package is stated in
scaled variables whose data are near order one (see :class:`Scaling`); the
problem functions convert back to physical units.

Solver statuses. A problem ends 'optimal' (Clarabel's 'Solved') or raises
:class:`SolverError` naming its status, what the status means here
(:data:`STATUS_HINTS`: 'infeasible' is the stress form's, 'unbounded' the
displacement form's, an over-constrained motion) and Clarabel's measures. One rule
decides an 'AlmostSolved' end ('optimal_inaccurate'), whose tolerances Clarabel met
only in their reduced form: it is *certified* by its own measures, the primal and dual
residuals and the duality gap relative to the objective (:func:`clarabel_measures`),
and its answer is accepted with an :class:`AlmostSolvedWarning` stating them when
each is within :data:`CERTIFY`, else raised. No uncertified number is returned
silently, no certified one refused; a Solved solve is untouched. The PFEM loop,
which accepts and counts such ends itself, passes ``accept_inaccurate=True``.
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
        self.measures = None  # Clarabel's measures (MEASURES), when known

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


#: what a non-optimal status means in this package's problems. Every problem here is
#: stated in its stress (static) form, a maximum over stresses and forces; its dual is
#: the displacement (kinematic) form, whose variables are the displacement increments
#: and whose constraints are the prescribed motions. Clarabel and cvxpy name the status
#: of the stated (stress) form: 'infeasible' is the stress form's (no admissible stress
#: field), 'unbounded' the displacement form's infeasibility read from the stress side.
_INFEASIBLE = ("no admissible stress field equilibrates the loads (the stress form is "
               "infeasible; its displacement form, a mechanism, is unbounded): the load "
               "exceeds the collapse load, or a body is unsupported")
_UNBOUNDED = ("the prescribed motions cannot be met: an over-constrained scene, e.g. a "
              "body moving into a closed box, or a live load no admissible mechanism "
              "moves (the displacement form is infeasible, so the stresses of the stress "
              "form grow without bound); check the prescribed motions, the moving bodies "
              "and the supports, or data scaled far from order one (a tiny time step)")
STATUS_HINTS = {
    cp.INFEASIBLE: _INFEASIBLE,
    cp.INFEASIBLE_INACCURATE: "(to reduced tolerances) " + _INFEASIBLE,
    cp.UNBOUNDED: _UNBOUNDED,
    cp.UNBOUNDED_INACCURATE: "(to reduced tolerances) " + _UNBOUNDED,
    cp.OPTIMAL_INACCURATE: "the solver stopped short of its tolerances",
    cp.USER_LIMIT: "the solver reached its iteration or time limit",
}

#: Clarabel's measures of a solve (``DefaultSolver.get_info``): the relative primal and
#: dual residuals, the duality gap relative to the objective and absolute, the ratio
#: kappa/tau (large near an infeasible problem).
MEASURES = ("res_primal", "res_dual", "gap_rel", "gap_abs", "ktratio")

#: An 'AlmostSolved' end (cvxpy's 'optimal_inaccurate') is certified, and its answer
#: accepted with an :class:`AlmostSolvedWarning`, when each of these of its own measures
#: is at most the bound: a tenth of Clarabel's reduced feasibility tolerance (1e-4) and a
#: fifth of its reduced gap (5e-5), still 1000x its full ones (1e-8). The relative gap
#: bounds the objective's relative error (a load factor's, say). Measured on the thick
#: sphere's limit analyses (book/axisymmetry.md, tests/test_certified_solves.py): the 10
#: AlmostSolved ends of 45 solves had residuals <= 7.6e-6 and a gap <= 6.9e-6, their load
#: factors within 4.2e-6 of the closed form, as the Solved ends' (3.6e-7 to 5.7e-6).
CERTIFY = dict(res_primal=1e-5, res_dual=1e-5, gap_rel=1e-5)


class AlmostSolvedWarning(UserWarning):
    """An 'AlmostSolved' answer accepted because its own measures certify it (:data:`CERTIFY`)."""


def clarabel_measures(solver):
    """Clarabel's status and measures (:data:`MEASURES`) of ``solver``'s last solve
    (a dict), or None without a solver."""
    if solver is None or not hasattr(solver, "get_info"):
        return None
    info = solver.get_info()
    return {"status": str(info.status), **{name: float(getattr(info, name)) for name in MEASURES}}


def certified(measures):
    """Whether ``measures`` (:func:`clarabel_measures`) are within :data:`CERTIFY` (None: no)."""
    return measures is not None and all(
        np.isfinite(measures[name]) and measures[name] <= bound
        for name, bound in CERTIFY.items())


def _describe(measures):
    if measures is None:
        return "Clarabel's measures unavailable"
    return (f"primal residual {measures['res_primal']:.1e}, dual residual "
            f"{measures['res_dual']:.1e}, relative gap {measures['gap_rel']:.1e}")


def certify(status, what, measures):
    """The rule for an 'AlmostSolved' end: accept it with an :class:`AlmostSolvedWarning`
    when its ``measures`` are within :data:`CERTIFY`, else raise :class:`SolverError`
    naming the status and the measures; any other non-optimal status raises too."""
    if status == cp.OPTIMAL:
        return
    bounds = ", ".join(f"{name} <= {bound:.0e}" for name, bound in CERTIFY.items())
    if status == cp.OPTIMAL_INACCURATE and certified(measures):
        warnings.warn(f"{what}: Clarabel stopped '{measures['status']}' ('{status}'); accepted, "
                      f"certified by its measures: {_describe(measures)} ({bounds})",
                      AlmostSolvedWarning, stacklevel=3)
        return
    check_status(status, what, measures=measures)


def check_status(status, what, accept_inaccurate=False, measures=None):
    """Raise :class:`SolverError` naming ``status`` unless it is optimal.

    'optimal_inaccurate' is accepted as it is with ``accept_inaccurate=True`` (the
    caller counts it), and otherwise by the rule of :func:`certify`. The message names
    the status, what it means (:data:`STATUS_HINTS`) and Clarabel's ``measures``.
    """
    if status == cp.OPTIMAL or (status == cp.OPTIMAL_INACCURATE and accept_inaccurate):
        return
    if status == cp.OPTIMAL_INACCURATE and certified(measures):
        certify(status, what, measures)
        return
    hint = STATUS_HINTS.get(status, "")
    if status == cp.OPTIMAL_INACCURATE:
        bounds = ", ".join(f"{name} <= {bound:.0e}" for name, bound in CERTIFY.items())
        hint += f"; its measures do not certify the answer ({bounds})"
    if measures is None:
        measured = ""
    elif status in (cp.INFEASIBLE, cp.UNBOUNDED):      # a certificate: no residuals to read
        measured = f" [Clarabel '{measures['status']}']"
    else:
        measured = f" [Clarabel '{measures['status']}': {_describe(measures)}]"
    err = SolverError(f"{what}: solver status '{status}'" + (f": {hint}" if hint else "")
                      + measured, status)
    err.measures = measures
    raise err


def solve(problem, *, what="problem", verbose=False, accept_inaccurate=False,
          defer_certify=False, **settings):
    """Solve a cvxpy problem with Clarabel; raise :class:`SolverError` unless optimal or certified.

    Parameters
    ----------
    problem : cvxpy.Problem
    what : str, a name for the problem used in error messages.
    accept_inaccurate : bool, accept cvxpy's 'optimal_inaccurate' (Clarabel's
        'AlmostSolved') as it is, for a caller that counts it. By default such an end is
        certified by Clarabel's own measures (:func:`certify`): accepted with an
        :class:`AlmostSolvedWarning` when they are within :data:`CERTIFY`, else raised.
    defer_certify : bool, return an 'optimal_inaccurate' end uncertified, for a caller
        that certifies it itself (:func:`certify` with ``info.extra["measures"]``).
    settings : Clarabel settings, overriding :data:`CLARABEL_DEFAULTS`.

    Returns
    -------
    SolveInfo, with Clarabel's measures (:func:`clarabel_measures`) as
    ``extra["measures"]``.
    """
    opts = {**CLARABEL_DEFAULTS, **settings}
    if not accept_inaccurate:
        # Clarabel's 'InsufficientProgress' keeps its last iterate: cvxpy unpacks it as
        # 'optimal_inaccurate', and the iterate is certified by its measures or raised
        opts["accept_unknown"] = True
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
    # cvxpy keeps Clarabel's solver object in the problem's cache (private, hence guarded)
    measures = clarabel_measures(getattr(problem, "_solver_cache", {}).get(cp.CLARABEL))
    check_status(status, what, accept_inaccurate or defer_certify, measures)
    stats = problem.solver_stats
    solve_time = stats.solve_time if stats.solve_time is not None else wall
    return SolveInfo(status=status, iterations=int(stats.num_iters or 0),
                     compile_time=float(problem.compilation_time or 0.0),
                     solve_time=float(solve_time), objective=float(problem.value),
                     extra={} if measures is None else {"measures": measures})


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
