"""Limit analysis with strict bounds (plane strain): the lower- and upper-bound SOCPs.

The thesis' mixed element (Ch 3, (3.45) rigid-plastic) brackets nothing: its stresses
are admissible only at three interior points and its dissipation is a quadrature.
These two elements bound the true collapse load alpha* from below and above.

Lower bound (Sloan 1988; Makrodimopoulos & Martin 2006, IJNME 66): a
stress linear in each element, discontinuous across edges:

.. math::
    \\max_{\\alpha, \\sigma}\\ \\alpha \\quad\\text{s.t.}\\quad
    \\nabla\\cdot\\sigma_e + \\alpha b + b_0 = 0 \\ \\text{in each element},\\quad
    [\\![\\sigma n]\\!] = 0 \\ \\text{at both ends of each interior edge},\\quad
    \\sigma n = \\alpha t + t_0 \\ \\text{on loaded edges},\\quad
    \\rho(\\sigma_{ej}) \\in \\mathcal K \\ \\text{at each vertex}

Every constraint is linear in a linear field, so it holds along whole edges and
elements, and the cone holds everywhere by convexity: the field is statically
admissible and alpha_L <= alpha*.

Upper bound (Makrodimopoulos & Martin 2007, IJNAMG 31): the thesis' P2 velocities,
whose strain rate is linear, with the plastic dissipation D(eps) = sup sigma : eps over
the yield set written through the criterion's own cone rho = D sigma + d in K (App A):
D(eps) <= d . lambda for every lambda in K with D^T lambda = -eps (weak conic duality),
imposed at the vertices:

.. math::
    \\min_{u, \\Lambda}\\ \\sum_{e,j} d\\cdot\\Lambda_{ej} - f_0^T u \\quad\\text{s.t.}\\quad
    D^T\\Lambda_{ej} + B_{ej} u = 0,\\quad \\Lambda_{ej} \\in \\mathcal K,\\quad
    f^T u = 1,\\quad u = 0 \\ \\text{on supports}

with B_ej = (A_e / 3) eps(x_j). D is convex and eps linear, so its integral over an
element is at most (A_e / 3) sum_j D(eps_j): the objective is at least the mechanism's
dissipation, and alpha_U >= alpha*. With the thesis' points (1/6, 4/6, 1/6) in place of
the vertices the same statement is the conic dual of the thesis' limit analysis
(:func:`~pfem_skfem.problems.static.limit_analysis`): ``kinematic(..., 'gauss')``.

Both bounds are exact cones where the criterion is one in (sx, sy, sz, sxy): Tresca,
Mohr-Coulomb (A.9)-(A.12) and Drucker-Prager (A.17) in plane strain. A rigid punch
(a footing pushed at a velocity v) replaces the load multiplier by the force it needs:
both bounds then bound the power of its reactions divided by |v|.

A given pore-pressure field (``pore_pressure``) makes both bounds effective-stress ones:
the criterion holds for sigma', equilibrium for sigma' - p I
(:mod:`pfem_skfem.problems.effective_stress` derives both terms).
"""
import warnings
from dataclasses import dataclass, field, replace
from typing import Callable, Optional

import cvxpy as cp
import numpy as np
import scipy.sparse as sp
from skfem import MeshTri

from ..discretisation.bounds import LowerBoundOperators, element_gradients, vertex_discretise
from ..discretisation.static import (assemble_B, body_force_vector, boundary_facets,
                                     check_mesh, discretise, traction_vector)
from ..materials.criteria import YieldCriterion
from .conic import AlmostSolvedWarning, SolveInfo, SolverError, solve, solver_backend
from .effective_stress import (as_pore_pressure, pore_body_force, pore_load_vector,
                               punch_pore_power)

#: a bound is the objective of its own field, so it holds when that field is feasible:
#: an 'AlmostSolved' end is accepted when the field's largest constraint violation
#: (scaled: stresses by the strength, lengths by an element size) is below
#: ``feasibility``; ``gap`` (Clarabel's relative duality gap) only says how far from
#: the best bound of the mesh it stopped, and is reported
BOUND_CERTIFY = dict(feasibility=1e-6, gap=1e-3)

#: Clarabel's settings tried in turn when it stops with a NumericalError (cvxpy's
#: 'solver_error') or an uncertified field, which the bound problems of refined footing
#: meshes met near their optimum; equilibration off and a larger static regularisation
#: then end with a feasible field (book, performance appendix)
BOUND_RETRIES = (dict(), dict(equilibrate_enable=False, static_regularization_constant=1e-7))

_COMPONENTS = {"x": (0,), "y": (1,), "xy": (0, 1)}


def _check_components(components):
    if components not in _COMPONENTS:
        raise ValueError(f"components must be 'x', 'y' or 'xy', got {components!r}")
    return _COMPONENTS[components]


@dataclass(frozen=True)
class Support:
    """Velocity components (global x, y) held at zero on the boundary facets whose
    midpoints x (2, m) satisfy ``where(x)``: 'x' or 'y' a smooth wall normal to that
    axis, 'xy' a rough wall of any direction."""

    where: Callable
    components: str = "xy"

    def __post_init__(self):
        _check_components(self.components)


@dataclass(frozen=True)
class Traction:
    """A constant traction t = (tx, ty) on the selected boundary facets; ``live``: scaled
    by the load multiplier, else a dead load."""

    where: Callable
    t: tuple
    live: bool = True

    def __post_init__(self):
        t = np.asarray(self.t, dtype=float)
        if t.shape != (2,) or not np.all(np.isfinite(t)):
            raise ValueError(f"t must be a finite (tx, ty), got {self.t!r}")


@dataclass(frozen=True)
class Punch:
    """A rigid footing on the selected facets moving at ``velocity``: its ``components``
    are prescribed ('y' a smooth footing, 'xy' a rough one), the others free of traction."""

    where: Callable
    velocity: tuple = (0.0, -1.0)
    components: str = "y"

    def __post_init__(self):
        _check_components(self.components)
        v = np.asarray(self.velocity, dtype=float)
        if v.shape != (2,) or not np.all(np.isfinite(v)) or not np.any(v):
            raise ValueError(f"velocity must be a non-zero (vx, vy), got {self.velocity!r}")


@dataclass(frozen=True)
class LimitProblem:
    """A plane-strain limit-analysis problem on a triangle mesh.

    The reference load is either live loads (``body_live``, live ``tractions``: the
    bounds are multipliers alpha of them) or a ``punch`` (the bounds are the power of its
    force on its velocity v divided by the speed of v, per unit thickness); ``body_dead``
    and dead tractions are carried as they are.
    Boundary facets neither supported nor loaded are free surfaces.
    ``pore_pressure``: a callable p(x) (a dead load), a
    :class:`~pfem_skfem.problems.effective_stress.PorePressure` (live or dead) or a
    :class:`~pfem_skfem.problems.effective_stress.WaterTable`; the criterion is then of
    the effective stress, the bounds' ``sigma`` effective, and free boundaries carry the
    water's pressure p (:mod:`~pfem_skfem.problems.effective_stress`).
    """

    mesh: object
    criterion: YieldCriterion
    supports: tuple = ()
    tractions: tuple = ()
    body_live: tuple = (0.0, 0.0)
    body_dead: tuple = (0.0, 0.0)
    punch: Optional[Punch] = None
    pore_pressure: object = None

    def __post_init__(self):
        if type(self.mesh) is not MeshTri:
            raise TypeError("mesh must be a straight-sided skfem.MeshTri, got "
                            f"{type(self.mesh).__name__}")
        check_mesh(self.mesh)
        for name, kind in (("supports", Support), ("tractions", Traction)):
            if not all(isinstance(x, kind) for x in getattr(self, name)):
                raise TypeError(f"{name} must be a tuple of {kind.__name__}")
        if not isinstance(self.criterion, YieldCriterion):
            raise TypeError(f"criterion must be a YieldCriterion, got {self.criterion!r}")
        for name in ("body_live", "body_dead"):
            b = np.asarray(getattr(self, name), dtype=float)
            if b.shape != (2,) or not np.all(np.isfinite(b)):
                raise ValueError(f"{name} must be a finite (bx, by), got {getattr(self, name)!r}")
        object.__setattr__(self, "pore_pressure", as_pore_pressure(self.pore_pressure))
        pore = self.pore_pressure
        if pore is not None:
            pore.nodal(self.mesh)              # finite, one value a vertex: now
            if pore.live and self.punch is not None:
                raise ValueError("pore_pressure: a live pore pressure needs a load "
                                 "multiplier; with a punch give a dead one (live=False)")
        live = (np.any(self.body_live) or any(t.live and np.any(t.t) for t in self.tractions)
                or (pore is not None and pore.live))
        if (self.punch is None) == (not live):
            raise ValueError("state one reference load: live loads (body_live or a live "
                             "traction) or a punch, not both" if live else
                             "no reference load: give body_live, a live traction or a punch")

    def pore_nodal(self, live):
        """p at the vertices when the pore pressure is given and ``live`` matches it
        (zeros otherwise)."""
        pore = self.pore_pressure
        if pore is None or pore.live != live:
            return np.zeros(self.mesh.p.shape[1])
        return pore.nodal(self.mesh)

    def refined(self, elements=None):
        """The same problem on the mesh refined at ``elements`` (all with None)."""
        mesh = self.mesh.refined(1 if elements is None else np.asarray(elements))
        return replace(self, mesh=mesh)

    def boundary_states(self):
        """Per boundary facet and component: 'fixed', 'punch' or 'free' (traction given).

        Returns (facets, state) with state an (m, 2) array of those strings."""
        mesh = self.mesh
        facets = mesh.boundary_facets()
        mid = mesh.p[:, mesh.facets[:, facets]].mean(axis=1)
        state = np.full((facets.size, 2), "free", dtype=object)
        for s in self.supports:
            on = np.asarray(s.where(mid), dtype=bool)
            for k in _COMPONENTS[s.components]:
                state[on, k] = "fixed"
        if self.punch is not None:
            on = np.asarray(self.punch.where(mid), dtype=bool)
            if not on.any():
                raise ValueError("the punch selects no boundary facet")
            for k in _COMPONENTS[self.punch.components]:
                state[on, k] = "punch"
        return facets, state

    def applied_tractions(self, facets):
        """(m, 2) live and dead tractions on ``facets`` (boundary facets)."""
        mesh = self.mesh
        mid = mesh.p[:, mesh.facets[:, facets]].mean(axis=1)
        live, dead = np.zeros((facets.size, 2)), np.zeros((facets.size, 2))
        for t in self.tractions:
            on = np.asarray(t.where(mid), dtype=bool)
            (live if t.live else dead)[on] += np.asarray(t.t, dtype=float)
        return live, dead


@dataclass
class Bound:
    """One bound (or the mixed element's estimate) of a :class:`LimitProblem`.

    kind : 'lower', 'upper' or 'mixed';  load : the multiplier alpha, or the punch force;
    sigma : (3 n_el, 4) vertex stresses (lower bound);
    velocity : (n_u,) the mechanism, f . u = 1 (or u = v on the punch) (upper, mixed);
    dissipation : (n_el,) the dissipation of each element (upper, mixed);
    info : the solver's report.
    """

    kind: str
    load: float
    info: SolveInfo
    sigma: np.ndarray = None
    velocity: np.ndarray = None
    dissipation: np.ndarray = None
    extra: dict = field(default_factory=dict)


def cone_matrices(criterion):
    """The criterion's cone rho = D sigma + d as arrays: D (m, 4), d (m,)."""
    def rho(s):
        t, rest = criterion.cone_vector(*s)
        return np.array([t] + list(rest), dtype=float)
    d = rho(np.zeros(4))
    D = np.stack([rho(e) - d for e in np.eye(4)], axis=1)
    return D, d


def _length_scale(mesh):
    """The square root of the median element area."""
    return float(np.sqrt(np.median(element_gradients(mesh)[1])))


def lower_bound(problem, solver="clarabel", **solver_settings):
    """The strict lower bound: the largest load a statically admissible linear stress
    field carries (module docstring). Returns a :class:`Bound` with ``sigma``.

    Raises SolverError (status 'infeasible') when no multiple of the live load, negative
    ones included, lets an admissible field carry the dead loads, (status 'unbounded')
    when the load is never limited. A live load along the dead load gives a negative
    multiplier (the live load reversed), not an error. ``solver``: the conic solver
    (:data:`~pfem_skfem.problems.conic.SOLVERS`), ``solver_settings`` its settings."""
    solver_backend(solver)                     # an unknown or unavailable solver: refused now
    mesh, crit = problem.mesh, problem.criterion
    ops = LowerBoundOperators.build(mesh)
    s0 = crit.strength_scale()                 # stresses / s0; rows scaled per element
    D, d = cone_matrices(crit.scaled(s0))   # in units of s0: exact under any rescaling
    n_el = mesh.t.shape[1]
    facets, state = problem.boundary_states()
    length, normal = ops.facet_geometry(facets)
    live, dead = problem.applied_tractions(facets)
    # sigma n at either end of each boundary facet, rows (2 facet + component)
    ends = [ops.traction(ops.point(mesh.f2t[0, facets], mesh.facets[k, facets]), normal)
            for k in (0, 1)]
    given = np.flatnonzero((state == "free").ravel())          # rows with a traction given
    load_control = problem.punch is None

    S = cp.Variable((ops.n_points, 4))         # sigma / s0 at each element vertex
    s = cp.vec(S, order="C")                   # point-major, as every stress field here
    alpha = cp.Variable() if load_control else 0.0
    # each element's two rows times its own size h_e: rows of order one on graded meshes
    h = np.repeat(np.sqrt(2 * ops.area), 2)
    # the pore pressure a body force -grad p_h (effective_stress.py), live or dead
    p_live, p_dead = problem.pore_nodal(True), problem.pore_nodal(False)
    b_live = (np.tile(np.asarray(problem.body_live, float), n_el)
              + pore_body_force(mesh, p_live).ravel())
    b_dead = (np.tile(np.asarray(problem.body_dead, float), n_el)
              + pore_body_force(mesh, p_dead).ravel())
    b = alpha * (b_live * h / s0) + b_dead * h / s0
    t = (alpha * live.ravel()[given] + dead.ravel()[given]) / s0
    constraints = [
        # div sigma + alpha b + b0 = 0 in each element (exact: sigma is linear)
        sp.diags(h) @ ops.equilibrium @ s + b == 0,
        # [sigma n] = 0 at both ends of every interior edge
        ops.interior_continuity() @ s == 0,
        # sigma n = alpha t + t0 at both ends of every edge not supported (0 when free)
        ends[0][given] @ s == t,
        ends[1][given] @ s == t,
        # rho = D sigma + d in K at every vertex, hence everywhere (convexity)
        cp.SOC(S @ D[0] + d[0], S @ D[1:].T + d[1:], axis=1),
    ]
    if not D[:, 2].any():
        constraints.append(S[:, 2] == 0)       # sz enters no cone (plane strain): unused
    if load_control:
        objective = alpha                      # the multiplier of the live loads
    else:
        # the punch's power / (|v| s0 l), l its width: int (sigma n) . v ds (exact: linear)
        v = np.asarray(problem.punch.velocity, float) / np.linalg.norm(problem.punch.velocity)
        width = length[(state == "punch").any(axis=1)].sum()
        w = 0.5 * (length / width)[:, None] * v[None, :] * (state == "punch")
        # the total traction's: sigma' n - p_h n (a dead pore pressure)
        objective = (w.ravel() @ (ends[0] @ s) + w.ravel() @ (ends[1] @ s)
                     - punch_pore_power(mesh, facets, normal, length, state == "punch",
                                        p_dead, v) / (s0 * width))
    prob = cp.Problem(cp.Maximize(objective), constraints)
    info = _solve_bound(prob, "lower bound", solver_settings, "static", solver)
    load = float(objective.value * (1.0 if load_control else s0 * width))
    return Bound("lower", load, info, sigma=S.value * s0, extra=info.extra["bound"])


def kinematic(problem, points="vertices", solver="clarabel", **solver_settings):
    """The upper bound (``points='vertices'``) or the thesis' mixed element in kinematic
    form (``points='gauss'``, the conic dual of its limit analysis; not a bound).

    Returns a :class:`Bound` with the mechanism ``velocity`` and the dissipation of each
    element. Raises SolverError (status 'infeasible') when the
    supports leave no mechanism, ('unbounded') when the dead loads alone collapse it.
    ``solver``: the conic solver (:data:`~pfem_skfem.problems.conic.SOLVERS`)."""
    if points not in ("vertices", "gauss"):
        raise ValueError(f"points must be 'vertices' or 'gauss', got {points!r}")
    solver_backend(solver)                     # an unknown or unavailable solver: refused now
    mesh, crit = problem.mesh, problem.criterion
    disc = vertex_discretise(mesh) if points == "vertices" else discretise(mesh)
    s0, L0 = crit.strength_scale(), _length_scale(mesh)
    D, d = cone_matrices(crit.scaled(s0))   # in units of s0: exact under any rescaling
    B = assemble_B(disc)                       # rows w_j eps(u)(x_j), point-major
    n_p, n_u = disc.n_points, disc.n_u
    keep = np.flatnonzero(D.any(axis=0) | np.asarray(abs(B).sum(axis=1)).reshape(n_p, 4)
                          .any(axis=0))        # components in a cone or a strain
    f_live = _load_vector(disc, problem, live=True) / (s0 * L0)
    f_dead = _load_vector(disc, problem, live=False) / (s0 * L0)
    fixed, punched, v_hat = _velocity_conditions(disc, problem)

    # strain rate at each point times its element's size: h_e eps_j(u), of order u
    w = disc.weights
    h = np.sqrt(2 * _per_element(disc, w) / 3)[disc.point_element]   # sqrt(2 A_e / 3)
    H = sp.diags(np.repeat(h / w, 4)) @ B

    u = cp.Variable(n_u)                       # velocities (scaled: f . u = 1, or u = v / |v|)
    Lam = cp.Variable((n_p, D.shape[0]))       # Lambda_j (h_e / U): one cone vector per point
    Hu = cp.reshape(H @ u, (n_p, 4), order="C")
    constraints = [
        # D^T Lambda_j + eps_j(u) = 0: Lambda_j certifies D(eps_j) <= d . Lambda_j
        (Lam @ D)[:, keep] + Hu[:, keep] == 0,
        # Lambda_j in K (K is self-dual)
        cp.SOC(Lam[:, 0], Lam[:, 1:], axis=1),
        # supports
        u[fixed] == 0,
    ]
    if problem.punch is None:
        constraints.append(f_live @ u == 1)    # the reference load's power normalised
    else:
        constraints.append(u[punched] == v_hat)   # the punch's velocity, |v| = 1
    # sum_j w_j d . lambda_j: the dissipation of each point (units of s0 L0 U)
    dissipation = cp.multiply(w / (h * L0), Lam @ d)
    prob = cp.Problem(cp.Minimize(cp.sum(dissipation) - f_dead @ u), constraints)
    info = _solve_bound(prob, "upper bound" if points == "vertices" else "mixed element",
                        solver_settings, "kinematic", solver)
    if problem.punch is None:       # u = U u_hat, U = 1 / (s0 L0): loads in alpha
        u_scale, force = 1.0 / (s0 * L0), 1.0
    else:                           # u = |v| u_hat: loads as forces
        u_scale, force = float(np.linalg.norm(problem.punch.velocity)), s0 * L0
    per_point = dissipation.value * force
    value = float(np.sum(dissipation.value) - f_dead @ u.value)     # the field's own
    if problem.punch is None:
        value /= float(f_live @ u.value)       # f . u = 1 to round-off: make it exact
    return Bound("upper" if points == "vertices" else "mixed", value * force, info,
                 velocity=u.value * u_scale, extra=info.extra["bound"],
                 dissipation=_per_element(disc, per_point))


def _relative_violation(constraint):
    """A constraint's largest violation over the size of the values it relates."""
    size = max((float(np.max(np.abs(a.value), initial=0.0)) for a in constraint.args),
               default=0.0)
    return float(np.max(constraint.violation(), initial=0.0)) / max(1.0, size)


#: what an infeasible or unbounded end means for each form (conic.py's hints are the
#: stress form's and the displacement form's of the PFEM step)
BOUND_HINTS = {
    ("static", "infeasible"): "no multiple of the live load lets a statically admissible "
                              "stress field carry the dead loads",
    ("static", "unbounded"): "the load is never limited: the supports carry any multiple "
                             "of it",
    ("kinematic", "infeasible"): "no mechanism fits the supports with the reference load "
                                 "doing work (f . u = 1 or the punch's motion cannot be met)",
    ("kinematic", "unbounded"): "the dead loads alone collapse a mechanism (the load "
                                "multiplier is minus infinity)",
}


def _solve_bound(prob, what, settings, form, solver="clarabel"):
    """Solve with the settings of :data:`BOUND_RETRIES` in turn (Clarabel's; another
    solver: its own settings, once) until the field is certified (:data:`BOUND_CERTIFY`);
    an 'AlmostSolved' end kept comes with an AlmostSolvedWarning giving its gap;
    ``info.extra['bound']`` records what was done."""
    accept = settings.pop("accept_inaccurate", False)
    backend = solver_backend(solver)           # unknown, unavailable: refused here
    retries = BOUND_RETRIES if backend.name == "clarabel" else (dict(),)
    tries = [retries[0]] if any(k in settings for k in retries[-1]) else retries
    label = backend.label
    for attempt, extra in enumerate(tries):
        last = attempt == len(tries) - 1
        try:
            info = solve(prob, what=what, solver=solver, defer_certify=True,
                         **{**extra, **settings})
        except SolverError as err:
            kind = err.status.replace("_inaccurate", "")
            if (form, kind) in BOUND_HINTS:
                raise SolverError(f"{what}: solver status '{err.status}': "
                                  f"{BOUND_HINTS[form, kind]}", err.status) from None
            if err.status != "solver_error" or last:
                raise
            continue                           # a NumericalError: the next settings
        violation = max(_relative_violation(c) for c in prob.constraints)
        measures = info.extra.get("measures") or {}
        gap = measures.get("gap_rel", np.nan if info.status != cp.OPTIMAL else 0.0)
        info.extra["bound"] = dict(violation=violation, gap_rel=gap, status=info.status,
                                   settings=extra)
        if info.status == cp.OPTIMAL or accept:
            return info
        if violation <= BOUND_CERTIFY["feasibility"] and gap <= BOUND_CERTIFY["gap"]:
            warnings.warn(f"{what}: {label} stopped 'AlmostSolved'; the bound is its "
                          f"field's own value (largest relative violation {violation:.1e} "
                          f"<= {BOUND_CERTIFY['feasibility']:.0e}), within a relative gap "
                          f"of {gap:.1e} of the mesh's best", AlmostSolvedWarning,
                          stacklevel=3)
            return info
        if last:
            raise SolverError(
                f"{what}: {label} stopped 'AlmostSolved' with a field violating its "
                f"constraints by {violation:.1e} (> {BOUND_CERTIFY['feasibility']:.0e}) or "
                f"a relative gap {gap:.1e} (> {BOUND_CERTIFY['gap']:.0e}): not a certified "
                "bound", info.status)


def upper_bound(problem, solver="clarabel", **solver_settings):
    """The strict upper bound (module docstring): ``kinematic(problem, 'vertices')``."""
    return kinematic(problem, "vertices", solver, **solver_settings)


def _per_element(disc, values):
    out = np.zeros(disc.mesh.t.shape[1])
    np.add.at(out, disc.point_element, values)
    return out


def _load_vector(disc, problem, live):
    """f of the live (or dead) loads for the P2 velocities, integrated exactly (the
    thesis' 3-point rule for the body force, order 4 on the edges; same dofs)."""
    exact = discretise(disc.mesh)
    f = body_force_vector(exact, problem.body_live if live else problem.body_dead)
    if problem.pore_pressure is not None and problem.pore_pressure.live == live:
        facets, state = problem.boundary_states()
        v = np.asarray(problem.punch.velocity, float) if problem.punch else np.zeros(2)
        f = f + pore_load_vector(exact, problem.pore_nodal(live),
                                 [(facets[state[:, k] == "punch"], k) for k in (0, 1)],
                                 v / max(np.linalg.norm(v), 1e-300))
    for t in problem.tractions:
        if t.live == live and np.any(t.t):
            facets = boundary_facets(exact, t.where)
            if facets.size:
                f = f + traction_vector(exact, facets, tuple(t.t))
    return np.asarray(f, dtype=float)


def _velocity_conditions(disc, problem):
    """Fixed dofs, punched dofs and their scaled velocities (v / |v|)."""
    facets, state = problem.boundary_states()
    fixed, punched, values = [], [], []
    v = np.asarray(problem.punch.velocity, float) if problem.punch else np.zeros(2)
    for k in (0, 1):
        name = f"u^{k + 1}"
        for kind, store in (("fixed", fixed), ("punch", punched)):
            on = facets[state[:, k] == kind]
            if on.size:
                dofs = np.unique(disc.basis_u.get_dofs(on).all(name))
                store.append(dofs)
                if kind == "punch":
                    values.append(np.full(dofs.size, v[k] / np.linalg.norm(v)))
    fixed = np.unique(np.concatenate(fixed)) if fixed else np.zeros(0, int)
    punched = np.concatenate(punched) if punched else np.zeros(0, int)
    values = np.concatenate(values) if values else np.zeros(0)
    clash = np.intersect1d(fixed, punched)
    if clash.size and np.any(values[np.isin(punched, clash)]):
        raise ValueError(f"{clash.size} velocity dof(s) are both supported and moved by the "
                         "punch: let the supports and the punch select different facets")
    keep = ~np.isin(punched, fixed)
    return fixed, punched[keep], values[keep]


def local_gap(problem, lower, upper):
    """The bound gap of each element: eta_e = sum_j d . Lambda_ej - int_e sigma_L : eps(u_U).

    Each eta_e >= 0 (sigma_L is admissible everywhere; D(eps) >= sigma : eps), and their
    sum is upper.load - lower.load exactly (the virtual work of the statically admissible
    sigma_L on the mechanism u_U), so they say where the mesh loses the bracket."""
    disc = vertex_discretise(problem.mesh)
    B = assemble_B(disc)
    w = np.repeat(disc.weights, 4)
    scale = 1.0 if problem.punch is None else float(np.linalg.norm(problem.punch.velocity))
    eps = (B @ upper.velocity / w).reshape(-1, 3, 4)      # strain rate at the vertices
    sig = lower.sigma.reshape(-1, 3, 4)
    area = 3 * disc.weights.reshape(-1, 3)[:, 0]
    # int of a product of two linear fields: A / 12 (sum_j a_j b_j + sum_j a_j sum_k b_k)
    work = area / 12 * (np.einsum("ejk,ejk->e", sig, eps)
                        + np.einsum("ek,ek->e", sig.sum(axis=1), eps.sum(axis=1)))
    return upper.dissipation - work / scale
