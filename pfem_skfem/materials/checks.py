"""The checks of the materials' parameters (shared by the cones and the PFEM materials)."""
import numpy as np


def _is_real(value):
    """A real scalar (a 0-d array too), not a bool, text or None (a TypeError in isfinite)."""
    kind = np.asarray(value).dtype if np.ndim(value) == 0 else None
    return kind is not None and (np.issubdtype(kind, np.floating)
                                 or np.issubdtype(kind, np.integer))


def _check_positive(name, value):
    if not _is_real(value) or not np.isfinite(value) or value <= 0:
        raise ValueError(f"{name} must be positive and finite, got {value!r}")


def check_cohesion(c):
    """c (cohesion) must be finite and >= 0: checked before any stand-in value is put in
    its place (a zero-c material validates phi on a MohrCoulomb of c = 1)."""
    if not (_is_real(c) and np.isfinite(c) and c >= 0):
        raise ValueError(f"c (cohesion) must be finite and >= 0, got {c!r}")


def _check_angle(name, degrees, upper=90.0):
    if not _is_real(degrees) or not np.isfinite(degrees) or not 0.0 <= degrees < upper:
        raise ValueError(f"{name} must lie in [0, {upper:g}) degrees, got {degrees!r}")

