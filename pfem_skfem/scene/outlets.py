"""Outlets of a PFEM scene: regions where material leaves the body (a silo's orifice).

After each step the particles inside an outlet's region are removed from the cloud,
counted, and their mass recorded as discharged through that outlet.
"""
from dataclasses import dataclass

import numpy as np

from .regions import _path, _signed, check_polygon


@dataclass(frozen=True)
class HalfPlane:
    """The points x with (x - point) . normal > 0."""

    point: tuple
    normal: tuple

    def __post_init__(self):
        p, n = np.asarray(self.point, dtype=float), np.asarray(self.normal, dtype=float)
        if p.shape != (2,) or n.shape != (2,) or not np.all(np.isfinite(np.r_[p, n])):
            raise ValueError("a half-plane needs a finite point (x, y) and normal (nx, ny)")
        if np.linalg.norm(n) == 0:
            raise ValueError("the normal of a half-plane must not be zero")
        object.__setattr__(self, "point", tuple(map(float, p)))
        object.__setattr__(self, "normal", tuple(map(float, n / np.linalg.norm(n))))

    def contains(self, x, tol=0.0):
        """Points beyond the plane (``tol`` > 0: also those within tol of it)."""
        return (np.atleast_2d(x) - np.asarray(self.point)) @ np.asarray(self.normal) > -tol


@dataclass(frozen=True)
class PolygonZone:
    """The points strictly inside a polygon."""

    vertices: tuple

    def __post_init__(self):
        v = check_polygon(self.vertices, "outlet polygon")
        object.__setattr__(self, "vertices", tuple(map(tuple, v)))

    def contains(self, x, tol=0.0):
        """Points inside (``tol`` > 0: also those within tol of its edges)."""
        v = np.asarray(self.vertices)
        return _path(v).contains_points(np.atleast_2d(x), radius=_signed(v, tol))


@dataclass(frozen=True)
class Outlet:
    """A named outlet: particles in ``zone`` (HalfPlane or PolygonZone) leave the body."""

    name: str
    zone: object

    def __post_init__(self):
        if not hasattr(self.zone, "contains"):
            raise ValueError(f"outlet {self.name!r}: zone must be a HalfPlane or PolygonZone, "
                             f"got {self.zone!r}")
