"""The materials of the PFEM runs: what the engine asks of a material, declared once.

:class:`PFEMMaterial` is the protocol (as scikit-fem's ``Element`` declares its
vocabulary): typed class attributes with defaults, and the verbs the engine calls,
``cone``, ``strength_scale``, ``mean_stress`` and ``viscous`` (and ``at_strain`` of a
``softening`` material, :mod:`pfem_skfem.materials.softening`). A material sets only what
differs. The engine (``Scene``, ``pfem.assemble``, ``problems.nonassociated.lagged_step``)
reads these attributes and makes these calls, nothing else. A subclass without a
``name``, its ``geometries``, a ``cone`` or a ``strength_scale`` (or with a one-geometry
material and no ``counterpart``) is refused when its class is made.

The materials here are the schemes of the thesis' [80] (Krabbenhoft, Karim, Lyamin &
Sloan 2012) and the thesis' 6.4.1 and 7.2; :class:`RegionCones` is the step's material
when regions have different materials. The rate-dependent ones are in
:mod:`pfem_skfem.materials.rate`.
"""
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .axisymmetric import (TrescaField3, VonMisesField, drucker_prager_match, mean_stress)
from .checks import _check_positive, check_cohesion
from .criteria import MohrCoulomb, Tresca, TrescaField, davis, mohr_coulomb_radius
from .elastic import Elastic

#: the geometries a material may declare (a Scene's ``geometry``)
GEOMETRIES = ("plane", "axisymmetric")


class PFEMMaterial:
    """What the PFEM engine asks of a material: the cone of each step (thesis [80]).

    Attributes
    ----------
    name : str
        Shown in records and tables (required).
    geometries : tuple of str
        The geometries it is for, among ``("plane", "axisymmetric")`` (required): a Scene
        refuses it in another, naming ``counterpart``.
    counterpart : str
        The material to use instead in the other geometry (required when ``geometries``
        has one).
    lagged : bool
        The cone depends on the lagged mean stress (fixed-point passes help).
    rate_dependent : bool
        The cone and a viscous stress depend on the shear rate (mu(I)); ``lagged_step``
        hands it the previous pass's shear rate.
    hoop : bool
        The shear rate counts the hoop strain (axisymmetry).
    needs_container : bool
        A fluid: a Scene refuses it without rigid bodies to hold it.
    softening : bool
        The cone depends on the plastic shear strain gamma^p the state carries at the
        stress points: the step's material is ``at_strain(gamma_p, size)``, and gamma^p is
        updated after the step (:mod:`pfem_skfem.pfem.softening`).
    elastic : Elastic or None
        None for rigid-plastic (C = 0 in (4.23)).
    c, phi : float
        Cohesion (checked by :func:`check_cohesion`) and friction angle in degrees: the
        stress scale without gravity, and Jaky's K0 = 1 - sin(phi) of a geostatic stress.

    Methods
    -------
    cone(sigma_m, stress_scale, *, shear_rate=None)
        The step's yield criterion at the lagged mean stresses of the stress points.
    strength_scale(sigma_m, stress_scale)
        A stress of the step, to scale the conic problem.
    mean_stress(sigma)
        The lagged quantity of stresses (n, 4): (sx + sy)/2 unless a material lags another.
    viscous(sigma_m, stress_scale, shear_rate, weights)
        The step's viscous stress (ViscousStress, RateDissipation) or None.
    at_strain(gamma_p, size)
        A ``softening`` material only: the material of a step whose stress points carry
        the plastic shear strains ``gamma_p`` in elements of sizes ``size``.
    """

    name: ClassVar[str]
    geometries: ClassVar[tuple]
    counterpart: ClassVar[str] = "another material"
    lagged: ClassVar[bool] = False
    rate_dependent: ClassVar[bool] = False
    hoop: ClassVar[bool] = False
    needs_container: ClassVar[bool] = False
    softening: ClassVar[bool] = False
    elastic = None
    c = 0.0
    phi = 0.0

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        missing = [a for a in ("name", "geometries") if not hasattr(cls, a)]
        missing += [f"{m}()" for m in ("cone", "strength_scale")
                    if getattr(cls, m) is getattr(PFEMMaterial, m)]
        if missing:
            raise TypeError(f"PFEMMaterial {cls.__name__} does not declare "
                            f"{', '.join(missing)}: the PFEM engine needs them")
        if (not isinstance(cls.geometries, tuple) or not cls.geometries
                or not set(cls.geometries) <= set(GEOMETRIES)):
            raise TypeError(f"PFEMMaterial {cls.__name__}: geometries must be a non-empty "
                            f"tuple of {GEOMETRIES}, got {cls.geometries!r}")
        if len(set(cls.geometries)) < len(GEOMETRIES) and cls.counterpart is \
                PFEMMaterial.counterpart:
            raise TypeError(f"PFEMMaterial {cls.__name__} is for {cls.geometries!r} only: "
                            f"declare its counterpart (the material of the other geometry)")

    def __post_init__(self):
        check_cohesion(self.c)

    def cone(self, sigma_m, stress_scale=1.0, *, shear_rate=None):
        """The step's criterion at the lagged mean stresses ``sigma_m`` of the points."""
        raise NotImplementedError

    def strength_scale(self, sigma_m, stress_scale=1.0):
        """A stress of the step, to scale the conic problem."""
        raise NotImplementedError

    def mean_stress(self, sigma):
        """The lagged quantity: (sx + sy)/2 of stresses (n, 4)."""
        return 0.5 * (sigma[:, 0] + sigma[:, 1])

    def viscous(self, sigma_m, stress_scale, shear_rate, weights):
        """The step's viscous stress: none for a rate-independent material."""
        return None


# -- plane strain (and Tresca) -------------------------------------------------------------
@dataclass(frozen=True)
class ZeroDilationMohrCoulomb(PFEMMaterial):
    """Mohr-Coulomb with zero dilation by the scheme of Krabbenhoft, Karim, Lyamin & Sloan
    (2012), the thesis' [80]: each step solves an associated problem on the flow surface
    of psi = 0, a Tresca-type cone whose radius is the Mohr-Coulomb strength at a known
    (lagged) mean stress sigma_m = (sx + sy)/2, tension positive:

    .. math::
        \\sqrt{(\\sigma_x-\\sigma_y)^2 + 4\\tau_{xy}^2} \\le k_j, \\quad
        k_j = \\max(2c\\cos\\phi - 2\\sin\\phi\\,\\sigma_{m,j},\\; k_{min})

    Parameters
    ----------
    c : cohesion (>= 0);  phi : friction angle in degrees;  k_min : least radius, in units
        of the problem's stress scale (a PFEM scene's rho g L), so that the model keeps
        no absolute stress;  elastic : :class:`Elastic` for the elastoplastic variant
        (None: rigid-plastic, C = 0 in (4.23)).
    """

    c: float = 0.0
    phi: float = 30.0
    k_min: float = 0.005
    elastic: Elastic = None

    name = "Mohr-Coulomb, zero dilation [80]"
    lagged = True           # the cone depends on the mean stress: fixed-point passes help
    geometries = ("plane",)     # a Scene refuses it in another geometry, naming:
    counterpart = "ZeroDilationMohrCoulombAxisymmetric (or ZeroDilationDruckerPrager)"

    def __post_init__(self):
        super().__post_init__()                                   # check_cohesion
        MohrCoulomb(self.c if self.c > 0 else 1.0, self.phi)      # validates phi
        _check_positive("k_min (least cone radius / stress scale)", self.k_min)

    def radius(self, sigma_m, stress_scale=1.0):
        """k_j at mean stresses ``sigma_m`` (:func:`mohr_coulomb_radius`)."""
        return mohr_coulomb_radius(self.c, self.phi, sigma_m, self.k_min * stress_scale)

    def cone(self, sigma_m, stress_scale=1.0, *, shear_rate=None):
        """The step's criterion: :class:`TrescaField` of the radii at ``sigma_m``."""
        return TrescaField(self.radius(sigma_m, stress_scale))

    def strength_scale(self, sigma_m, stress_scale=1.0):
        """A stress of the step (half the median radius), to scale the conic problem."""
        return TrescaField(self.radius(sigma_m, stress_scale)).strength_scale()


@dataclass(frozen=True)
class DavisMohrCoulomb(ZeroDilationMohrCoulomb):
    """Mohr-Coulomb with the Davis reduction for a dilation angle psi (:func:`davis`): an
    associated cone of c* = beta c, tan(phi*) = beta tan(phi), held at the same least
    radius 2 c* cos(phi*) >= k_min as :class:`ZeroDilationMohrCoulomb` (so that it keeps an
    interior for c = 0). Its cone does not depend on the mean stress.
    """

    psi: float = 0.0

    name = "Mohr-Coulomb, Davis reduction"
    lagged = False

    def __post_init__(self):
        super().__post_init__()
        davis(self.c, self.phi, self.psi)                         # validates psi

    def cone(self, sigma_m=None, stress_scale=1.0, *, shear_rate=None):
        c_star, phi_star = davis(self.c, self.phi, self.psi)
        c_floor = self.k_min * stress_scale / (2 * np.cos(np.radians(phi_star)))
        return MohrCoulomb(max(c_star, c_floor), phi_star)


@dataclass(frozen=True)
class CohesiveTresca(PFEMMaterial):
    """Undrained (Tresca) soil of cohesion c for a PFEM run, sqrt((sx-sy)^2 + 4 sxy^2) <= 2c:
    no pressure term, so no least radius and no lagged mean stress (thesis 6.4.1).

    Parameters
    ----------
    c : undrained shear strength (> 0);  elastic : :class:`Elastic` or None (rigid-plastic).
    """

    c: float
    elastic: Elastic = None

    name = "Tresca"
    lagged = False
    geometries = ("plane",)     # a Scene refuses it in another geometry, naming:
    counterpart = "ZeroDilationMohrCoulombAxisymmetric with phi = 0"

    def __post_init__(self):
        _check_positive("c (undrained shear strength)", self.c)
        super().__post_init__()

    def cone(self, sigma_m=None, stress_scale=1.0, *, shear_rate=None):
        return Tresca(self.c)

    def strength_scale(self, sigma_m=None, stress_scale=1.0):
        return self.c


# -- axisymmetry (thesis 7.2) ---------------------------------------------------------------
@dataclass(frozen=True)
class ZeroDilationDruckerPrager(PFEMMaterial):
    """The Drucker-Prager cone (7.10) with zero dilation, for the PFEM loop in axisymmetry.

    The scheme of [80] as in the thesis' 7.2: each step solves an associated problem on
    the flow surface of psi = 0, G = sqrt(J2), whose radius is the strength of (7.10) at
    the lagged mean stress p = I1/3 carried by the particles (:func:`mean_stress`):

    .. math::
        \\sqrt{J_2} \\le k_j, \\quad k_j = \\max(k - 3\\alpha\\, p_j,\\; k_{min})

    with J2 (7.11) reading the hoop stress, (alpha, k) of :func:`drucker_prager_match`
    (``match``: the thesis' 'compression-meridian' (7.10) by default). At a fixed point
    (p_j the solution's) the strength is that of (7.10) and the flow isochoric. In plane
    strain (s_z the out-of-plane stress) the same object serves, with p = I1/3 too.

    Parameters
    ----------
    c : cohesion (>= 0);  phi : friction angle in degrees;  k_min : least radius in units of
        the scene's stress scale rho g L;  match : see :func:`drucker_prager_match`;
        elastic : :class:`~pfem_skfem.materials.Elastic` (None: rigid-plastic).
    """

    c: float = 0.0
    phi: float = 30.0
    k_min: float = 0.005
    match: str = "compression-meridian"
    elastic: Elastic = None

    name = "Drucker-Prager (7.10), zero dilation [80]"
    lagged = True
    geometries = ("plane", "axisymmetric")    # J2 reads s_z: the hoop or out-of-plane stress

    def __post_init__(self):
        self.criterion                          # validates c, phi and match
        super().__post_init__()
        if not np.isfinite(self.k_min) or self.k_min <= 0:
            raise ValueError(f"k_min (least cone radius / stress scale) must be positive, "
                             f"got {self.k_min!r}")

    @property
    def criterion(self):
        """The associated cone (7.10): :class:`~pfem_skfem.materials.DruckerPrager`."""
        return drucker_prager_match(self.c, self.phi, self.match)

    @staticmethod
    def mean_stress(sigma):
        """The lagged quantity: I1/3 (:func:`mean_stress`)."""
        return mean_stress(sigma)

    def radii(self, p, stress_scale=1.0):
        """k_j = max(k - 3 alpha p_j, k_min stress_scale) at mean stresses p = I1/3."""
        dp = self.criterion
        return np.maximum(dp.k - 3 * dp.alpha * np.asarray(p, dtype=float),
                          self.k_min * stress_scale)

    def cone(self, p, stress_scale=1.0, *, shear_rate=None):
        """The step's criterion: :class:`VonMisesField` of the radii at ``p``."""
        return VonMisesField(self.radii(p, stress_scale))

    def strength_scale(self, p, stress_scale=1.0):
        """A stress of the step (the median radius), to scale the conic problem."""
        return self.cone(p, stress_scale).strength_scale()


@dataclass(frozen=True)
class ZeroDilationMohrCoulombAxisymmetric(PFEMMaterial):
    """Mohr-Coulomb in axisymmetry with zero dilation, for the PFEM loop: the three Tresca
    cones of :class:`TrescaField3` (one per principal pair, the hoop stress principal),
    each with the Mohr-Coulomb radius at the lagged mean stress p = I1/3:

    .. math::
        s_i - s_j \\le k_j = \\max(2c\\cos\\phi - 2p_j\\sin\\phi,\\; k_{min})
        \\quad \\\\ \\text{for every principal pair } (i, j)

    The particles carry one lagged scalar, so each pair's sum s_i + s_j is taken as 2p:
    the flow is isochoric (Tresca's), the strength Mohr-Coulomb's where the mean of the
    major and minor principal stresses is I1/3 (the intermediate stress midway), weaker
    than exact Mohr-Coulomb in triaxial compression (s_2 = s_1) and stronger in extension.
    Compare with :class:`ZeroDilationDruckerPrager`, which lags exactly what its radius needs.

    Parameters
    ----------
    c, phi, k_min, elastic : as :class:`ZeroDilationDruckerPrager`.
    """

    c: float = 0.0
    phi: float = 30.0
    k_min: float = 0.005
    elastic: Elastic = None

    name = "Mohr-Coulomb (axisymmetric, 3 cones), zero dilation [80]"
    lagged = True
    geometries = ("axisymmetric",)
    counterpart = "ZeroDilationMohrCoulomb"

    def __post_init__(self):
        super().__post_init__()                 # check_cohesion
        MohrCoulomb(self.c if self.c > 0 else 1.0, self.phi)
        if not np.isfinite(self.k_min) or self.k_min <= 0:
            raise ValueError(f"k_min (least cone radius / stress scale) must be positive, "
                             f"got {self.k_min!r}")

    @staticmethod
    def mean_stress(sigma):
        """The lagged quantity: I1/3 (:func:`mean_stress`)."""
        return mean_stress(sigma)

    def radii(self, p, stress_scale=1.0):
        """k_j = max(2c cos(phi) - 2 p_j sin(phi), k_min stress_scale)."""
        sn, co = np.sin(np.radians(self.phi)), np.cos(np.radians(self.phi))
        return np.maximum(2 * self.c * co - 2 * sn * np.asarray(p, dtype=float),
                          self.k_min * stress_scale)

    def cone(self, p, stress_scale=1.0, *, shear_rate=None):
        """The step's criterion: :class:`TrescaField3`, the same radius for the three pairs."""
        k = self.radii(p, stress_scale)
        return TrescaField3(np.vstack([k, k, k]))

    def strength_scale(self, p, stress_scale=1.0):
        """A stress of the step (half the median radius), to scale the conic problem."""
        return self.cone(p, stress_scale).strength_scale()


# -- regions of different materials --------------------------------------------------------
def _per_point(cone, n):
    """(family, radii) of a step's cone with a radius at each of its n points: TrescaField
    (Tresca-type, a phi = 0 MohrCoulomb as k = 2c everywhere), VonMisesField,
    TrescaField3; None for a cone whose radius depends on the stress (it cannot be
    stitched into another's)."""
    if isinstance(cone, (TrescaField, VonMisesField, TrescaField3)):
        return type(cone), cone.k
    if type(cone) in (MohrCoulomb, Tresca) and cone.phi == 0:
        return TrescaField, np.full(n, 2.0 * cone.c)
    return None


class RegionCones(PFEMMaterial):
    """The step's material when regions have different materials: each stress point takes
    the cone of its region's material, the radii stitched into one cone of their family
    (Tresca-type, von Mises or the three axisymmetric pairs), each region's mean stress
    its material's, and the shear rate and viscous stress handed to each material on
    its points (thesis [80] per region).

    Parameters
    ----------
    materials : the regions' PFEM materials, in the scene's order.
    point_region : (n_points,) the region of each stress point (of its element).
    """

    name = "regions of different materials"
    geometries = GEOMETRIES            # the Scene checks each region's own material

    def __init__(self, materials, point_region):
        self.materials = tuple(materials)
        self.point_region = np.asarray(point_region)
        self.check(self.materials)

    @staticmethod
    def check(materials):
        """Refuse materials that cannot share a step (ValueError naming them): a cone whose
        radius depends on the stress, cones of different kinds, different elasticities, a
        viscous stress (mu(I)) that would not cover every region."""
        soft = [type(m).__name__ for m in materials if m.softening]
        if soft:
            raise ValueError(f"regions of different materials: a softening material "
                             f"({', '.join(soft)}) cannot share a step with other regions yet "
                             f"(its gamma^p is bound to the whole step's points)")
        families = {}
        for m in materials:            # a cone at one point tells the family
            found = _per_point(m.cone(np.zeros(1), 1.0), 1)
            if found is None:
                raise ValueError(f"regions of different materials: {m.name} "
                                 f"({type(m).__name__}) has a cone whose radius depends on "
                                 f"the stress, which cannot share a step's cone with another "
                                 f"material's")
            families.setdefault(found[0].__name__, type(m).__name__)
        if len(families) > 1:
            raise ValueError(f"regions of different materials: their cones are of different "
                             f"kinds ({', '.join(f'{v}: {k}' for k, v in families.items())})")
        if len({repr(m.elastic) for m in materials}) > 1:
            raise ValueError("every region must have the same elasticity (or none)")
        viscous = [(type(m).__name__, type(m.viscous(-np.ones(1), 1.0, np.zeros(1),
                                                     np.ones(1))).__name__) for m in materials]
        if len({v for _, v in viscous}) > 1:
            shown = ", ".join(f"{k}: {v}" for k, v in viscous)
            raise ValueError(f"regions of different materials: the viscous stress of a "
                             f"rate-dependent material must cover every region, of one kind "
                             f"({shown.replace('NoneType', 'none')})")

    @property
    def lagged(self):
        return any(m.lagged for m in self.materials)

    @property
    def rate_dependent(self):
        return any(m.rate_dependent for m in self.materials)

    @property
    def hoop(self):
        return any(m.hoop for m in self.materials)

    @property
    def elastic(self):
        return self.materials[0].elastic

    @property
    def c(self):
        return max(m.c for m in self.materials)

    def _each(self):
        # a region with no points in the step (discharged) has no cone to give
        for i, m in enumerate(self.materials):
            mine = self.point_region == i
            if mine.any():
                yield m, mine

    def cone(self, sigma_m, stress_scale=1.0, *, shear_rate=None):
        """The cone of the points' materials, their radii in one array."""
        k = None
        for m, mine in self._each():
            rate = None if shear_rate is None else shear_rate[mine]
            family, radii = _per_point(m.cone(sigma_m[mine], stress_scale, shear_rate=rate),
                                       int(mine.sum()))
            if k is None:
                k = np.empty(np.shape(radii)[:-1] + (len(sigma_m),))
            k[..., mine] = radii
        return family(k)

    def strength_scale(self, sigma_m, stress_scale=1.0):
        """Half the median radius; the scene's stress scale where most points are a fluid's
        (radius zero: water has no strength to scale by)."""
        scale = self.cone(sigma_m, stress_scale).strength_scale()
        return scale if scale > 0 else stress_scale

    def mean_stress(self, sigma):
        """Each point's material's lagged quantity."""
        if all(type(m).mean_stress is PFEMMaterial.mean_stress for m in self.materials):
            return PFEMMaterial.mean_stress(self, sigma)
        out = np.empty(len(sigma))
        for m, mine in self._each():
            out[mine] = m.mean_stress(sigma[mine])
        return out

    def viscous(self, sigma_m, stress_scale, shear_rate, weights):
        """The materials' viscous stresses on their points, in one: all of one kind, or none."""
        parts = [(m.viscous(sigma_m[mine], stress_scale,
                            None if shear_rate is None else shear_rate[mine], weights[mine]),
                  mine) for m, mine in self._each()]
        if all(v is None for v, _ in parts):
            return None
        first = parts[0][0]
        arrays = {}
        for name in ("eta", "c", "tau_max"):
            if hasattr(first, name):
                arrays[name] = np.empty(len(sigma_m))
                for v, mine in parts:
                    arrays[name][mine] = getattr(v, name)
        return type(first)(**arrays, weights=weights, hoop=first.hoop)
