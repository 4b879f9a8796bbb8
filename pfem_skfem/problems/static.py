"""Static problems: the incremental elastoplastic SOCP (3.45) and limit analysis.

Both are stated in cvxpy almost as printed, in scaled variables (see
:class:`~pfem_skfem.problems.conic.Scaling`): stresses in units of the material
strength, lengths in units of an element size. Displacement increments come back
as the duals of the equilibrium constraints. An 'AlmostSolved' end is returned only
when its own measures certify it (:func:`~pfem_skfem.problems.conic.certify`).

Sign convention, settled by the KKT conditions (3.47) and the tests: with the
Lagrangian J = -1/2 ds^T C ds + du^T (B^T s - f) of (3.46), cvxpy's dual y of the
equality in a maximisation is -du.

The increment (3.45) is equilibrium and the yield cones; its optional parts are the terms of
:mod:`~pfem_skfem.problems.step_terms`, the objects the dynamic step (4.23) adds, in this
order: the compliance when C is given (:class:`~pfem_skfem.problems.step_terms.Compliance`),
the caller's (contacts (5.12), :class:`~pfem_skfem.problems.step_terms.Contact`; springs,
:class:`~pfem_skfem.problems.step_terms.ElasticSupport`), and the work of the reactions on
the prescribed dofs (:class:`~pfem_skfem.problems.step_terms.PrescribedWork`). Each writes
its part of the cvxpy statement (:class:`StaticStatement`) in the scaled units of
:class:`StaticStep`, the names of the dynamic step's; a term that needs a time step (a rate
stress) says so (``StepTerm.static``) and is refused.
"""
from dataclasses import dataclass, field

import cvxpy as cp
import numpy as np

from .conic import (Scaling, SolveInfo, SolverError, certify, point_multipliers,
                    prescribed_values, solve, solver_backend, split_dofs)
from .step_scaling import ScaledSolution, StepUnits
from .step_terms import Compliance, Contact, PrescribedWork


@dataclass
class StaticIncrement:
    """Solution of one increment of (3.45).

    sigma : (n_points, 4) stresses at t_{n+1};
    p, q : (nc,) normal and tangential contact forces (empty without contacts);
    du : (n_u,) displacement increments (prescribed values on prescribed dofs);
    reactions : (n_u,) B^T sigma - f, the support reactions (zero on free dofs);
    plastic_multiplier : (n_points,) integrated plastic multipliers (area x strain;
        divide by the stress-point weights for a value per unit volume; summed over
        the cones of a criterion with several cones per point);
    info : solver report;
    parts : what other terms of the increment return, by name (``spring_forces``, ...).
    """

    sigma: np.ndarray
    du: np.ndarray
    reactions: np.ndarray
    plastic_multiplier: np.ndarray
    info: SolveInfo
    p: np.ndarray = None
    q: np.ndarray = None
    parts: dict = field(default_factory=dict)


@dataclass
class StaticStep(StepUnits):
    """The scaled data of one increment of (3.45), in the names its terms read in the dynamic
    step's :class:`~pfem_skfem.problems.step_scaling.ScaledStep`.

    Bh (4n, n_u) : B / length;  f_h : f / force;  s_n : sigma_n / stress (4n,);
    free, P : the free and the prescribed dofs;  u_P : the prescribed increments / u_ref;
    Ch : C / compliance (CSR; None: rigid-plastic);  stress, length, u_ref : the units.
    The objective is measured in force x u_ref, in which 1/2 ds^T C ds weighs one
    (``kappa_C``: u_ref is the yield strain x length), and equilibrium holds at t_{n+1}
    (``theta1`` one).
    """

    Bh: object
    f_h: np.ndarray
    s_n: np.ndarray
    free: np.ndarray
    P: np.ndarray
    u_P: np.ndarray
    stress: float
    length: float
    u_ref: float
    Ch: object = None
    kappa_C = 1.0
    theta1 = 1.0


class StaticStatement:
    """What the terms of (3.45) write on, as on the dynamic step's ``CvxpyStatement``: the
    scaled step ``step``, the stresses ``S`` (n, 4) and ``s`` (their vector, point-major), the
    objective, the constraints and ``internal``, the internal forces B^T sigma (n_u,) that a
    term adds its forces to."""

    def __init__(self, step):
        self.step = step
        self.S = cp.Variable((step.n, 4))            # sigma_{n+1} / stress, one row per point
        self.s = cp.vec(self.S, order="C")           # point-major as (3.28)
        self.stress = self.s
        self.objective = 0
        self.constraints = []
        self.internal = step.Bh.T @ self.s           # B^T sigma


def static_increment(B, C, f, sigma_n, criterion, *, fixed, prescribed=((), ()),
                     contacts=None, terms=(), scaling=None, solver="clarabel",
                     **solver_settings):
    """Solve the incremental elastoplastic static problem (3.45).

    .. math::
        \\max_{\\sigma}\\; -\\tfrac12 \\Delta\\sigma^T C \\Delta\\sigma
          + \\Delta\\bar u_P^T (B_P^T \\sigma - f_P)
        \\quad \\text{s.t.}\\quad B_F^T \\sigma = f_F,\\quad F(\\sigma_j) \\le 0

    with Delta sigma = sigma - sigma_n, F the free dofs and P the dofs with a
    prescribed increment (the last objective term is the work of their
    reactions; it vanishes for load control). With ``C=None`` the material is
    rigid-plastic and the problem is the displacement-controlled limit analysis
    (maximise the power of the reactions on the prescribed velocity).

    With ``contacts`` (a :class:`~pfem_skfem.problems.contact.ContactSet`) the
    rigid frictional boundaries of (5.12) join: equilibrium gains the contact
    forces G (p, q), the objective the term - sum g0_j p_j, and ``|q_j| <= mu_j p_j``
    (the term :class:`~pfem_skfem.problems.step_terms.Contact`). Other ``terms`` of
    :mod:`~pfem_skfem.problems.step_terms` follow it (module docstring).

    Parameters
    ----------
    B : (4 n_points, n_u) sparse, (3.41).  C : (4 n_points,)^2 sparse (3.43) or None.
    f : (n_u,) external forces at t_{n+1} (3.42).  sigma_n : (n_points, 4) stresses at t_n.
    criterion : a :class:`~pfem_skfem.materials.YieldCriterion`.
    fixed : dofs with zero increment.  prescribed : (dofs, increments): the dofs with a
        prescribed increment and its values.
    contacts : a ContactSet or None.  terms : further terms (``StepTerm.static``), stated
        after the contacts.
    scaling : :class:`Scaling`; by default the criterion's strength and medians of B, C.
    solver : the conic solver (:data:`~pfem_skfem.problems.conic.SOLVERS`; 'clarabel').
    solver_settings : the solver's settings, and ``accept_inaccurate``
        (:func:`~pfem_skfem.problems.conic.solve`).

    Returns
    -------
    StaticIncrement

    Warns
    -----
    AlmostSolvedWarning
        Clarabel stopped 'AlmostSolved' (after the rescaled re-solve, where one applies)
        and its measures certify the answer (:func:`~pfem_skfem.problems.conic.certify`);
        uncertified, SolverError is raised.
    """
    solver_backend(solver)                 # an unknown or unavailable solver: refused now
    n_s, n_u = B.shape
    n = n_s // 4
    sigma_n = np.asarray(sigma_n, dtype=float).reshape(n, 4)
    f = np.asarray(f, dtype=float)
    free, P = split_dofs(n_u, fixed, prescribed[0])
    du_P = prescribed_values(P, prescribed[1])
    terms = static_terms(B, C, criterion, P, contacts, terms)
    closing = 0.0 if contacts is None else max(0.0, -float(np.min(contacts.gap)))
    if C is None and not np.any(du_P) and closing == 0:
        raise ValueError("a rigid-plastic increment needs a non-zero prescribed motion "
                         "(of dofs or of a rigid body); use limit_analysis for load control")
    # stresses in units of the strength, or of the stresses reached so far if larger
    sc = scaling or Scaling.from_operators(
        B, C, max(criterion.strength_scale(), float(np.sqrt(np.mean(sigma_n ** 2)))))
    accept = solver_settings.get("accept_inaccurate", False)
    solver_settings = dict(solver_settings, solver=solver)
    supports = (free, P, du_P)
    res = _static_increment(B, C, f, sigma_n, criterion, supports, terms, closing, sc,
                            solver_settings)
    if res.info.status == cp.OPTIMAL_INACCURATE and scaling is None:
        # Frictional materials can carry stresses far above their cohesion, and the
        # solver's absolute tolerances then stop it short ('AlmostSolved'). Rescale
        # by the stress level of that near-solution and solve once more.
        level = float(np.sqrt(np.mean(res.sigma ** 2)))
        if np.isfinite(level) and level > sc.stress:
            sc = Scaling(stress=level, length=sc.length, compliance=sc.compliance)
            res = _static_increment(B, C, f, sigma_n, criterion, supports, terms, closing,
                                    sc, solver_settings)
    if not accept:          # an AlmostSolved end: certified by its measures, or raised
        try:
            certify(res.info.status, "static increment (3.45)", res.info.extra.get("measures"))
        except SolverError as err:
            err.sigma = res.sigma                    # the near-solution, for a caller's look
            raise
    return res


def static_terms(B, C, criterion, P, contacts=None, terms=()):
    """The terms of one increment of (3.45), in the order they are stated: the compliance
    (C given), the contacts, the caller's ``terms``, the work of the prescribed dofs ``P``;
    a term the static step cannot state, or whose data do not fit B and C, refused."""
    terms = (((Compliance(),) if C is not None else ())
             + ((Contact(contacts),) if contacts is not None else ()) + tuple(terms)
             + ((PrescribedWork(),) if np.size(P) else ()))
    ops = StaticOperators(B, C)
    for term in terms:
        if not term.static:
            raise ValueError(f"{term.name}: a term of the dynamic step only (it needs a time "
                             "step); the static increment (3.45) cannot state it")
        term.check(ops, criterion)
    return terms


@dataclass(frozen=True)
class StaticOperators:
    """The operators a term checks its data against (``StepTerm.check``): B and C (or None)."""

    B: object
    C: object = None


def _static_increment(B, C, f, sigma_n, criterion, supports, terms, closing, sc,
                      solver_settings):
    """(3.45) in the scaled variables of ``sc``, ``supports`` the free dofs, the prescribed
    ones and their increments, ``terms`` from :func:`static_terms`; see
    :func:`static_increment`.

    .. math::
        \\max_{s}\\; \\text{terms}(s) \\quad \\text{s.t.}\\quad
        \\hat B_F^T s + \\text{terms' forces}_F = \\hat f_F,\\quad F(s_j) \\le 0
    """
    free, P, du_P = supports
    n_u = B.shape[1]
    # reference displacement: yield strain x element size, or the prescribed motion
    u_ref = (sc.stress * sc.compliance / sc.length if C is not None
             else max(np.abs(du_P).max(initial=0.0), closing))
    step = StaticStep(Bh=(B / sc.length).tocsc(), f_h=f / (sc.stress * sc.length),
                      s_n=sigma_n.ravel() / sc.stress, free=free, P=P, u_P=du_P / u_ref,
                      stress=sc.stress, length=sc.length, u_ref=u_ref,
                      Ch=None if C is None else (C / sc.compliance).tocsr())
    st = StaticStatement(step)
    for term in terms:                        # compliance, contacts, ..., prescribed work
        term.cvxpy(st)
    equilibrium = st.internal[free] == step.f_h[free]     # B^T sigma (- G (p, q)) - f = 0
    yield_cone = criterion.scaled(sc.stress).constraint(st.S)   # F(sigma_j) <= 0
    problem = cp.Problem(cp.Maximize(st.objective), [equilibrium, yield_cone] + st.constraints)
    # 'AlmostSolved' comes back: static_increment rescales, then certifies or raises
    info = solve(problem, what="static increment (3.45)", defer_certify=True,
                 **solver_settings)
    solution = ScaledSolution(s=st.S.value.ravel(), r=None,
                              dual_equilibrium=equilibrium.dual_value,
                              dual_yield=yield_cone.dual_value[0], info=info)
    for term in terms:                        # contact forces, ...
        term.read(st, solution)

    sigma = st.S.value * sc.stress
    du = np.zeros(n_u)
    du[free] = -solution.dual_equilibrium * u_ref
    du[P] = du_P
    multiplier = point_multipliers(solution.dual_yield, step.n) * sc.length * u_ref
    increment = StaticIncrement(sigma, du, B.T @ sigma.ravel() - f, multiplier, info,
                                np.zeros(0), np.zeros(0))
    for term in terms:                        # their forces off the reactions
        term.invert(solution, increment, step)
    increment.reactions[free] = 0.0
    return increment


@dataclass
class LimitLoad:
    """Solution of a load-controlled limit analysis.

    load_factor : collapse multiplier alpha of the live load;
    sigma : (n_points, 4) a statically admissible stress field at collapse;
    velocity : (n_u,) collapse mechanism, normalised so that f_live . velocity = 1;
    info : solver report.
    """

    load_factor: float
    sigma: np.ndarray
    velocity: np.ndarray
    info: SolveInfo


def limit_analysis(B, f_live, criterion, *, fixed, f_dead=None, scaling=None,
                   solver="clarabel", **solver_settings):
    """Rigid-plastic limit analysis: the largest multiplier of the live load.

    .. math::
        \\max_{\\alpha, \\sigma}\\; \\alpha \\quad \\text{s.t.}\\quad
        B_F^T \\sigma = \\alpha f_F + f^0_F,\\quad F(\\sigma_j) \\le 0

    This is (3.45) with the compliance dropped (rigid-plastic) and the load
    scaled by alpha; the dual of equilibrium is the collapse mechanism.

    Parameters
    ----------
    B : (4 n_points, n_u) sparse, (3.41).  f_live : (n_u,) the load multiplied by alpha.
    criterion : a :class:`~pfem_skfem.materials.YieldCriterion`.
    fixed : dofs with zero velocity.  f_dead : (n_u,) a load not multiplied, or None.
    scaling : :class:`Scaling`; by default the criterion's strength and a median of B.
    solver : the conic solver (:data:`~pfem_skfem.problems.conic.SOLVERS`; 'clarabel').
    solver_settings : the solver's settings, and ``accept_inaccurate``
        (:func:`~pfem_skfem.problems.conic.solve`).

    Returns
    -------
    LimitLoad

    Warns
    -----
    AlmostSolvedWarning
        Clarabel stopped 'AlmostSolved' and its measures certify the answer
        (:func:`~pfem_skfem.problems.conic.certify`); uncertified, SolverError is raised.
    """
    solver_backend(solver)                 # an unknown or unavailable solver: refused now
    n_s, n_u = B.shape
    n = n_s // 4
    free, _ = split_dofs(n_u, fixed, ())
    f_live = np.asarray(f_live, dtype=float)
    f_dead = np.zeros(n_u) if f_dead is None else np.asarray(f_dead, dtype=float)
    if not np.any(f_live[free]):
        raise ValueError("the live load has no component on a free dof")
    sc = scaling or Scaling.from_operators(B, None, criterion.strength_scale())
    force = sc.stress * sc.length
    Bh = (B / sc.length).tocsc()[:, free]

    alpha = cp.Variable()
    S = cp.Variable((n, 4))
    s = cp.vec(S, order="C")
    equilibrium = Bh.T @ s == alpha * f_live[free] / force + f_dead[free] / force
    yield_cone = criterion.scaled(sc.stress).constraint(S)
    problem = cp.Problem(cp.Maximize(alpha), [equilibrium, yield_cone])
    info = solve(problem, what="limit analysis", solver=solver, **solver_settings)

    velocity = np.zeros(n_u)
    velocity[free] = -equilibrium.dual_value / force
    return LimitLoad(float(alpha.value), S.value * sc.stress, velocity, info)
