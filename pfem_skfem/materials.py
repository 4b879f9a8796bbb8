"""Materials: isotropic elasticity (3.9)-(3.10) and yield criteria as second-order cones (App A).

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


def _check_positive(name, value):
    if not np.isfinite(value) or value <= 0:
        raise ValueError(f"{name} must be positive and finite, got {value!r}")


def _check_angle(name, degrees, upper=90.0):
    if not np.isfinite(degrees) or not 0.0 <= degrees < upper:
        raise ValueError(f"{name} must lie in [0, {upper:g}) degrees, got {degrees!r}")


@dataclass(frozen=True)
class Elastic:
    """Isotropic linear elasticity with Young's modulus E and Poisson's ratio nu."""

    E: float
    nu: float

    def __post_init__(self):
        _check_positive("E (Young's modulus)", self.E)
        if not np.isfinite(self.nu) or not -1.0 < self.nu < 0.5:
            raise ValueError(f"nu (Poisson's ratio) must lie in (-1, 0.5), got {self.nu!r}")

    @property
    def shear_modulus(self):
        return self.E / (2 * (1 + self.nu))

    @property
    def lame_lambda(self):
        return self.E * self.nu / ((1 + self.nu) * (1 - 2 * self.nu))

    def compliance(self):
        """4x4 compliance of (3.10) for (sx, sy, sz, sxy): strains (ex, ey, ez, 2exy) = C sigma."""
        E, nu = self.E, self.nu
        return np.array([[1, -nu, -nu, 0],
                         [-nu, 1, -nu, 0],
                         [-nu, -nu, 1, 0],
                         [0, 0, 0, 2 * (1 + nu)]]) / E


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
class MohrCoulomb(YieldCriterion):
    """Plane-strain Mohr-Coulomb (A.9)-(A.12), tension positive.

    .. math::
        \\sqrt{(\\sigma_x-\\sigma_y)^2 + 4\\tau_{xy}^2} + (\\sigma_x+\\sigma_y)\\sin\\phi
        - 2c\\cos\\phi \\le 0

    Cone vector rho = D sigma + d = (2c cos(phi) - (sx + sy) sin(phi), sx - sy, 2 sxy).

    Parameters
    ----------
    c : cohesion (>= 0), phi : friction angle in degrees, in [0, 90).
    """

    c: float
    phi: float = 0.0

    name = "Mohr-Coulomb"

    def __post_init__(self):
        if not np.isfinite(self.c) or self.c < 0:
            raise ValueError(f"c (cohesion) must be >= 0, got {self.c!r}")
        _check_angle("phi (friction angle)", self.phi)
        if self.c == 0 and self.phi == 0:
            raise ValueError("c and phi are both zero: the yield set has no interior")

    def cone_vector(self, sx, sy, sz, sxy):
        s, co = np.sin(np.radians(self.phi)), np.cos(np.radians(self.phi))
        return 2 * self.c * co - (sx + sy) * s, [sx - sy, 2 * sxy]

    def strength_scale(self):
        return self.c if self.c > 0 else 1.0

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
    """

    name = "Tresca field"

    def __init__(self, k):
        k = np.asarray(k, dtype=float)
        if k.ndim != 1 or k.size == 0 or not np.all(np.isfinite(k)) or np.any(k <= 0):
            raise ValueError("k (cone radii) must be a non-empty array of positive values")
        self.k = k

    def cone_vector(self, sx, sy, sz, sxy):
        return self.k, [sx - sy, 2 * sxy]

    def strength_scale(self):
        return float(np.median(self.k)) / 2

    def scaled(self, stress):
        return TrescaField(self.k / stress)


def mohr_coulomb_radius(c, phi, sigma_m, floor):
    """Radius 2c cos(phi) - 2 sin(phi) sigma_m of the plane-strain Mohr-Coulomb circle.

    ``sigma_m`` = (sx + sy) / 2 (tension positive) at each stress point; the radius
    is held at least ``floor`` > 0 where the mean stress is tensile, so that the
    cone keeps an interior.
    """
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
    MohrCoulomb(c if c > 0 else 1.0, phi)
    _check_angle("psi (dilation angle)", psi, upper=phi + 1e-12 if phi > 0 else 1e-12)
    ph, ps = np.radians(phi), np.radians(psi)
    beta = np.cos(ps) * np.cos(ph) / (1 - np.sin(ps) * np.sin(ph))
    return beta * c, float(np.degrees(np.arctan(beta * np.tan(ph))))


# -- axisymmetric cones (thesis Ch 7) --
#
# In axisymmetry the stored stress (sx, sy, sz, sxy) is (s_rr, s_zz, s_tt, s_rz)
# (see pfem_skfem.geometry): the hoop stress s_tt sits where plane strain keeps s_z.
# s_tt is a principal stress (s_rt = s_zt = 0); the other two are s +- R with
# s = (s_rr + s_zz)/2, R = ||((s_rr - s_zz)/2, s_rz)||.

#: the Drucker-Prager matches to Mohr-Coulomb of :func:`drucker_prager_match`
DP_MATCHES = ("compression-meridian", "plane-strain", "plane-strain-psi0")


def drucker_prager_match(c, phi, match="compression-meridian"):
    """Drucker-Prager alpha I1 + sqrt(J2) <= k matched to Mohr-Coulomb (c, phi).

    * ``"compression-meridian"``: the thesis' (7.10) as printed,
      alpha = 2 sin(phi) / (sqrt3 (3 - sin(phi))), k = 6 c cos(phi) / (sqrt3 (3 - sin(phi))).
      It equals Mohr-Coulomb on triaxial-compression states (the two largest
      principal stresses equal, tension positive): the outer cone. The thesis'
      text calls it the plane-strain match; it is not (research notes, section 0.1).
    * ``"plane-strain"``: (A.17), alpha = tan(phi)/sqrt(9 + 12 tan^2 phi),
      k = 3c/sqrt(9 + 12 tan^2 phi): the plane-strain match with associated flow.
    * ``"plane-strain-psi0"``: alpha = sin(phi)/3, k = c cos(phi): the plane-strain
      match when the out-of-plane stress is the mean in-plane stress (zero dilation).

    In axisymmetry J2 (7.11) reads the hoop stress as the out-of-plane component.

    Returns
    -------
    DruckerPrager
    """
    if match == "compression-meridian":
        return DruckerPrager.compression_cone(c, phi)
    if match == "plane-strain":
        return DruckerPrager.plane_strain(c, phi)
    if match == "plane-strain-psi0":
        MohrCoulomb(c, phi)
        ph = np.radians(phi)
        return DruckerPrager(alpha=np.sin(ph) / 3, k=c * np.cos(ph))
    raise ValueError(f"match must be one of {DP_MATCHES}, got {match!r}")


def _stack(parts):
    """Concatenate per-cone pieces (numpy arrays or cvxpy expressions), cone-major."""
    if any(isinstance(p, cp.Expression) for p in parts):
        return cp.hstack(parts)
    n = max(np.size(p) for p in parts)
    return np.concatenate([np.broadcast_to(np.asarray(p, dtype=float), (n,)) for p in parts])


class _ThreeCones(YieldCriterion):
    """A yield set of three second-order cones per stress point (cone-major order).

    ``cone_vector`` returns (t, [X1, X2]) of length 3 n for n points: entry
    i n + p is cone i at point p. ``F`` and ``yield_ratio`` take the largest of the
    three at each point.
    """

    n_cones = 3

    def _in_plane(self, sx, sy, sxy):
        return (sx + sy) / 2, [(sx - sy) / 2, sxy]

    def F(self, sigma):
        t, norm = self._parts(sigma)
        return (norm - t).reshape(3, -1).max(axis=0)

    def yield_ratio(self, sigma):
        return super().yield_ratio(sigma).reshape(3, -1).max(axis=0)


@dataclass(frozen=True)
class MohrCoulombAxisymmetric(_ThreeCones):
    """Exact Mohr-Coulomb in axisymmetry: three second-order cones per stress point.

    With s = (s_rr + s_zz)/2, R = ||((s_rr - s_zz)/2, s_rz)|| (the in-plane
    principal stresses are s +- R) and the hoop stress s_tt principal, tension
    positive:

    .. math::
        \\text{(i)}\\;& 2R \\le 2c\\cos\\phi - 2s\\sin\\phi \\\\
        \\text{(ii)}\\;& (1+\\sin\\phi) R \\le 2c\\cos\\phi - (1+\\sin\\phi)s
            + (1-\\sin\\phi)\\sigma_{\\theta\\theta} \\\\
        \\text{(iii)}\\;& (1-\\sin\\phi) R \\le 2c\\cos\\phi - (1+\\sin\\phi)\\sigma_{\\theta\\theta}
            + (1-\\sin\\phi)s

    (i) is the in-plane pair, (ii) the in-plane major with the hoop stress minor,
    (iii) the hoop stress major with the in-plane minor; the other three ordered
    pairs are implied. Together: max over principal pairs of
    (s_i - s_j) + (s_i + s_j) sin(phi) <= 2c cos(phi), Mohr-Coulomb exactly, with
    no assumption on which stress is intermediate. phi = 0 is Tresca.

    Parameters
    ----------
    c : cohesion (>= 0), phi : friction angle in degrees, in [0, 90).
    """

    c: float
    phi: float = 0.0

    name = "Mohr-Coulomb (axisymmetric, 3 cones)"

    def __post_init__(self):
        MohrCoulomb(self.c, self.phi)           # validates c and phi

    def cone_vector(self, sx, sy, sz, sxy):
        sn, co = np.sin(np.radians(self.phi)), np.cos(np.radians(self.phi))
        s, X = self._in_plane(sx, sy, sxy)
        t = _stack([2 * self.c * co - 2 * s * sn,                          # (i)
                    2 * self.c * co - (1 + sn) * s + (1 - sn) * sz,         # (ii)
                    2 * self.c * co - (1 + sn) * sz + (1 - sn) * s])        # (iii)
        return t, [_stack([2 * X[k], (1 + sn) * X[k], (1 - sn) * X[k]]) for k in range(2)]

    def strength_scale(self):
        return self.c if self.c > 0 else 1.0

    def scaled(self, stress):
        return MohrCoulombAxisymmetric(c=self.c / stress, phi=self.phi)


class TrescaAxisymmetric(MohrCoulombAxisymmetric):
    """Exact Tresca in axisymmetry: max |s_i - s_j| <= 2 Su over the three principal
    stresses (s +- R and s_tt); :class:`MohrCoulombAxisymmetric` with phi = 0."""

    name = "Tresca (axisymmetric, 3 cones)"

    def __init__(self, su):
        super().__init__(c=su, phi=0.0)

    def __repr__(self):
        return f"TrescaAxisymmetric(su={self.c!r})"

    def scaled(self, stress):
        return TrescaAxisymmetric(self.c / stress)


class VonMisesField(YieldCriterion):
    """von Mises cone with its own radius at every stress point: sqrt(J2) <= k_j.

    .. math::
        \\sqrt{J_2} = \\Big\\|\\Big(\\tfrac{\\sigma_x-\\sigma_y}{\\sqrt6},
        \\tfrac{\\sigma_y-\\sigma_z}{\\sqrt6}, \\tfrac{\\sigma_z-\\sigma_x}{\\sqrt6},
        \\tau_{xy}\\Big)\\Big\\| \\le k_j

    The flow surface of the Drucker-Prager cone (7.10) with zero dilation
    (G = sqrt(J2) of (7.10) with psi = 0): the scheme of [80] (Krabbenhoft, Karim,
    Lyamin & Sloan 2012) with k_j = k - alpha I1 at lagged stresses
    (:func:`drucker_prager_radius`). Read with s_z = s_tt in axisymmetry.
    """

    name = "von Mises field"

    def __init__(self, k):
        k = np.asarray(k, dtype=float)
        if k.ndim != 1 or k.size == 0 or not np.all(np.isfinite(k)) or np.any(k <= 0):
            raise ValueError("k (cone radii) must be a non-empty array of positive values")
        self.k = k

    def cone_vector(self, sx, sy, sz, sxy):
        r6 = np.sqrt(6.0)
        return self.k, [(sx - sy) / r6, (sy - sz) / r6, (sz - sx) / r6, sxy]

    def strength_scale(self):
        return float(np.median(self.k))

    def scaled(self, stress):
        return VonMisesField(self.k / stress)


class TrescaField3(_ThreeCones):
    """Three Tresca-type cones per stress point with their own radii: s_i - s_j <= k_ij.

    .. math::
        \\text{(i)}\\; 2R \\le k_1,\\quad
        \\text{(ii)}\\; R \\le k_2 - s + \\sigma_{\\theta\\theta},\\quad
        \\text{(iii)}\\; R \\le k_3 + s - \\sigma_{\\theta\\theta}

    for the pairs of :class:`MohrCoulombAxisymmetric` (in-plane; in-plane major and
    hoop; hoop and in-plane minor). The flow surface of axisymmetric Mohr-Coulomb
    with zero dilation, for the scheme of [80] with k_ij from
    :func:`mohr_coulomb_pair_radii` at lagged stresses.

    Parameters
    ----------
    k : (3, n) positive radii, one row per pair.
    """

    name = "Tresca field (axisymmetric, 3 cones)"

    def __init__(self, k):
        k = np.asarray(k, dtype=float)
        if (k.ndim != 2 or k.shape[0] != 3 or k.shape[1] == 0
                or not np.all(np.isfinite(k)) or np.any(k <= 0)):
            raise ValueError("k (cone radii) must be a (3, n) array of positive values")
        self.k = k

    def cone_vector(self, sx, sy, sz, sxy):
        s, X = self._in_plane(sx, sy, sxy)
        t = _stack([self.k[0], self.k[1] - s + sz, self.k[2] + s - sz])
        return t, [_stack([2 * X[k], X[k], X[k]]) for k in range(2)]

    def strength_scale(self):
        return float(np.median(self.k)) / 2

    def scaled(self, stress):
        return TrescaField3(self.k / stress)


def drucker_prager_radius(criterion, sigma, floor):
    """Radii k - alpha I1 of the zero-dilation scheme for a :class:`DruckerPrager` cone.

    ``sigma`` (n, 4) are the lagged stresses; the radius is held at least
    ``floor`` > 0 where the stress is near or beyond the apex.
    """
    if not isinstance(criterion, DruckerPrager):
        raise ValueError("criterion must be a DruckerPrager cone")
    if not np.isfinite(floor) or floor <= 0:
        raise ValueError(f"floor must be positive, got {floor!r}")
    sigma = np.atleast_2d(np.asarray(sigma, dtype=float))
    i1 = sigma[:, 0] + sigma[:, 1] + sigma[:, 2]
    return np.maximum(criterion.k - criterion.alpha * i1, floor)


def mohr_coulomb_pair_radii(c, phi, sigma, floor):
    """Radii 2c cos(phi) - (s_i + s_j) sin(phi) of the three pairs of :class:`TrescaField3`.

    ``sigma`` (n, 4) are the lagged stresses (s_rr, s_zz, s_tt, s_rz); the pairs are
    (s + R, s - R), (s + R, s_tt), (s_tt, s - R). Each radius is held at least
    ``floor`` > 0. Returns a (3, n) array.
    """
    MohrCoulomb(c if c > 0 else 1.0, phi)
    if not np.isfinite(floor) or floor <= 0:
        raise ValueError(f"floor must be positive, got {floor!r}")
    sigma = np.atleast_2d(np.asarray(sigma, dtype=float))
    s = 0.5 * (sigma[:, 0] + sigma[:, 1])
    R = np.hypot(0.5 * (sigma[:, 0] - sigma[:, 1]), sigma[:, 3])
    st = sigma[:, 2]
    sums = np.stack([2 * s, s + R + st, st + s - R])
    sn, co = np.sin(np.radians(phi)), np.cos(np.radians(phi))
    return np.maximum(2 * c * co - sn * sums, floor)


def zero_dilation_cone(criterion, sigma, floor):
    """The flow surface with zero dilation of ``criterion`` at the lagged stresses ``sigma``.

    The scheme of [80] (Krabbenhoft, Karim, Lyamin & Sloan 2012): the friction is
    carried as a stress-dependent cohesion frozen at known stresses, so the
    associated problem on the returned cone has psi = 0 flow and, once the stresses
    stop changing, the original strength.

    * :class:`DruckerPrager` (e.g. (7.10)) -> :class:`VonMisesField`, radii k - alpha I1;
    * :class:`MohrCoulombAxisymmetric` -> :class:`TrescaField3`, radii
      2c cos(phi) - (s_i + s_j) sin(phi) per principal pair.

    ``floor`` > 0 bounds the radii below (stresses near or beyond the apex).
    """
    if isinstance(criterion, DruckerPrager):
        return VonMisesField(drucker_prager_radius(criterion, sigma, floor))
    if isinstance(criterion, MohrCoulombAxisymmetric):
        return TrescaField3(mohr_coulomb_pair_radii(criterion.c, criterion.phi, sigma, floor))
    raise ValueError(f"no zero-dilation cone for {type(criterion).__name__}: use a "
                     "DruckerPrager or MohrCoulombAxisymmetric criterion")
