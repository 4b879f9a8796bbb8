"""The water of a saturated scene: the pore pressure of the PFEM (issue 54, item 5).

A scene with ``water=Water(...)`` is saturated: every region (or those named in
``Water.regions``; the others free-draining) is the skeleton of a saturated soil (its PFEM
material the cone of the effective stress), and each step adds the
pore pressure to (4.23) as
:class:`~pfem_skfem.problems.pore_term.PorePressureTerm` (Darcy's dissipation, the storage
1/M, Biot's alpha p in equilibrium of the total stress, p = p_bar on the drained faces).

The pore pressure is continuous P1 on the step's mesh: one value per vertex, and every
vertex of a PFEM mesh is a particle, so p is a particle variable (as the lagged mean stress
is). Remeshing keeps each particle's p (no projection, no smoothing of the field); a node a
remesher adds takes the old P1 field's value at its place.

Without a water table p is the excess pore pressure (no weight of water); with one (the
height y_w of a horizontal table, gravity along -y) p is the total pore pressure, the water
has the weight rho_w g (gamma_w |g| / |g|), the hydrostatic p_h = gamma_w (y_w - y) is the
initial p, and the excess p - p_h is written beside p.
"""
from dataclasses import dataclass

import numpy as np

from ..problems.consolidation import SaturatedSoil


@dataclass(frozen=True)
class Drained:
    """A drained face: the mesh's boundary vertices in ``zone`` (a
    :class:`~pfem_skfem.scene.outlets.HalfPlane` or
    :class:`~pfem_skfem.scene.outlets.PolygonZone`, its edge included), or with ``zone``
    None the free surface (the boundary vertices that touch no rigid body), hold p = p_h + p
    (p_h the hydrostatic pressure of the water table, 0 without one; ``p`` the excess held
    there, e.g. a drawdown - q)."""

    zone: object = None
    p: float = 0.0

    def __post_init__(self):
        if self.zone is not None and not hasattr(self.zone, "contains"):
            raise ValueError(f"Drained: zone must be None (the free surface), a HalfPlane or a "
                             f"PolygonZone, got {self.zone!r}")
        if isinstance(self.p, bool) or not np.isfinite(float(self.p)):
            raise ValueError(f"Drained: p (the excess pore pressure held) must be finite, "
                             f"got {self.p!r}")
        object.__setattr__(self, "p", float(self.p))


@dataclass(frozen=True)
class Water:
    """The water of a saturated scene (module docstring).

    Parameters
    ----------
    k : hydraulic conductivity (length / time), >= 0 (0: undrained).
    gamma_w : unit weight of water (force / volume), > 0.
    M : Biot's modulus (stress), > 0; inf for incompressible constituents.
    alpha : Biot's coefficient, in (0, 1].
    table : the height y_w of the water table (gravity along -y), or None: p is the excess
        pore pressure and the water has no weight.
    drained : :class:`Drained` faces (none: every face impermeable, an undrained body).
    regions : the names of the saturated regions, or None: every region. The others are
        free-draining (a dry fill, a gravel layer): no Darcy term and no storage, their p
        held at :meth:`free_draining` (the hydrostatic pressure below the table, zero above
        it: dry, no suction), so that a saturated region drains into them through every
        vertex they share; the effective stress is the total less that p there too.
    """

    k: float
    gamma_w: float = 9.81
    M: float = np.inf
    alpha: float = 1.0
    table: float = None
    drained: tuple = ()
    regions: tuple = None

    def __post_init__(self):
        SaturatedSoil(None, self.k, self.gamma_w, self.M, self.alpha)   # refused by name
        if self.table is not None and not np.isfinite(float(self.table)):
            raise ValueError(f"Water: table (the water table's height) must be finite or "
                             f"None, got {self.table!r}")
        drained = (self.drained,) if isinstance(self.drained, Drained) else tuple(self.drained)
        for face in drained:
            if not isinstance(face, Drained):
                raise ValueError(f"Water: drained must hold Drained faces, got {face!r}")
        object.__setattr__(self, "drained", drained)
        if self.regions is not None:
            names = (self.regions,) if isinstance(self.regions, str) else tuple(self.regions)
            if not names or not all(isinstance(n, str) for n in names):
                raise ValueError(f"Water: regions must name the saturated regions (a tuple of "
                                 f"region names) or be None (every region), got "
                                 f"{self.regions!r}")
            object.__setattr__(self, "regions", names)

    def check(self, gravity, theta1):
        """Refuse a table without gravity along -y and a step that is not backward Euler."""
        gx, gy = gravity
        if self.table is not None and not (gx == 0 and gy < 0):
            raise ValueError(f"water.table: a water table needs gravity along -y, the scene's "
                             f"is {gravity!r}")
        if theta1 != 1.0:
            raise ValueError(f"water: the pore pressure is backward Euler, the scene's "
                             f"config.theta must have theta1 = 1, got {theta1!r}")

    def soil(self):
        """The :class:`~pfem_skfem.problems.consolidation.SaturatedSoil` of the step's term
        (its skeleton the step's cone, not held here)."""
        weight = (0.0, -self.gamma_w) if self.table is not None else (0.0, 0.0)
        return SaturatedSoil(None, self.k, self.gamma_w, self.M, self.alpha, weight)

    def saturated(self, regions):
        """Whether each of the scene's ``regions`` (Region objects, in order) is saturated."""
        return np.array([self.regions is None or r.name in self.regions for r in regions])

    def free_draining(self, x):
        """The pore pressure of a free-draining region at the points x (n, 2): the
        hydrostatic pressure where it is positive (below the table), zero above (dry)."""
        return np.maximum(self.hydrostatic(x), 0.0)

    def hydrostatic(self, x):
        """p_h = gamma_w (y_w - y) at the points x (n, 2); zero without a table."""
        x = np.atleast_2d(x)
        if self.table is None:
            return np.zeros(len(x))
        return self.gamma_w * (float(self.table) - x[:, 1])
