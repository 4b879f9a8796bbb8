"""Plane strain or axisymmetry: what the operators integrate over (thesis Ch 3 and Ch 7).

Both geometries use the same triangle mesh, the same element (Fig 3.1 / Fig 7.3)
and the same four-component stress vector, stored in the plane-strain order

    (s_x, s_y, s_z, s_xy)  =  (s_rr, s_zz, s_tt, s_rz)

(x = r, the radius; y = z, the axis; the out-of-plane component z = theta, the hoop
direction). The thesis writes (7.5) in the order (s_rr, s_tt, s_zz, s_rz);
:data:`THESIS_ORDER` and :func:`to_thesis_order` convert. Keeping the plane order
lets every problem of the package (static, dynamic, contact) and every yield cone
that reads the out-of-plane stress (Drucker-Prager, elasticity) serve both
geometries unchanged: only the operators differ.

Axisymmetry (7.6)-(7.8) changes them in two ways:

* the strain gains the hoop component eps_tt = u_r / r in the out-of-plane row
  (zero in plane strain);
* every volume integral is weighted by 2 pi r (dOmega = 2 pi r dr dz): forces,
  masses and volumes are those of the whole body of revolution, not per radian.

The weight raises each integrand's polynomial degree by one, so each quadrature
order rises by one (:meth:`Geometry.intorder`); the hoop row of B integrates
N_sigma (N_u / r) r = N_sigma N_u, a polynomial, with no 1/r left.
"""
from dataclasses import dataclass

import numpy as np

#: positions of (s_rr, s_tt, s_zz, s_rz) (the thesis' (7.5)) in the stored vector
THESIS_ORDER = (0, 2, 1, 3)


@dataclass(frozen=True)
class Geometry:
    """Plane strain (unit thickness) or a body of revolution about the axis x = r = 0."""

    name: str
    axisymmetric: bool

    def intorder(self, plane_order):
        """Quadrature order for an integrand exact at ``plane_order`` in plane strain."""
        return plane_order + 1 if self.axisymmetric else plane_order

    def weight(self, x):
        """Volume weight at points x (2, ...): 1, or 2 pi r."""
        return 2 * np.pi * x[0] if self.axisymmetric else 1.0


PLANE_STRAIN = Geometry("plane strain", False)
AXISYMMETRIC = Geometry("axisymmetric", True)
GEOMETRIES = {"plane": PLANE_STRAIN, "plane strain": PLANE_STRAIN,
              "axisymmetric": AXISYMMETRIC}


def as_geometry(geometry):
    """A :class:`Geometry` from itself or its name ('plane', 'axisymmetric')."""
    if isinstance(geometry, Geometry):
        return geometry
    try:
        return GEOMETRIES[geometry]
    except (KeyError, TypeError):
        raise ValueError(f"geometry must be one of {sorted(GEOMETRIES)} or a Geometry, "
                         f"got {geometry!r}") from None


def to_thesis_order(sigma):
    """Stresses (n, 4) stored as (s_rr, s_zz, s_tt, s_rz) in the thesis' order (7.5)."""
    return np.asarray(sigma)[..., list(THESIS_ORDER)]


def check_axisymmetric_mesh(p, t, doflocs=None):
    """Raise ValueError unless every node lies in r >= 0 and no element crosses the axis.

    Parameters
    ----------
    p : (2, n_nodes) node coordinates (x = r).  t : (3+, n_elements) connectivity.
    doflocs : optional (2, n) further points (P2 midside nodes) to check.
    """
    scale = float(np.ptp(p, axis=1).max()) or 1.0
    tol = 1e-12 * scale                      # round-off on the axis counts as r = 0
    r = p[0, t[:3]]
    crossing = (r.min(axis=0) < -tol) & (r.max(axis=0) > tol)
    if np.any(crossing):
        raise ValueError(f"mesh crosses the axis r = 0: {int(crossing.sum())} element(s) have "
                         "nodes on both sides; an axisymmetric mesh must lie in r >= 0")
    r_all = p[0] if doflocs is None else np.concatenate([p[0], doflocs[0]])
    if np.any(r_all < -tol):
        raise ValueError(f"a node lies at r < 0 (min r = {r_all.min():.6g}): an axisymmetric "
                         "mesh must lie in r >= 0 (x is the radius)")
