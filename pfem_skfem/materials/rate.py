"""Rate-dependent friction: the mu(I) rheology of dense granular flow (Jop, Forterre &
Pouliquen 2006) as a PFEM material, beyond the thesis (its 6.4.3 and 7.2.3 name rate
dependence as the cure for the columns' run-out), and the rate terms it adds to the
dynamic step (:class:`ViscousStress`, :class:`RateDissipation`).

.. math::
    \\mu(I) = \\mu_s + \\frac{\\mu_2 - \\mu_s}{1 + I_0 / I}, \\qquad
    I = \\frac{\\dot\\gamma\\, d}{\\sqrt{p / \\rho_s}}

with the shear rate gamma_dot = sqrt((e_x - e_y)^2 + g_xy^2) (rates; Jop's
sqrt(2 D:D) for an isochoric plane flow) and the pressure p = -(sx + sy)/2. In plane
strain with zero dilation the yield set is the circle R <= mu(I) p, R the radius of the
in-plane Mohr circle, which is the zero-dilation Mohr-Coulomb cone of [80] with
sin(phi) replaced by mu(I) at each stress point (so mu is Jop's ``|tau| / p``).
"""
from dataclasses import dataclass

import numpy as np

from .axisymmetric import VonMisesField, mean_stress
from .checks import _check_positive
from .criteria import TrescaField
from .elastic import Elastic
from .pfem import PFEMMaterial

LAGS = ("friction", "viscosity", "implicit")


# -- the rate terms of the dynamic step (the solvers of problems/dynamic.py state them) ------
@dataclass(frozen=True)
class ViscousStress:
    """A viscous stress beside the yield cone (see ``viscous`` of
    :func:`~pfem_skfem.problems.dynamic.dynamic_increment`): eta (n_points,) viscosities
    > 0, weights (n_points,) the stress points' weights; ``hoop``: the deviator has the
    hoop component of axisymmetry (3 components, not 2)."""

    eta: np.ndarray
    weights: np.ndarray
    hoop: bool = False

    def __post_init__(self):
        eta, w = np.asarray(self.eta, dtype=float), np.asarray(self.weights, dtype=float)
        if eta.shape != w.shape or not np.all(np.isfinite(eta)) or np.any(eta <= 0):
            raise ValueError("eta (viscosities) must be positive, one per stress point")


@dataclass(frozen=True)
class RateDissipation:
    """The rate part of mu(I) at frozen pressure beside the yield cone (``viscous`` of
    :func:`~pfem_skfem.problems.dynamic.dynamic_increment`): per point
    c_j = (mu_2 - mu_s) p_j I_0 / kappa_j, kappa_j = d / sqrt(p_j / rho_s),
    tau_max_j = (mu_2 - mu_s) p_j (both > 0), and the stress points' weights; ``hoop`` as
    :class:`ViscousStress`."""

    c: np.ndarray
    tau_max: np.ndarray
    weights: np.ndarray
    hoop: bool = False

    def __post_init__(self):
        for name in ("c", "tau_max"):
            value = np.asarray(getattr(self, name), dtype=float)
            if value.shape != np.shape(self.weights) or not np.all(np.isfinite(value)) \
                    or np.any(value <= 0):
                raise ValueError(f"{name} must be positive, one per stress point")



# -- mu(I) ----------------------------------------------------------------------------------
@dataclass(frozen=True)
class MuIRheology(PFEMMaterial):
    """mu(I) friction as a PFEM material: the pressure of every stress point lagged (the
    previous pass's smoothed mean stress) as in the zero-dilation scheme of [80], the shear
    rate entering in one of three ways. ``lag="friction"``: the whole of mu(I) in the cone,
    at the previous pass's shear rate,

    .. math::
        \\sqrt{(\\sigma_x-\\sigma_y)^2 + 4\\tau_{xy}^2} \\le k_j, \\\\
        k_j = \\max\\bigl(2\\,\\mu(I_j)\\, p_j,\\; k_{min}\\bigr), \\\\
        I_j = \\frac{\\dot\\gamma_j d}{\\sqrt{\\max(p_j, p_{min}) / \\rho_s}}

    (the rate enters explicitly: its fixed point is not stable at practical time steps).
    ``lag="viscosity"``: mu_s in the cone (k_j = max(2 mu_s p_j, k_min)) and the rest as a
    viscous stress of lagged viscosity (:class:`ViscousStress`),

    .. math::
        \\eta_j = \\frac{(\\mu(I_j) - \\mu_s)\\, p_j}{\\dot\\gamma_j}
               = \\frac{(\\mu_2 - \\mu_s)\\, d \\sqrt{\\rho_s \\max(p_j, p_{min})}}{I_0 + I_j}

    finite as gamma_dot -> 0, so that the step is implicit in the shear rate; at the
    fixed point R = mu_s p + eta gamma_dot = mu(I) p at every flowing point.
    ``lag="implicit"``: mu_s in the cone and the rate part of the dissipation of mu(I) in
    the step at frozen (lagged) pressure,
    D(gamma_dot) = (mu_2 - mu_s) p [gamma_dot - (I_0 / kappa) ln(1 + kappa gamma_dot / I_0)],
    kappa = d / sqrt(p / rho_s), stated by its conjugate

    .. math::
        D^*(\\tau) = \\frac{(\\mu_2 - \\mu_s) p I_0}{\\kappa}
                    \\left(-s - \\ln(1 - s)\\right), \\quad s = \\frac{\\tau}{(\\mu_2 - \\mu_s) p}

    (:class:`RateDissipation`, exponential cones): within the
    step R = mu(I) p at the step's own shear rate.

    Parameters
    ----------
    mu_s : static friction coefficient (I -> 0), > 0.
    mu_2 : limiting friction coefficient (I -> inf), >= mu_s (mu_2 = mu_s: rate independent).
    I_0 : the inertial number at which mu is half-way from mu_s to mu_2, > 0.
    d : grain diameter [m], > 0.   rho_s : grain (solid) density [kg/m3], > 0.
    p_min : least pressure in I, in units of the problem's stress scale (where p -> 0 at a
        free surface the ratio gamma_dot / sqrt(p) is not defined).
    k_min : least cone radius in units of the stress scale (as
        :class:`~pfem_skfem.materials.ZeroDilationMohrCoulomb`).
    elastic : :class:`~pfem_skfem.materials.Elastic` or None (rigid-plastic). The shear
        rate is that of the step's total strain, the plastic one for a rigid-plastic
        material and in steady flow. ``lag="viscosity"`` is rigid-plastic only.
    lag : "friction", "viscosity" or "implicit" (above).
    """

    mu_s: float = 0.38
    mu_2: float = 0.64
    I_0: float = 0.279
    d: float = 0.53e-3
    rho_s: float = 2450.0
    p_min: float = 1e-3
    k_min: float = 0.005
    elastic: Elastic = None
    lag: str = "viscosity"

    name = "mu(I), lagged"
    lagged = True              # the cone depends on the mean stress and the shear rate
    rate_dependent = True      # lagged_step hands it the previous pass's shear rate
    hoop = False               # plane: the in-plane deviator is the whole deviator
    geometries = ("plane",)    # a Scene refuses it in another geometry, naming:
    counterpart = "MuIRheologyAxisymmetric"

    def __post_init__(self):
        for name in ("mu_s", "I_0", "d", "rho_s", "p_min", "k_min"):
            _check_positive(name, getattr(self, name))
        if not np.isfinite(self.mu_2) or self.mu_2 < self.mu_s:
            raise ValueError(f"mu_2 must be finite and >= mu_s = {self.mu_s!r}, got {self.mu_2!r}")
        if self.lag not in LAGS:
            raise ValueError(f"lag must be one of {LAGS}, got {self.lag!r}")
        if self.lag != "friction" and self.elastic is not None:
            raise ValueError(f"lag={self.lag!r} is rigid-plastic only: elastic must be None")

    @property
    def phi(self):
        """The static friction angle in degrees, sin(phi) = mu_s (a scene's Jaky K0 reads it)."""
        return float(np.degrees(np.arcsin(min(self.mu_s, 1.0))))

    def friction(self, inertial_number):
        """mu(I) = mu_s + (mu_2 - mu_s) I / (I_0 + I)."""
        I = np.asarray(inertial_number, dtype=float)
        return self.mu_s + (self.mu_2 - self.mu_s) * I / (self.I_0 + I)

    def inertial_number(self, shear_rate, sigma_m, stress_scale=1.0):
        """I = gamma_dot d / sqrt(max(p, p_min) / rho_s), p = -sigma_m."""
        p = np.maximum(-np.asarray(sigma_m, dtype=float), self.p_min * stress_scale)
        return np.abs(np.asarray(shear_rate, dtype=float)) * self.d / np.sqrt(p / self.rho_s)

    def cone_friction(self, sigma_m, stress_scale, shear_rate):
        """The friction of the cone: mu(I_j) (lag 'friction') or mu_s (the others)."""
        if self.lag != "friction":
            return self.mu_s
        return self.friction(self.inertial_number(shear_rate, sigma_m, stress_scale))

    def radius(self, sigma_m, stress_scale, shear_rate):
        """k_j = max(2 mu p_j, k_min), mu = mu(I_j) (lag 'friction') or mu_s ('viscosity')."""
        mu = self.cone_friction(sigma_m, stress_scale, shear_rate)
        return np.maximum(-2 * mu * np.asarray(sigma_m, dtype=float), self.k_min * stress_scale)

    def viscosity(self, sigma_m, stress_scale, shear_rate):
        """eta_j = (mu_2 - mu_s) d sqrt(rho_s max(p_j, p_min)) / (I_0 + I_j)."""
        p = np.maximum(-np.asarray(sigma_m, dtype=float), self.p_min * stress_scale)
        I = self.inertial_number(shear_rate, sigma_m, stress_scale)
        return (self.mu_2 - self.mu_s) * self.d * np.sqrt(self.rho_s * p) / (self.I_0 + I)

    def viscous(self, sigma_m, stress_scale, shear_rate, weights):
        """The pass's rate stress: ViscousStress (lag 'viscosity'), RateDissipation
        ('implicit'), None for lag 'friction' or mu_2 = mu_s."""
        if self.lag == "friction" or self.mu_2 == self.mu_s:
            return None
        if self.lag == "implicit":
            p = np.maximum(-np.asarray(sigma_m, dtype=float), self.p_min * stress_scale)
            tau_max = (self.mu_2 - self.mu_s) * p
            kappa = self.d / np.sqrt(p / self.rho_s)
            return RateDissipation(tau_max * self.I_0 / kappa, tau_max, weights, hoop=self.hoop)
        rate = np.zeros(len(sigma_m)) if shear_rate is None else shear_rate
        return ViscousStress(self.viscosity(sigma_m, stress_scale, rate), weights, hoop=self.hoop)

    def cone(self, sigma_m, stress_scale=1.0, *, shear_rate=None):
        """The pass's criterion: :class:`TrescaField` of the radii (no rate: mu_s)."""
        rate = np.zeros(len(sigma_m)) if shear_rate is None else shear_rate
        return TrescaField(self.radius(sigma_m, stress_scale, rate))

    def strength_scale(self, sigma_m, stress_scale=1.0):
        """A stress of the step (half the median radius at mu_s), to scale the conic problem."""
        return self.cone(sigma_m, stress_scale).strength_scale()


@dataclass(frozen=True)
class MuIRheologyAxisymmetric(MuIRheology):
    """mu(I) for the PFEM loop in axisymmetry, Jop's tensorial form
    sigma' = mu(I) p D' / sqrt(D':D' / 2), i.e. sqrt(J2) = mu(I) p at a flowing point, with
    its cone of mu_s,

    .. math::
        \\sqrt{J_2} \\le k_j, \\quad k_j = \\max\\bigl(\\mu_s\\, p_j,\\; k_{min}\\bigr), \\quad
        p_j = -I_1 / 3, \\\\
        \\dot\\gamma = \\sqrt{2 D':D'} \\\\
        = \\sqrt{\\tfrac23\\bigl((D_{rr}-D_{zz})^2
        + (D_{zz}-D_{\\theta\\theta})^2 + (D_{\\theta\\theta}-D_{rr})^2\\bigr)
        + \\dot\\gamma_{rz}^2}

    (J2 of (7.11) reading the hoop stress,
    :class:`~pfem_skfem.materials.axisymmetric.VonMisesField`; in simple shear
    sqrt(J2) = ``|tau|`` and gamma_dot is the shear rate, so mu is Jop's ``|tau| / p``), the
    pressure lagged as I1/3 as the axisymmetric cones. The rate part is that of
    :class:`MuIRheology` on the whole deviator of axisymmetry,
    (a, -a, 0, b) + c (1, 1, -2, 0) / sqrt3 (sqrt(J2) = ||(a, b, c)||, ``hoop`` of
    :class:`ViscousStress`), whose conjugate rate has the norm
    gamma_dot above (the hoop strain counted,
    :func:`~pfem_skfem.discretisation.fields.plastic_strain_increment` with ``hoop``): at a flowing
    point sigma_p and sigma_v share the direction of D', so
    sqrt(J2) = mu_s p + eta gamma_dot = mu(I) p at the fixed point (lag 'viscosity') or
    within the step (lag 'implicit'). ``lag="friction"`` puts mu(I) of the full rate in
    the cone. Parameters as :class:`MuIRheology`.
    """

    name = "mu(I), axisymmetric, lagged"
    hoop = True                # the rate deviator and shear rate count the hoop strain
    geometries = ("axisymmetric",)
    counterpart = "MuIRheology"

    @staticmethod
    def mean_stress(sigma):
        """The lagged quantity: I1/3 (the hoop stress counts)."""
        return mean_stress(sigma)

    def radius(self, sigma_m, stress_scale, shear_rate):
        """k_j = max(mu p_j, k_min), mu = mu(I_j) (lag 'friction') or mu_s, p = -I1/3."""
        mu = self.cone_friction(sigma_m, stress_scale, shear_rate)
        return np.maximum(-mu * np.asarray(sigma_m, dtype=float), self.k_min * stress_scale)

    def cone(self, sigma_m, stress_scale=1.0, *, shear_rate=None):
        """The pass's criterion: :class:`VonMisesField` of the radii (no rate: mu_s)."""
        rate = np.zeros(len(sigma_m)) if shear_rate is None else shear_rate
        return VonMisesField(self.radius(sigma_m, stress_scale, rate))
