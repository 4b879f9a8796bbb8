"""Static problems: the incremental elastoplastic SOCP (3.45) and limit analysis.

Both are stated in cvxpy almost as printed, in scaled variables (see
:class:`~pfem_skfem.problems.conic.Scaling`): stresses in units of the material
strength, lengths in units of an element size. Displacement increments come back
as the duals of the equilibrium constraints. An 'AlmostSolved' end is returned only
when its own measures certify it (:func:`~pfem_skfem.problems.conic.certify`).

Sign convention, settled by the KKT conditions (3.47) and the tests: with the
Lagrangian J = -1/2 ds^T C ds + du^T (B^T s - f) of (3.46), cvxpy's dual y of the
equality in a maximisation is -du.
"""
from dataclasses import dataclass

import cvxpy as cp
import numpy as np

from .conic import (Scaling, SolveInfo, SolverError, certify, point_multipliers,
                    prescribed_values, solve, solver_backend, split_dofs)
from .contact import contact_terms


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
    info : solver report.
    """

    sigma: np.ndarray
    du: np.ndarray
    reactions: np.ndarray
    plastic_multiplier: np.ndarray
    info: SolveInfo
    p: np.ndarray = None
    q: np.ndarray = None


def static_increment(B, C, f, sigma_n, criterion, *, fixed, prescribed=((), ()),
                     contacts=None, scaling=None, solver="clarabel", **solver_settings):
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
    forces G (p, q), the objective the term - sum g0_j p_j, and ``|q_j| <= mu_j p_j``.

    Parameters
    ----------
    B : (4 n_points, n_u) sparse, (3.41).  C : (4 n_points,)^2 sparse (3.43) or None.
    f : (n_u,) external forces at t_{n+1} (3.42).  sigma_n : (n_points, 4) stresses at t_n.
    criterion : a :class:`~pfem_skfem.materials.YieldCriterion`.
    fixed : dofs with zero increment.  prescribed : (dofs, increments): the dofs with a
        prescribed increment and its values.
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
    res = _static_increment(B, C, f, sigma_n, criterion, supports, contacts, closing, sc,
                            solver_settings)
    if res.info.status == cp.OPTIMAL_INACCURATE and scaling is None:
        # Frictional materials can carry stresses far above their cohesion, and the
        # solver's absolute tolerances then stop it short ('AlmostSolved'). Rescale
        # by the stress level of that near-solution and solve once more.
        level = float(np.sqrt(np.mean(res.sigma ** 2)))
        if np.isfinite(level) and level > sc.stress:
            sc = Scaling(stress=level, length=sc.length, compliance=sc.compliance)
            res = _static_increment(B, C, f, sigma_n, criterion, supports, contacts, closing,
                                    sc, solver_settings)
    if not accept:          # an AlmostSolved end: certified by its measures, or raised
        try:
            certify(res.info.status, "static increment (3.45)", res.info.extra.get("measures"))
        except SolverError as err:
            err.sigma = res.sigma                    # the near-solution, for a caller's look
            raise
    return res


def _static_increment(B, C, f, sigma_n, criterion, supports, contacts, closing, sc,
                      solver_settings):
    """(3.45) in the scaled variables of ``sc``, ``supports`` the free dofs, the prescribed
    ones and their increments; see :func:`static_increment`."""
    free, P, du_P = supports
    n_s, n_u = B.shape
    n = n_s // 4
    # reference displacement: yield strain x element size, or the prescribed motion
    u_ref = (sc.stress * sc.compliance / sc.length if C is not None
             else max(np.abs(du_P).max(initial=0.0), closing))

    Bh = (B / sc.length).tocsc()
    B_F, B_P = Bh[:, free], Bh[:, P]
    f_h = f / (sc.stress * sc.length)
    u_P = du_P / u_ref
    s_n = sigma_n.ravel() / sc.stress

    S = cp.Variable((n, 4))                      # sigma_{n+1} / sigma_ref, one row per point
    s = cp.vec(S, order="C")                     # point-major as (3.28)
    if contacts is not None:
        ct = contact_terms(contacts, n_u, length_scale=u_ref,
                           force_scale=sc.stress * sc.length)
        g = ct.force()                            # G (p, q): contact forces on the solid
        internal = B_F.T @ s - g[free]
        work_P = u_P @ (B_P.T @ s - f_h[P] - g[P]) if P.size else 0
        contact_objective, contact_cones = ct.objective, ct.constraints
    else:
        internal = B_F.T @ s
        work_P = u_P @ (B_P.T @ s - f_h[P]) if P.size else 0
        contact_objective, contact_cones = 0, []
    if C is not None:
        Ch = (C / sc.compliance).tocsr()
        complementary = 0.5 * cp.quad_form(s, cp.psd_wrap(Ch)) - (Ch @ s_n) @ s
        objective = cp.Maximize(-complementary + work_P + contact_objective)
    else:
        objective = cp.Maximize(work_P + contact_objective)
    equilibrium = internal == f_h[free]           # B^T sigma_{n+1} (+ E^T rho) - f = 0
    yield_cone = criterion.scaled(sc.stress).constraint(S)   # F(sigma_j) <= 0
    problem = cp.Problem(objective, [equilibrium, yield_cone] + contact_cones)
    # 'AlmostSolved' comes back: static_increment rescales, then certifies or raises
    info = solve(problem, what="static increment (3.45)", defer_certify=True,
                 **solver_settings)

    sigma = S.value * sc.stress
    du = np.zeros(n_u)
    du[free] = -equilibrium.dual_value * u_ref
    du[P] = du_P
    force = sc.stress * sc.length
    p = q = np.zeros(0)
    reactions = B.T @ sigma.ravel() - f
    if contacts is not None:
        p, q = ct.p.value * force, ct.q.value * force
        reactions -= ct.G @ np.concatenate([p, q])
    reactions[free] = 0.0
    multiplier = point_multipliers(yield_cone.dual_value[0], n) * sc.length * u_ref
    return StaticIncrement(sigma, du, reactions, multiplier, info, p, q)


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
