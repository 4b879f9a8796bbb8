"""Water and mud as PFEM materials: Newtonian and Bingham fluids in the step (4.23).

Beyond the thesis: the PFEM was born for free-surface fluids (Idelsohn, Onate & Del Pin
2004), and (4.23) already holds what an incompressible fluid needs. The stress of a
point is sigma = sigma_p + sigma_v, as for the rate terms of mu(I)
(:class:`~pfem_skfem.materials.rate.ViscousStress`):

* sigma_p, the rigid-plastic part, lies in a cone of zero dilation whose radius is the
  fluid's yield stress, sqrt((sx - sy)^2 + 4 sxy^2) <= 2 tau_y in plane strain
  (:class:`~pfem_skfem.materials.TrescaField`), sqrt(J2) <= tau_y in axisymmetry
  (:class:`~pfem_skfem.materials.VonMisesField`). Its multiplier makes the flow
  isochoric, so the pressure is the multiplier of incompressibility. For water
  (tau_y = 0) the cone is the single point of zero deviator, which the problems state
  as equalities (its ``PRESSURE_ROWS``): sigma_p is a pressure;
* sigma_v, a deviator, adds - dt sum_j w_j tau_j^2 / (2 mu) to the objective (the
  complementary viscous dissipation: a diagonal block of Clarabel's P), so that at a
  flowing point the shear stress is tau_y + mu gamma_dot, gamma_dot the full shear rate
  sqrt(2 D':D'): Bingham's law (tau_y = 0: Newton's, sigma' = 2 mu D'). mu = 0
  (inviscid water) states no sigma_v.

A fluid is rigid-plastic (no elasticity: C = 0 in (4.23)) and keeps no absolute stress:
its stresses are scaled by the scene's rho g L, so that rho, tau_y and mu multiplied by
one factor leave a run the same bit for bit.
"""
from dataclasses import dataclass

import numpy as np

from .axisymmetric import VonMisesField, mean_stress
from .checks import _is_real
from .criteria import TrescaField
from .pfem import PFEMMaterial
from .rate import ViscousStress


def _check_nonnegative(name, value):
    if not _is_real(value) or not np.isfinite(value) or value < 0:
        raise ValueError(f"{name} must be finite and >= 0, got {value!r}")


class _Fluid:
    """What a Bingham and a Newtonian fluid share (tau_y, mu; plane strain)."""

    lagged = False              # neither the cone nor the viscosity depends on the stress
    needs_container = True      # a Scene refuses a fluid region without rigid bodies

    @property
    def c(self):
        """The yield stress: a scene's stress scale without gravity."""
        return float(self.tau_y)

    def radius(self, n):
        """The cone's radius at n points: 2 tau_y (sqrt((sx-sy)^2 + 4 sxy^2) = 2 tau)."""
        return np.full(n, 2.0 * self.tau_y)

    def cone(self, sigma_m, stress_scale=1.0, *, shear_rate=None):
        """:class:`~pfem_skfem.materials.TrescaField` of radius 2 tau_y (0: water)."""
        return TrescaField(self.radius(len(sigma_m)))

    def strength_scale(self, sigma_m, stress_scale=1.0):
        """The scene's stress scale rho g L (a fluid's stresses are its pressures)."""
        return stress_scale

    def viscous(self, sigma_m, stress_scale, shear_rate, weights):
        """:class:`~pfem_skfem.materials.rate.ViscousStress` of viscosity mu; none if mu = 0."""
        if self.mu == 0:
            return None
        return ViscousStress(np.full(len(weights), float(self.mu)), weights, hoop=self.hoop)


class _Axisymmetric:
    """The same in axisymmetry: sqrt(J2) <= tau_y, the hoop stress and rate counted."""

    hoop = True

    @staticmethod
    def mean_stress(sigma):
        """I1/3 (the hoop stress counts)."""
        return mean_stress(sigma)

    def radius(self, n):
        """sqrt(J2) <= tau_y."""
        return np.full(n, float(self.tau_y))

    def cone(self, sigma_m, stress_scale=1.0, *, shear_rate=None):
        """:class:`~pfem_skfem.materials.VonMisesField` of radius tau_y (0: water)."""
        return VonMisesField(self.radius(len(sigma_m)))


@dataclass(frozen=True)
class BinghamFluid(_Fluid, PFEMMaterial):
    """Mud: a Bingham fluid of yield stress tau_y and plastic viscosity mu, incompressible.

    .. math::
        \\tau = \\tau_y + \\mu\\,\\dot\\gamma \\;\\text{where it flows}, \\quad
        \\tau \\le \\tau_y \\;\\text{where it is rigid}, \\quad
        \\operatorname{tr} D = 0

    in plane strain tau the radius of the in-plane Mohr circle and gamma_dot =
    sqrt((e_x - e_y)^2 + g_xy^2) (rates); in simple shear tau = tau_xy and gamma_dot =
    du/dy. Its cone is :class:`~pfem_skfem.materials.TrescaField` of radius 2 tau_y, its
    viscous stress :class:`~pfem_skfem.materials.rate.ViscousStress` of viscosity mu.

    Parameters
    ----------
    tau_y : yield stress [Pa], > 0.   mu : plastic viscosity [Pa s], >= 0.
    """

    tau_y: float
    mu: float = 0.0

    name = "Bingham fluid"
    geometries = ("plane",)
    counterpart = "BinghamFluidAxisymmetric"

    def __post_init__(self):
        if not (_is_real(self.tau_y) and np.isfinite(self.tau_y) and self.tau_y > 0):
            raise ValueError(f"tau_y (yield stress) must be positive and finite, got "
                             f"{self.tau_y!r} (no yield stress: NewtonianFluid)")
        _check_nonnegative("mu (viscosity)", self.mu)


@dataclass(frozen=True)
class NewtonianFluid(_Fluid, PFEMMaterial):
    """Water: an incompressible Newtonian fluid of viscosity mu >= 0 (0: inviscid),
    sigma = -p I + 2 mu D', tr D = 0: a Bingham fluid without yield stress, whose cone of
    radius zero makes the rigid-plastic stress a pressure.

    Parameters
    ----------
    mu : dynamic viscosity [Pa s], >= 0 (water at 20 C: 1.0e-3).
    """

    mu: float = 0.0

    tau_y = 0.0
    name = "Newtonian fluid"
    geometries = ("plane",)
    counterpart = "NewtonianFluidAxisymmetric"

    def __post_init__(self):
        _check_nonnegative("mu (viscosity)", self.mu)


@dataclass(frozen=True)
class BinghamFluidAxisymmetric(_Axisymmetric, BinghamFluid):
    """:class:`BinghamFluid` in axisymmetry: sqrt(J2) <= tau_y
    (:class:`~pfem_skfem.materials.VonMisesField`, the hoop stress read), the viscous
    deviator with its hoop component, gamma_dot = sqrt(2 D':D') the hoop rate counted;
    in simple shear sqrt(J2) = ``|tau|`` as in the plane."""

    name = "Bingham fluid, axisymmetric"
    geometries = ("axisymmetric",)
    counterpart = "BinghamFluid"


@dataclass(frozen=True)
class NewtonianFluidAxisymmetric(_Axisymmetric, NewtonianFluid):
    """:class:`NewtonianFluid` in axisymmetry (sigma' = 2 mu D', the hoop rate counted)."""

    name = "Newtonian fluid, axisymmetric"
    geometries = ("axisymmetric",)
    counterpart = "NewtonianFluid"
