"""Domain detection by the alpha-shape method, in Cremonesi's form (thesis Section 2.3, Fig 2.3).

Steps (Fig 2.3 (a)-(c)): Delaunay triangulation of the particles; delete every
triangle whose circumcircle radius exceeds alpha * h, h being the characteristic
spacing of the triangle (here the mean of its three particles' spacings, so
non-uniform clouds work, Section 2.3.1). Because Delaunay circumcircles are empty,
this is the alpha-shape of Edelsbrunner and Muecke [47] (Cremonesi et al. [36]).

From the kept triangles follow: boundary edges (edges of one kept triangle),
bodies (connected components of kept triangles sharing an edge), boundary loops
(outer loops counter-clockwise, holes clockwise), free-surface particles (on a
boundary edge), free particles (in no kept triangle) and the domain area.

Degenerate clouds never raise: duplicate particles are merged (the copies are
reported free, with ``duplicate_of``), zero-area Delaunay triangles are dropped,
and a cloud Qhull cannot triangulate (fewer than three distinct points, all
collinear) gives an empty domain with every particle free.
"""
from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import Delaunay, QhullError, cKDTree

from .particles import check_positions, check_spacing

#: a triangle whose twice-area is below this times its longest edge squared is degenerate
DEGENERATE = 1e-12


@dataclass
class AlphaShape:
    """The detected domain V^n of a particle cloud (Section 2.3).

    Attributes
    ----------
    points : (n, 2) particle positions; h : (n,) spacings; alpha : the parameter.
    delaunay : (M, 3) all Delaunay triangles, counter-clockwise (particle indices).
    radius : (M,) circumradius of each Delaunay triangle divided by its h.
    kept : (M,) bool, triangle belongs to the domain.
    triangles : (m, 3) the kept triangles, counter-clockwise.
    body : (m,) body label of each kept triangle (0 .. n_bodies - 1).
    edges : (k, 2) boundary edges, oriented with the domain on their left.
    edge_loop : (k,) loop label of each boundary edge.
    loop_area : (L,) signed area enclosed by each loop: > 0 outer, < 0 hole.
    loop_body : (L,) body each loop bounds.
    hole_seeds : (H, 2) one point inside each void enclosed by the domain.
    free_surface : (n,) bool, particle on a boundary edge.
    free : (n,) bool, particle in no kept triangle (isolated, or a duplicate).
    duplicate_of : (n,) index of the particle each one was merged into (itself if unique).
    """

    points: np.ndarray
    h: np.ndarray
    alpha: float
    delaunay: np.ndarray
    radius: np.ndarray
    kept: np.ndarray
    triangles: np.ndarray
    body: np.ndarray
    n_bodies: int
    edges: np.ndarray
    edge_loop: np.ndarray
    loop_area: np.ndarray
    loop_body: np.ndarray
    hole_seeds: np.ndarray
    free_surface: np.ndarray
    free: np.ndarray
    duplicate_of: np.ndarray
    _next_edge: np.ndarray = None

    @property
    def area(self):
        """Area of the detected domain (sum of the kept triangles)."""
        return float(triangle_areas(self.points, self.triangles).sum())

    @property
    def body_area(self):
        """(n_bodies,) area of each body."""
        return np.bincount(self.body, triangle_areas(self.points, self.triangles),
                           minlength=self.n_bodies)

    @property
    def n_holes(self):
        """Number of inner boundary loops (voids enclosed by a body); slits of zero area are not."""
        scale = np.ptp(self.points, axis=0).max() ** 2
        return int(np.sum(self.loop_area < -DEGENERATE * scale))

    def loops(self):
        """Boundary loops as lists of particle indices, in the order of ``loop_area``."""
        out = [None] * len(self.loop_area)
        seen = np.zeros(len(self.edges), dtype=bool)
        for e0 in range(len(self.edges)):
            if seen[e0]:
                continue
            loop, e = [], e0
            while not seen[e]:
                seen[e] = True
                loop.append(int(self.edges[e, 0]))
                e = self._next_edge[e]
            out[self.edge_loop[e0]] = np.array(loop)
        return out


def triangle_areas(points, tri):
    """Signed areas of triangles (m, 3) of ``points``; positive when counter-clockwise."""
    a, b, c = (points[tri[:, k]] for k in range(3))
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                  - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1]))


def triangle_volumes(points, tri):
    """Signed volumes 2 pi A r_c of triangles (m, 3) of ``points`` revolved about the axis
    x = 0 (Pappus; exact for straight-sided triangles, r_c the centroid's radius)."""
    r_c = (points[tri[:, 0], 0] + points[tri[:, 1], 0] + points[tri[:, 2], 0]) / 3.0
    return 2 * np.pi * triangle_areas(points, tri) * r_c


def measure(points, tri, axisymmetric=False):
    """(m,) areas of triangles (m, 3), or in axisymmetry their volumes of revolution."""
    return triangle_volumes(points, tri) if axisymmetric else triangle_areas(points, tri)


def circumradius(points, tri):
    """Circumradius R = abc / (4 A) of each triangle; inf for a zero-area triangle."""
    a, b, c = (points[tri[:, k]] for k in range(3))
    la, lb, lc = (np.linalg.norm(u - v, axis=1) for u, v in ((b, c), (c, a), (a, b)))
    twice = np.abs(2 * triangle_areas(points, tri))
    with np.errstate(divide="ignore", invalid="ignore"):
        r = la * lb * lc / (2 * twice)
    return np.where(twice > 0, r, np.inf)


def in_triangles(p, t, x, tol=1e-12):
    """(n,) bool: the point x_i lies in (or on) a triangle of ``t`` (m, 3) of vertices ``p``.

    Candidates are the triangles whose centroid is within the largest centroid-to-vertex
    distance of the mesh (no point of a triangle is further from its centroid); the test
    is on area coordinates, for either orientation; zero-area triangles contain nothing.
    """
    x = np.asarray(x, dtype=float).reshape(-1, 2)
    inside = np.zeros(len(x), dtype=bool)
    t = np.asarray(t, dtype=int).reshape(-1, 3)
    if len(t) == 0 or len(x) == 0:
        return inside
    a, b, c = (np.asarray(p, dtype=float)[t[:, k]] for k in range(3))
    centroid = (a + b + c) / 3.0
    reach = max(np.linalg.norm(v - centroid, axis=1).max() for v in (a, b, c))
    near = cKDTree(centroid).query_ball_point(x, reach * (1 + 1e-9) + 1e-300)
    i = np.repeat(np.arange(len(x)), [len(n) for n in near])
    j = np.concatenate([np.asarray(n, dtype=int) for n in near])
    cross = lambda u, v: u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]       # noqa: E731
    twice = cross(b[j] - a[j], c[j] - a[j])
    q = x[i]
    with np.errstate(divide="ignore", invalid="ignore"):
        la = cross(b[j] - q, c[j] - q) / twice
        lb = cross(c[j] - q, a[j] - q) / twice
    ok = (twice != 0) & (la >= -tol) & (lb >= -tol) & (1 - la - lb >= -tol)
    inside[i[ok]] = True
    return inside


def notches(points, tri, kept, p, t, h):
    """Indices of the kept triangles that fill a notch of the advected mesh's surface:
    two of their edges are consecutive boundary edges of (p, t) and their centroid lies
    outside it. Such a triangle joins no two parts of the body (its three particles were
    neighbours on the surface); the alpha test would add its area from nothing.

    The particles are matched to the vertices of ``p`` by position (to 1e-9 h: the
    advected mesh's vertices are the moved particles themselves); a particle not among
    them that lies near the midpoint of a boundary edge (within half its length: a
    particle added on a stretched surface edge) splits that edge in two."""
    t = np.asarray(t, dtype=int).reshape(-1, 3)
    if len(t) == 0 or not kept.any():
        return np.empty(0, dtype=int)
    edges = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    edges, count = np.unique(edges, axis=0, return_counts=True)
    boundary = edges[count == 1]                       # edges of one triangle of (p, t)
    dist, vertex = cKDTree(p).query(points)
    vertex = np.where(dist <= 1e-9 * h, vertex, -1)
    new = np.flatnonzero(vertex < 0)
    if new.size and len(boundary):                     # particles added on surface edges
        mid = 0.5 * (p[boundary[:, 0]] + p[boundary[:, 1]])
        half = 0.5 * np.linalg.norm(p[boundary[:, 1]] - p[boundary[:, 0]], axis=1)
        d, e = cKDTree(mid).query(points[new])
        on = d <= half[e]
        new, e = new[on], e[on]
        e, first = np.unique(e, return_index=True)     # one particle an edge
        new = new[first]
        vertex[new] = len(p) + np.arange(len(new))
        split = np.concatenate([np.stack([boundary[e, 0], vertex[new]], axis=1),
                                np.stack([vertex[new], boundary[e, 1]], axis=1)])
        boundary = np.sort(np.concatenate([np.delete(boundary, e, axis=0), split]), axis=1)
    n_ids = len(p) + len(points)
    on_surface = np.zeros(n_ids, dtype=bool)
    on_surface[boundary.ravel()] = True
    cand = np.flatnonzero(kept)
    v = vertex[tri[cand]]
    ok = np.all(v >= 0, axis=1)
    cand, v = cand[ok], v[ok]
    ok = np.all(on_surface[v], axis=1)
    cand, v = cand[ok], v[ok]
    if len(cand) == 0:
        return cand
    key = boundary[:, 0] * n_ids + boundary[:, 1]
    pairs = np.sort(np.stack([v[:, [0, 1]], v[:, [1, 2]], v[:, [2, 0]]], axis=1), axis=2)
    on_edge = np.isin(pairs[..., 0] * n_ids + pairs[..., 1], key)
    cand = cand[on_edge.sum(axis=1) >= 2]
    return cand[~in_triangles(p, t, points[tri[cand]].mean(axis=1))]


def merge_duplicates(points, h, tol=1e-9):
    """Representative of each particle: particles closer than tol * h are one point.

    Returns (n,) indices; each group of coincident particles maps to its lowest index.
    """
    n = len(points)
    pairs = cKDTree(points).query_pairs(r=tol * float(h.min()), output_type="ndarray")
    if len(pairs) == 0:
        return np.arange(n)
    g = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, label = connected_components(g, directed=False)
    rep = np.full(label.max() + 1, n)
    np.minimum.at(rep, label, np.arange(n))
    return rep[label]


def _delaunay(points, unique):
    """Delaunay triangles (ccw, particle indices) and neighbours; empty if Qhull cannot."""
    idx = np.flatnonzero(unique)
    if len(idx) < 3:
        return np.empty((0, 3), dtype=int), np.empty((0, 3), dtype=int)
    xy = points[idx] - points[idx].mean(axis=0)
    try:
        d = Delaunay(xy)
    except (QhullError, ValueError):
        # all points collinear (a flat initial simplex): no two-dimensional domain
        return np.empty((0, 3), dtype=int), np.empty((0, 3), dtype=int)
    simplices, nb = d.simplices, d.neighbors.copy()
    real = np.all(simplices < len(idx), axis=1)
    if not real.all():
        # a nearly collinear cloud: Qhull's point at infinity (option Qz, index len(idx))
        # is left in some simplices; drop them, and renumber the neighbours (-1 stays -1)
        renumber = np.full(len(simplices) + 1, -1)
        renumber[:-1][real] = np.arange(real.sum())
        simplices, nb = simplices[real], renumber[nb[real]]
    tri = idx[simplices]
    flip = triangle_areas(points, tri) < 0
    # swapping vertices 1 and 2 swaps the neighbours opposite them
    tri[flip] = tri[flip][:, [0, 2, 1]]
    nb[flip] = nb[flip][:, [0, 2, 1]]
    return tri, nb


def components(n, i, j):
    """Connected-component labels of n nodes joined by the pairs (i, j)."""
    g = coo_matrix((np.ones(len(i)), (i, j)), shape=(n, n))
    return connected_components(g, directed=False)


def _pair_edges(points, edges):
    """Successor of each boundary edge along its loop (vectorised).

    At a vertex j with several boundary wedges (two bodies touching at a point), the
    edge arriving at j continues with the outgoing edge nearest clockwise from the
    reversed arriving direction, which walks each wedge separately.
    """
    i, j = edges[:, 0], edges[:, 1]
    d = points[j] - points[i]
    out_angle = np.mod(np.arctan2(d[:, 1], d[:, 0]), 2 * np.pi)
    in_angle = np.mod(np.arctan2(-d[:, 1], -d[:, 0]), 2 * np.pi)
    key_out = i * 10.0 + out_angle   # angles < 2 pi < 10 keep the vertices apart
    order = np.argsort(key_out, kind="stable")
    sorted_key = key_out[order]
    pos = np.searchsorted(sorted_key, j * 10.0 + in_angle) - 1
    first = np.searchsorted(sorted_key, j * 10.0)
    last = np.searchsorted(sorted_key, j * 10.0 + 10.0) - 1
    wrap = pos < first
    pos[wrap] = last[wrap]
    return order[pos]


def alpha_shape(points, h, alpha, *, merge_tol=1e-9, advected=None, alpha_advected=0.0):
    """Detect the domain of a particle cloud: Delaunay, then remove circumradius > alpha h.

    Parameters
    ----------
    points : (n, 2) particle positions (the vertex nodes, Section 2.3.1).
    h : float or (n,) characteristic spacing; a triangle uses the mean of its nodes'.
    alpha : the alpha-shape parameter (> 0); the thesis uses 1.4-1.6 (Section 2.3.2).
    merge_tol : particles closer than merge_tol * min(h) are treated as one.
    advected : None, or (p, t) the previous step's mesh moved with its particles
        (vertices (k, 2), triangles (m, 3)). With ``alpha_advected`` > alpha, a triangle
        that fails the alpha test is still kept when its centroid lies in that mesh and
        its circumradius is at most alpha_advected h: what was one body a step ago stays
        one until stretched beyond alpha_advected (the advected domain as a predicate of
        the detection, after Leyssens, Lambrechts & Remacle 2025, arXiv:2512.20347). A
        triangle across a gap (centroid outside) is judged by alpha alone, so bodies
        merge as before, except one that fills a notch of that mesh's surface (two of
        its edges consecutive boundary edges there: :func:`notches`), which joins nothing.
    alpha_advected : the larger parameter of the triangles inside ``advected`` (0: off).

    Returns
    -------
    AlphaShape

    Raises
    ------
    ValueError for an empty cloud, non-finite coordinates, h <= 0 or alpha <= 0.
    """
    points = check_positions(points)
    n = len(points)
    h = check_spacing(h, n)
    if not np.isfinite(alpha) or alpha <= 0:
        raise ValueError(f"alpha must be positive and finite, got {alpha!r}")
    duplicate_of = merge_duplicates(points, h, merge_tol)
    tri, nb = _delaunay(points, duplicate_of == np.arange(n))
    m_all = len(tri)

    # Fig 2.3 (c): keep the triangles whose circumradius is at most alpha * h
    h_tri = h[tri].mean(axis=1) if m_all else np.empty(0)
    radius = circumradius(points, tri) / h_tri if m_all else np.empty(0)
    edge_sq = np.stack([np.sum((points[tri[:, k]] - points[tri[:, k - 1]]) ** 2, axis=1)
                        for k in range(3)], axis=1) if m_all else np.empty((0, 3))
    solid = 2 * triangle_areas(points, tri) > DEGENERATE * edge_sq.max(axis=1, initial=0)
    kept = (radius <= alpha) & solid
    if advected is not None and alpha_advected > alpha:
        again = np.flatnonzero(~kept & solid & (radius <= alpha_advected))
        if again.size:                  # a flattened triangle of material that was meshed
            kept[again] = in_triangles(*advected, points[tri[again]].mean(axis=1))
        kept[notches(points, tri, kept, *advected, h)] = False
    triangles = tri[kept]
    m = len(triangles)

    # bodies: kept triangles sharing an edge
    t_of, k_of = np.nonzero(nb >= 0)
    other = nb[t_of, k_of]
    both = kept[t_of] & kept[other]
    new_index = np.cumsum(kept) - 1
    n_bodies, body = components(m, new_index[t_of[both]], new_index[other[both]]) \
        if m else (0, np.empty(0, dtype=int))

    # boundary edges: edge k of a kept triangle is opposite vertex k; it is on the
    # boundary when the neighbour across it is absent or removed
    nb_kept = nb[kept]
    on_bnd = (nb_kept < 0) | ~kept[np.where(nb_kept < 0, 0, nb_kept)]
    t_b, k_b = np.nonzero(on_bnd)
    edges = np.stack([triangles[t_b, (k_b + 1) % 3], triangles[t_b, (k_b + 2) % 3]], axis=1)
    edge_body = body[t_b]

    # loops and their signed areas (shoelace over each loop's edges)
    if len(edges):
        nxt = _pair_edges(points, edges)
        n_loops, edge_loop = components(len(edges), np.arange(len(edges)), nxt)
        c = points.mean(axis=0)
        p, q = points[edges[:, 0]] - c, points[edges[:, 1]] - c
        loop_area = 0.5 * np.bincount(edge_loop, p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1],
                                      minlength=n_loops)
        loop_body = np.zeros(n_loops, dtype=int)
        loop_body[edge_loop] = edge_body
    else:
        nxt = edge_loop = np.empty(0, dtype=int)
        loop_area, loop_body = np.empty(0), np.empty(0, dtype=int)

    hole_seeds = _hole_seeds(points, tri, nb, kept)
    in_domain = np.zeros(n, dtype=bool)
    in_domain[triangles.ravel()] = True
    free_surface = np.zeros(n, dtype=bool)
    free_surface[edges.ravel()] = True
    return AlphaShape(points, h, float(alpha), tri, radius, kept, triangles, body,
                      int(n_bodies), edges, edge_loop, loop_area, loop_body, hole_seeds,
                      free_surface, ~in_domain, duplicate_of, nxt)


def _hole_seeds(points, tri, nb, kept):
    """A point in each void enclosed by kept triangles (the removed components not on the hull)."""
    removed = np.flatnonzero(~kept)
    if len(removed) == 0:
        return np.empty((0, 2))
    local = np.full(len(tri), -1)
    local[removed] = np.arange(len(removed))
    t_of, k_of = np.nonzero(nb[removed] >= 0)
    other = local[nb[removed][t_of, k_of]]
    pair = other >= 0
    n_c, label = components(len(removed), t_of[pair], other[pair])
    on_hull = np.zeros(n_c, dtype=bool)
    on_hull[label[np.any(nb[removed] < 0, axis=1)]] = True
    area = triangle_areas(points, tri[removed])
    # seed each enclosed component at the centroid of its largest triangle
    order = np.lexsort((area, label))
    best = order[np.flatnonzero(np.diff(label[order], append=n_c))]   # last of each label
    seeds = [points[tri[removed[b]]].mean(axis=0)
             for c, b in enumerate(best) if not on_hull[c] and area[b] > 0]
    return np.array(seeds).reshape(-1, 2)


def adaptive_alpha(alpha0, m0, m_n):
    """Alpha for the next detection, alpha_n = m0 alpha0 / m_n (thesis Ch 8, Section 8.3).

    The thesis adapts alpha at every step so that the detected mass (the area times
    the density of an incompressible material) stays near its initial value: a cloud
    that lost mass (m_n < m0) is detected with a larger alpha.

    Parameters
    ----------
    alpha0 : the initial alpha; m0 : the initial mass (or area); m_n : the mass now.
    """
    for name, value in (("alpha0", alpha0), ("m0", m0), ("m_n", m_n)):
        if not np.isfinite(value) or value <= 0:
            raise ValueError(f"{name} must be positive and finite, got {value!r}")
    return m0 * alpha0 / m_n
