"""A rectangular column of material on a floor against a wall, released: the scene of the
granular column collapse (thesis 6.4.3), the dam break and the slump benchmarks; and the
column of revolution in its container, lifted at t = 0 (thesis 7.4), in axisymmetry
(:class:`ColumnOfRevolution`, :func:`granular_column_axisymmetric`), with the sizes that
resolve it (:func:`particles_across_radius`, :func:`courant_steps`).
"""
from dataclasses import dataclass, field, fields

import numpy as np

from ..discretisation.theta import ThetaMethod
from ..materials import ZeroDilationDruckerPrager, ZeroDilationMohrCoulombAxisymmetric
from ..pfem.remesh import AlphaMesh
from ..problems.contact import RigidSegment
from .bodies import Body
from .config import PFEMConfig
from .regions import Geostatic, Region
from .scene import Scene

__all__ = ["Column", "column_scene", "AXISYMMETRIC_MATERIALS", "ColumnOfRevolution",
           "granular_column_axisymmetric", "particles_across_radius", "courant_steps"]


@dataclass(frozen=True)
class Column:
    """A column ``width`` x ``height`` of ``material`` (particles ``spacing`` apart on a
    square lattice) standing on the floor y = 0 against the wall x = 0: the parameters of
    the scene, which :meth:`scene` builds.

    Attributes
    ----------
    material, rho, name, stress : the column's :class:`~pfem_skfem.scene.Region` (``stress``
        None: unstressed, or :class:`~pfem_skfem.scene.Geostatic`).
    g, dt : gravity (downwards) and the time step.
    floor_friction : friction coefficient of the floor.
    wall_friction : friction coefficient of the wall x = 0 and of the gate x = ``width``.
    gate_removed_at : None: no gate (the column released from the start); else the time at
        which the gate holding the column's other side goes (``np.inf``: it stays; 0: gone
        before the first step).
    far : how far the floor and the walls reach (default: 50 times the column's size).
    body_names : the names of the floor, the wall and the gate in the records.
    alpha, t_end : the :class:`~pfem_skfem.scene.Scene`'s; its length is ``height``.
    theta1, theta2 : the :class:`~pfem_skfem.discretisation.theta.ThetaMethod`'s.
    config : the rest of the :class:`~pfem_skfem.scene.config.PFEMConfig` (passes, contact,
        solver, volume_correction, ...), a dict.
    """

    material: object
    width: float
    height: float
    spacing: float
    rho: float
    g: float
    dt: float
    name: str = "column"
    stress: object = None
    floor_friction: float = 0.0
    wall_friction: float = 0.0
    gate_removed_at: float = None
    far: float = None
    body_names: tuple = ("floor", "wall", "gate")
    alpha: float = 1.6
    t_end: float = None
    theta1: float = 1.0
    theta2: float = 1.0
    config: dict = field(default_factory=dict)

    def scene(self):
        """The :class:`~pfem_skfem.scene.Scene` of the column, its floor, wall and gate."""
        far = 50 * max(self.width, self.height) if self.far is None else self.far
        w, h, s = self.width, self.height, self.spacing
        floor, wall, gate = self.body_names
        column = Region(((0.0, 0.0), (w, 0.0), (w, h), (0.0, h)), self.material, self.rho, s,
                        stress=self.stress, name=self.name)
        bodies = (Body(floor, RigidSegment((-far, 0.0), (far, 0.0), self.floor_friction)),
                  Body(wall, RigidSegment((0.0, far), (0.0, -s), self.wall_friction)))
        if self.gate_removed_at is not None:   # the solid: above the floor, right of the wall
            bodies += (Body(gate, RigidSegment((w, -s), (w, far), self.wall_friction),  # left
                            removed_at=self.gate_removed_at),)
        numerics = PFEMConfig(theta=ThetaMethod(self.dt, self.theta1, self.theta2), **self.config)
        return Scene(regions=(column,), bodies=bodies, gravity=(0.0, -self.g), alpha=self.alpha,
                     t_end=self.t_end, length=h, config=numerics)


_FIELDS = {f.name for f in fields(Column)} - {"config"}


def column_scene(material, width, height, spacing, **parameters):
    """(state, scene) of a :class:`Column` of ``material``; ``parameters`` are its other
    attributes (``rho``, ``g``, ``dt`` needed) and the rest of its PFEMConfig (passes, contact,
    solver, volume_correction, ...)."""
    config = {k: v for k, v in parameters.items() if k not in _FIELDS}
    column = Column(material, width, height, spacing, config=config,
                    **{k: v for k, v in parameters.items() if k in _FIELDS})
    scene = column.scene()
    return scene.initial_state(), scene


#: The materials of the column of revolution by name: 'dp' the Drucker-Prager cone (7.10)
#: of thesis 7.4 (the compression-meridian match), 'mc' Mohr-Coulomb (three cones), both
#: with zero dilation by the scheme of [80].
AXISYMMETRIC_MATERIALS = {"dp": ZeroDilationDruckerPrager,
                          "mc": ZeroDilationMohrCoulombAxisymmetric}


@dataclass(frozen=True)
class ColumnOfRevolution:
    """The axisymmetric column of thesis 7.4: a cylinder ``r0`` in radius and h0 = ``a`` r0
    high (x = r, y = z), of particles on a square lattice (``nr`` across the radius, the
    axis row included), on a rigid base z = 0 inside a smooth container r = r0: the
    parameters of the scene, which :meth:`scene` builds.

    Attributes
    ----------
    a, nr : the aspect ratio h0 / r0 (positive) and the particles across r0 (two at least).
    r0, rho, g : the radius, the density and gravity (downwards).
    phi, c, material : the material, ``material`` 'dp' (the (7.10) cone with zero dilation)
        or 'mc' (Mohr-Coulomb, three cones, zero dilation), of
        :data:`AXISYMMETRIC_MATERIALS`; the lagged mean stress I1/3 starts geostatic with
        K0 = 1 - sin phi.
    floor_fraction : the least cone radius in units of rho g h0.
    soil : a material object in place of ``material`` (None: ``material``'s).
    phi_s : the base's friction angle, mu = tan phi_s (None: phi).
    container : the container stays (True) or is removed at t = 0.
    dt : the time step (None: 0.01 sqrt(h0/g)).
    alpha, adaptive_alpha, t_end : the :class:`~pfem_skfem.scene.Scene`'s
        (``adaptive_alpha``: alpha_n = m0 alpha / m_n, thesis Ch 8); its length is h0.
    config : the rest of the :class:`~pfem_skfem.scene.config.PFEMConfig` (passes, solver,
        volume_correction, ...), a dict; the remesher is the alpha-shape's.
    """

    a: float
    nr: int
    r0: float = 1.0
    rho: float = 2.0
    g: float = 9.8
    phi: float = 30.0
    phi_s: float = None
    c: float = 0.0
    material: str = "dp"
    container: bool = False
    floor_fraction: float = 0.005
    dt: float = None
    alpha: float = 1.6
    t_end: float = None
    soil: object = None
    adaptive_alpha: bool = False
    config: dict = field(default_factory=dict)

    def __post_init__(self):
        if self.a <= 0:
            raise ValueError(f"a (aspect ratio h0/r0) must be positive, got {self.a!r}")
        if not self.nr >= 2:
            raise ValueError(f"nr must be >= 2, got {self.nr!r}")

    def scene(self):
        """The :class:`~pfem_skfem.scene.Scene` of the column, its base and its container."""
        a, nr, r0, g, phi = self.a, self.nr, self.r0, self.g, self.phi
        h0 = a * r0
        h = r0 / (nr - 1)
        mu = np.tan(np.radians(phi if self.phi_s is None else self.phi_s))
        top = 20 * h0 + 10 * r0
        soil = self.soil
        if soil is None:
            soil = AXISYMMETRIC_MATERIALS[self.material](c=self.c, phi=phi,
                                                         k_min=self.floor_fraction)
        column = Region(((0.0, 0.0), (r0, 0.0), (r0, h0), (0.0, h0)), soil, self.rho, h,
                        stress=Geostatic(), name="column")
        bodies = (Body("base", RigidSegment((-h, 0.0), (top, 0.0), mu)),          # solid below
                  Body("container", RigidSegment((r0, -h), (r0, top), 0.0),       # smooth
                       removed_at=np.inf if self.container else 0.0))
        dt = 0.01 * np.sqrt(h0 / g) if self.dt is None else self.dt
        numerics = PFEMConfig(theta=ThetaMethod(dt, 1.0, 1.0), remesher=AlphaMesh(),
                              **self.config)
        return Scene(regions=(column,), bodies=bodies, gravity=(0.0, -g), alpha=self.alpha,
                     adaptive_alpha=self.adaptive_alpha, t_end=self.t_end, length=h0,
                     config=numerics, geometry="axisymmetric")


_REVOLUTION_FIELDS = {f.name for f in fields(ColumnOfRevolution)} - {"config"}


def granular_column_axisymmetric(a, nr, **parameters):
    """The axisymmetric column of thesis 7.4 as a scene, and its initial state: a
    :class:`ColumnOfRevolution` of aspect ratio ``a``, ``nr`` particles across its radius;
    ``parameters`` are its other attributes and the rest of its PFEMConfig (passes, solver,
    volume_correction, alpha_advected, ...).

    Returns (state, scene).
    """
    config = {k: v for k, v in parameters.items() if k not in _REVOLUTION_FIELDS}
    column = ColumnOfRevolution(a, nr, config=config,
                                **{k: v for k, v in parameters.items()
                                   if k in _REVOLUTION_FIELDS})
    scene = column.scene()
    return scene.initial_state(), scene


def particles_across_radius(a, nr):
    """Particles across r0 that put ``nr`` across the smaller of r0 and h0 = a r0: a short
    column (a < 1) gets as many spacings over its height as a = 1 has over its radius
    (at 10 across, a = 0.5 would otherwise stand 5 spacings high, and its foot, a few
    particles, moves by whole spacings)."""
    return int(nr) if a >= 1 else int(np.ceil((nr - 1) / a - 1e-9)) + 1


def courant_steps(a, nr, courant):
    """Steps to t = 4 sqrt(h0/g) with sqrt(2 g h0) dt / h <= ``courant`` (h = r0/(nr - 1)):
    4 sqrt(2) a (nr - 1) / courant, whatever r0 and g. A step moves the falling top of a tall
    column by about this many spacings; the second-order volume error of the update grows
    as its square (the book's "Where the volume goes")."""
    return int(np.ceil(4 * np.sqrt(2) * a * (nr - 1) / courant))
