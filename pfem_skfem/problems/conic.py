"""Shared conic machinery: solving with the chosen conic solver, status checks and scaling.

The solver is a choice (:data:`SOLVERS`: 'clarabel', the default, 'qoco', 'mosek' where
licensed, 'scs'): each backend declares the cones it supports, its default settings and
how to read its measures, and a problem whose cones it lacks, or a solver not installed
or not licensed, is refused by name before any work (:func:`solver_backend`).

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
import functools
import time
import warnings

import cvxpy as cp
import numpy as np

#: Clarabel settings measured on this project's problems (../shared/NOTES.md):
#: qdldl is faster and more robust than the automatic choice here.
CLARABEL_DEFAULTS = dict(direct_solve_method="qdldl")

#: QOCO's settings tried in turn after a 'numerical error' (cvxpy's 'solver_error'), its own
#: defaults first: larger static regularisations than its own (1e-8 on A, 1e-13 on P and
#: G), which met a NaN first iterate on some limit analyses; not from the start, which
#: costs accuracy (book, performance appendix, "Choosing the solver").
QOCO_RETRIES = (dict(kkt_static_reg_A=1e-7, kkt_static_reg_P=1e-8, kkt_static_reg_G=1e-8),
                dict(kkt_static_reg_A=1e-6, kkt_static_reg_P=1e-8, kkt_static_reg_G=1e-8))

#: the cone kinds a backend may declare (:attr:`SolverBackend.cones`)
CONE_KINDS = frozenset({"zero", "nonneg", "soc", "exp", "psd", "power"})


class SolverError(RuntimeError):
    """The conic solver did not return an optimal solution; ``status`` says why."""

    def __init__(self, message, status):
        super().__init__(message)
        self.status = status
        self.sigma = None  # the near-solution's stresses, when a problem attaches them
        self.measures = None  # the solver's measures (MEASURES), when known

    def __reduce__(self):          # picklable, so a worker process can report it
        return (SolverError, (str(self), self.status))


class NonFiniteDataError(SolverError, ValueError):
    """The conic data hold NaN or infinity (status ``'NonFiniteData'``): refused before the
    solve. A :class:`SolverError`, so that a run stops on it as on any failed solve (the
    last completed step checkpointed), and a ValueError (the data are wrong, not the
    solver)."""

    def __init__(self, message, status="NonFiniteData"):
        super().__init__(message, status)

    def __reduce__(self):
        return (NonFiniteDataError, (str(self), self.status))


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
#: bounds the objective's relative error (a load factor's, say); the thick sphere's limit
#: analyses are the evidence (book/axisymmetry.md, tests/test_certified_solves.py).
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


def _label(measures):
    """The solver that reported ``measures`` (Clarabel's carry no name)."""
    return "Clarabel" if measures is None else measures.get("solver", "Clarabel")


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
        warnings.warn(f"{what}: {_label(measures)} stopped '{measures['status']}' ('{status}'); "
                      "accepted, "
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
        measured = f" [{_label(measures)} '{measures['status']}']"
    else:
        measured = f" [{_label(measures)} '{measures['status']}': {_describe(measures)}]"
    err = SolverError(f"{what}: solver status '{status}'" + (f": {hint}" if hint else "")
                      + measured, status)
    err.measures = measures
    raise err


def _absolute_measures(name, status, pres, dres, gap, objective):
    """A backend's measures in the keys of :data:`MEASURES` from absolute residuals and
    gap (QOCO's and SCS's, in the data cvxpy hands them: order one here, :class:`Scaling`);
    the gap made relative to max(1, |objective|). Absolute residuals are at least as
    strict as relative ones normalised by max(1, ...), so :data:`CERTIFY` applies as it is."""
    gap = float(gap)
    objective = float(objective) if objective is not None else np.nan
    scale = max(1.0, abs(objective)) if np.isfinite(objective) else 1.0
    return {"solver": name, "status": str(status), "res_primal": float(pres),
            "res_dual": float(dres), "gap_rel": abs(gap) / scale, "gap_abs": abs(gap),
            "ktratio": np.nan}


class SolverBackend:
    """A conic solver reached through cvxpy: its name, cvxpy's constant, the cones it
    supports (:data:`CONE_KINDS`), its default settings, and how to read its measures
    and whether it can run here (:meth:`unavailable`)."""

    name = ""                 # the name a user gives (``solver=``)
    label = ""                # the name in messages
    constant = ""             # cvxpy's solver constant
    module = ""               # the Python module that must import
    cones = frozenset()
    defaults = {}
    retries = ()              # settings tried in turn after a numerical error ('solver_error')

    def measures(self, problem):
        """The solver's measures of ``problem``'s last solve (keys of :data:`MEASURES`,
        ``status`` and ``solver``), or None where it reports none."""
        return None

    def settings(self, settings, accept_inaccurate):
        """The settings passed to cvxpy: the defaults overridden by ``settings``."""
        return {**self.defaults, **settings}

    def unavailable(self):
        """Why the solver cannot run here (a sentence), or None."""
        import importlib.util
        if importlib.util.find_spec(self.module) is None:
            return f"the Python package '{self.module}' is not installed"
        if self.constant not in cp.installed_solvers():
            return f"cvxpy {cp.__version__} does not list it among its installed solvers"
        return None


class ClarabelBackend(SolverBackend):
    """Clarabel (the default): every cone kind but power-ND here; :data:`CLARABEL_DEFAULTS`."""

    name, label, constant, module = "clarabel", "Clarabel", cp.CLARABEL, "clarabel"
    cones = frozenset({"zero", "nonneg", "soc", "exp", "psd", "power"})
    defaults = CLARABEL_DEFAULTS

    def measures(self, problem):
        # cvxpy keeps Clarabel's solver object in the problem's cache (private, hence guarded)
        return clarabel_measures(getattr(problem, "_solver_cache", {}).get(cp.CLARABEL))

    def settings(self, settings, accept_inaccurate):
        opts = {**self.defaults, **settings}
        if not accept_inaccurate:
            # Clarabel's 'InsufficientProgress' keeps its last iterate: cvxpy unpacks it as
            # 'optimal_inaccurate', and the iterate is certified by its measures or raised
            opts["accept_unknown"] = True
        return opts


class QOCOBackend(SolverBackend):
    """QOCO (BSD, PyPI): zero, non-negative and second-order cones, a quadratic objective;
    no exponential, PSD or power cone; its own defaults, then :data:`QOCO_RETRIES` after
    a numerical error. Its measures: absolute residuals and gap."""

    name, label, constant, module = "qoco", "QOCO", "QOCO", "qoco"
    cones = frozenset({"zero", "nonneg", "soc"})
    retries = QOCO_RETRIES

    def measures(self, problem):
        extra = problem.solver_stats.extra_stats if problem.solver_stats else None
        if not extra or "pres" not in extra:
            return None
        return _absolute_measures(self.label, extra.get("status", ""), extra["pres"],
                                  extra["dres"], extra["gap"], problem.value)


class SCSBackend(SolverBackend):
    """SCS (first order, low accuracy: 1e-4 by default): every cone kind; its measures:
    absolute residuals and gap."""

    name, label, constant, module = "scs", "SCS", cp.SCS, "scs"
    cones = frozenset({"zero", "nonneg", "soc", "exp", "psd", "power"})

    def measures(self, problem):
        extra = problem.solver_stats.extra_stats if problem.solver_stats else None
        info = (extra or {}).get("info")
        if not info or "res_pri" not in info:
            return None
        return _absolute_measures(self.label, info.get("status", ""), info["res_pri"],
                                  info["res_dual"], info["gap"], problem.value)


class MOSEKBackend(SolverBackend):
    """MOSEK (commercial): every cone kind, available where ``import mosek`` works and a
    licence is found. cvxpy hands back no measures of an inaccurate end: refused unless
    ``accept_inaccurate``."""

    name, label, constant, module = "mosek", "MOSEK", cp.MOSEK, "mosek"
    cones = frozenset({"zero", "nonneg", "soc", "exp", "psd", "power"})

    def unavailable(self):
        why = super().unavailable()
        return why if why is not None else _mosek_licence_problem()


def _mosek_licence_problem():
    """Why MOSEK's licence cannot be checked out (a sentence), or None; asked once."""
    global _MOSEK_LICENCE
    if _MOSEK_LICENCE is False:
        try:
            import mosek
            with mosek.Env() as env:
                env.checkoutlicense(mosek.feature.pts)
            _MOSEK_LICENCE = None
        except Exception as err:                       # mosek.Error, or no such feature
            _MOSEK_LICENCE = f"no MOSEK licence was found ({err})"
    return _MOSEK_LICENCE


_MOSEK_LICENCE = False        # not asked yet


class IPMBackend(SolverBackend):
    """The package's interior point (:mod:`pfem_skfem.problems.ipm`) behind cvxpy's Clarabel
    interface: zero, non-negative and second-order cones; a problem whose cones or
    quadratic join large sets of variables is refused ('NotStructured'); its measures in
    Clarabel's keys."""

    name, label, module = "ipm", "the interior point", "cvxopt"
    cones = frozenset({"zero", "nonneg", "soc"})

    @property
    def constant(self):
        from .ipm.cvxpy_solver import IPMCvxpy
        return IPMCvxpy()

    def measures(self, problem):
        sol = getattr(problem, "_solver_cache", {}).get("PFEM_IPM")
        return None if sol is None else sol.measures

    def settings(self, settings, accept_inaccurate):
        return dict(settings)

    def unavailable(self):
        import importlib.util
        if importlib.util.find_spec(self.module) is None:
            return "the Python package 'cvxopt' (its CHOLMOD) is not installed"
        return None

#: the solvers a problem may be solved by, by name (``solver=``)
SOLVERS = {b.name: b for b in (ClarabelBackend(), QOCOBackend(), MOSEKBackend(), SCSBackend(),
                               IPMBackend())}


def cone_kinds(problem):
    """The cone kinds (:data:`CONE_KINDS`) of a cvxpy problem, read from its constraints'
    types and the atoms whose cvxpy form needs an exponential or PSD cone; no compile."""
    from cvxpy import atoms
    from cvxpy.constraints import (PSD, SOC, ExpCone, Equality, Inequality, NonNeg,
                                   NonPos, PowCone3D, PowConeND, Zero)
    kinds = set()
    for con in problem.constraints:
        for types, kind in (((Equality, Zero), "zero"), ((Inequality, NonNeg, NonPos), "nonneg"),
                            ((SOC,), "soc"), ((ExpCone,), "exp"), ((PSD,), "psd"),
                            ((PowCone3D, PowConeND), "power")):
            if isinstance(con, types):
                kinds.add(kind)
    exp_atoms = tuple(getattr(atoms, a) for a in (
        "exp", "log", "entr", "log_sum_exp", "logistic", "kl_div", "rel_entr", "log1p")
        if isinstance(getattr(atoms, a, None), type))
    psd_atoms = tuple(getattr(atoms, a) for a in (
        "log_det", "lambda_max", "lambda_min", "lambda_sum_largest", "normNuc",
        "sigma_max", "matrix_frac") if isinstance(getattr(atoms, a, None), type))
    for atom in problem.atoms():
        if issubclass(atom, exp_atoms):
            kinds.add("exp")
        if issubclass(atom, psd_atoms):
            kinds.add("psd")
    return kinds


@functools.lru_cache(maxsize=None)
def _unavailable(name):
    """:meth:`SolverBackend.unavailable` of a backend, asked once a process (about 1 ms)."""
    return SOLVERS[name].unavailable()


def solver_backend(solver, problem=None, cones=None):
    """The backend named ``solver`` (:data:`SOLVERS`), checked before any work: a
    ValueError for an unknown name, or a problem (a cvxpy one, or the cone ``kinds``
    given) with a cone it does not support; a :class:`SolverError` (status
    'unavailable') when it is not installed or not licensed."""
    backend = SOLVERS.get(str(solver).lower()) if isinstance(solver, str) else None
    if backend is None:
        raise ValueError(f"solver must be one of {tuple(SOLVERS)}, got {solver!r}")
    needed = set(cones or ())
    if problem is not None and backend.cones != CONE_KINDS:   # Clarabel's: nothing to check
        needed |= cone_kinds(problem)
    missing = sorted(needed - backend.cones)
    if missing:
        raise ValueError(f"solver {backend.name!r} ({backend.label}) does not support the "
                         f"{', '.join(missing)} cone(s) of this problem; it supports "
                         f"{', '.join(sorted(backend.cones))} (use 'clarabel')")
    why = _unavailable(backend.name)
    if why is not None:
        raise SolverError(f"solver {backend.name!r} ({backend.label}) is not available: "
                          f"{why}", "unavailable")
    return backend


def solve(problem, *, solver="clarabel", what="problem", verbose=False,
          accept_inaccurate=False, defer_certify=False, **settings):
    """Solve a cvxpy problem with the chosen solver; raise :class:`SolverError` unless
    optimal or certified.

    Parameters
    ----------
    problem : cvxpy.Problem
    solver : a name of :data:`SOLVERS`: 'clarabel' (the default; the library's settings
        :data:`CLARABEL_DEFAULTS`), 'qoco' (zero, non-negative and second-order cones),
        'mosek' (where ``import mosek`` works and a licence is found), 'scs'. An unknown
        name, or a problem with a cone the solver lacks (:func:`cone_kinds`), is a
        ValueError, an uninstalled or unlicensed solver a SolverError (status
        'unavailable'), each raised before any work (:func:`solver_backend`).
    what : str, a name for the problem used in error messages.
    accept_inaccurate : bool, accept cvxpy's 'optimal_inaccurate' (Clarabel's
        'AlmostSolved', QOCO's 'solved inaccurate') as it is, for a caller that counts it.
        By default such an end is certified by the solver's own measures (:func:`certify`;
        QOCO's and SCS's absolute residuals and gap, :func:`_absolute_measures`): accepted
        with an :class:`AlmostSolvedWarning` when they are within :data:`CERTIFY`, else
        raised; a solver that reports none (MOSEK through cvxpy) has it raised.
    defer_certify : bool, return an 'optimal_inaccurate' end uncertified, for a caller
        that certifies it itself (:func:`certify` with ``info.extra["measures"]``).
    settings : the solver's settings, overriding its defaults (Clarabel's:
        :data:`CLARABEL_DEFAULTS`; the others': their own). After a numerical error
        (cvxpy's 'solver_error') the backend's ``retries`` (QOCO's :data:`QOCO_RETRIES`) are
        tried in turn, unless ``settings`` name their keys; ``extra["retry"]`` says which
        ended it.

    Returns
    -------
    SolveInfo, with the solver's measures (:func:`clarabel_measures`, or the keys of
    :data:`MEASURES` with ``solver``) as ``extra["measures"]``.
    """
    backend = solver_backend(solver, problem)
    opts = backend.settings(settings, accept_inaccurate)
    retries = [r for r in backend.retries if not set(r) & set(settings)]
    t0 = time.perf_counter()
    for attempt, retry in enumerate([None] + retries):
        if retry is not None:
            # a fresh copy (the same variables and constraints, which take the solution):
            # a retry of the failed problem itself failed where a fresh one did not
            problem = cp.Problem(problem.objective, problem.constraints)
        try:
            with warnings.catch_warnings():
                # the status is checked below and reported as a SolverError
                warnings.filterwarnings("ignore", message="Solution may be inaccurate")
                problem.solve(solver=backend.constant, verbose=verbose,
                              **{**opts, **(retry or {})})
            break
        except cp.error.SolverError as err:
            if attempt == len(retries):
                # cvxpy says only "Solver '...' failed": the solver's own status and
                # measures, where it keeps them (the interior point's 'NumericalError')
                measures = backend.measures(problem)
                measured = "" if measures is None else (
                    f" [{_label(measures)} '{measures['status']}': {_describe(measures)}]")
                failed = SolverError(f"{what}: {backend.label} failed ({err}){measured}",
                                     "solver_error")
                failed.measures = measures
                raise failed from err
    wall = time.perf_counter() - t0
    status = problem.status
    measures = backend.measures(problem)
    if (status == cp.OPTIMAL_INACCURATE and measures is None and backend.name != "clarabel"
            and not (accept_inaccurate or defer_certify)):
        raise SolverError(f"{what}: solver status '{status}': {backend.label} stopped short "
                          "of its tolerances and reports no measures to certify the answer "
                          "by (pass accept_inaccurate=True to take it)", status)
    check_status(status, what, accept_inaccurate or defer_certify, measures)
    stats = problem.solver_stats
    solve_time = stats.solve_time if stats.solve_time is not None else wall
    extra = {} if measures is None else {"measures": measures}
    if retry is not None:        # the settings that ended it, and the time of every try
        extra.update(retry=retry, wall_time=wall)
    return SolveInfo(status=status, iterations=int(stats.num_iters or 0),
                     compile_time=float(problem.compilation_time or 0.0),
                     solve_time=float(solve_time), objective=float(problem.value),
                     extra=extra)


@dataclass(frozen=True)
class Scaling:
    """Reference magnitudes that make a problem's data order one.

    stress : a stress of the problem (the material strength, say);
    length : a length of the problem (typical ``|B|`` entry: an element size);
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
        """Take length and compliance as medians of ``|B|`` and of diag(C)."""
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


def point_multipliers(dual, n):
    """Yield-cone duals as one value per stress point (summed over a criterion's cones).

    Criteria with several cones per point (``n_cones``, cone-major order, e.g. exact
    Mohr-Coulomb in axisymmetry) give n_cones x n duals; one cone gives them as they are.
    """
    dual = np.asarray(dual).ravel()
    return dual if dual.size == n else dual.reshape(-1, n).sum(axis=0)
