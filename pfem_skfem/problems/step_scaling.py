"""The scaling of the dynamic step (4.23) as one named pair: ``scaled, inverse = scale_step(...)``
and ``inverse.invert(solution)``, and the step's answer, :class:`DynamicIncrement`.

Clarabel's tolerances are absolute, so the step is stated in scaled variables whose data
are near order one (the module docstring of :mod:`~pfem_skfem.problems.dynamic` says why
r = rho~ v_n / dt + r'):

* stresses in ``stress``, B in its median entry ``length``, forces in stress x length;
* the dynamic force r' in ``dynamic_force``, the displacement increment in ``displacement``
  (the scaled dual of equilibrium is du / displacement);
* the objective in force x displacement (``j_ref``), D and C in their median diagonals.

:func:`scale_step` makes a :class:`ScaledStep` (what every statement of the step reads:
the scaled operators, loads, state, supports and weights) and a :class:`StepInverse`
(what maps a :class:`ScaledSolution` back to a physical
:class:`~pfem_skfem.problems.step_scaling.DynamicIncrement`). Nothing in either is an absolute
constant: a c = 0 run is density-invariant bit for bit.
"""
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from .conic import SolveInfo, point_multipliers, prescribed_values, split_dofs


@dataclass(frozen=True)
class DynamicScales:
    """Reference stress, displacement increment and dynamic force r' of one step of (4.23).

    Forces are measured in stress x length (length = median ``|B|`` entry), the
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
    density stress x ``|B| / |A|`` that balances stress gradients.
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


@dataclass
class DynamicIncrement:
    """Solution of one step of (4.23).

    Attributes
    ----------
    sigma : (n_points, 4) stresses at t_{n+1}.
    du : (n_u,) displacement increments.
    v : (n_u,) velocities at t_{n+1} (4.7).
    r : (n_r,) dynamic forces r' = r - rho~ v_n/dt.
    reactions : (n_u,) B^T sigma + A^T r' - f' on supported dofs (zero on free dofs).
    plastic_multiplier : (n_points,) integrated plastic multipliers (zero if elastic).
    info : solver report.
    scales : the solution's own magnitudes, a good ``scaling`` for the next step.
    p, q : (nc,) normal and tangential contact forces of the step (empty without
        contacts), the forces of the momentum balance, i.e. theta1 times the
        multipliers of the theta1-weighted equilibrium.
    parts : what other terms of the step return, by name (``spring_forces``, ...).
    """

    sigma: np.ndarray
    du: np.ndarray
    v: np.ndarray
    r: np.ndarray
    reactions: np.ndarray
    plastic_multiplier: np.ndarray
    info: SolveInfo
    scales: DynamicScales = None
    p: np.ndarray = None
    q: np.ndarray = None
    parts: dict = field(default_factory=dict)


class StepUnits:
    """What a scaled step (dynamic or static) derives from its ``Bh``, ``stress``, ``length``
    and ``u_ref``: the stress points ``n``, the dofs ``n_u``, the unit of force and of the
    objective."""

    @property
    def n(self):
        """Stress points."""
        return self.Bh.shape[0] // 4

    @property
    def n_u(self):
        return self.Bh.shape[1]

    @property
    def force(self):
        return self.stress * self.length

    @property
    def j_ref(self):
        return self.force * self.u_ref


@dataclass
class ScaledStep(StepUnits):
    """The scaled data of one step of (4.23), read by every statement of it.

    ops : the step's DynamicOperators (D, G, C in physical units; ``Dh``, ``Ch`` scaled);
    Bh (4n, n_u), Ah (n_r, n_u) : B / length, A r_ref / force;
    f_h : f' / force;  s_n : sigma_n / stress (4n,);  v_h : v_n dt / u_ref;
    free, P : the free and the prescribed dofs;  u_P : the prescribed increments / u_ref;
    kappa, kappa_C : the weights of dt^2 r'^T D r' and ds^T C ds in units of j_ref;
    stress, length, u_ref, r_ref, force (stress x length), j_ref (force x u_ref),
    d_ref, c_ref (medians of diag D and diag C; None without C), dt, theta1 : the units.
    """

    ops: object
    Bh: object
    Ah: object
    f_h: np.ndarray
    s_n: np.ndarray
    v_h: np.ndarray
    free: np.ndarray
    P: np.ndarray
    u_P: np.ndarray
    kappa: float
    kappa_C: float
    stress: float
    length: float
    u_ref: float
    r_ref: float
    d_ref: float
    c_ref: float = None

    @property
    def n_r(self):
        return self.Ah.shape[0]

    @property
    def dt(self):
        return self.ops.theta.dt

    @property
    def theta1(self):
        return self.ops.theta.theta1

    @cached_property
    def Dh(self):
        """D / d_ref (CSR)."""
        return (self.ops.D / self.d_ref).tocsr()

    @cached_property
    def Ch(self):
        """C / c_ref (CSR), or None for a rigid-plastic step."""
        return None if self.ops.C is None else (self.ops.C / self.c_ref).tocsr()


@dataclass
class ScaledSolution:
    """A statement's answer in the scaled variables: the total stress s (4n,) and r' (n_r,),
    the dual of equilibrium on the free dofs (-du_F / u_ref) and each yield cone's first
    dual, the solver's report, and ``parts``: what the terms read off (contact forces, ...)."""

    s: np.ndarray
    r: np.ndarray
    dual_equilibrium: np.ndarray
    dual_yield: np.ndarray
    info: SolveInfo
    parts: dict = field(default_factory=dict)


@dataclass
class StepInverse:
    """What maps a :class:`ScaledSolution` back to physical units (:meth:`invert`)."""

    step: ScaledStep
    f: np.ndarray                 # f' (physical)
    v_n: np.ndarray
    du_P: np.ndarray
    scales: DynamicScales         # the scales the step was stated in
    plastic: bool                 # a yield criterion (its multipliers, a fixed stress scale)
    terms: tuple = ()

    def invert(self, solution):
        """The :class:`~pfem_skfem.problems.step_scaling.DynamicIncrement` of ``solution``: the
        stresses, r', du (-dual x u_ref on the free dofs, the prescribed values on P), the
        reactions B^T sigma + A^T r' - f' on the supported dofs (each term's forces taken
        off), the plastic multipliers and the scales for the next step."""
        st, ops = self.step, self.step.ops
        n, n_u = st.n, st.n_u
        sigma = solution.s.reshape(n, 4) * st.stress
        r = solution.r * st.r_ref
        du = np.zeros(n_u)
        du[st.free] = -solution.dual_equilibrium * st.u_ref
        du[st.P] = self.du_P
        inc = DynamicIncrement(sigma, du, ops.theta.velocity(du, self.v_n), r,
                               ops.B.T @ sigma.ravel() + ops.A.T @ r - self.f, None,
                               solution.info, None, np.zeros(0), np.zeros(0))
        for term in self.terms:                  # contact forces, ... in physical units
            term.invert(solution, inc, st)
        inc.reactions[st.free] = 0.0
        inc.plastic_multiplier = (point_multipliers(solution.dual_yield, n) * st.length * st.u_ref
                                  if self.plastic else np.zeros(n))
        inc.scales = self.next_scales(sigma, du, r)
        return inc

    def next_scales(self, sigma, du, r):
        """The solution's own magnitudes, a good scaling for the next step; the old scale kept
        where a field vanished (and the stress scale of a plastic step: its strength)."""
        sc = self.scales
        s_max, u_max, r_max = np.abs(sigma).max(), np.abs(du).max(), np.abs(r).max()
        return DynamicScales(
            stress=sc.stress if self.plastic or s_max < 1e-9 * sc.stress else s_max,
            displacement=u_max if u_max > 1e-9 * sc.displacement else sc.displacement,
            dynamic_force=r_max if r_max > 1e-9 * sc.dynamic_force else sc.dynamic_force)


def scale_step(ops, f, sigma_n, v_n, criterion, supports, scaling=None):
    """(ScaledStep, StepInverse) of one step of (4.23).

    ops : DynamicOperators;  f : (n_u,) f' (the theta-weighted loads less B^T sigma_n terms,
    ``ThetaMethod.equilibrium_rhs``);  sigma_n : (n, 4);  v_n : (n_u,);  criterion : the yield
    criterion or None (its ``strength_scale`` for a first step's stress scale);
    supports : (fixed dofs, prescribed dofs, their increments);  scaling : DynamicScales,
    by default :func:`estimate_scales`.
    """
    fixed, prescribed, du_prescribed = supports
    B, C, A, D = ops.B, ops.C, ops.A, ops.D
    th = ops.theta
    n = B.shape[0] // 4
    sigma_n = np.asarray(sigma_n, dtype=float).reshape(n, 4)
    v_n = np.asarray(v_n, dtype=float)
    free, P = split_dofs(B.shape[1], fixed, prescribed)
    du_P = prescribed_values(P, du_prescribed)
    # units: medians of |B|, diag D, diag C; stress, displacement, r' from the scales
    length = float(np.median(np.abs(B.data)))
    d_ref = float(np.median(D.diagonal()))
    c_ref = float(np.median(C.diagonal())) if C is not None else None
    sc = scaling or estimate_scales(ops, f, v_n, sigma_n, free, criterion, du_P)
    stress, u_ref, r_ref = sc.stress, sc.displacement, sc.dynamic_force
    force = stress * length                                  # B^T sigma, f in force
    j_ref = force * u_ref                                    # objective; du = u_ref x dual
    step = ScaledStep(
        ops=ops, Bh=(B / length).tocsc(), Ah=(A * (r_ref / force)).tocsc(),
        f_h=f / force, s_n=sigma_n.ravel() / stress, v_h=v_n * th.dt / u_ref, free=free, P=P,
        u_P=du_P / u_ref,
        kappa=th.dt ** 2 * r_ref ** 2 * d_ref / j_ref,           # weight of dt^2 r'^T D r'
        kappa_C=stress ** 2 * c_ref / j_ref if C is not None else 0.0,   # of ds^T C ds
        stress=stress, length=length, u_ref=u_ref, r_ref=r_ref, d_ref=d_ref, c_ref=c_ref)
    return step, StepInverse(step, f, v_n, du_P, sc, criterion is not None)

