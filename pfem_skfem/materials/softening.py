"""Strain softening: a strength that falls with the accumulated plastic shear strain.

Beyond the thesis; the model of Zhang, Sheng, Sloan & Bleyer (IJNME 112, 2017) for the
intact sensitive clay: Tresca (or Mohr-Coulomb) whose cohesion c falls from its peak c_p to
its remoulded value c_r as the plastic shear strain gamma^p accumulates (sensitivity
S_t = c_p / c_r). The laws:

.. math::
    c_{lin}(\\gamma^p) = \\max\\bigl(c_r,\\; c_p - (c_p - c_r)\\,\\gamma^p/\\gamma_r\\bigr),
    \\qquad
    c_{exp}(\\gamma^p) = c_r + (c_p - c_r)\\, e^{-3\\gamma^p/\\gamma_{95}}

(the linear one has the softening modulus H = dc/dgamma^p = -(c_p - c_r)/gamma_r until
c_r; the exponential one has lost 95 % of c_p - c_r at gamma_95).

The step stays convex: a strength that depended on the plastic strain of the same step
would not be a cone. So the strength is data of each step, taken at the start of the step
(:meth:`SofteningTresca.criterion`), and updated after it from the plastic strain increment
at each stress point (:func:`plastic_strain_increment`, :func:`shear_invariant`):

.. math::
    \\Delta\\varepsilon^p = \\varepsilon(\\Delta u) - C^{-1}(\\sigma_{n+1} - \\sigma_n),\\qquad
    \\Delta\\gamma^p = \\sqrt{(\\Delta\\varepsilon^p_{xx} - \\Delta\\varepsilon^p_{yy})^2
                              + (2\\Delta\\varepsilon^p_{xy})^2},\\qquad
    c_{n+1} = c(\\gamma^p_n + \\Delta\\gamma^p)

In axisymmetry (:mod:`pfem_skfem.materials.softening_axisymmetric`) the cone is the three
Tresca pairs of the principal stresses (the hoop stress principal) and Delta gamma^p the
invariant of the hoop strain too (its Tresca dissipation per unit strength).

The update lags by one step; a cap on the strength drop of a step (the step is re-solved
with a smaller increment above it: :func:`pfem_skfem.drivers.softening.softening_control`)
makes the lag as small as wanted.

Regularisation (:class:`FractureEnergy`): a local softening law localises in one element,
so the energy it dissipates scales with the element size h. With a length ell, the law's
strain scale (gamma_r or gamma_95) is that of a band ell thick, and in an element of size
h it is scaled by ell / h: the plastic slip h gamma^p at which the strength is spent, and
the energy per unit band area G_f = ell gamma_r (c_p - c_r) / 2 (linear; ell gamma_95
(c_p - c_r) / 3 exponential) dissipated as it falls to c_r, do not depend on h.

Viscosity (``eta``, Zhang et al.'s elastoviscoplastic clay): the Bingham term of the dynamic
step beside the softened cone (:class:`~pfem_skfem.problems.step_terms.BinghamStress`, the
compliance on the total stress), so that where the clay flows
R(sigma) = c(gamma^p_n) + eta Delta gamma^p / dt, the overstress carried by the rate of the
measure gamma^p accumulates (in simple shear tau = c + eta gamma_dot^p). Still convex: c is
data of the step, the viscous term a concave quadratic.
"""
from dataclasses import dataclass
import warnings

import numpy as np

from .checks import _check_positive, _is_real
from .criteria import TrescaField, mohr_coulomb_radius
from .elastic import Elastic
from .pfem import PFEMMaterial
from .rate import ViscousStress


def _check_strengths(c_p, c_r):
    """c_p > 0 and 0 <= c_r <= c_p, each named."""
    _check_positive("c_p (peak strength)", c_p)
    if not (_is_real(c_r) and np.isfinite(c_r) and c_r >= 0):
        raise ValueError(f"c_r (residual strength) must be finite and >= 0, got {c_r!r}")
    if c_r > c_p:
        raise ValueError(f"c_r (residual strength) = {c_r!r} exceeds c_p (peak strength) = "
                         f"{c_p!r}: the strength would harden")


@dataclass(frozen=True)
class LinearSoftening:
    """c = max(c_r, c_p - (c_p - c_r) gamma^p / gamma_r): softening modulus
    H = -(c_p - c_r) / gamma_r until the residual strength c_r at gamma^p = gamma_r."""

    c_p: float
    c_r: float
    gamma_r: float

    def __post_init__(self):
        _check_strengths(self.c_p, self.c_r)
        _check_positive("gamma_r (plastic shear strain at the residual strength)", self.gamma_r)

    @property
    def steepest_rate(self):
        """abs(dc/dgamma^p) at its largest (gamma^p = 0): abs(H) = (c_p - c_r) / gamma_r."""
        return (self.c_p - self.c_r) / self.gamma_r

    def strength(self, gamma_p, scale=1.0):
        """c at plastic shear strains ``gamma_p``, the strain scale times ``scale``."""
        g = np.asarray(gamma_p, dtype=float) / (self.gamma_r * np.asarray(scale, dtype=float))
        return np.maximum(self.c_r, self.c_p - (self.c_p - self.c_r) * g)

    def drop(self, gamma_old, gamma_new, scale=1.0):
        """c(gamma_old) - c(gamma_new), the strength a step from ``gamma_old`` to ``gamma_new``
        spends (the strain scale times ``scale``): abs(H) Delta gamma^p while c stays above c_r,
        what was left above c_r where it reaches it (0 at c_r)."""
        rate = self.steepest_rate / np.asarray(scale, dtype=float)
        spent = rate * (np.asarray(gamma_new, dtype=float) - np.asarray(gamma_old, dtype=float))
        return np.minimum(spent, self.strength(gamma_old, scale) - self.c_r)

    def strain_at(self, c, scale=1.0):
        """The plastic shear strain at which the strength is ``c`` (c_r < c <= c_p)."""
        spent = (self.c_p - np.asarray(c, dtype=float)) / (self.c_p - self.c_r)
        return self.gamma_r * scale * spent

    def softening_energy(self, scale=1.0):
        """int (c - c_r) dgamma^p from 0 to full softening, per unit volume."""
        return 0.5 * (self.c_p - self.c_r) * self.gamma_r * scale


@dataclass(frozen=True)
class ExponentialSoftening:
    """c = c_r + (c_p - c_r) exp(-3 gamma^p / gamma_95): 95 % of c_p - c_r lost at gamma_95
    (the Einav-Randolph form; the laws of Dey et al. 2015 and Troncone et al. are of it)."""

    c_p: float
    c_r: float
    gamma_95: float

    def __post_init__(self):
        _check_strengths(self.c_p, self.c_r)
        _check_positive("gamma_95 (plastic shear strain at 95 % softening)", self.gamma_95)

    @property
    def steepest_rate(self):
        """abs(dc/dgamma^p) at its largest (gamma^p = 0): 3 (c_p - c_r) / gamma_95."""
        return 3.0 * (self.c_p - self.c_r) / self.gamma_95

    def strength(self, gamma_p, scale=1.0):
        """c at plastic shear strains ``gamma_p``, the strain scale times ``scale``."""
        g = np.asarray(gamma_p, dtype=float) / (self.gamma_95 * np.asarray(scale, dtype=float))
        return self.c_r + (self.c_p - self.c_r) * np.exp(-3.0 * g)

    def drop(self, gamma_old, gamma_new, scale=1.0):
        """c(gamma_old) - c(gamma_new), the strength a step from ``gamma_old`` to ``gamma_new``
        spends (the strain scale times ``scale``):
        (c_p - c_r) exp(-3 gamma_old / gamma_95) (1 - exp(-3 Delta gamma^p / gamma_95)),
        the law's rate at the step's start times Delta gamma^p at most; it vanishes as c nears
        c_r, which the law never reaches."""
        s = self.gamma_95 * np.asarray(scale, dtype=float)
        g0 = np.asarray(gamma_old, dtype=float)
        dg = np.asarray(gamma_new, dtype=float) - g0
        return (self.c_p - self.c_r) * np.exp(-3.0 * g0 / s) * -np.expm1(-3.0 * dg / s)

    def strain_at(self, c, scale=1.0):
        """The plastic shear strain at which the strength is ``c`` (c_r < c <= c_p)."""
        left = (np.asarray(c, dtype=float) - self.c_r) / (self.c_p - self.c_r)
        return -self.gamma_95 * scale * np.log(left) / 3.0

    def softening_energy(self, scale=1.0):
        """int (c - c_r) dgamma^p from 0 to infinity, per unit volume."""
        return (self.c_p - self.c_r) * self.gamma_95 * scale / 3.0


@dataclass(frozen=True)
class FractureEnergy:
    """The softening law's strain scale belongs to a band ``length`` (ell) thick: in an
    element of size h it is scaled by ell / h, so that the slip and the energy per unit
    band area at which the strength is spent (G_f = ell x the law's softening energy per
    unit volume) do not depend on h."""

    length: float

    def __post_init__(self):
        _check_positive("length (ell, the regularisation length)", self.length)

    def scale(self, size):
        """ell / h at element sizes ``size``."""
        size = np.asarray(size, dtype=float)
        if np.any(~np.isfinite(size)) or np.any(size <= 0):
            raise ValueError("element sizes must be positive and finite")
        return self.length / size


@dataclass(frozen=True)
class NonlocalAverage:
    """Each step's increment of gamma^p averaged over the stress points within ``length``
    (ell) of each (:func:`nonlocal_average`, rebuilt on each step's points), the law's strain
    scale left as it is: the band is spread over about ell, whatever the element size. For
    the PFEM loop (:mod:`pfem_skfem.pfem.softening`); static increments take their average
    from :class:`~pfem_skfem.drivers.softening.StepControl`."""

    length: float

    def __post_init__(self):
        _check_positive("length (ell, the nonlocal averaging length)", self.length)

    def scale(self, size):
        """1 at every point: the average, not the law, is regularised."""
        return np.ones_like(np.asarray(size, dtype=float))


def nonlocal_average(points, weights, length):
    """The nonlocal average over a length ell as a sparse (n, n) operator A:

    .. math::
        (A\\gamma)_i = \\frac{\\sum_j w_j\\,\\phi_{ij}\\,\\gamma_j}{\\sum_j w_j\\,\\phi_{ij}},\\qquad
        \\phi_{ij} = \\bigl(1 - r_{ij}^2/\\ell^2\\bigr)^2 \\ (r_{ij} < \\ell)

    over the stress points (or particles) at ``points`` (n, 2) of weights ``w``: the bell
    function, a constant kept. A length below the points' spacing (their median distance to
    the nearest other) averages nothing: warned, the operator then nearly the identity.
    """
    from scipy.sparse import coo_matrix, diags, identity
    from scipy.spatial import cKDTree

    _check_positive("length (ell, the nonlocal averaging length)", length)
    points, weights = np.asarray(points, dtype=float), np.asarray(weights, dtype=float)
    tree = cKDTree(points)
    spacing = float(np.median(tree.query(points, k=2)[0][:, 1])) if len(points) > 1 else 0.0
    if length <= spacing:
        warnings.warn(f"nonlocal length {length:g} is below the points' spacing {spacing:g}: "
                      f"the average is local", stacklevel=2)
    r = tree.sparse_distance_matrix(tree, length, output_type="coo_matrix")
    other = r.row != r.col            # scipy keeps each point's zero distance to itself
    phi = coo_matrix(((1 - (r.data[other] / length) ** 2) ** 2,
                      (r.row[other], r.col[other])), shape=r.shape)
    W = (phi.tocsr() + identity(len(points), format="csr")) @ diags(weights)
    return (diags(1.0 / np.asarray(W.sum(axis=1)).ravel()) @ W).tocsr()


def plastic_strain_increment(B, du, C, sigma_new, sigma_old, weights):
    """Delta eps^p = eps(du) - C^-1 (sigma_{n+1} - sigma_n) at each stress point, (n, 4) in
    (xx, yy, zz, 2xy).

    B (4n, n_u) and C (4n, 4n) are the integrated operators of (3.41), (3.43): a point's rows
    of B du and of C dsigma are its strain and elastic strain times its ``weights``. C = None
    (rigid-plastic): every strain is plastic.
    """
    n = len(weights)
    total = (B @ du).reshape(n, 4)
    if C is not None:
        total = total - (C @ (np.asarray(sigma_new) - np.asarray(sigma_old)).ravel()).reshape(n, 4)
    return total / np.asarray(weights, dtype=float)[:, None]


def shear_invariant(deps):
    """sqrt((de_xx - de_yy)^2 + (2 de_xy)^2) of strains (n, 4) (xx, yy, zz, 2xy): the
    engineering shear strain of simple shear, the measure gamma^p accumulates."""
    deps = np.asarray(deps, dtype=float)
    return np.hypot(deps[:, 0] - deps[:, 1], deps[:, 3])


def point_sizes(weights):
    """Element size at each stress point of a plane-strain mesh: sqrt(2 A), A = 3 w the area of
    its element (three points of equal weight): the side of a square cell of two triangles."""
    return np.sqrt(6.0 * np.asarray(weights, dtype=float))


def strength_drop(material, gamma_old, gamma_new, size, *, steepest=False):
    """The largest strength drop of a step as a fraction of c_p - c_r, the step controls'
    measure; 0 without softening.

    The exponential law: c before minus c after (its :meth:`~ExponentialSoftening.drop`,
    exact), which falls with exp(-3 gamma^p / gamma_95): a remoulded point (c near c_r,
    which the law never reaches) drops next to nothing whatever its Delta gamma^p. (Until
    2026-12-07 it was the law's steepest rate times Delta gamma^p at every point: a bound
    that kept halving dt for debris already remoulded.)

    The linear law: abs(H) Delta gamma^p at the points above c_r at the step's start, its
    exact drop wherever a point stays above c_r; at a point that reaches c_r within the step
    it overstates the drop (c before - c_r, :meth:`~LinearSoftening.drop`). That bound is
    kept so that the linear law's recorded runs stand (sensitive_clay's quick S_t = 10 bank
    takes 104 steps instead of 122 with the exact drop, its run-out 6.42 m instead of 5.96).

    ``steepest``: the law's steepest rate times Delta gamma^p at the points above c_r for
    either law, the static increments' measure
    (:func:`~pfem_skfem.drivers.softening.softening_control`): a cap on each increment's
    plastic strain in units of the law's strain scale, which keeps the one-increment lag of
    the exponential law's tail, a strain, as small as at its peak (with the exact drop the
    quick ``softening_cylinder`` and ``softening_layer`` miss their exponential curve checks,
    3.2e-2 of eps_95 against 1e-2 and 3.0e-2 of delta_95 against 2e-2)."""
    law = material.law
    span = law.c_p - law.c_r
    if span <= 0:
        return 0.0
    scale = material.scale(size)
    if steepest or isinstance(law, LinearSoftening):
        rate = law.steepest_rate / scale
        softening = law.strength(gamma_old, scale) > law.c_r * (1 + 1e-12)
        return float(np.max(rate[softening] * (gamma_new - gamma_old)[softening],
                            initial=0.0)) / span
    return float(np.max(law.drop(gamma_old, gamma_new, scale), initial=0.0)) / span


@dataclass(frozen=True)
class SofteningTresca(PFEMMaterial):
    """Tresca whose strength c(gamma^p) at each stress point is data of a step:

    .. math::
        \\sqrt{(\\sigma_x-\\sigma_y)^2 + 4\\tau_{xy}^2} \\le 2\\,c(\\gamma^p_j)

    For static increments (:func:`pfem_skfem.drivers.softening.softening_control`) and the
    PFEM loop: a PFEM material (``softening``) whose step is :meth:`at_strain`, the cone at
    the gamma^p the state carries at the step's stress points
    (:mod:`pfem_skfem.pfem.softening`); its own :meth:`cone` is the intact one (gamma^p = 0).

    Parameters
    ----------
    law : :class:`LinearSoftening` or :class:`ExponentialSoftening`.
    elastic : :class:`Elastic`.
    regularisation : :class:`FractureEnergy`, :class:`NonlocalAverage` (PFEM runs), or
        None (local softening: the strength is spent in one element, whatever its size).
    eta : the Bingham viscosity [Pa s] of Zhang et al.'s elastoviscoplastic clay, >= 0
        (0: rate-independent, the run of a material without it bit for bit). With eta > 0
        the PFEM step adds the viscous stress
        :class:`~pfem_skfem.materials.rate.ViscousStress` beside the cone (:meth:`viscous`):
        at a yielding point R(sigma) = c(gamma^p) + eta gamma_dot^p (in simple shear
        tau = c + eta dgamma^p/dt), gamma_dot^p the rate of the measure gamma^p accumulates.
        Static increments have no time step: they refuse eta > 0.
    """

    law: object
    elastic: Elastic
    regularisation: FractureEnergy = None
    eta: float = 0.0

    name = "Tresca, strain softening"
    softening = True
    geometries = ("plane",)
    counterpart = "SofteningTrescaAxisymmetric"

    @property
    def c(self):
        """The peak strength c_p: the stress scale of a scene without gravity."""
        return self.law.c_p

    def __post_init__(self):
        if not isinstance(self.law, (LinearSoftening, ExponentialSoftening)):
            raise ValueError(f"law must be a LinearSoftening or an ExponentialSoftening, "
                             f"got {type(self.law).__name__}")
        if not isinstance(self.elastic, Elastic):
            raise ValueError(f"elastic must be an Elastic, got {type(self.elastic).__name__}")
        if self.regularisation is not None and not isinstance(
                self.regularisation, (FractureEnergy, NonlocalAverage)):
            raise ValueError(f"regularisation must be a FractureEnergy, a NonlocalAverage or "
                             f"None, got {type(self.regularisation).__name__}")
        if not (_is_real(self.eta) and np.isfinite(self.eta) and self.eta >= 0):
            raise ValueError(f"eta (Bingham viscosity) must be finite and >= 0, got {self.eta!r}")

    def viscous(self, sigma_m, stress_scale, shear_rate, weights):
        """The step's viscous stress: :class:`~pfem_skfem.materials.rate.ViscousStress` of
        viscosity eta at every point; None for eta = 0."""
        if self.eta == 0:
            return None
        return ViscousStress(np.full(len(weights), float(self.eta)), weights)

    def shear_strain(self, deps):
        """Delta gamma^p of plastic strain increments (n, 4): :func:`shear_invariant`."""
        return shear_invariant(deps)

    def sizes(self, weights, points):
        """Element size at each stress point of weights ``weights`` (at ``points``):
        :func:`point_sizes`."""
        return point_sizes(weights)

    def scale(self, size):
        """The law's strain-scale factor at element sizes ``size``: ell / h (a fracture
        energy), or 1."""
        if self.regularisation is None:
            return np.ones_like(np.asarray(size, dtype=float))
        return self.regularisation.scale(size)

    def strength(self, gamma_p, size):
        """c at the points' plastic shear strains and element sizes."""
        return self.law.strength(gamma_p, self.scale(size))

    def criterion(self, gamma_p, size, sigma_m=None, stress_scale=1.0):
        """The step's cone: :class:`TrescaField` of radii 2 c(gamma^p_j) (no mean stress)."""
        return TrescaField(2.0 * self.strength(gamma_p, size))

    def at_strain(self, gamma_p, size):
        """The PFEM material of a step whose points carry ``gamma_p`` in elements of sizes
        ``size`` (:class:`SofteningStep`)."""
        return SofteningStep(self, gamma_p, size)

    def cone(self, sigma_m, stress_scale=1.0, *, shear_rate=None):
        """The intact cone (gamma^p = 0) at the points of ``sigma_m``."""
        n = len(np.atleast_1d(sigma_m))
        return self.criterion(np.zeros(n), np.ones(n), np.atleast_1d(sigma_m), stress_scale)

    def strength_scale(self, sigma_m, stress_scale=1.0):
        """A stress of the step (half the median radius of the intact cone)."""
        return self.cone(sigma_m, stress_scale).strength_scale()


@dataclass(frozen=True)
class SofteningMohrCoulomb(SofteningTresca):
    """Mohr-Coulomb with zero dilation ([80], as
    :class:`~pfem_skfem.materials.ZeroDilationMohrCoulomb`) whose cohesion softens:

    .. math::
        \\sqrt{(\\sigma_x-\\sigma_y)^2 + 4\\tau_{xy}^2} \\le
        \\max(2c(\\gamma^p_j)\\cos\\phi - 2\\sin\\phi\\,\\sigma_{m,j},\\; k_{min})

    ``phi`` (degrees) stays; ``k_min`` is the least radius in units of the stress scale
    given to :meth:`criterion`.
    """

    phi: float = 0.0
    k_min: float = 0.005

    name = "Mohr-Coulomb, zero dilation, cohesion softening"
    lagged = True           # the cone depends on the mean stress: fixed-point passes help
    counterpart = "SofteningMohrCoulombAxisymmetric"

    def __post_init__(self):
        super().__post_init__()
        mohr_coulomb_radius(1.0, self.phi, 0.0, 1.0)          # validates phi
        _check_positive("k_min (least cone radius / stress scale)", self.k_min)

    def criterion(self, gamma_p, size, sigma_m=None, stress_scale=1.0):
        """:class:`TrescaField` of the Mohr-Coulomb radii at the lagged mean stresses."""
        c = self.strength(gamma_p, size)
        sigma_m = np.zeros_like(c) if sigma_m is None else sigma_m
        s, co = np.sin(np.radians(self.phi)), np.cos(np.radians(self.phi))
        return TrescaField(np.maximum(2 * c * co - 2 * s * np.asarray(sigma_m, dtype=float),
                                      self.k_min * stress_scale))


class SofteningStep(PFEMMaterial):
    """The PFEM material of one step of a softening material: its cone at the plastic shear
    strains ``gamma_p`` the state carries at the step's stress points (data of the step:
    the step stays convex), made by the engine (:meth:`SofteningTresca.at_strain`).

    Parameters
    ----------
    material : :class:`SofteningTresca` or :class:`SofteningMohrCoulomb` (or their
        axisymmetric counterparts, :mod:`~pfem_skfem.materials.softening_axisymmetric`).
    gamma_p, size : (n_points,) plastic shear strain and element size at each point.
    """

    name = "softening material at the step's gamma^p"
    geometries = ("plane", "axisymmetric")      # its material's (the Scene checks that one)

    def __init__(self, material, gamma_p, size):
        if not isinstance(material, SofteningTresca):
            raise ValueError(f"material must be a SofteningTresca or a SofteningMohrCoulomb, "
                             f"got {type(material).__name__}")
        self.material = material
        self.gamma_p = np.asarray(gamma_p, dtype=float)
        self.size = np.asarray(size, dtype=float)
        if self.gamma_p.shape != self.size.shape or self.gamma_p.ndim != 1:
            raise ValueError(f"gamma_p and size must be (n_points,) alike, got "
                             f"{self.gamma_p.shape} and {self.size.shape}")

    @property
    def lagged(self):
        return self.material.lagged

    @property
    def elastic(self):
        return self.material.elastic

    @property
    def c(self):
        return self.material.c

    @property
    def phi(self):
        return self.material.phi

    def mean_stress(self, sigma):
        """The material's lagged quantity of stresses (n, 4)."""
        return self.material.mean_stress(sigma)

    def strength(self):
        """c(gamma^p) at the step's points."""
        return self.material.strength(self.gamma_p, self.size)

    def viscous(self, sigma_m, stress_scale, shear_rate, weights):
        """The material's viscous stress (eta > 0) or None."""
        return self.material.viscous(sigma_m, stress_scale, shear_rate, weights)

    def cone(self, sigma_m, stress_scale=1.0, *, shear_rate=None):
        """The step's criterion at the carried gamma^p (and the lagged ``sigma_m``)."""
        return self.material.criterion(self.gamma_p, self.size, sigma_m, stress_scale)

    def strength_scale(self, sigma_m, stress_scale=1.0):
        """Half the median radius of the step's cone."""
        return self.cone(sigma_m, stress_scale).strength_scale()
