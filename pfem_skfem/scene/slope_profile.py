"""A slope profile: the slip surface and the ground surface before a failure, on the same
abscissae, and the sliding mass between them (:class:`Profile`); its CSV form
(:func:`read_profile`: a header ``x,z_slip,z_surface``, comments ``#``).

A landslide's scene is built from it: the mass fills :meth:`Profile.mass_polygon` (a
:class:`~pfem_skfem.scene.Region`) and the slip surface is a rigid polyline through the
profile's points (a :class:`~pfem_skfem.scene.Body`); the Yangbaodi landslide
(``verification/landslide_yangbaodi.py``, ``--profile PATH``) reads any profile of this form,
checked before any work.
"""
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["Profile", "read_profile"]


@dataclass(frozen=True)
class Profile:
    """A slope profile: the slip surface z_slip(x) and the ground surface z_surface(x) before
    failure, on the same points, x strictly increasing; the sliding mass lies where
    z_surface > z_slip (one interval of x)."""

    x: np.ndarray
    z_slip: np.ndarray
    z_surface: np.ndarray
    source: str = "profile"

    def __post_init__(self):
        x, zs, zt = (np.asarray(getattr(self, k), dtype=float)
                     for k in ("x", "z_slip", "z_surface"))
        name = self.source
        if not (x.ndim == zs.ndim == zt.ndim == 1 and len(x) == len(zs) == len(zt)):
            raise ValueError(f"{name}: x, z_slip and z_surface must be columns of one length")
        if len(x) < 2:
            raise ValueError(f"{name}: a profile needs at least two points, got {len(x)}")
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(zs)) and np.all(np.isfinite(zt))):
            raise ValueError(f"{name}: every x, z_slip and z_surface must be a finite number")
        back = np.flatnonzero(np.diff(x) <= 0)
        if back.size:
            i = int(back[0]) + 1
            raise ValueError(f"{name}: the profile is not a function of x: x must increase "
                             f"strictly, but row {i + 1} has x = {x[i]:g} after x = {x[i - 1]:g}")
        tol = 1e-9 * max(np.ptp(zs), np.ptp(x))
        below = np.flatnonzero(zt < zs - tol)
        if below.size:
            i = int(below[0])
            raise ValueError(f"{name}: the mass lies below the slip surface at x = {x[i]:g} "
                             f"(z_surface {zt[i]:g} < z_slip {zs[i]:g}): the ground surface "
                             f"must be on or above the slip surface")
        mass = zt > zs + tol
        if not mass.any():
            raise ValueError(f"{name}: there is no sliding mass (z_surface = z_slip everywhere)")
        runs = np.flatnonzero(np.diff(mass.astype(int)) == 1)
        if runs.size + (1 if mass[0] else 0) > 1:
            raise ValueError(f"{name}: the sliding mass must be one interval of x "
                             f"(z_surface > z_slip), found {runs.size + int(mass[0])}")
        for k, v in (("x", x), ("z_slip", zs), ("z_surface", np.where(mass, zt, zs))):
            object.__setattr__(self, k, v)

    @property
    def mass_range(self):
        """Indices (first, last) of the profile points bounding the mass."""
        inside = np.flatnonzero(self.z_surface > self.z_slip)
        return max(int(inside[0]) - 1, 0), min(int(inside[-1]) + 1, len(self.x) - 1)

    def mass_polygon(self):
        """The sliding mass, counter-clockwise: along the slip surface downhill, back along
        the ground surface (a side where the mass meets an end of the profile is vertical)."""
        i0, i1 = self.mass_range
        bottom = [(self.x[i], self.z_slip[i]) for i in range(i0, i1 + 1)]
        top = [(self.x[i], self.z_surface[i]) for i in range(i1, i0 - 1, -1)
               if self.z_surface[i] > self.z_slip[i]]
        return tuple(bottom + top)

    @property
    def thickness(self):
        """The largest vertical thickness of the mass."""
        return float(np.max(self.z_surface - self.z_slip))

    @property
    def concave(self):
        """Whether the slip surface's slope never increases (no convex bend)."""
        slope = np.diff(self.z_slip) / np.diff(self.x)
        return bool(np.all(np.diff(slope) >= -1e-4))    # rounding of the table


def read_profile(path):
    """The :class:`Profile` of a CSV file (comments '#', header x,z_slip,z_surface);
    ValueError naming the file and what is wrong."""
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: no such profile file")
    rows = [line.strip() for line in path.read_text().splitlines()
            if line.strip() and not line.lstrip().startswith("#")]
    if not rows or [c.strip() for c in rows[0].split(",")] != ["x", "z_slip", "z_surface"]:
        raise ValueError(f"{path}: the first line that is not a comment must be the header "
                         f"x,z_slip,z_surface")
    try:
        table = np.array([[float(c) for c in r.split(",")] for r in rows[1:]], dtype=float)
    except ValueError as err:
        raise ValueError(f"{path}: every row must be three numbers x,z_slip,z_surface "
                         f"({err})") from None
    if table.size == 0:
        table = np.zeros((0, 3))
    if table.ndim != 2 or table.shape[1] != 3:
        raise ValueError(f"{path}: every row must be three numbers x,z_slip,z_surface")
    return Profile(table[:, 0], table[:, 1], table[:, 2], source=str(path))
