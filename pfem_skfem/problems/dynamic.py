"""The dynamic problem: theta-method in time (4.3)-(4.11) and the SOCP (4.23).

Each time step solves

.. math::
    \\max_{\\sigma, r}\\; -\\tfrac12 \\Delta\\sigma^T C \\Delta\\sigma
        - \\tfrac12 \\Delta t^2\\, r^T D r
    \\quad\\text{s.t.}\\quad B^T\\sigma + A^T r = f,\\quad F(\\sigma_j) \\le 0

(4.23), with rho~ = rho/(theta1 theta2) in D, and f the discrete form of
b~ and t~ (4.6), (4.10) (the inertia of the state at t_n included).

KKT conditions (4.25), re-derived (the printed first row has a sign error, see
MAP.md). With the Lagrangian

    L = -1/2 ds^T C ds - 1/2 dt^2 r^T D r + du^T (B^T sigma + A^T r - f)

stationarity gives  B du = C ds + dlambda grad F  (flow rule, (4.11)),
dt^2 D r = A du  (r = rho~ du/dt^2, the dynamic force), and eliminating r,
B^T sigma + (A^T D^-1 A) du / dt^2 = f with A^T D^-1 A = int rho~ N_u^T N_u
(4.26)-(4.27). So the multiplier of the equality is +du; cvxpy's dual of an
equality in a maximisation is its negative (tests: free fall, standard-FE agreement).

Scaling. As stated, f carries the inertia rho~ v_n/dt, which dwarfs gravity and
the tractions when dt is small, and Clarabel's tolerances are absolute. We
therefore write r = rho~ v_n / dt + r' (exact: v_n restricted to an element is in
the discontinuous P2 space of r). Then A^T (rho~ v_n/dt) = M~ v_n/dt cancels the
inertia in f, D (rho~ v_n/dt) = A v_n/dt, and the problem becomes

    max  -1/2 ds^T C ds - 1/2 dt^2 r'^T D r' - dt v_n^T A^T r'
    s.t. B^T sigma + A^T r' = f'     (f' = f - M~ v_n/dt: loads and sigma_n only)

with the same multiplier du. Stresses, r' and du are measured in scales
(:class:`DynamicScales`) taken from an elastic predictor of the step
(:func:`estimate_scales`) or, when stepping, from the previous step's solution;
B is measured in its median entry and the objective in force x displacement, so
the scaled dual is du / displacement scale and the data are near order one.
Measured: a body in free fall then falls g dt^2 (N(N-1)/2 + N theta2) in N steps
to round-off with either material model (tests/test_dynamics.py).
"""
from dataclasses import dataclass

import cvxpy as cp
import numpy as np

from ..materials.criteria import yield_constraints
from ..materials.rate import RateDissipation, ViscousStress
# ThetaMethod, DynamicOperators, dynamic_operators and the block inverses live in
# discretisation/ since issue 37; re-exported here for their users
from ..discretisation.dynamic import (DynamicOperators, block_inverse,  # noqa: F401
                                      block_inverse_elements, dynamic_operators)
from ..discretisation.theta import ThetaMethod  # noqa: F401
from .conic import SolveInfo, prescribed_values, solve, solver_backend, split_dofs
from .direct_engines import ENGINES
from .contact import contact_matrix, contact_terms
from .static import point_multipliers


@dataclass
class DynamicIncrement:
    """Solution of one step of (4.23).

    sigma : (n_points, 4) stresses at t_{n+1};  du : (n_u,) displacement increments;
    v : (n_u,) velocities at t_{n+1} (4.7);  r : (n_r,) dynamic forces r' = r - rho~ v_n/dt;
    reactions : (n_u,) B^T sigma + A^T r' - f' on supported dofs (zero on free dofs);
    plastic_multiplier : (n_points,) integrated plastic multipliers (zero if elastic);
    info : solver report;  scales : the solution's own magnitudes, a good
        ``scaling`` for the next step;
    p, q : (nc,) normal and tangential contact forces of the step (empty without
        contacts), the forces of the momentum balance, i.e. theta1 times the
        multipliers of the theta1-weighted equilibrium.
    """

    sigma: np.ndarray
    du: np.ndarray
    v: np.ndarray
    r: np.ndarray
    reactions: np.ndarray
    plastic_multiplier: np.ndarray
    info: SolveInfo
    scales: "DynamicScales" = None
    p: np.ndarray = None
    q: np.ndarray = None


@dataclass(frozen=True)
class DynamicScales:
    """Reference stress, displacement increment and dynamic force r' of one step of (4.23).

    Forces are measured in stress x length (length = median |B| entry), the
    objective in force x displacement, so the scaled dual of equilibrium is
    du / displacement; r' is measured in ``dynamic_force``.
    """

    stress: float
    displacement: float
    dynamic_force: float

    def __post_init__(self):
        for name in ("stress", "displacement", "dynamic_force"):
            value = getattr(self, name)
            if not np.isfinite(value) or value <= 0:
                raise ValueError(f"scaling {name} must be positive, got {value!r}")


def estimate_scales(ops, f, v_n, sigma_n, free, criterion, du_prescribed=()):
    """Scales from an elastic predictor of the step (used for a first step).

    Solves the linear step (K + M~/dt^2) du = f' + M~ v_n/dt - B^T sigma_n on the
    free dofs, K = B^T C^-1 B (zero for a rigid-plastic material: the mass alone),
    and takes its magnitudes: displacement |du|, stress the strength (or the
    larger of the predicted |sigma| and |f'| / length), dynamic force
    |D^-1 A (du - dt v_n)| / dt^2, for a rigid-plastic body at least the force
    density stress x |B| / |A| that balances stress gradients.
    """
    from scipy.sparse.linalg import splu

    th = ops.theta
    lhs = ops.M_tilde / th.dt ** 2
    if ops.K is not None:
        lhs = lhs + ops.K
    rhs = f + ops.M_tilde @ v_n / th.dt - ops.B.T @ np.ravel(sigma_n)
    du = np.zeros(len(v_n))
    du[free] = splu(lhs.tocsc()[free][:, free].tocsc()).solve(rhs[free])
    u = max(np.abs(du).max(), np.abs(du_prescribed).max(initial=0.0))
    r = np.abs(ops.D_inverse @ (ops.A @ (du - th.dt * v_n))).max() / th.dt ** 2
    if criterion is not None:
        stress = float(criterion.strength_scale())
    else:
        sigma = np.ravel(sigma_n) + ops.C_inverse @ (ops.B @ du)
        # a body in rigid motion has no stress: then measure forces by the loads
        stress = max(np.abs(sigma).max(), np.abs(f).max() / np.median(np.abs(ops.B.data)))
    stress = stress if stress > 0 else 1.0
    u = u if u > 0 else 1.0
    # r' that balances stress gradients of the stress scale; a rigid-plastic body's
    # plastic resistance is of this size, which its predictor (mass only) cannot see
    r_stress = stress * np.median(np.abs(ops.B.data)) / np.median(np.abs(ops.A.data))
    r = max(r, r_stress) if ops.C is None else max(r, 1e-6 * r_stress)
    return DynamicScales(stress=stress, displacement=u, dynamic_force=r)


D_FORMS = ("quad_form", "cone")
BACKENDS = ("cvxpy", "clarabel")


def dynamic_increment(ops, f_n, f_next, sigma_n, v_n, criterion=None, *, fixed=(),
                      prescribed=(), du_prescribed=(), contacts=None, scaling=None,
                      d_form="quad_form", backend="cvxpy", viscous=None, solver="clarabel",
                      **solver_settings):
    """Solve one time step of the dynamic problem (4.23).

    .. math::
        \\max_{\\sigma, r'}\\; -\\tfrac12 \\Delta\\sigma^T C \\Delta\\sigma
          - \\tfrac12 \\Delta t^2 r'^T D r' - \\Delta t\\, v_n^T A^T r'
          + \\Delta\\bar u_P^T (B_P^T\\sigma + A_P^T r' - f'_P)

        \\text{s.t.}\\quad B_F^T\\sigma + A_F^T r' = f'_F, \\quad F(\\sigma_j) \\le 0

    which is (4.23) with r = rho~ v_n/dt + r' (see the module docstring), F the
    free dofs and P the dofs with prescribed increments (last term: work of their
    reactions). ``C = None`` in ``ops`` means rigid-plastic (no C term);
    ``criterion = None`` means elastic (no yield cone). With ``contacts`` (a
    :class:`~pfem_skfem.problems.contact.ContactSet`) it is (5.12): the contact
    forces G (p, q) join equilibrium, - sum g0_j p_j the objective, and
    |q_j| <= mu_j p_j the constraints (or |q_j| <= mu_j p~_j for contacts
    given a lagged normal force, :func:`~pfem_skfem.problems.contact.with_friction_bound`).

    Parameters
    ----------
    ops : :class:`DynamicOperators`.
    f_n, f_next : (n_u,) external forces (3.42) at t_n and t_{n+1}.
    sigma_n : (n_points, 4) stresses at t_n.  v_n : (n_u,) velocities at t_n.
    criterion : yield criterion or None (elastic).
    fixed : dofs held at zero increment.  prescribed, du_prescribed : dofs and increments.
    scaling : :class:`DynamicScales` (stress, displacement); by default
        :func:`estimate_scales`. Pass the previous step's ``scales`` when stepping.
    d_form : "quad_form" (r'^T D r' as a quadratic objective, cvxpy ``quad_form``) or
        "cone" (one rotated second-order cone per element through D = G^T G, App A).
    backend : "cvxpy" (the statement above, the reference) or "clarabel" (the same
        scaled problem assembled in Clarabel's standard form by
        :mod:`~pfem_skfem.problems.clarabel_direct`, without cvxpy's compile step;
        ``d_form="quad_form"`` only).
    solver : the conic solver (:data:`~pfem_skfem.problems.conic.SOLVERS`; 'clarabel').
        With ``backend="clarabel"`` the direct assembly is handed to it where it has an
        engine there (:data:`~pfem_skfem.problems.direct_engines.ENGINES`: Clarabel,
        QOCO); another solver gets the cvxpy statement (``backend="cvxpy"``). A solver lacking the exponential cone of a
        :class:`RateDissipation` is refused before any work.
    viscous : None, :class:`ViscousStress` or :class:`RateDissipation` (rigid-plastic
        only): sigma = sigma_p + sigma_v with sigma_p in the cone and a rate deviator
        sigma_v = (a, -a, 0, b) at each point, with tau_j = ||(a_j, b_j)|| = sqrt(J2)
        (its ``hoop``: sigma_v = (a, -a, 0, b) + c (1, 1, -2, 0) / sqrt3, the deviators of
        axisymmetry, tau_j = ||(a_j, b_j, c_j)||, gamma_dot the full sqrt(2 D':D')). ViscousStress:
        the term - sum_j dt w_j tau_j^2 / (2 eta_j) in the objective (a Bingham
        dissipation, as Zhang et al. 2017 add to (4.23)), so that at a flowing point
        R(sigma) = R(sigma_p) + eta_j gamma_dot_j. RateDissipation: the complementary
        dissipation of mu(I) at frozen pressure, - sum_j dt w_j c_j (-s_j - ln(1 - s_j)),
        s_j = tau_j / tau_max_j (exponential cones), so that R(sigma) = mu(I_j) p_j.

    Returns
    -------
    DynamicIncrement
    """
    if d_form not in D_FORMS:
        raise ValueError(f"d_form must be one of {D_FORMS}, got {d_form!r}")
    if backend not in BACKENDS:
        raise ValueError(f"backend must be one of {BACKENDS}, got {backend!r}")
    if backend == "clarabel" and (d_form != "quad_form" or criterion is None):
        raise ValueError("backend='clarabel' supports d_form='quad_form' with a yield criterion")
    if ops.C is None and criterion is None:
        raise ValueError("a rigid-plastic material (C = None) needs a yield criterion")
    # an unknown, unavailable or too weak solver refused now (mu(I): exponential cones)
    name = solver_backend(solver, cones={"exp"} if isinstance(viscous, RateDissipation)
                          else None).name
    if name not in ENGINES:                      # no engine of the direct assembly:
        backend = "cvxpy"                        # the cvxpy statement
    elif backend == "clarabel":
        solver_settings["engine"] = name
    if backend == "cvxpy":                       # which has no choice of form
        solver_settings.pop("form", None)
    if viscous is not None and not isinstance(viscous, (ViscousStress, RateDissipation)):
        raise ValueError(f"viscous must be a ViscousStress or RateDissipation, got {viscous!r}")
    if viscous is not None and (ops.C is not None or criterion is None):
        raise ValueError("viscous: only for a rigid-plastic material with a yield criterion")
    th = ops.theta
    B, C, A, D = ops.B, ops.C, ops.A, ops.D
    n_s, n_u = B.shape
    n = n_s // 4
    sigma_n = np.asarray(sigma_n, dtype=float).reshape(n, 4)
    v_n = np.asarray(v_n, dtype=float)
    free, P = split_dofs(n_u, fixed, prescribed)
    du_P = prescribed_values(P, du_prescribed)
    f = th.equilibrium_rhs(f_n, f_next, B, sigma_n)           # f' of the module docstring

    # -- scales (module docstring): stress, displacement, r'; medians of |B|, diag D, diag C
    length = float(np.median(np.abs(B.data)))
    d_ref = float(np.median(D.diagonal()))
    c_ref = float(np.median(C.diagonal())) if C is not None else None
    sc = scaling or estimate_scales(ops, f, v_n, sigma_n, free, criterion, du_P)
    stress, u_ref, r_ref = sc.stress, sc.displacement, sc.dynamic_force
    force = stress * length                                  # B^T sigma, f in force
    j_ref = force * u_ref                                    # objective; du = u_ref x dual
    kappa = th.dt ** 2 * r_ref ** 2 * d_ref / j_ref          # weight of dt^2 r'^T D r'
    kappa_C = stress ** 2 * c_ref / j_ref if C is not None else 0.0   # weight of ds^T C ds

    Bh = (B / length).tocsc()
    Ah = (A * (r_ref / force)).tocsc()
    f_h = f / force
    s_n = sigma_n.ravel() / stress
    v_h = v_n * th.dt / u_ref
    u_P = du_P / u_ref
    # weights of the rate terms in the scaled variables: - 1/2 sum kv_j |(a_j, b_j)|^2,
    # or - sum kw_j (t_j - s_j) with |(a_j, b_j)| <= tau_max_j s_j, t_j >= -ln(1 - s_j)
    kv = rate_log = None
    hoop = bool(getattr(viscous, "hoop", False))
    if isinstance(viscous, ViscousStress):
        kv = th.dt * stress * viscous.weights / (viscous.eta * length * u_ref)
    elif viscous is not None:
        rate_log = dict(kw=th.dt * viscous.weights * viscous.c / j_ref,
                        tau_max=viscous.tau_max / stress)

    if backend == "clarabel":                    # the same problem, assembled directly
        sol = _solve_direct(ops, criterion.scaled(stress), contacts, Bh, Ah, f_h, s_n, v_h,
                            u_P, free, P, kappa, kappa_C, d_ref, c_ref, u_ref,
                            force * th.theta1, dict(solver_settings, viscous=kv,
                                                    rate_log=rate_log, hoop=hoop))
    else:
        sol = _solve_cvxpy(ops, criterion, stress, contacts, Bh, Ah, f_h, s_n, v_h, u_P, free,
                           P, kappa, kappa_C, d_ref, c_ref, u_ref, force * th.theta1, d_form,
                           dict(solver_settings, solver=solver), kv, rate_log, hoop)

    sigma = sol["s"].reshape(n, 4) * stress
    r = sol["q"] * r_ref
    du = np.zeros(n_u)
    du[free] = -sol["dual_equilibrium"] * u_ref
    du[P] = du_P
    reactions = B.T @ sigma.ravel() + A.T @ r - f
    p_c = q_c = np.zeros(0)
    if contacts is not None:
        p_c, q_c = sol["p"] * force, sol["qc"] * force
        reactions -= contact_matrix(contacts, n_u) @ np.concatenate([p_c, q_c])
        p_c, q_c = th.theta1 * p_c, th.theta1 * q_c       # forces of the momentum balance
    reactions[free] = 0.0
    multiplier = (point_multipliers(sol["dual_yield"], n) * length * u_ref
                  if criterion is not None else np.zeros(n))
    info = sol["info"]
    s_max, u_max, r_max = np.abs(sigma).max(), np.abs(du).max(), np.abs(r).max()
    scales = DynamicScales(                     # keep the old scale where the field vanished
        stress=sc.stress if criterion is not None or s_max < 1e-9 * sc.stress else s_max,
        displacement=u_max if u_max > 1e-9 * sc.displacement else sc.displacement,
        dynamic_force=r_max if r_max > 1e-9 * sc.dynamic_force else sc.dynamic_force)
    return DynamicIncrement(sigma, du, th.velocity(du, v_n), r, reactions, multiplier, info,
                            scales, p_c, q_c)



def _solve_cvxpy(ops, criterion, stress, contacts, Bh, Ah, f_h, s_n, v_h, u_P, free, P, kappa,
                 kappa_C, d_ref, c_ref, u_ref, contact_force, d_form, solver_settings, kv=None,
                 rate_log=None, hoop=False):
    """The scaled step of :func:`dynamic_increment` stated in cvxpy (the reference).

    Returns the scaled solution: s, q (r'), p, qc (contact forces, or None), the dual of
    the equality on the free dofs and of the yield cones, and the solver report.
    """
    n, n_u = Bh.shape[0] // 4, Bh.shape[1]
    n_r = Ah.shape[0]
    S = cp.Variable((n, 4))                      # sigma_{n+1} / stress, one row per point
    s = cp.vec(S, order="C")                     # point-major as (3.28)
    q = cp.Variable(n_r)                         # r' / r_ref, element-major (12 per element)
    constraints = []
    # -1/2 dt^2 r'^T D r' - dt v_n^T A^T r'   (in units of j_ref)
    if d_form == "quad_form":
        inertia_term = 0.5 * kappa * cp.quad_form(q, cp.psd_wrap((ops.D / d_ref).tocsr()))
    else:                                        # sum_e |G_e q_e|^2 <= 2 sum_e t_e (A.4)-(A.8)
        W = cp.reshape((ops.G / np.sqrt(d_ref)) @ q, (n_r // 12, 12), order="C")
        t = cp.Variable(n_r // 12)
        rest = cp.reshape(2 * t - 1, (-1, 1), order="C")
        constraints.append(cp.SOC(2 * t + 1, cp.hstack([2 * W, rest]), axis=1))
        inertia_term = kappa * cp.sum(t)
    objective_terms = -inertia_term - (Ah @ v_h) @ q
    if ops.C is not None:                        # -1/2 ds^T C ds, C scaled by c_ref
        Ch = (ops.C / c_ref).tocsr()
        objective_terms += -kappa_C * (0.5 * cp.quad_form(s, cp.psd_wrap(Ch)) - (Ch @ s_n) @ s)
    s_total = s
    if kv is not None or rate_log is not None:   # sigma = sigma_p + E (a, b), a rate stress
        from .clarabel_direct import viscous_stress_map
        V = cp.Variable((n, 3 if hoop else 2))   # (a, b[, c]) per point
        s_total = s + viscous_stress_map(n, hoop) @ cp.vec(V, order="C")
    if kv is not None:                           # - 1/2 sum kv_j |(a_j, b_j)|^2   (Bingham)
        objective_terms += -0.5 * cp.sum(cp.multiply(kv, cp.sum(cp.square(V), axis=1)))
    if rate_log is not None:                     # - sum kw_j (-s_j - ln(1 - s_j))   (mu(I))
        sv, tv = cp.Variable(n), cp.Variable(n)
        objective_terms += -cp.sum(cp.multiply(rate_log["kw"], tv - sv))
        constraints += [cp.SOC(cp.multiply(rate_log["tau_max"], sv), V, axis=1),  # tau <= tau_max s
                        cp.constraints.ExpCone(-tv, np.ones(n), 1 - sv)]      # t >= -ln(1 - s)
    internal = Bh.T @ s_total + Ah.T @ q         # B^T sigma + A^T r
    if contacts is not None:                     # + E^T rho = - G (p, q)   (5.12)
        # a friction bound is a force of the momentum balance (theta1 x the variable)
        ct = contact_terms(contacts, n_u, length_scale=u_ref, force_scale=contact_force)
        internal = internal - ct.force()
        objective_terms += ct.objective          # - sum g0_j p_j
        constraints += ct.constraints            # |q_j| <= mu_j p_j
    if P.size:                                   # work of the reactions on prescribed dofs
        objective_terms += u_P @ (internal[P] - f_h[P])
    equilibrium = internal[free] == f_h[free]    # B^T sigma + A^T r + E^T rho = f
    constraints.insert(0, equilibrium)
    if criterion is not None:                    # F(sigma_j) <= 0 (a fluid's point: rho_2..m = 0)
        yield_cones, yield_multipliers = yield_constraints(criterion.scaled(stress), S)
        constraints += yield_cones
    problem = cp.Problem(cp.Maximize(objective_terms), constraints)
    info = solve(problem, what="dynamic step (4.23)", **solver_settings)
    # cvxpy's dual of an equality in a maximisation is minus its multiplier
    s_value = S.value.ravel() if kv is None and rate_log is None else s_total.value
    return {"s": s_value, "q": q.value,
            "p": None if contacts is None else ct.p.value,
            "qc": None if contacts is None else ct.q.value,
            "dual_equilibrium": equilibrium.dual_value,
            "dual_yield": yield_multipliers() if criterion is not None else None,
            "info": info}


def _solve_direct(ops, criterion, contacts, Bh, Ah, f_h, s_n, v_h, u_P, free, P, kappa, kappa_C,
                  d_ref, c_ref, u_ref, contact_force, solver_settings):
    """The same scaled step assembled for Clarabel (:mod:`.clarabel_direct`); same returns."""
    from .clarabel_direct import solve_dynamic_step

    contact = None
    if contacts is not None:
        bound = contacts.friction_bound
        contact = {"G": contact_matrix(contacts, Bh.shape[1]), "gap": contacts.gap / u_ref,
                   "mu": contacts.mu,
                   "bound": None if bound is None else np.asarray(bound) / contact_force,
                   "slip": None if contacts.slip is None else contacts.slip / u_ref}
    out = solve_dynamic_step(
        Bh=Bh, Ah=Ah, Dh=(ops.D / d_ref).tocsr(),
        Ch=None if ops.C is None else (ops.C / c_ref).tocsr(), kappa=kappa, kappa_C=kappa_C,
        s_n=s_n, v_h=v_h, f_h=f_h, free=free, P=P, u_P=u_P, criterion=criterion,
        contact=contact, **solver_settings)
    return {"s": out["s"], "q": out["q"], "p": out["p"], "qc": out["qc"],
            "dual_equilibrium": out["dual_equilibrium"], "dual_yield": out["dual_yield"],
            "info": out["info"]}
