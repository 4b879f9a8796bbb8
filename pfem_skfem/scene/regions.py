"""Material regions of a PFEM scene: polygons (with holes) filled with particles.

Each region is a polygon with optional holes, a material (the cone of each step,
:mod:`pfem_skfem.materials`), a density, a particle spacing h on a square or
triangular lattice (or the nodes of a Triangle quality mesh of edge about h), and an
initial stress (zero, or geostatic with a given K0).
The lattice is fitted to the region's bounding box (its rows and columns reach both
sides, so a rectangle is filled edge to edge), and each edge of the polygon that
the lattice does not follow gets particles of its own at a spacing of about h, so
that the alpha-shape finds the polygon again.
"""
from dataclasses import dataclass

import numpy as np
from matplotlib.path import Path

from ..materials.pfem import PFEMMaterial

LATTICES = ("square", "triangular", "triangle")


def polygon_area(vertices):
    """Signed area of a polygon (counter-clockwise positive)."""
    x, y = np.asarray(vertices, dtype=float).T
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def polygon_moment(vertices):
    """Signed first moment int x dA of a polygon (counter-clockwise positive); 2 pi times it
    is the volume of the polygon revolved about the axis x = 0 (Pappus)."""
    x, y = np.asarray(vertices, dtype=float).T
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    return float(np.sum((x + xn) * (x * yn - xn * y))) / 6.0


def volume_shares(region, x, refinement=8):
    """Each particle's share of the region's volume of revolution about x = 0 (axisymmetry).

    The share of particle i is the volume of its Voronoi cell within the region,
    int 2 pi r dA, by the midpoint rule on a grid of spacing h / ``refinement`` (each
    cell's centre to its nearest particle), scaled so that the shares sum to
    ``region.volume`` exactly; a region of density rho then has particle masses
    rho * shares summing to rho V. On a square lattice aligned with the grid the cells
    are exact: an interior particle gets 2 pi r h^2, one on the axis pi h^3 / 4.
    """
    from scipy.spatial import cKDTree
    x = np.asarray(x, dtype=float)
    poly = np.asarray(region.polygon, dtype=float)
    lo, hi = poly.min(axis=0), poly.max(axis=0)
    s = region.h / refinement
    n = np.maximum(np.ceil((hi - lo) / s - 1e-9).astype(int), 1)
    gx, gy = (lo[k] + (np.arange(n[k]) + 0.5) * (hi[k] - lo[k]) / n[k] for k in range(2))
    centres = np.stack(np.meshgrid(gx, gy, indexing="ij"), axis=-1).reshape(-1, 2)
    centres = centres[region.contains(centres)]
    cell = np.prod((hi - lo) / n)
    nearest = cKDTree(x).query(centres)[1]
    w = np.bincount(nearest, 2 * np.pi * centres[:, 0] * cell, minlength=len(x))
    if not w.sum() > 0:
        raise ValueError(f"region {region.name!r}: its particles span no volume of revolution")
    return region.volume * w / w.sum()


def _orient(a, b, c):
    """Sign of the turn a -> b -> c for arrays of points (n, 2)."""
    return np.sign((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                   - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def crossing_edges(a, b, chunk=1_000_000):
    """Pairs (i, j) of edges a[i] and b[j] ((n, 2, 2) and (m, 2, 2) segments) whose open
    segments intersect properly (not at shared ends, not along a common line).

    A sweep in x: the edges are sorted by their left end and each is tested against those
    that start before it ends (and overlap it in y), in chunks of at most ``chunk``
    candidates, so a polygon of 10,000 vertices takes milliseconds, not the minutes of all
    k^2 pairs.
    """
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    seg = np.concatenate([a, b])
    side = np.r_[np.zeros(len(a), dtype=bool), np.ones(len(b), dtype=bool)]
    order = np.argsort(seg[:, :, 0].min(axis=1), kind="stable")
    seg, side, index = seg[order], side[order], np.r_[np.arange(len(a)), np.arange(len(b))][order]
    x0, x1 = seg[:, :, 0].min(axis=1), seg[:, :, 0].max(axis=1)
    y0, y1 = seg[:, :, 1].min(axis=1), seg[:, :, 1].max(axis=1)
    stop = np.searchsorted(x0, x1, side="right")       # edges starting before i ends
    count = stop - np.arange(len(seg)) - 1
    found = []
    first = 0
    while first < len(seg):
        last = first + max(int(np.searchsorted(np.cumsum(count[first:]), chunk)), 1)
        i = np.repeat(np.arange(first, min(last, len(seg))), count[first:last])
        j = i + 1 + (np.arange(len(i)) - np.repeat(np.cumsum(count[first:last])
                                                     - count[first:last], count[first:last]))
        keep = (side[i] != side[j]) & (y0[j] <= y1[i]) & (y0[i] <= y1[j])
        i, j = i[keep], j[keep]
        p, q, r, t = seg[i, 0], seg[i, 1], seg[j, 0], seg[j, 1]
        hit = ((_orient(p, q, r) * _orient(p, q, t) < 0)
               & (_orient(r, t, p) * _orient(r, t, q) < 0))
        i, j = i[hit], j[hit]
        swap = side[i]                                  # report (edge of a, edge of b)
        found.append(np.column_stack([np.where(swap, index[j], index[i]),
                                      np.where(swap, index[i], index[j])]))
        first = last
    return np.vstack(found) if found else np.empty((0, 2), dtype=int)


def _edges(vertices):
    v = np.asarray(vertices, dtype=float)
    return np.stack([v, np.roll(v, -1, axis=0)], axis=1)


def check_polygon(vertices, name):
    """(k, 2) float vertices of a simple polygon with k >= 3 and non-zero area, or ValueError
    naming ``name``. A last vertex that is the first again (a ring written closed) is
    dropped; any other repeated vertex is refused (:func:`_check_not_touching`)."""
    try:
        v = np.asarray(vertices, dtype=float)
    except (TypeError, ValueError) as err:              # ragged, None, text
        raise ValueError(f"{name}: a polygon is a list of (x, y) vertices ({err})") from None
    if v.ndim != 2 or v.shape[1] != 2 or len(v) < 3:
        raise ValueError(f"{name}: a polygon needs at least three (x, y) vertices, got shape "
                         f"{v.shape}")
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{name}: polygon vertices must be finite")
    if len(v) > 3 and np.all(np.abs(v[-1] - v[0]) <= 1e-9 * np.ptp(v, axis=0).max()):
        v = v[:-1]                      # a closed ring (GIS, shapely): its first vertex again
    # before the area: a bowtie's area is zero, and it intersects itself
    pairs = crossing_edges(_edges(v), _edges(v))
    k = len(v)
    pairs = pairs[(pairs[:, 0] < pairs[:, 1]) & (pairs[:, 1] - pairs[:, 0] > 1)
                  & ~((pairs[:, 0] == 0) & (pairs[:, 1] == k - 1))]   # neighbours touch
    if len(pairs):
        i, j = pairs[0]
        raise ValueError(f"{name}: the polygon intersects itself (edges {i} and {j})")
    if abs(polygon_area(v)) <= 1e-12 * np.ptp(v, axis=0).max() ** 2:
        raise ValueError(f"{name}: the polygon is empty (zero area)")
    _check_not_touching(v, name)
    return v


def _check_not_touching(v, name):
    """ValueError naming ``name`` and the vertex when a polygon touches itself: a vertex
    repeated (a zero-length edge, or a zero-width spike or pinch when not adjacent) or lying
    on an edge that does not end at it, within 1e-9 of the polygon's extent. The crossing
    test finds proper crossings only, and a spike out to a point and back along the same
    line crosses nothing: the edge particles put on it carry mass on a line of no area (a
    spike of 0.5 on a unit square: 9.7 % of the mass outside the material)."""
    from scipy.spatial import cKDTree
    k = len(v)
    tol = 1e-9 * float(np.ptp(v, axis=0).max())
    for i, j in sorted(cKDTree(v).query_pairs(tol)):
        at = tuple(map(float, v[j]))
        if j - i == 1 or (i, j) == (0, k - 1):
            raise ValueError(f"{name}: vertices {i} and {j} are the same point {at} (a "
                             f"zero-length edge): remove one of them")
        raise ValueError(f"{name}: the polygon touches itself: vertex {j} {at} is vertex {i} "
                         f"again (a zero-width spike or a pinch: its particles would carry "
                         f"mass on a line of no area); remove the spike, or make two regions")
    # a vertex on another edge: a cross of two tiny segments through it crosses that edge
    # properly (not its own edges, which end at its centre)
    crosses = np.concatenate([np.stack([v - (tol, 0.0), v + (tol, 0.0)], axis=1),
                              np.stack([v - (0.0, tol), v + (0.0, tol)], axis=1)])
    hits = crossing_edges(_edges(v), crosses)
    if len(hits):
        edge, vertex = int(hits[0, 0]), int(hits[0, 1]) % k
        raise ValueError(f"{name}: the polygon touches itself: vertex {vertex} "
                         f"{tuple(map(float, v[vertex]))} lies on edge {edge} (vertices "
                         f"{edge} and {(edge + 1) % k}; a zero-width spike or a pinch: its "
                         f"particles would carry mass on a line of no area); remove the "
                         f"spike, or make two regions")


def _inside(vertices, x, tol):
    """Points strictly inside a polygon by more than ``tol`` (its edges are not inside)."""
    return _path(vertices).contains_points(x, radius=_signed(vertices, -tol))


def _probe_points(loops):
    """The vertices and edge midpoints of polygons (to test one inside another)."""
    return np.vstack([np.vstack([e.mean(axis=1), e[:, 0]]) for e in map(_edges, loops)])


def shapes_overlap(a, b, tol):
    """Whether the interiors of two shapes overlap: each a list of loops, the outer polygon
    and its holes. They overlap where their edges cross properly, or a vertex or edge
    midpoint of one lies inside the other by more than ``tol`` (inside the polygon and
    outside its holes); shapes that share edges or vertices only do not overlap."""
    ea, eb = np.vstack([_edges(v) for v in a]), np.vstack([_edges(v) for v in b])
    if len(crossing_edges(ea, eb)):
        return True
    for one, other in ((a, b), (b, a)):
        x = _probe_points(one)
        inside = _inside(other[0], x, tol)
        for hole in other[1:]:
            inside &= ~_path(hole).contains_points(x, radius=_signed(hole, tol))
        if inside.any():
            return True
    return False


def check_holes(polygon, holes, label):
    """Each hole lies within the polygon (edges may touch), leaves some area and overlaps
    no other hole; ValueError naming the region and the hole."""
    tol = 1e-9 * np.ptp(np.asarray(polygon), axis=0).max()
    for i, hole in enumerate(holes):
        hole = np.asarray(hole)
        outside = ~_path(polygon).contains_points(_probe_points([hole]),
                                                  radius=_signed(polygon, tol))
        if outside.any() or len(crossing_edges(_edges(hole), _edges(polygon))):
            raise ValueError(f"{label}, hole {i}: the hole must lie inside the region's "
                             f"polygon (it reaches outside it)")
        if abs(polygon_area(hole)) >= abs(polygon_area(polygon)) * (1 - 1e-12):
            raise ValueError(f"{label}, hole {i}: the hole covers the whole polygon (the "
                             f"region has no area left)")
        for j in range(i):
            if shapes_overlap([hole], [np.asarray(holes[j])], tol):
                raise ValueError(f"{label}, holes {j} and {i} overlap")


@dataclass(frozen=True)
class Geostatic:
    """Geostatic initial stress below a free surface at height ``top`` (None: the top of
    the region): sy = -rho g (top - y), sx = K0 sy, sz = nu (sx + sy) (plane strain,
    nu of the material's elasticity, else 0). K0 = None: Jaky's 1 - sin(phi)."""

    k0: float = None
    top: float = None

    def __post_init__(self):
        if self.k0 is not None and not (np.isfinite(self.k0) and self.k0 >= 0):
            raise ValueError(f"Geostatic: k0 must be >= 0 (None: Jaky's 1 - sin(phi)), a "
                             f"negative K0 is a tensile lateral stress; got {self.k0!r}")
        if self.top is not None and not np.isfinite(self.top):
            raise ValueError(f"Geostatic: top must be finite, got {self.top!r}")


@dataclass(frozen=True)
class Region:
    """A region of material filled with particles.

    Parameters
    ----------
    polygon : (k, 2) outer boundary;  holes : polygons cut out of it.
    material : the PFEM material (e.g. ZeroDilationMohrCoulomb, CohesiveTresca).
    rho : density;  h : particle spacing;  lattice : 'square', 'triangular' or 'triangle'
        (the nodes of a Triangle quality mesh of the polygon, edges about h; each hole's
        vertex mean must lie inside the hole).
    stress : None (zero initial stress) or :class:`Geostatic`.
    name : for the records (mass of each region).
    """

    polygon: tuple
    material: object
    rho: float
    h: float
    lattice: str = "square"
    holes: tuple = ()
    stress: Geostatic = None
    name: str = "material"

    def __post_init__(self):
        label = f"region {self.name!r}"
        poly = check_polygon(self.polygon, label)
        holes = tuple(tuple(map(tuple, check_polygon(hole, f"{label}, hole {i}")))
                      for i, hole in enumerate(self.holes))
        check_holes(poly, holes, label)
        object.__setattr__(self, "polygon", tuple(map(tuple, poly)))
        object.__setattr__(self, "holes", holes)
        for key in ("rho", "h"):
            value = getattr(self, key)
            if (isinstance(value, bool) or not isinstance(value, (int, float, np.number))
                    or not np.isfinite(value) or value <= 0):
                raise ValueError(f"{label}: {key} must be positive, got {value!r}")
        if self.lattice not in LATTICES:
            raise ValueError(f"{label}: lattice must be one of {LATTICES}, got {self.lattice!r}")
        if not isinstance(self.material, PFEMMaterial):
            raise ValueError(f"{label}: material must be a PFEM material with a cone() "
                             f"(a PFEMMaterial, e.g. ZeroDilationMohrCoulomb), got "
                             f"{self.material!r}")
        if self.stress is not None and not isinstance(self.stress, Geostatic):
            raise ValueError(f"{label}: stress must be None or Geostatic, got {self.stress!r}")

    @property
    def area(self):
        """Area of the region: the polygon less its holes."""
        return abs(polygon_area(self.polygon)) - sum(abs(polygon_area(h)) for h in self.holes)

    @property
    def volume(self):
        """Volume of the region revolved about the axis x = 0 (axisymmetry): 2 pi int x dA."""
        return 2 * np.pi * (abs(polygon_moment(self.polygon))
                            - sum(abs(polygon_moment(h)) for h in self.holes))

    def contains(self, x, tol=0.0):
        """Points inside the polygon and outside its holes (``tol`` widens the polygon)."""
        x = np.atleast_2d(x)
        inside = _path(self.polygon).contains_points(x, radius=_signed(self.polygon, tol))
        for hole in self.holes:
            inside &= ~_path(hole).contains_points(x, radius=_signed(hole, -tol))
        return inside

    def particles(self):
        """(n, 2) particles filling the region (lattice plus the edges it misses)."""
        return fill_region(self)


def _path(vertices):
    return Path(np.vstack([vertices, vertices[:1]]), closed=True)


def _signed(vertices, tol):
    # matplotlib widens a counter-clockwise path for radius > 0, a clockwise one for < 0
    return tol if polygon_area(vertices) > 0 else -tol


def fitted_lattice(lo, hi, h, lattice):
    """Lattice points of spacing about h over the box [lo, hi]: the first and last row and
    column on the box's sides (a square lattice through linspace, as many points as
    round(extent / h) + 1; a triangular one with rows h sqrt(3)/2 apart, every other row
    shifted by half a spacing)."""
    (x0, y0), (x1, y1) = lo, hi
    nx = int(round((x1 - x0) / h)) + 1
    if lattice == "square":
        ny = int(round((y1 - y0) / h)) + 1
        X, Y = np.meshgrid(np.linspace(x0, x1, max(nx, 2)), np.linspace(y0, y1, max(ny, 2)))
        return np.column_stack([X.ravel(), Y.ravel()])
    ny = int(round((y1 - y0) / (h * np.sqrt(3) / 2))) + 1
    xs = np.linspace(x0, x1, max(nx, 2))
    dx = xs[1] - xs[0]
    rows = []
    for j, y in enumerate(np.linspace(y0, y1, max(ny, 2))):
        row = xs + (0.5 * dx if j % 2 else 0.0)
        rows.append(np.column_stack([row[row <= x1 + 1e-9 * dx], np.full((row <= x1 + 1e-9 * dx).sum(), y)]))
    return np.vstack(rows)


def _edge_points(vertices, h):
    """Points along each edge of a closed polygon, about h apart, ends included once."""
    out = []
    k = len(vertices)
    for i in range(k):
        a, b = np.asarray(vertices[i]), np.asarray(vertices[(i + 1) % k])
        m = max(int(round(np.linalg.norm(b - a) / h)), 1)     # as the fitted lattice
        s = np.arange(m) / m
        out.append(a + s[:, None] * (b - a))
    return np.vstack(out)


def triangle_nodes(region):
    """Nodes of a Triangle quality mesh (minimum angle 30 degrees) of the region with edges
    about h, its boundary divided as :func:`_edge_points` does."""
    from meshpy.triangle import MeshInfo, build

    loops = [np.asarray(region.polygon)] + [np.asarray(hole) for hole in region.holes]
    points, facets, seeds = [], [], []
    for k, loop in enumerate(loops):
        pts = _edge_points(loop, region.h)
        start = len(points)
        points += pts.tolist()
        facets += [(start + i, start + (i + 1) % len(pts)) for i in range(len(pts))]
        if k:
            seed = loop.mean(axis=0)
            if not _path(loop).contains_point(seed):
                raise ValueError(f"region {region.name!r}: hole {k - 1} does not contain the "
                                 "mean of its vertices (needed by lattice='triangle')")
            seeds.append(tuple(seed))
    info = MeshInfo()
    info.set_points(points)
    info.set_facets(facets)
    if seeds:
        info.set_holes(seeds)
    target = np.sqrt(3) / 4 * region.h ** 2                      # equilateral, edge h
    tri = build(info, max_volume=target, min_angle=30.0, allow_boundary_steiner=False)
    return np.asarray(tri.points, dtype=float)


def fill_region(region):
    """Particles of a region: the fitted lattice inside (boundary included), and particles
    along every polygon edge the lattice leaves more than 1e-6 h away; lattice points
    closer than h/2 to an added edge particle are dropped (lattice 'triangle': the nodes
    of :func:`triangle_nodes`)."""
    if region.lattice == "triangle":
        return triangle_nodes(region)
    h = region.h
    poly = np.asarray(region.polygon)
    loops = [poly] + [np.asarray(hole) for hole in region.holes]
    lo, hi = poly.min(axis=0), poly.max(axis=0)
    grid = fitted_lattice(lo, hi, h, region.lattice)
    grid = grid[region.contains(grid, tol=1e-9 * h)]
    edges = np.vstack([_edge_points(loop, h) for loop in loops])
    # an edge point the lattice already has (within 1e-6 h) is not added again
    from scipy.spatial import cKDTree
    if len(grid):
        d, _ = cKDTree(grid).query(edges)
        edges = edges[d > 1e-6 * h]
    if len(edges) and len(grid):
        d, _ = cKDTree(edges).query(grid)
        grid = grid[d >= 0.5 * h]
    x = np.vstack([grid, edges]) if len(edges) else grid
    return x


def geostatic_stress(x, top, rho, g, k0, nu=0.0, pore=None):
    """Geostatic stresses (n, 4) (sx, sy, sz, sxy): sy = -rho g (top - y), sx = k0 sy and
    the plane-strain sz = nu (sx + sy). With ``pore`` (n,), the pore pressure at x, they
    are the effective stresses of a saturated soil: sy = -rho g (top - y) + p (rho the
    saturated density), K0 and nu on the effective stress."""
    sy = -rho * g * np.clip(top - x[:, 1], 0, None)
    if pore is not None:
        sy = sy + pore
    sx = k0 * sy
    return np.column_stack([sx, sy, nu * (sx + sy), np.zeros_like(sy)])
