"""Yield criteria as second-order cones (App A).

Stresses are tension positive and ordered (sx, sy, sz, sxy) as in (3.23). On the
numpy side a stress field is an array of shape (n_points, 4); on the cvxpy side an
expression of the same shape. Every yield criterion writes its cone as
``rho = D sigma + d`` with ``rho_1 >= ||(rho_2, ..., rho_m)||`` (A.10)-(A.12),
(A.18)-(A.20), and the same code evaluates it on arrays and builds the cvxpy
constraint, so post-processing and the optimisation problem cannot disagree.
"""
from dataclasses import dataclass

import cvxpy as cp
import numpy as np

from .checks import _check_angle, check_cohesion


class YieldCriterion:
    """A convex yield set F(sigma) <= 0 written as a second-order cone.

    Subclasses implement ``cone_vector(sx, sy, sz, sxy)`` returning
    ``(rho_1, [rho_2, ..., rho_m])``; the set is ``rho_1 >= ||rho_2..m||``.
    """

    name = "yield criterion"

    def cone_vector(self, sx, sy, sz, sxy):  # pragma: no cover - abstract
        raise NotImplementedError

    # -- cvxpy -------------------------------------------------------------
    def constraint(self, S):
        """One vectorised SOC constraint over all rows (stress points) of S (n, 4)."""
        t, X = self.cone_vector(S[:, 0], S[:, 1], S[:, 2], S[:, 3])
        return cp.SOC(t, cp.vstack(X), axis=0)

    # -- numpy -------------------------------------------------------------
    def _parts(self, sigma):
        sigma = np.atleast_2d(np.asarray(sigma, dtype=float))
        t, X = self.cone_vector(*sigma.T)
        return np.asarray(t, dtype=float), np.sqrt(sum(np.asarray(x) ** 2 for x in X))

    def F(self, sigma):
        """Yield function ||rho_2..m|| - rho_1 (units of stress); <= 0 is admissible."""
        t, norm = self._parts(sigma)
        return norm - t

    def yield_ratio(self, sigma):
        """||rho_2..m|| / rho_1: 1 on the yield surface, < 1 inside, inf beyond the apex."""
        t, norm = self._parts(sigma)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(t > 0, norm / np.where(t > 0, t, 1.0), np.inf)
        return np.where((t <= 0) & (norm == 0) & (t == 0), 1.0, ratio)

    def strength_scale(self):
        """A stress magnitude of the criterion, used to non-dimensionalise problems."""
        raise NotImplementedError

    def scaled(self, stress):
        """The same criterion for stresses measured in units of ``stress``."""
        raise NotImplementedError


@dataclass(frozen=True)
class _CohesionFriction:
    """What the Mohr-Coulomb criteria share, plane (:class:`MohrCoulomb`) and axisymmetric
    (:class:`~pfem_skfem.materials.axisymmetric.MohrCoulombAxisymmetric`): the cohesion c
    (>= 0) and friction angle phi (degrees, in [0, 90)), not both zero, and c as the
    strength scale."""

    c: float
    phi: float = 0.0

    def __post_init__(self):
        check_cohesion(self.c)
        _check_angle("phi (friction angle)", self.phi)
        if self.c == 0 and self.phi == 0:
            raise ValueError("c and phi are both zero: the yield set has no interior")

    def strength_scale(self):
        return self.c if self.c > 0 else 1.0


@dataclass(frozen=True)
class MohrCoulomb(_CohesionFriction, YieldCriterion):
    """Plane-strain Mohr-Coulomb (A.9)-(A.12), tension positive.

    .. math::
        \\sqrt{(\\sigma_x-\\sigma_y)^2 + 4\\tau_{xy}^2} + (\\sigma_x+\\sigma_y)\\sin\\phi
        - 2c\\cos\\phi \\le 0

    Cone vector rho = D sigma + d = (2c cos(phi) - (sx + sy) sin(phi), sx - sy, 2 sxy).

    Parameters
    ----------
    c : cohesion (>= 0), phi : friction angle in degrees, in [0, 90).
    """

    name = "Mohr-Coulomb"

    def cone_vector(self, sx, sy, sz, sxy):
        s, co = np.sin(np.radians(self.phi)), np.cos(np.radians(self.phi))
        return 2 * self.c * co - (sx + sy) * s, [sx - sy, 2 * sxy]

    def scaled(self, stress):
        return MohrCoulomb(c=self.c / stress, phi=self.phi)


class Tresca(MohrCoulomb):
    """Plane-strain Tresca: Mohr-Coulomb with phi = 0, c = Su; sqrt((sx-sy)^2 + 4 sxy^2) <= 2 Su."""

    name = "Tresca"

    def __init__(self, su):
        super().__init__(c=su, phi=0.0)

    def __repr__(self):
        return f"Tresca(su={self.c!r})"


@dataclass(frozen=True)
class DruckerPrager(YieldCriterion):
    """Drucker-Prager (A.13)-(A.20): alpha I1 + sqrt(J2) - k <= 0.

    .. math::
        \\alpha I_1 + \\sqrt{J_2} \\le k, \\quad
        J_2 = \\tfrac16[(\\sigma_x-\\sigma_y)^2 + (\\sigma_y-\\sigma_z)^2
        + (\\sigma_z-\\sigma_x)^2] + \\tau_{xy}^2

    Cone vector rho = (k - alpha I1, (sx-sy)/sqrt6, (sy-sz)/sqrt6, (sz-sx)/sqrt6, sxy),
    the matrix D of (A.20) rebuilt from (A.13)-(A.16). Use the constructors
    :meth:`plane_strain` (A.17), matched to plane-strain Mohr-Coulomb, or
    :meth:`compression_cone`, the 3D form through the compressive meridians.
    """

    alpha: float
    k: float

    name = "Drucker-Prager"

    def __post_init__(self):
        if not np.isfinite(self.alpha) or self.alpha < 0:
            raise ValueError(f"alpha must be >= 0, got {self.alpha!r}")
        if not np.isfinite(self.k) or self.k < 0:
            raise ValueError(f"k must be >= 0, got {self.k!r}")
        if self.alpha == 0 and self.k == 0:
            raise ValueError("alpha and k are both zero: the yield set has no interior")

    @classmethod
    def plane_strain(cls, c, phi):
        """(A.17): alpha = tan(phi)/sqrt(9 + 12 tan^2 phi), k = 3c/sqrt(9 + 12 tan^2 phi)."""
        MohrCoulomb(c, phi)  # validates c and phi
        t = np.tan(np.radians(phi))
        root = np.sqrt(9 + 12 * t ** 2)
        return cls(alpha=t / root, k=3 * c / root)

    @classmethod
    def compression_cone(cls, c, phi):
        """3D cone through the compressive meridians of Mohr-Coulomb."""
        MohrCoulomb(c, phi)
        s = np.sin(np.radians(phi))
        den = np.sqrt(3) * (3 - s)
        return cls(alpha=2 * s / den, k=6 * c * np.cos(np.radians(phi)) / den)

    def cone_vector(self, sx, sy, sz, sxy):
        r6 = np.sqrt(6.0)
        return (self.k - self.alpha * (sx + sy + sz),
                [(sx - sy) / r6, (sy - sz) / r6, (sz - sx) / r6, sxy])

    def strength_scale(self):
        return self.k if self.k > 0 else 1.0

    def scaled(self, stress):
        return DruckerPrager(alpha=self.alpha, k=self.k / stress)


class TrescaField(YieldCriterion):
    """Tresca-type cone with its own radius at every stress point.

    .. math::
        \\sqrt{(\\sigma_x-\\sigma_y)^2 + 4\\tau_{xy}^2} \\le k_j

    The flow potential of Mohr-Coulomb with zero dilation: used by the
    non-associated scheme of Krabbenhoft, Karim, Lyamin & Sloan (2012) (the
    thesis' [80]) with ``k_j`` from :func:`mohr_coulomb_radius`.

    A radius of zero is a fluid's point (no shear strength, :mod:`~pfem_skfem.materials.fluids`):
    its cone has no interior, so the problems state it as the equalities
    sx - sy = 0, 2 sxy = 0 (:data:`PRESSURE_ROWS`, the cone's own vector), the same set.
    """

    name = "Tresca field"

    #: the rows of the cone vector that vanish where the radius is zero: (sx - sy, 2 sxy)
    PRESSURE_ROWS = np.array([[1.0, -1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 2.0]])

    def __init__(self, k):
        self.k = _radii(k)

    def cone_vector(self, sx, sy, sz, sxy):
        return self.k, [sx - sy, 2 * sxy]

    def strength_scale(self):
        return float(np.median(self.k)) / 2

    def scaled(self, stress):
        return TrescaField(self.k / stress)

    def at(self, points):
        """The same cone at a subset of the points (an index or a mask)."""
        return TrescaField(self.k[points])


def _radii(k):
    """Cone radii per point: finite, >= 0 (zero: a point without shear strength)."""
    k = np.asarray(k, dtype=float)
    if k.ndim != 1 or k.size == 0 or not np.all(np.isfinite(k)) or np.any(k < 0):
        raise ValueError("k (cone radii) must be a non-empty array of values >= 0 "
                         "(0: no shear strength, a fluid)")
    return k


def zero_radius(criterion):
    """(n,) mask of the points whose cone has radius zero (a fluid's), or None if none."""
    rows = getattr(criterion, "PRESSURE_ROWS", None)
    if rows is None or getattr(criterion, "n_cones", 1) != 1:
        return None
    zero = np.asarray(criterion.k) == 0
    return zero if zero.any() else None


def yield_constraints(criterion, S):
    """F(sigma_j) <= 0 on the rows of the cvxpy expression S (n, 4): (constraints,
    multipliers), multipliers() giving each point's plastic multiplier after the solve.

    One SOC over the points with an interior (the criterion's own, :meth:`constraint`);
    where a radius is zero (a fluid's point) the cone is the single point rho_2..m = 0,
    which has no interior for an interior-point solver: it is stated as the equalities
    PRESSURE_ROWS sigma_j = 0 instead (the same set), and the point's multiplier is the
    norm of their duals (the cone's first dual component: both rows are the cone's vector).
    """
    zero = zero_radius(criterion)
    if zero is None:
        cone = criterion.constraint(S)
        return [cone], lambda: np.asarray(cone.dual_value[0]).ravel()
    live, dead = np.flatnonzero(~zero), np.flatnonzero(zero)
    constraints = []
    if live.size:
        cone = criterion.at(live).constraint(S[live, :])
        constraints.append(cone)
    equal = cp.vec(S[dead, :] @ criterion.PRESSURE_ROWS.T, order="C") == 0
    constraints.append(equal)

    def multipliers():
        out = np.zeros(zero.size)
        if live.size:
            out[live] = np.asarray(cone.dual_value[0]).ravel()
        rows = len(criterion.PRESSURE_ROWS)
        out[dead] = np.linalg.norm(np.reshape(equal.dual_value, (dead.size, rows)), axis=1)
        return out
    return constraints, multipliers


def mohr_coulomb_radius(c, phi, sigma_m, floor):
    """Radius 2c cos(phi) - 2 sin(phi) sigma_m of the plane-strain Mohr-Coulomb circle.

    ``sigma_m`` = (sx + sy) / 2 (tension positive) at each stress point; the radius
    is held at least ``floor`` > 0 where the mean stress is tensile, so that the
    cone keeps an interior.
    """
    check_cohesion(c)
    MohrCoulomb(c if c > 0 else 1.0, phi)   # validates phi
    if not np.isfinite(floor) or floor <= 0:
        raise ValueError(f"floor must be positive, got {floor!r}")
    s, co = np.sin(np.radians(phi)), np.cos(np.radians(phi))
    return np.maximum(2 * c * co - 2 * s * np.asarray(sigma_m, dtype=float), floor)


def davis(c, phi, psi):
    """Davis' reduced strength for non-associated flow: (c*, phi*) in degrees.

    beta = cos(psi) cos(phi) / (1 - sin(psi) sin(phi)); c* = beta c,
    tan(phi*) = beta tan(phi). With psi = 0, tan(phi*) = sin(phi).
    """
    check_cohesion(c)
    MohrCoulomb(c if c > 0 else 1.0, phi)
    _check_angle("psi (dilation angle)", psi, upper=phi + 1e-12 if phi > 0 else 1e-12)
    ph, ps = np.radians(phi), np.radians(psi)
    beta = np.cos(ps) * np.cos(ph) / (1 - np.sin(ps) * np.sin(ph))
    return beta * c, float(np.degrees(np.arctan(beta * np.tan(ph))))

