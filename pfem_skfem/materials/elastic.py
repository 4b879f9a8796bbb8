"""Isotropic linear elasticity (3.9)-(3.10).

Stresses are tension positive and ordered (sx, sy, sz, sxy) as in (3.23).
"""
from dataclasses import dataclass

import numpy as np

from .checks import _check_positive


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

