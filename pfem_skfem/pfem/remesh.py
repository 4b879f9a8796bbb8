"""Meshes of the detected domain (thesis Sections 2.3.1 and 2.4).

Two paths, both giving a straight-sided scikit-fem ``MeshTri`` whose vertices
include the particles (the P2 basis of :mod:`pfem_skfem.discretisation.elements` adds the midside
nodes, Section 2.3.1: only the vertices are particles):

(a) :func:`alpha_mesh`: the alpha-filtered Delaunay triangulation itself (Fig 2.3 (c)).
    Needs no Triangle, so it is free of Triangle's licence terms.
(b) :func:`quality_remesh`: a quality mesh of the same domain made by Triangle
    (Section 2.4, through meshpy) refining (a): the particles stay vertices, the
    boundary and the voids stay as detected, and Triangle adds nodes where an
    element is larger than the target size or has an angle below the bound.

Every returned triangle is counter-clockwise with positive area.
"""
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree
from skfem import MeshTri

from .alpha_shape import AlphaShape, triangle_areas


@dataclass
class ParticleMesh:
    """A mesh whose vertices are (mostly) particles.

    mesh : skfem.MeshTri; particle : (n_vertices,) particle index of each mesh vertex,
    -1 for a node added by the mesher.
    """

    mesh: MeshTri
    particle: np.ndarray

    @property
    def added(self):
        """Mask of the vertices that are not particles."""
        return self.particle < 0


def _orient(p, t):
    """Triangles (m, 3) made counter-clockwise."""
    t = np.array(t, dtype=np.int64)
    flip = triangle_areas(p, t) < 0
    t[flip] = t[flip][:, [0, 2, 1]]
    return t


def _as_mesh(p, t):
    return MeshTri(np.ascontiguousarray(p.T), np.ascontiguousarray(t.T), sort_t=False)


def alpha_mesh(shape):
    """Path (a): the kept Delaunay triangles as a mesh, particles = vertices (Fig 2.3 (c)).

    Parameters
    ----------
    shape : AlphaShape from :func:`~pfem_skfem.pfem.alpha_shape.alpha_shape`.

    Returns
    -------
    ParticleMesh; unused particles (the free ones) are not vertices.

    Raises
    ------
    ValueError if the domain is empty (no kept triangle).
    """
    _check_shape(shape)
    used = np.unique(shape.triangles)
    index = np.full(len(shape.points), -1)
    index[used] = np.arange(len(used))
    t = _orient(shape.points[used], index[shape.triangles])
    return ParticleMesh(_as_mesh(shape.points[used], t), used)


def _check_shape(shape):
    if not isinstance(shape, AlphaShape):
        raise ValueError(f"shape must be an AlphaShape, got {type(shape).__name__}")
    if len(shape.triangles) == 0:
        raise ValueError("the detected domain is empty (no triangle has circumradius "
                         "<= alpha * h): increase alpha or check the cloud")


def equilateral_area(edge):
    """Area of an equilateral triangle with the given edge length."""
    return np.sqrt(3) / 4 * np.asarray(edge) ** 2


def quality_remesh(shape, *, size=1.5, min_angle=25.0):
    """Path (b): a quality mesh of the detected domain by Triangle, keeping the particles.

    The alpha-filtered triangulation is handed to Triangle as a mesh to refine
    (its ``-r`` mode), so its boundary edges and voids are kept exactly, every
    particle stays a vertex, and Triangle only adds nodes.

    Parameters
    ----------
    shape : AlphaShape.
    size : largest element edge, in units of h: a triangle larger than the
        equilateral one of edge ``size * h`` is split (h of the kept triangle it
        comes from, the mean of its particles' h, so non-uniform clouds work).
    min_angle : Triangle's minimum-angle bound in degrees (its ``q`` switch; it is
        guaranteed up to about 20.7 and works in practice up to about 33 degrees).
        Angles between two boundary edges smaller than the bound stay as they are.

    Returns
    -------
    ParticleMesh: the domain's particles first, in the order of ``np.unique``
    of the kept triangles, then the nodes Triangle added (``particle == -1``).
    """
    from meshpy.triangle import MeshInfo, refine

    _check_shape(shape)
    if not np.isfinite(size) or size <= 0:
        raise ValueError(f"size must be positive, got {size!r}")
    if not 0 <= min_angle <= 34:
        raise ValueError(f"min_angle must lie in [0, 34] degrees, got {min_angle!r}")
    used = np.unique(shape.triangles)
    index = np.full(len(shape.points), -1)
    index[used] = np.arange(len(used))
    origin = shape.points[used].mean(axis=0)     # Triangle works in shifted coordinates
    xy = shape.points[used] - origin
    tri = index[shape.triangles]
    max_area = equilateral_area(size * shape.h[shape.triangles].mean(axis=1))

    info = MeshInfo()
    info.set_points(xy)
    info.elements.resize(len(tri))
    info.element_volumes.setup()
    for i, (element, a) in enumerate(zip(tri.tolist(), max_area.tolist())):
        info.elements[i] = element
        info.element_volumes[i] = a
    out = refine(info, min_angle=float(min_angle))
    p = np.asarray(out.points, dtype=float)
    t = _orient(p, np.asarray(out.elements, dtype=np.int64))
    particle = np.full(len(p), -1)
    # Triangle numbers the input vertices first; confirm by coordinates
    tol = 1e-12 * (1 + np.abs(xy).max())
    if len(p) >= len(used) and np.allclose(p[:len(used)], xy, rtol=0, atol=tol):
        particle[:len(used)] = used
    else:
        d, k = cKDTree(p).query(xy)
        particle[k[d <= tol]] = used[d <= tol]
    return ParticleMesh(_as_mesh(p + origin, t), particle)


def mesh_quality(mesh):
    """Element-quality figures of a triangle mesh.

    Returns
    -------
    dict with ``n_elements``, ``min_angle`` (degrees), ``max_aspect`` (circumradius
    over twice the inradius: 1 for an equilateral triangle, growing as it degenerates),
    ``min_area``, ``max_area`` (signed; negative means inverted).
    """
    p, t = mesh.p.T, mesh.t.T
    e = np.stack([np.linalg.norm(p[t[:, (k + 1) % 3]] - p[t[:, (k + 2) % 3]], axis=1)
                  for k in range(3)], axis=1)       # edge k is opposite vertex k
    area = triangle_areas(p, t)
    a, b, c = e.T
    cos = np.clip(np.stack([(b**2 + c**2 - a**2) / (2 * b * c),
                            (c**2 + a**2 - b**2) / (2 * c * a),
                            (a**2 + b**2 - c**2) / (2 * a * b)]), -1, 1)
    s = 0.5 * e.sum(axis=1)
    with np.errstate(divide="ignore"):
        aspect = (a * b * c / (4 * np.abs(area))) / (2 * np.abs(area) / s)
    return {"n_elements": int(len(t)), "min_angle": float(np.degrees(np.arccos(cos)).min()),
            "max_aspect": float(aspect.max()), "min_area": float(area.min()),
            "max_area": float(area.max())}


def drop_degenerate(pm, h):
    """Remove triangles of (near) zero area, below 1e-8 h^2, from a particle mesh
    (collapsed slivers), with the vertices only they used."""
    p, t = pm.mesh.p.T, pm.mesh.t.T
    area = triangle_areas(p, t)
    good = area > 1e-8 * np.min(h) ** 2
    if good.all():
        return pm
    used = np.unique(t[good])
    index = np.full(len(p), -1)
    index[used] = np.arange(len(used))
    return ParticleMesh(_as_mesh(p[used], index[t[good]]), pm.particle[used])


@dataclass(frozen=True)
class AlphaMesh:
    """Remesher (a): the alpha-shape's own triangles, the particles as vertices (Fig 2.3 (c)).

    thin : before each detection, remove particles closer than ``thin`` h to another one
        (:func:`~pfem_skfem.pfem.particles.thin_cloud`; each merges into the nearest kept
        particle of its region, :func:`~pfem_skfem.pfem.bookkeeping.hand_on_mass`); 0 (the
        default): none. Why: the midside nodes of stretched surface edges become
        particles, and a splash piles them up where it meets a wall; their slivers carry
        no mass, so the step may give their vertices any speed (the clay block into the
        tank, book/water_and_mud.md).
    keep_surface : thin the free surface without moving it: of a close pair, a particle
        on the free surface (the previous mesh's boundary) is kept over one inside, and a
        kept surface particle takes the merged mass where it stands
        (:func:`~pfem_skfem.pfem.bookkeeping.hand_on_mass`'s ``stay``). Why: merged at
        their centre of mass, the surface's pairs pull the boundary in at each remeshing,
        and ``keep_area`` grows the area back by lifting the water (the clay block into
        the tank, book/water_and_mud.md). Off by default.
    """

    thin: float = 0.0
    keep_surface: bool = False

    def __post_init__(self):
        if not (np.isfinite(self.thin) and 0 <= self.thin < 1):
            raise ValueError(f"thin (a distance in units of h) must lie in [0, 1), got "
                             f"{self.thin!r}")
        if not isinstance(self.keep_surface, (bool, np.bool_)):
            raise ValueError(f"keep_surface must be True or False, got {self.keep_surface!r}")

    @property
    def thin_fraction(self):
        return self.thin

    def __call__(self, shape):
        return drop_degenerate(alpha_mesh(shape), shape.h)


@dataclass(frozen=True)
class QualityRemesh:
    """Remesher (b): Triangle refines the alpha-shape (Section 2.4); added nodes become
    particles, so the cloud is thinned first (:func:`~pfem_skfem.pfem.particles.thin_cloud`,
    particles closer than 0.4 h) to hold the spacing near h.

    size : target element edge in units of h (:func:`quality_remesh`).
    """

    size: float = 1.5
    thin_fraction = 0.4                 # particles closer than 0.4 h are thinned
    keep_surface = False                # merged at their centre of mass (AlphaMesh's)

    def __post_init__(self):
        if not np.isfinite(self.size) or self.size <= 0:
            raise ValueError(f"size (target edge / h) must be positive, got {self.size!r}")

    def __call__(self, shape):
        return drop_degenerate(quality_remesh(shape, size=self.size), shape.h)


def last_declared_region(region, vertex_particle):
    """The rule of :func:`~pfem_skfem.pfem.assemble.element_regions` on an
    element-by-vertex array of particle indices (n_elements, 3): the largest of the
    vertices' regions, a vertex with no particle (a negative index: thinned away since the
    mesh was made) counting for none (-1). Shared by the step's mesh and the map source's
    (:func:`~pfem_skfem.pfem.transfer.old_regions`). Here, beside :class:`ParticleMesh`,
    so that both import it without a cycle (assemble -> scene -> transfer)."""
    return np.where(vertex_particle >= 0, region[np.maximum(vertex_particle, 0)],
                    -1).max(axis=1)
