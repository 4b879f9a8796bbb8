"""Particle state of the PFEM cloud C^n (thesis Section 2.2, step 0).

The particles are the vertex nodes of the mesh (Section 2.3.1: with the six-node
triangle only the vertices take part in the domain detection). Each carries its
position, velocity, optionally an acceleration, a characteristic spacing h (the
cloud may be non-uniform, Section 6.4.1) and two tags: on the free surface, and in
contact with a rigid body.
"""
from dataclasses import dataclass, replace
from typing import ClassVar

import numpy as np


def _vectors(name, value, n):
    a = np.asarray(value, dtype=float)
    if a.shape != (n, 2):
        raise ValueError(f"{name} must have shape ({n}, 2), got {a.shape}")
    if not np.all(np.isfinite(a)):
        bad = int(np.sum(~np.isfinite(a).all(axis=1)))
        raise ValueError(f"{name} has non-finite values at {bad} particle(s)")
    return a


def _tags(name, value, n):
    a = np.zeros(n, dtype=bool) if value is None else np.asarray(value, dtype=bool)
    if a.shape != (n,):
        raise ValueError(f"{name} must have shape ({n},), got {a.shape}")
    return a


def check_positions(x, allow_empty=False):
    """Return ``x`` as an (n, 2) float array; ValueError for misshapen or non-finite input,
    and for an empty one unless ``allow_empty``."""
    x = np.asarray(x, dtype=float)
    if allow_empty and x.size == 0:
        x = x.reshape(0, 2)
    if x.ndim != 2 or x.shape[1] != 2:
        raise ValueError(f"positions must be an (n, 2) array, got shape {x.shape}")
    if x.shape[0] == 0 and not allow_empty:
        raise ValueError("the particle cloud is empty (positions has 0 rows)")
    if not np.all(np.isfinite(x)):
        bad = np.flatnonzero(~np.isfinite(x).all(axis=1))
        raise ValueError(f"positions has non-finite coordinates at particle(s) {bad[:5].tolist()}"
                         + (" ..." if bad.size > 5 else ""))
    return x


def check_spacing(h, n):
    """Return h broadcast to (n,); ValueError unless every value is positive and finite."""
    h = np.asarray(h, dtype=float)
    if h.ndim == 0:
        h = np.full(n, float(h))
    if h.shape != (n,):
        raise ValueError(f"h (characteristic spacing) must be a number or shape ({n},), "
                         f"got shape {h.shape}")
    if not np.all(np.isfinite(h)) or np.any(h <= 0):
        raise ValueError("h (characteristic spacing) must be positive and finite everywhere")
    return h


@dataclass
class Particles:
    """A cloud of particles: the PFEM state that survives remeshing.

    Attributes
    ----------
    x : (n, 2) positions.
    h : (n,) characteristic spacing (a number is broadcast).
    v : (n, 2) velocities (zero by default).
    a : (n, 2) accelerations, or None when the scheme does not keep them.
    free_surface : (n,) bool, particle lies on the boundary of the detected domain.
    contact : (n,) bool, particle touches a rigid body.
    """

    x: np.ndarray
    h: np.ndarray
    v: np.ndarray = None
    a: np.ndarray = None
    free_surface: np.ndarray = None
    contact: np.ndarray = None
    may_be_empty: ClassVar[bool] = False      # a cloud has particles

    def __post_init__(self):
        self.x = check_positions(self.x, allow_empty=self.may_be_empty)
        n = self.x.shape[0]
        self.h = check_spacing(self.h, n)
        self.v = np.zeros((n, 2)) if self.v is None else _vectors("v (velocities)", self.v, n)
        if self.a is not None:
            self.a = _vectors("a (accelerations)", self.a, n)
        self.free_surface = _tags("free_surface", self.free_surface, n)
        self.contact = _tags("contact", self.contact, n)

    @property
    def n(self):
        """Number of particles."""
        return self.x.shape[0]

    def moved(self, dx, dv=None):
        """A new cloud with positions x + dx (and velocities v + dv); step 2b of Section 2.2."""
        dx = _vectors("dx", dx, self.n)
        v = self.v if dv is None else self.v + _vectors("dv", dv, self.n)
        return replace(self, x=self.x + dx, v=v)

    def subset(self, keep):
        """The particles selected by a boolean mask or index array."""
        keep = np.asarray(keep)
        return Particles(self.x[keep], self.h[keep], self.v[keep],
                         None if self.a is None else self.a[keep],
                         self.free_surface[keep], self.contact[keep])


def nodal_spacing(points, triangles):
    """Characteristic spacing of each vertex: the mean length of the mesh edges at it.

    Gives the h of a non-uniform cloud from the mesh its particles came from
    (Section 2.3.1: a large h where the mesh is coarse). Vertices in no triangle get nan.

    Parameters
    ----------
    points : (n, 2); triangles : (m, 3) vertex indices.
    """
    points = check_positions(points)
    t = np.asarray(triangles, dtype=int)
    edges = np.unique(np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1),
                      axis=0)
    length = np.linalg.norm(points[edges[:, 0]] - points[edges[:, 1]], axis=1)
    total = np.bincount(edges.ravel(), np.repeat(length, 2), minlength=len(points))
    count = np.bincount(edges.ravel(), minlength=len(points))
    with np.errstate(invalid="ignore", divide="ignore"):
        return total / count


def thin_cloud(points, h, *, fraction=0.5, protect=None, prefer=None):
    """Keep-mask that removes particles crowding another one (closer than fraction * h).

    Triangle can only add nodes; when particles bunch up (or added nodes became
    particles) the mesh would refine around each close pair. Removing one particle of
    each close pair holds the spacing near h. Of a close pair (i, j), i < j, j is
    removed unless it is protected (e.g. free-surface or contact particles, whose
    removal would change the domain), in which case i is, unless both are protected.
    A preferred particle wins the same way over one that is not, but of two preferred
    particles one (j) is still removed.

    Parameters
    ----------
    points : (n, 2); h : float or (n,); fraction : distance, in units of the pair's
    smaller h, below which two particles crowd each other; protect, prefer : (n,) bool.

    Returns
    -------
    (n,) bool, True for the particles to keep.
    """
    from scipy.spatial import cKDTree

    points = check_positions(points)
    n = len(points)
    h = check_spacing(h, n)
    if not 0 <= fraction < 1:
        raise ValueError(f"fraction must lie in [0, 1), got {fraction!r}")
    protect = np.zeros(n, dtype=bool) if protect is None else np.asarray(protect, dtype=bool)
    keep = np.ones(n, dtype=bool)
    if fraction == 0:
        return keep
    pairs = cKDTree(points).query_pairs(fraction * h.max(), output_type="ndarray")
    if len(pairs) == 0:
        return keep
    i, j = pairs.T
    close = np.linalg.norm(points[i] - points[j], axis=1) < fraction * np.minimum(h[i], h[j])
    i, j = i[close], j[close]
    if prefer is not None:                   # the preferred one of a mixed pair stays
        prefer = np.asarray(prefer, dtype=bool)
        j, i = np.where(prefer[j] & ~prefer[i], (i, j), (j, i))
    drop = np.where(protect[j], i, j)
    keep[drop[~(protect[i] & protect[j])]] = False
    return keep
