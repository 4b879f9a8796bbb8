"""Meshes of the benchmark domains, made by Triangle (through meshpy).

Triangle's licence forbids commercial redistribution without its author's
permission; see the README.
"""
import numpy as np
from skfem import MeshTri


def _check_length(name, value):
    if not np.isfinite(value) or value <= 0:
        raise ValueError(f"{name} must be positive, got {value!r}")


def triangulate_polygon(points, size, *, min_angle=30.0, holes=()):
    """Quality triangulation of a polygon with a local element size ``size(x, y)``.

    Parameters
    ----------
    points : (n, 2) polygon vertices in order (closed implicitly).
    size : callable (x, y) -> target edge length, or a number.
    min_angle : Triangle's minimum-angle bound in degrees.

    Returns
    -------
    skfem.MeshTri (straight-sided; the P2 basis adds the midside nodes).
    """
    from meshpy.triangle import MeshInfo, build

    points = np.asarray(points, dtype=float)
    if points.ndim != 2 or points.shape[0] < 3 or points.shape[1] != 2:
        raise ValueError("points must be an (n >= 3, 2) array of polygon vertices")
    h = size if callable(size) else (lambda x, y, s=float(size): s)
    info = MeshInfo()
    info.set_points(points.tolist())
    n = len(points)
    info.set_facets([(i, (i + 1) % n) for i in range(n)])
    if holes:
        info.set_holes([tuple(p) for p in holes])

    def refine(vertices, area):
        cx, cy = np.mean(np.asarray(vertices), axis=0)
        target = h(cx, cy)
        return area > 0.5 * np.sqrt(3) / 2 * target ** 2   # area of an equilateral triangle

    tri = build(info, refinement_func=refine, min_angle=min_angle)
    p = np.ascontiguousarray(np.asarray(tri.points, dtype=float).T)
    t = np.ascontiguousarray(np.asarray(tri.elements, dtype=np.int64).T)
    return MeshTri(p, t)


def graded_rectangle(width, depth, focus, *, h_min, h_max, growth=0.3, min_angle=30.0):
    """Rectangle [0, width] x [-depth, 0] refined towards a point ``focus`` on its top edge.

    The element size grows linearly from ``h_min`` at the focus with slope ``growth``,
    capped at ``h_max``. The focus is a vertex of the mesh.
    """
    for name, value in (("width", width), ("depth", depth), ("h_min", h_min),
                        ("h_max", h_max), ("growth", growth)):
        _check_length(name, value)
    fx, fy = focus
    if not (0 < fx < width and fy == 0):
        raise ValueError("focus must lie inside the top edge (0 < x < width, y = 0)")
    corners = [(0.0, -depth), (width, -depth), (width, 0.0), (fx, 0.0), (0.0, 0.0)]

    def size(x, y):
        return min(h_max, h_min + growth * np.hypot(x - fx, y - fy))

    return triangulate_polygon(corners, size, min_angle=min_angle)


def graded_rectangle_with_elements(width, depth, focus, n_elements, *, ratio=12.0,
                                   growth=0.3, min_angle=30.0):
    """:func:`graded_rectangle` whose size scale is chosen to give about ``n_elements``.

    ``ratio`` = h_max / h_min.
    """
    return fit_element_count(
        lambda h: graded_rectangle(width, depth, focus, h_min=h / ratio, h_max=h,
                                   growth=growth, min_angle=min_angle),
        n_elements, first_size=2 * np.sqrt(2.3 * width * depth / n_elements))


def fit_element_count(build, n_elements, first_size, *, tolerance=0.05, tries=8):
    """The mesh ``build(h)`` whose element count is closest to ``n_elements``.

    The count scales like 1 / h^2, so a few secant updates of the size scale h in
    that law reach the target within ``tolerance`` (relative).
    """
    if not n_elements or n_elements < 4:
        raise ValueError(f"n_elements must be at least 4, got {n_elements!r}")
    h, best = first_size, None
    for _ in range(tries):
        mesh = build(h)
        n = mesh.t.shape[1]
        if best is None or abs(n - n_elements) < abs(best.t.shape[1] - n_elements):
            best = mesh
        if abs(n - n_elements) <= tolerance * n_elements:
            break
        h *= np.sqrt(n / n_elements)
    return best


def to_curved(mesh, center, radius, *, tol=1e-9):
    """P2-geometry mesh (skfem ``MeshTri2``) whose facets on a circle are curved onto it.

    Facets with both end points on the circle of ``radius`` about ``center`` get
    their midside node moved radially onto the circle, so the quadratic elements
    follow the circle exactly at their nodes (a pipe, a cylinder).
    """
    from dataclasses import replace

    from skfem import MeshTri2

    _check_length("radius", radius)
    m2 = MeshTri2.from_mesh(mesh)
    c = np.asarray(center, dtype=float)[:, None]
    on = np.abs(np.linalg.norm(mesh.p - c, axis=0) - radius) < tol * max(1.0, radius)
    facets = np.flatnonzero(on[mesh.facets].all(axis=0))
    dofs = m2.dofs.get_facet_dofs(facets).flatten()
    doflocs = m2.doflocs.copy()
    d = doflocs[:, dofs] - c
    doflocs[:, dofs] = c + radius * d / np.linalg.norm(d, axis=0)
    return replace(m2, doflocs=doflocs)


def pipe_half_domain(width, height, depth, radius, *, h_min, h_max, growth=0.25,
                     n_arc=None, min_angle=30.0):
    """Half soil column [0, width] x [-height, 0] around a pipe of ``radius`` centred on
    the symmetry axis x = 0 at ``depth`` below the surface; refined at the pipe.

    Returns a curved ``MeshTri2`` (midside nodes on the pipe lie on the circle).
    """
    for name, value in (("width", width), ("height", height), ("depth", depth),
                        ("radius", radius), ("h_min", h_min), ("h_max", h_max)):
        _check_length(name, value)
    if not (radius < depth < height - radius) or radius >= width:
        raise ValueError("the pipe must lie inside the column")
    yc = -depth
    n_arc = n_arc or max(8, int(np.ceil(np.pi * radius / h_min)))
    theta = np.linspace(np.pi / 2, -np.pi / 2, n_arc + 1)       # top -> bottom, x >= 0
    arc = np.stack([radius * np.cos(theta), yc + radius * np.sin(theta)], axis=1)
    arc[:, 0] = np.where(np.abs(arc[:, 0]) < 1e-12, 0.0, arc[:, 0])
    outline = np.vstack([[(0.0, 0.0)], arc, [(0.0, -height), (width, -height), (width, 0.0)]])

    def size(x, y):
        dist = max(np.hypot(x, y - yc) - radius, 0.0)
        return min(h_max, h_min + growth * dist)

    # Triangle wants counter-clockwise order: reverse the clockwise outline above
    mesh = triangulate_polygon(outline[::-1], size, min_angle=min_angle)
    return to_curved(mesh, (0.0, yc), radius, tol=1e-7)
