"""The consolidation step of a saturated soil: Biot's principle after backward Euler, a cone
program (beyond the thesis; issue 54).

The static step (3.45) with a pore pressure p (continuous P1,
:mod:`pfem_skfem.discretisation.pressure`) beside the effective stresses sigma' (the
Gauss-point stresses of the thesis element). Tension positive, p compression positive,
total stress sigma = sigma' - alpha p I. For the step n -> n+1 of length dt:

.. math::
    \\begin{aligned}
    \\max_{\\sigma',\\,p}\\;
      & -\\tfrac12\\int(\\sigma'-\\sigma'_n):\\mathbb C^{-1}:(\\sigma'-\\sigma'_n)\\,dV
        -\\tfrac{\\Delta t}{2}\\int\\tfrac{k}{\\gamma_w}|\\nabla p-\\rho_w\\mathbf g|^2\\,dV \\\\
      & -\\int\\tfrac{(p-p_n)^2}{2M}\\,dV
        +\\Delta t\\int_{\\Gamma_q}\\bar q\\,p\\,dS \\\\
    \\text{s.t.}\\quad
      & \\int(\\sigma'-\\alpha p I):\\varepsilon(v)\\,dV = f(v)\\;\\forall v, \\\\
      & F(\\sigma')\\le 0,\\quad p=\\bar p\\text{ on }\\Gamma_p
        \\qquad (C.1)
    \\end{aligned}

How it comes from Biot's principle. The kinematic form of the step minimises, over the
displacement increment du and the water volume w = dt q that crosses each area during the
step, the stored energy of the skeleton, the storage energy M/2 (dzeta - alpha div du)^2 of
the water content zeta, the dissipation of Darcy's flow ``gamma_w |w|^2 / (2 k dt)`` less the work
rho_w g . w of the water's weight, less the work of the loads, subject to the mass balance
dzeta + div w = 0 (and w . n = - dt q_bar on Gamma_q). Its multiplier is p. Three Legendre
transforms give (C.1): the skeleton's energy becomes the complementary energy of sigma' (the
plastic part the indicator of the yield cone, as in (3.45)); min over w of
``gamma_w |w|^2 / (2 k dt) + w . (grad p - rho_w g)`` is
``- (dt/2) k/gamma_w |grad p - rho_w g|^2``
at w = - (k dt / gamma_w)(grad p - rho_w g), backward Euler of Darcy's law; the storage
energy becomes (p - p_n)^2 / 2M. What is left of the kinematic variables is du, the
multiplier of equilibrium of the total stress, as in (3.45).

The optimality conditions of (C.1) are the step:

* in sigma': C^-1 (sigma' - sigma'_n) + dI_B(sigma') contains eps(du), the elastoplastic
  return of (3.45) for the effective stress;
* in p (a test function dp of the P1 space, zero on Gamma_p): the discrete mass balance

  int dp alpha div(du) dV + dt int k/gamma_w (grad p - rho_w g) . grad dp dV
  + int (p - p_n) dp / M dV = dt int_Gamma_q q_bar dp dS,

  backward Euler of d(alpha eps_v + p/M)/dt + div q = 0 with q = - k/gamma_w (grad p - rho_w g);
* in du: equilibrium of the total stress.

Each term is concave (a negative semi-definite quadratic or linear) and the constraints are
the rows of (3.45) with the cones of its criterion: the problem class does not change, the
Darcy term is a sum of squares (Clarabel's quadratic cost, no new cone). dt = 0 is the
undrained step (p the multiplier of div du = 0 weakly, with 1/M = 0); dt k / h^2 large
the drained one.

It is stated in cvxpy as printed, in scaled variables (:class:`~.conic.Scaling`): stresses
and p in units of a stress of the problem, B in units of an element size, the objective in
units of stress^2 x compliance (the complementary energy order one). Sign convention as
:mod:`.static`: cvxpy's dual of the equilibrium of a maximisation is - du.
"""
from dataclasses import dataclass, field

import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from ..discretisation.pressure import drained_dofs, element_flux
from .conic import (Scaling, SolveInfo, point_multipliers, prescribed_values, solve,
                    solver_backend, split_dofs)


def _finite(name, value, low=-np.inf, *, strict=False, infinite=False):
    value = float(value)
    bad = (np.isnan(value) or (np.isinf(value) and not infinite)
           or (value <= low if strict else value < low))
    if bad:
        sign = ">" if strict else ">="
        raise ValueError(f"{name} must be {sign} {low:g}" + ("" if infinite else " and finite")
                         + f", got {value!r}")
    return value


@dataclass(frozen=True)
class SaturatedSoil:
    """A saturated soil: a skeleton of effective stresses and the water in its pores.

    Parameters
    ----------
    skeleton : the yield criterion of the effective stress (a
        :class:`~pfem_skfem.materials.YieldCriterion`), or None for an elastic skeleton.
    k : hydraulic conductivity (Darcy's permeability, length / time), >= 0; 0 is undrained.
    gamma_w : unit weight of water (force / volume), > 0.
    M : Biot's modulus (stress), > 0; inf (the default) for incompressible constituents.
    alpha : Biot's coefficient, in (0, 1]; 1 for incompressible grains.
    water_weight : rho_w g as a vector (force / volume): (0, -gamma_w) for the total pore
        pressure under gravity, (0, 0) (the default) for the excess pore pressure.
    """

    skeleton: object
    k: float
    gamma_w: float = 9.81
    M: float = np.inf
    alpha: float = 1.0
    water_weight: tuple = (0.0, 0.0)

    def __post_init__(self):
        _finite("k (hydraulic conductivity)", self.k, 0.0)
        _finite("gamma_w (unit weight of water)", self.gamma_w, 0.0, strict=True)
        _finite("M (Biot's modulus)", self.M, 0.0, strict=True, infinite=True)
        alpha = _finite("alpha (Biot's coefficient)", self.alpha, 0.0, strict=True)
        if alpha > 1:
            raise ValueError(f"alpha (Biot's coefficient) must lie in (0, 1], got {alpha!r}")
        weight = np.asarray(self.water_weight, dtype=float)
        if weight.shape != (2,) or not np.all(np.isfinite(weight)):
            raise ValueError(f"water_weight must be a finite vector (2,), got "
                             f"{self.water_weight!r}")
        norm = float(np.hypot(*weight))
        if norm and abs(norm / self.gamma_w - 1) > 1e-9:
            raise ValueError(f"water_weight (rho_w g) must be zero or of length gamma_w = "
                             f"{self.gamma_w:g}, got length {norm:g}")

    @property
    def k_over_gamma_w(self):
        """k / gamma_w: Darcy's flux per unit gradient of p."""
        return self.k / self.gamma_w

    def consolidation_coefficient(self, elastic):
        """c_v = k E_oed / gamma_w (E_oed the constrained modulus of ``elastic``), alpha = 1,
        1/M = 0: Terzaghi's coefficient of consolidation."""
        e_oed = elastic.lame_lambda + 2 * elastic.shear_modulus
        return self.k * e_oed / self.gamma_w


@dataclass
class Hydraulic:
    """The step's water boundaries: drained dofs with their pressure, and the inflow.

    Attributes
    ----------
    drained : (dofs, values): p = p_bar on these P1 dofs (boundary vertices).
    inflow : (n_p,) int q_bar N_p dS (:func:`~pfem_skfem.discretisation.pressure.inflow_vector`),
        or None: no prescribed flux (the other faces are impermeable).
    """

    drained: tuple = ((), ())
    inflow: np.ndarray = None

    @classmethod
    def drained_faces(cls, pressure, facets, p_bar=0.0, inflow=None):
        """p = p_bar on the vertices of the boundary ``facets`` (refused if one is not on the
        boundary); ``p_bar`` a number or a callable of the vertices' coordinates (2, n)."""
        dofs = drained_dofs(pressure, facets)
        x = pressure.basis.doflocs[:, dofs]
        values = p_bar(x) if callable(p_bar) else np.full(dofs.size, float(p_bar))
        return cls((dofs, np.asarray(values, dtype=float)), inflow)


@dataclass
class ConsolidationIncrement:
    """Solution of one step of (C.1).

    sigma : (n_points, 4) effective stresses at t_{n+1};  p : (n_p,) pore pressures;
    du : (n_u,) displacement increments;  reactions : (n_u,) B^T (sigma - alpha p I) - f on
    the supported dofs (zero on the free ones);  flux : (n_elements, 2) Darcy's flux;
    plastic_multiplier : (n_points,) integrated plastic multipliers (empty for an elastic
    skeleton);  info : solver report.
    """

    sigma: np.ndarray
    p: np.ndarray
    du: np.ndarray
    reactions: np.ndarray
    flux: np.ndarray
    info: SolveInfo
    plastic_multiplier: np.ndarray = field(default_factory=lambda: np.zeros(0))


def consolidation_increment(B, C, f, state, soil, pressure, dt, *, fixed, prescribed=((), ()),
                            hydraulic=None, solver="clarabel", **solver_settings):
    """Solve one consolidation step (C.1) (module docstring).

    Parameters
    ----------
    B : (4 n_points, n_u) sparse (3.41).  C : (4 n_points,)^2 sparse compliance (3.43).
    f : (n_u,) external forces at t_{n+1}.
    state : the step's start, with ``sigma`` (n_points, 4) and ``p`` (n_p,) (a
        :class:`ConsolidationIncrement`, or any object with both).
    soil : :class:`SaturatedSoil`.  pressure : its P1 field
        (:func:`~pfem_skfem.discretisation.pressure.pressure_field`).
    dt : the step's length, >= 0 (0: undrained).
    fixed, prescribed : the displacement supports, as in
        :func:`~pfem_skfem.problems.static.static_increment`.
    hydraulic : :class:`Hydraulic` (drained dofs, inflow); None: every face impermeable.
    solver, solver_settings : as :func:`~pfem_skfem.problems.static.static_increment`.

    Returns
    -------
    ConsolidationIncrement
    """
    solver_backend(solver)                 # an unknown or unavailable solver: refused now
    dt = _finite("dt (time step)", dt, 0.0)
    n_s, n_u = B.shape
    n = n_s // 4
    sigma_n = np.asarray(state.sigma, dtype=float).reshape(n, 4)
    p_n = np.asarray(state.p, dtype=float)
    f = np.asarray(f, dtype=float)
    if p_n.shape != (pressure.n_p,) or f.shape != (n_u,):
        raise ValueError(f"state.p must have shape ({pressure.n_p},) and f ({n_u},), got "
                         f"{p_n.shape} and {f.shape}")
    hydraulic = hydraulic or Hydraulic()
    dofs, p_bar = check_hydraulic(hydraulic, pressure)
    free, P = split_dofs(n_u, fixed, prescribed[0])
    du_P = prescribed_values(P, prescribed[1])
    # stresses (and p) in units of the stresses of the problem: those reached, the loads',
    # the drained faces', the elastic stress of the prescribed motion (u_P then order one)
    sc = Scaling.from_operators(B, C, 1.0)
    level = max(float(np.sqrt(np.mean(sigma_n ** 2))), float(np.abs(p_n).max(initial=0.0)),
                float(np.abs(f).max()) / sc.length, float(np.abs(p_bar).max(initial=0.0)),
                float(np.abs(du_P).max(initial=0.0)) * sc.length / sc.compliance)
    if level == 0.0:
        level = soil.skeleton.strength_scale() if soil.skeleton is not None else 1.0
    sc = Scaling(stress=level, length=sc.length, compliance=sc.compliance)
    supports = (free, P, du_P, dofs, p_bar)
    return _consolidation_increment(B, C, f, (sigma_n, p_n), soil, pressure, dt, supports,
                                    hydraulic.inflow, sc, dict(solver_settings, solver=solver))


def check_hydraulic(hydraulic, pressure):
    """The drained dofs and values, refused unless on boundary vertices; the inflow's shape."""
    dofs = np.asarray(hydraulic.drained[0], dtype=int).ravel()
    values = np.asarray(hydraulic.drained[1], dtype=float).ravel()
    if values.shape != dofs.shape or not np.all(np.isfinite(values)):
        raise ValueError("drained: one finite pressure per drained dof")
    if np.unique(dofs).size != dofs.size:
        raise ValueError("drained dofs must not repeat")
    if dofs.size and (dofs.min() < 0 or dofs.max() >= pressure.n_p
                      or not np.all(np.isin(dofs, pressure.drainable()))):
        raise ValueError("drained dofs must be vertices on the boundary (a drained face is "
                         "a boundary face) or of a free-draining region")
    inflow = hydraulic.inflow
    if inflow is not None and (np.shape(inflow) != (pressure.n_p,)
                               or not np.all(np.isfinite(inflow))):
        raise ValueError(f"inflow must be a finite vector ({pressure.n_p},)")
    return dofs, values


def _consolidation_increment(B, C, f, start, soil, pressure, dt, supports, inflow, sc,
                             solver_settings):
    """(C.1) in the scaled variables of ``sc``; see :func:`consolidation_increment`."""
    free, P, du_P, drained, p_bar = supports
    sigma_n, p_n = start
    n_u, n = B.shape[1], B.shape[0] // 4
    u_ref = sc.stress * sc.compliance / sc.length          # a strain of the yield stress x h
    Bh = (B / sc.length).tocsc()
    B_F, B_P = Bh[:, free], Bh[:, P]
    f_h = f / (sc.stress * sc.length)
    Ch = (C / sc.compliance).tocsr()
    s_n, p_nh = sigma_n.ravel() / sc.stress, p_n / sc.stress
    # Darcy: (dt/2) sum_e k/gamma_w V_e |G_e p - rho_w g|^2 = 1/2 |D p - d|^2 (scaled)
    root = np.repeat(np.sqrt(dt * soil.k_over_gamma_w * pressure.cell_volume / sc.compliance), 2)
    D = sp.diags(root) @ pressure.gradient
    d = root * np.tile(np.asarray(soil.water_weight, dtype=float) / sc.stress,
                       pressure.cell_volume.size)
    storage = pressure.storage / (soil.M * sc.compliance)   # int N N dV / M, scaled
    inflow_h = (0.0 if inflow is None
                else dt * np.asarray(inflow) / (sc.stress * sc.compliance))
    I_p = pressure.total_stress_map()                      # p -> p I at the stress points

    S = cp.Variable((n, 4))                      # sigma'_{n+1} / sigma_ref, one row per point
    s = cp.vec(S, order="C")
    p = cp.Variable(pressure.n_p)                # p_{n+1} / sigma_ref at the vertices
    total = s - soil.alpha * (I_p @ p)           # the total stress sigma' - alpha p I
    complementary = 0.5 * cp.quad_form(s, cp.psd_wrap(Ch)) - (Ch @ s_n) @ s
    darcy = 0.5 * cp.sum_squares(D @ p - d) if dt * soil.k > 0 else 0
    stored = (0.5 * cp.quad_form(p - p_nh, cp.psd_wrap(storage))
              if np.isfinite(soil.M) else 0)
    work_P = _prescribed_work(du_P / u_ref, B_P, total, f_h[P])
    objective = cp.Maximize(-complementary            # complementary energy of sigma'
                            - darcy                   # Darcy's dissipation over dt
                            - stored                  # storage (p - p_n)^2 / 2M
                            + (inflow_h @ p if inflow is not None else 0)   # dt q_bar p
                            + work_P)                 # reactions on prescribed motions
    equilibrium = B_F.T @ total == f_h[free]     # B^T (sigma' - alpha p I) = f
    constraints = [equilibrium]
    if drained.size:
        constraints.append(p[drained] == p_bar / sc.stress)       # p = p_bar on Gamma_p
    if soil.skeleton is not None:
        yield_cone = soil.skeleton.scaled(sc.stress).constraint(S)  # F(sigma'_j) <= 0
        constraints.append(yield_cone)
    problem = cp.Problem(objective, constraints)
    info = solve(problem, what="consolidation step (C.1)", **solver_settings)

    sigma, p_new = S.value * sc.stress, p.value * sc.stress
    du = np.zeros(n_u)
    du[free] = -equilibrium.dual_value * u_ref
    du[P] = du_P
    reactions = B.T @ (sigma.ravel() - soil.alpha * (I_p @ p_new)) - f
    reactions[free] = 0.0
    flux = element_flux(pressure, p_new, soil.k_over_gamma_w, soil.water_weight)
    multiplier = (point_multipliers(yield_cone.dual_value[0], n) * sc.length * u_ref
                  if soil.skeleton is not None else np.zeros(0))
    return ConsolidationIncrement(sigma, p_new, du, reactions, flux, info, multiplier)


def _prescribed_work(u_P, B_P, total, f_P):
    """The reactions' work on the prescribed motions, u_P^T (B_P^T sigma_total - f_P)."""
    return u_P @ (B_P.T @ total - f_P) if u_P.size else 0


@dataclass
class PoreState:
    """A state to start a step from: effective stresses (n_points, 4) and pore pressures."""

    sigma: np.ndarray
    p: np.ndarray

    @classmethod
    def zero(cls, disc, pressure):
        """At rest: no effective stress, no pore pressure."""
        return cls(np.zeros((disc.n_points, 4)), np.zeros(pressure.n_p))
