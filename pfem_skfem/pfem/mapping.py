"""Mapping the state from the old mesh to the new one (thesis Section 2.5, Fig 2.5-2.6).

Stresses live at the stress points (the Gauss points of the six-node triangle,
:class:`~pfem_skfem.discretisation.elements.ElementTriStress`); two schemes move them:

* Unique Element Method (UEM, Fig 2.6), the thesis' choice: find the old element
  that contains the new stress point and evaluate that element's linear stress
  field there, ``sigma(x) = sum_j (2 lambda_j(x) - 1/3) sigma_j`` (3.29). A point
  outside the old mesh takes the nearest old element, extrapolated.
* Inverse Distance Algorithm (IDA, Fig 2.5), (2.1)-(2.2): a weighted mean of the k
  nearest old stress points, weights ``w_i = d_i^-c``, c = 3.5 recommended.

Two stable variants (not in the thesis; it mentions the second as an "improved UEM"):

* bounded UEM ('uem_bounded'): the UEM value clipped, component by component, to the
  range of the old element's three recovered vertex values (patch recovery below, each
  limited to the range of the old values around its vertex): a limiter, as in slope
  limiting. It obeys a discrete maximum principle, so repeated remapping cannot amplify
  oscillations, and is still exact for a linear field in old elements whose vertices
  are interior and surrounded by their patches' stress points (every interior vertex
  of a quality mesh; not always next to a sliver). A new point that is an old stress
  point keeps its value unclipped, so a field mapped onto its own mesh is unchanged;
  given the old elements' regions, the vertex values are fitted region by region.
* patch recovery ('spr'): a continuous nodal field recovered by a least-squares linear
  fit to the stress points of the elements around each old vertex (superconvergent
  patch recovery, Zienkiewicz and Zhu [209]), interpolated linearly at the new points.
  Exact for linear fields everywhere; no maximum principle.

Nodal fields (velocities, accelerations: any function of a scikit-fem basis) are
interpolated with the old P2 basis at the new nodes (Section 2.5, last paragraph).

Meshes are straight-sided (``MeshTri``), so barycentric coordinates are the
element's area coordinates.
"""
import numpy as np
from scipy.spatial import cKDTree
from skfem import ElementVector

from ..discretisation.static import Discretisation

SCHEMES = ("uem", "ida", "uem_bounded", "spr")


def _affine(mesh):
    """Vertices (m, 3, 2) and the inverse Jacobians (m, 2, 2) of the elements."""
    p, t = mesh.p.T, mesh.t[:3].T
    v = p[t]
    jac = np.stack([v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]], axis=2)   # columns b-a, c-a
    return v, np.linalg.inv(jac)


def _barycentric(v, inv, x):
    """Area coordinates (n, k, 3) of points x (n, 2) in candidate elements given by v, inv (n, k, ...)."""
    xi = np.einsum("nkij,nkj->nki", inv, x[:, None, :] - v[:, :, 0])
    return np.concatenate([1 - xi.sum(axis=2, keepdims=True), xi], axis=2)


def _segment_distance(x, a, b):
    """Distance from points x (n, k, 2) to segments a-b (n, k, 2)."""
    d = b - a
    s = np.clip(np.sum((x - a) * d, axis=-1) / np.maximum(np.sum(d * d, axis=-1), 1e-300), 0, 1)
    return np.linalg.norm(x - a - s[..., None] * d, axis=-1)


def locate(mesh, x, *, k=8, tol=1e-10):
    """Element of ``mesh`` containing each point (vectorised point location).

    Candidates are the element with the nearest centroid (a KD-tree), then, for the
    points not in it, the k and then 8 k nearest; a point in none of them is outside the mesh
    and gets the candidate element nearest to it.

    Parameters
    ----------
    mesh : skfem.MeshTri; x : (n, 2) points.

    Returns
    -------
    element : (n,) element index; inside : (n,) bool; lam : (n, 3) area coordinates of
    the point in its element (outside [0, 1] for an extrapolated point).
    """
    x = np.atleast_2d(np.asarray(x, dtype=float))
    if x.ndim != 2 or x.shape[1] != 2 or not np.all(np.isfinite(x)):
        raise ValueError("points must be a finite (n, 2) array")
    v_all, inv_all = _affine(mesh)
    m = len(v_all)
    tree = cKDTree(v_all.mean(axis=1))
    n = len(x)
    element = np.full(n, -1)
    lam = np.zeros((n, 3))
    inside = np.zeros(n, dtype=bool)
    todo = np.arange(n)
    for kk in sorted({1, min(k, m), min(8 * k, m)}):
        _, cand = tree.query(x[todo], k=kk, workers=-1)
        cand = cand.reshape(len(todo), kk)
        bary = _barycentric(v_all[cand], inv_all[cand], x[todo])
        ok = bary.min(axis=2) >= -tol
        hit = ok.any(axis=1)
        first = ok.argmax(axis=1)
        rows = np.flatnonzero(hit)
        element[todo[rows]] = cand[rows, first[rows]]
        lam[todo[rows]] = bary[rows, first[rows]]
        inside[todo[rows]] = True
        todo, cand, bary = todo[~hit], cand[~hit], bary[~hit]
        if len(todo) == 0 or kk == m:
            break
    if len(todo):
        # outside the mesh: the nearest candidate element, measured to its edges
        vv = v_all[cand]
        xx = np.broadcast_to(x[todo][:, None, :], vv.shape[:2] + (2,))
        dist = np.min([_segment_distance(xx, vv[:, :, i], vv[:, :, (i + 1) % 3])
                       for i in range(3)], axis=0)
        best = dist.argmin(axis=1)
        element[todo] = cand[np.arange(len(todo)), best]
        lam[todo] = bary[np.arange(len(todo)), best]
    return element, inside, lam


def _stress_layout(old):
    if not isinstance(old, Discretisation):
        raise ValueError(f"old must be a Discretisation, got {type(old).__name__}")
    return old.mesh, old.basis_s.element_dofs, old.points


def _new_points(new):
    return new.points if isinstance(new, Discretisation) else np.asarray(new, dtype=float)


def _check_sigma(sigma, n):
    sigma = np.asarray(sigma, dtype=float)
    if sigma.shape[0] != n:
        raise ValueError(f"sigma must have {n} rows (one per old stress point), "
                         f"got shape {sigma.shape}")
    return sigma


def uem(old, sigma, new, *, k=8):
    """Unique Element Method (Fig 2.6): the old element's linear stress at the new points.

    sigma(x) = sum_j N_j(x) sigma_j with N_j = 2 lambda_j - 1/3 (3.29), lambda the
    area coordinates of x in the old element that contains it (or the nearest old
    element, extrapolating, for a point outside the old mesh).

    Parameters
    ----------
    old : Discretisation of the old mesh; sigma : (n_points_old, ...) values at its
        stress points (e.g. (n, 4) stresses); new : Discretisation or (n_new, 2) points.

    Returns
    -------
    (n_new, ...) array.
    """
    mesh, element_points, _ = _stress_layout(old)
    sigma = _check_sigma(sigma, element_points.max() + 1)
    x = _new_points(new)
    element, _, lam = locate(mesh, x, k=k)
    shape = 2 * lam - 1 / 3                       # (n_new, 3): N_j at x
    values = sigma[element_points[:, element].T]  # (n_new, 3, ...)
    return np.einsum("nj,nj...->n...", shape, values)


def ida(old, sigma, new, *, c=3.5, k=6):
    """Inverse Distance Algorithm (2.1)-(2.2): sigma(x) = sum w_i sigma_i / sum w_j, w_i = d_i^-c.

    Parameters
    ----------
    old : Discretisation of the old mesh (or (n, 2) old stress points);
    sigma : (n_points_old, ...) values at them; new : Discretisation or (n_new, 2) points;
    c : the exponent (2-4, 3.5 recommended [34, 50]); k : number of nearest old points.

    A new point that coincides with an old one takes its value.
    """
    if not np.isfinite(c) or c <= 0:
        raise ValueError(f"c (IDA exponent) must be positive, got {c!r}")
    pts = old.points if isinstance(old, Discretisation) else np.asarray(old, dtype=float)
    sigma = _check_sigma(sigma, len(pts))
    if int(k) < 1:
        raise ValueError(f"k (number of neighbours) must be at least 1, got {k!r}")
    k = min(int(k), len(pts))
    x = _new_points(new)
    d, i = cKDTree(pts).query(x, k=k)
    d, i = d.reshape(len(x), k), i.reshape(len(x), k)
    with np.errstate(divide="ignore"):
        w = d ** -c
    hit = d[:, 0] == 0
    w[hit] = 0.0
    w[hit, 0] = 1.0                               # a coincident old point wins
    w /= w.sum(axis=1, keepdims=True)
    return np.einsum("nk,nk...->n...", w, sigma[i])


def _flat(sigma):
    """(n, ...) -> (n, m) and the trailing shape, so that patch operations see columns."""
    return sigma.reshape(len(sigma), -1), sigma.shape[1:]


def _vertex_range(mesh, element_points, flat, corners=None, n=None):
    """Smallest and largest stress-point value (n_vertices, m) over the elements around each
    vertex (``corners``, (3, m_elements), and ``n``: the patches of :func:`_patches`)."""
    values = flat[element_points]                        # (3, m_elements, m)
    corners = mesh.t[:3] if corners is None else corners
    corner = corners.ravel()                             # the patch of each (corner, element)
    nv = mesh.p.shape[1] if n is None else n
    vmin = np.full((nv, flat.shape[1]), np.inf)
    vmax = np.full((nv, flat.shape[1]), -np.inf)
    np.minimum.at(vmin, corner, np.tile(values.min(axis=0), (3, 1)))
    np.maximum.at(vmax, corner, np.tile(values.max(axis=0), (3, 1)))
    return vmin, vmax


#: det(A) of a patch's normal equations below this times (its point count)^3 (the largest
#: it can be: the basis is scaled to |P| <= 1) is a patch without a plane fit
FLAT_PATCH = 1e-12


def recover_nodal(old, sigma, *, bounded=False):
    """Nodal values from the stress points by superconvergent patch recovery [209].

    At each old vertex v a linear polynomial a + b (x - x_v) + c (y - y_v) is fitted by
    least squares to the stress-point values of the elements containing v (at least 3
    points), and its value a at v is the nodal value. Exact for a linear field. A patch
    whose points are (nearly) collinear (slivers only) takes the mean of its values.

    Parameters
    ----------
    old : Discretisation; sigma : (n_points_old, ...) stress-point values;
    bounded : clip each nodal value, component by component, to the range of the
        stress-point values it was fitted to (for a linear field this changes nothing
        at a vertex inside the convex hull of its patch's stress points: every interior
        vertex of a quality mesh, not always one next to a sliver).

    Returns
    -------
    (n_vertices, ...) array.
    """
    mesh, element_points, _ = _stress_layout(old)
    sigma = _check_sigma(sigma, element_points.max() + 1)
    flat, trailing = _flat(sigma)
    nodal = _recover(old, flat, mesh.t[:3], mesh.p.shape[1], bounded)
    return nodal.reshape((mesh.p.shape[1],) + trailing)


def _patches(mesh, regions):
    """The patch of each element corner (3, m_elements) and their number: the corner's
    vertex, or with ``regions`` (one label per element) its vertex and its element's region,
    so that a vertex on an interface has one patch on each side."""
    t = mesh.t[:3]
    if regions is None:
        return t, mesh.p.shape[1]
    regions = np.asarray(regions)
    if regions.shape != (t.shape[1],):
        raise ValueError(f"regions must hold one label per old element ({t.shape[1]}), got "
                         f"shape {regions.shape}")
    labels, label = np.unique(regions, return_inverse=True)
    return t * len(labels) + label.reshape(1, -1), mesh.p.shape[1] * len(labels)


def _recover(old, flat, corners, nv, bounded):
    """The patch fits of :func:`recover_nodal`, one per patch: ``corners`` (3, m_elements)
    names the patch of each element corner, ``nv`` their number. Returns (nv, m)."""
    mesh, element_points, points = _stress_layout(old)
    t = mesh.t[:3]
    # every (patch, stress point) pair of an element: 3 x 3 per element
    vertex = np.broadcast_to(corners[:, None, :], (3,) + t.shape).ravel()
    point = np.broadcast_to(element_points[None, :, :], (3,) + element_points.shape).ravel()
    at = np.broadcast_to(t[:, None, :], (3,) + t.shape).ravel()    # the patch's vertex
    d = points[point] - mesh.p.T[at]
    scale = np.zeros(nv)
    np.maximum.at(scale, vertex, np.abs(d).max(axis=1))  # local length: keeps A well scaled
    scale[scale == 0] = 1.0
    P = np.c_[np.ones(len(d)), d / scale[vertex, None]]  # basis (1, dx, dy) of the fit
    A = np.zeros((nv, 3, 3))
    np.add.at(A, vertex, P[:, :, None] * P[:, None, :])
    b = np.zeros((nv, 3, flat.shape[1]))
    np.add.at(b, vertex, P[:, :, None] * flat[point][:, None, :])
    unused = np.ones(nv, dtype=bool)
    unused[corners.ravel()] = False
    A[unused] = np.eye(3)                                # vertices in no element: value 0
    # a patch whose stress points are (nearly) collinear or coincide (a vertex of slivers
    # only, met once in a clay block entering water) has no plane fit: there the
    # nodal value is the patch's mean (a constant fit), the others are left as they were
    count = A[:, 0, 0].copy()                           # the number of points
    flat_patch = ~unused & (np.abs(np.linalg.det(A)) <= FLAT_PATCH * count ** 3)
    if flat_patch.any():
        A[flat_patch] = np.diag([1.0, 1.0, 1.0])
        b[flat_patch, 0] /= count[flat_patch, None]
        b[flat_patch, 1:] = 0.0
    nodal = np.linalg.solve(A, b)[:, 0]
    if bounded:
        vmin, vmax = _vertex_range(mesh, element_points, flat, corners, nv)
        nodal[~unused] = np.clip(nodal, vmin, vmax)[~unused]
    return nodal


#: a new point whose shape functions N_j (3.29) in its old element are within this of
#: (1, 0, 0) (to rounding: the same vertices give the same point) is that old stress point
COINCIDENT = 1e-9


def uem_bounded(old, sigma, new, *, k=8, regions=None):
    """UEM (Fig 2.6) limited to the range of the element's recovered vertex values.

    sigma(x) = clip(sum_j N_j(x) sigma_j, lo_e, hi_e), component by component, where
    lo_e, hi_e are the smallest and largest of the three nodal values of the old element
    e recovered by :func:`recover_nodal` with ``bounded=True``. A limiter, as in slope
    limiting: the extrapolation of the element's linear field (N_j up to 5/3 at a
    vertex) can no longer carry an element-wise oscillation beyond the smooth recovered
    field, and each mapped value lies within the range of the old values around its
    element (a discrete maximum principle), so repeated remapping cannot amplify it.
    A linear field is mapped exactly in old elements whose vertices are interior and
    inside the convex hull of their patches' stress points (there the clips are
    inactive; true of every interior vertex of a quality mesh); near the boundary the
    clip can cut a gradient, a first-order error.

    A new point that is an old stress point (its N_j within :data:`COINCIDENT` of
    (1, 0, 0): an element the remeshing kept, whose vertices are the same particles)
    takes that point's value unclipped: there nothing is extrapolated, and the clip
    would only pull a datum towards the smoothed recovered field, which is not exact at
    the boundary nor across a kink of the field. So the map of a field onto its own
    mesh is the identity, and an element that survives a remeshing keeps its stresses
    as if the mesh had not been rebuilt. Without this, a column remeshed every step
    lost (under a load) or gained (under a heavy fill) settlement step by step, each
    step answering the clip with a strain (issue 54; book/saturated_soil.md, "In the
    PFEM").

    With ``regions`` (one label per old element: the PFEM's regions, their materials) the
    vertex values are fitted in each region apart, a vertex on an interface getting one
    value per side, as patch recovery is done material by material [209]: the stress of
    one region, its gradient, its jump at the interface, does not widen or narrow the
    bounds of the other's elements.

    Parameters and returns as :func:`uem`; regions : (n_old_elements,) labels or None
    (one fit per vertex).
    """
    mesh, element_points, _ = _stress_layout(old)
    sigma = _check_sigma(sigma, element_points.max() + 1)
    x = _new_points(new)
    element, _, lam = locate(mesh, x, k=k)
    shape = 2 * lam - 1 / 3                       # (n_new, 3): N_j at x
    values = np.einsum("nj,nj...->n...", shape, sigma[element_points[:, element].T])
    flat, trailing = _flat(sigma)
    corners, n = _patches(mesh, regions)
    nodal = _recover(old, flat, corners, n, True)[corners]       # (3, m, ...)
    nodal = nodal.reshape(nodal.shape[:2] + trailing)
    lo, hi = nodal.min(axis=0), nodal.max(axis=0)
    limited = np.clip(values, lo[element], hi[element])
    # at an old stress point the UEM returns its datum, nothing extrapolated: a value the
    # clip moved there is the datum itself (exactly: the sum would round it off the data)
    nearest = shape.argmax(axis=1)
    datum = np.abs(shape - np.eye(3)[nearest]).max(axis=1) <= COINCIDENT
    moved = (limited != values) & datum.reshape((-1,) + (1,) * (values.ndim - 1))
    limited[moved] = sigma[element_points[nearest, element]][moved]
    return limited


def spr(old, sigma, new, *, k=8):
    """Patch-recovered nodal stresses (:func:`recover_nodal`), interpolated linearly.

    sigma(x) = sum_j lambda_j(x) sigma(v_j) in the old element containing x (or the
    nearest, extrapolating), the "improved UEM" of Section 2.5. Exact for linear fields.

    Parameters and returns as :func:`uem`.
    """
    mesh, element_points, _ = _stress_layout(old)
    sigma = _check_sigma(sigma, element_points.max() + 1)
    nodal = recover_nodal(old, sigma)
    x = _new_points(new)
    element, _, lam = locate(mesh, x, k=k)
    return np.einsum("nj,nj...->n...", lam, nodal[mesh.t[:3, element].T])


def map_stress(old, sigma, new, method="uem", **options):
    """Stresses at the new stress points by ``method``.

    'uem' (Fig 2.6, the thesis' choice), 'ida' (2.1)-(2.2), 'uem_bounded' (UEM with a
    patch limiter, :func:`uem_bounded`) or 'spr' (patch recovery, :func:`spr`).
    """
    method = str(method).lower()
    schemes = {"uem": uem, "ida": ida, "uem_bounded": uem_bounded, "spr": spr}
    if method not in schemes:
        raise ValueError(f"method must be one of {SCHEMES}, got {method!r}")
    return schemes[method](old, sigma, new, **options)


def interpolate(basis, values, x, *, k=8, cells=None):
    """Values of a finite-element function of ``basis`` at points x (n, 2).

    The function is evaluated in the element containing each point; a point outside
    the mesh uses the nearest element's polynomial (extrapolation). ``cells``: the
    elements of the points when already located (:func:`locate`).

    Returns
    -------
    (n,) for a scalar basis, (2, n) for a vector basis (``ElementVector``); with
    ``values`` of shape (N, m), a trailing axis m.
    """
    x = np.atleast_2d(np.asarray(x, dtype=float))
    values = np.asarray(values, dtype=float)
    if values.shape[0] != basis.N:
        raise ValueError(f"values must have {basis.N} rows (the basis' dofs), got {values.shape}")
    if cells is None:
        cells, _, _ = locate(basis.mesh, x, k=k)
    local = basis.mapping.invF(x.T[:, :, None], tind=cells)
    phi = np.array([np.asarray(basis.elem.gbasis(basis.mapping, local, j, tind=cells)[0])
                    for j in range(basis.Nbfun)])
    phi = phi[..., 0]                              # (Nbfun, [comp,] n)
    dofs = values[basis.element_dofs[:, cells]]    # (Nbfun, n, ...)
    if phi.ndim == 2:
        return np.einsum("jn,jn...->n...", phi, dofs)
    return np.einsum("jcn,jn...->cn...", phi, dofs)


def map_nodal(old_basis, values, new_basis, *, k=8):
    """A nodal field (velocities, accelerations) of the old basis, interpolated to the new one.

    Each new degree of freedom takes the old function's value (its component, for a
    vector basis) at the dof's location; exact for fields the old basis represents
    (a quadratic field on P2).

    Returns
    -------
    (new_basis.N, ...) array of the new dofs.
    """
    values = np.asarray(values, dtype=float)
    if not isinstance(new_basis.elem, ElementVector):
        return interpolate(old_basis, values, new_basis.doflocs.T, k=k)
    if not isinstance(old_basis.elem, ElementVector):
        raise ValueError("old_basis must be a vector basis like new_basis")
    # one scalar interpolation for all components: vector dofs split into scalar ones
    old_split, new_split = old_basis.split_indices(), new_basis.split_indices()
    scalar_old = old_basis.with_element(old_basis.elem.elem)
    scalar_new = new_basis.with_element(new_basis.elem.elem)
    stacked = np.stack([values[idx] for idx in old_split], axis=1)     # (N_scalar, dim, ...)
    mapped = interpolate(scalar_old, stacked, scalar_new.doflocs.T, k=k)
    out = np.zeros((new_basis.N,) + values.shape[1:])
    for comp, idx in enumerate(new_split):
        out[idx] = mapped[:, comp]
    return out


def project_nodal(old_basis, values, new_basis, *, vertex_values=None, intorder=4, k=8):
    """A vector field of the old basis, L2-projected onto the new one: M_new v = int N^T v_old.

    The projection keeps the field's mean (momentum, for velocities) and cannot increase
    its L2 norm (kinetic energy) where the old field is known, unlike nodal interpolation
    (:func:`map_nodal`), which on every remeshing of a sheared P2 field adds energy (the
    granular column, book/pfem_large_deformation.md).
    Quadrature points of the new mesh outside the old one take, instead of an
    extrapolation, the linear interpolation of ``vertex_values`` (n_vertices, dim) of
    the new mesh (the particles' values) when given.

    Returns (new_basis.N,) dofs of the projected field.
    """
    from scipy.sparse.linalg import splu
    from skfem import Basis, BilinearForm, LinearForm, asm
    from skfem.helpers import dot

    values = np.asarray(values, dtype=float)
    mesh = new_basis.mesh
    basis = Basis(mesh, new_basis.elem, intorder=intorder)
    X = basis.mapping.F(basis.X)                                   # (2, nel, nqp)
    dim, nel, nqp = X.shape
    pts = X.reshape(dim, -1).T
    scalar_old = old_basis.with_element(old_basis.elem.elem)
    stacked = np.stack([values[idx] for idx in old_basis.split_indices()], axis=1)
    cells_old, inside, _ = locate(old_basis.mesh, pts, k=k)
    vq = interpolate(scalar_old, stacked, pts, cells=cells_old)     # (n, dim)
    if vertex_values is not None:
        if not inside.all():
            cells = np.repeat(np.arange(nel), nqp)[~inside]
            lam = basis.mapping.invF(pts[~inside].T[:, :, None], tind=cells)[:, :, 0]
            bary = np.column_stack([1 - lam.sum(axis=0), lam[0], lam[1]])
            vv = np.asarray(vertex_values, dtype=float)[mesh.t[:3, cells].T]   # (m, 3, dim)
            vq[~inside] = np.einsum("mk,mkd->md", bary, vv)
    field = vq.T.reshape(dim, nel, nqp)

    @BilinearForm
    def mass(u, v, w):
        return dot(u, v)

    @LinearForm
    def load(v, w):
        return dot(w["old"], v)

    M = asm(mass, basis).tocsc()
    b = asm(load, basis, old=field)
    return splu(M).solve(b)
