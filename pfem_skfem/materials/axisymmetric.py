"""Yield criteria for axisymmetry (thesis Ch 7) as second-order cones.

In axisymmetry the stored stress (sx, sy, sz, sxy) is (s_rr, s_zz, s_tt, s_rz) (see
:mod:`pfem_skfem.discretisation.geometry`): the hoop stress s_tt sits where plane strain
keeps s_z, so the plane-strain cones of :mod:`pfem_skfem.materials.criteria` that read s_z
(Drucker-Prager, elasticity) serve unchanged. s_tt is a principal stress
(s_rt = s_zt = 0); the other two are s +- R with s = (s_rr + s_zz)/2,
R = ||((s_rr - s_zz)/2, s_rz)||, which makes exact Mohr-Coulomb three cones per
stress point. Every cone follows the :class:`~pfem_skfem.materials.YieldCriterion`
contract (``cone_vector``, usable in cvxpy and on arrays); a criterion with
several cones per point says so by ``n_cones`` and orders them cone-major.
"""
from dataclasses import dataclass

import cvxpy as cp
import numpy as np

from .checks import check_cohesion
from .criteria import DruckerPrager, MohrCoulomb, YieldCriterion, _CohesionFriction, _radii


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
class MohrCoulombAxisymmetric(_CohesionFriction, _ThreeCones):
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

    name = "Mohr-Coulomb (axisymmetric, 3 cones)"

    def cone_vector(self, sx, sy, sz, sxy):
        sn, co = np.sin(np.radians(self.phi)), np.cos(np.radians(self.phi))
        s, X = self._in_plane(sx, sy, sxy)
        t = _stack([2 * self.c * co - 2 * s * sn,                          # (i)
                    2 * self.c * co - (1 + sn) * s + (1 - sn) * sz,         # (ii)
                    2 * self.c * co - (1 + sn) * sz + (1 - sn) * s])        # (iii)
        return t, [_stack([2 * X[k], (1 + sn) * X[k], (1 - sn) * X[k]]) for k in range(2)]

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

    A radius of zero is a fluid's point (no shear strength): stated as the equalities
    :data:`PRESSURE_ROWS` sigma_j = 0, an orthonormal basis of the deviator,
    ((sx - sy)/2, (sx + sy - 2 sz)/(2 sqrt3), sxy), whose norm is sqrt(J2) (the cone's
    four components are dependent: their sum is zero).
    """

    name = "von Mises field"

    #: rows whose norm is sqrt(J2): the deviator vanishes where the radius is zero
    PRESSURE_ROWS = np.array([[0.5, -0.5, 0.0, 0.0],
                              [0.5 / np.sqrt(3.0), 0.5 / np.sqrt(3.0), -1.0 / np.sqrt(3.0), 0.0],
                              [0.0, 0.0, 0.0, 1.0]])

    def __init__(self, k):
        self.k = _radii(k)

    def at(self, points):
        """The same cone at a subset of the points (an index or a mask)."""
        return VonMisesField(self.k[points])

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
    check_cohesion(c)
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


def mean_stress(sigma):
    """I1/3 = (s_rr + s_zz + s_tt)/3 of stresses (n, 4): the lagged quantity of the
    axisymmetric PFEM materials (the hoop stress counts)."""
    sigma = np.atleast_2d(np.asarray(sigma, dtype=float))
    return (sigma[:, 0] + sigma[:, 1] + sigma[:, 2]) / 3.0

