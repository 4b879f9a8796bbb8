"""Step 2b, optional: the moved vertices shifted so that every vertex patch keeps the
volume the step's linearised motion gives it.

Why. The particles move by d (the vertex values of du, with the bulge correction), so
each straight-sided triangle's area becomes det(I + grad d) times the old one:
1 + div d + det(grad d) in plane strain (with the hoop stretch in axisymmetry). The
conic step states the strain linearised, and for psi = 0 keeps it isochoric; the
quadratic term is stated nowhere and is lost at every step: O(dt^2) a step, O(dt) over
a run, a shrinking of every extensional flow (a collapsing column, a landslide
spreading on its base).

What. The volume of the patch of vertex i (its dual cell, weighted by its hat
function phi_i, in axisymmetry by 2 pi r) is

    V_i(x) = int phi_i dV   over the straight-sided triangles at the vertices x,

and the linearised motion states its value after the step

    V_i* = V_i(x_n) + grad V_i(x_n) . d  =  V_i(x_n) + int phi_i tr eps(d) dV

(d interpolated linearly, phi_i carried with the mesh),

so the moved patch misses V_i(x_n + d) - V_i* = Q_i(d), the quadratic rest (plane
strain: the integral of det grad d). The shift w of the moved vertices x = x_n + d is
the least (patch-volume weighted) one that meets the constraints linearised at x:

    minimise  1/2 sum_i m_i |w_i|^2   subject to   V_i(x) + grad V_i(x) . w = V_i*,
    w_i in the directions vertex i may move (none for a held vertex, along the axis
    on the axis, tangential to a rigid body it presses on),

so w = M^-1 P G^T lambda with (G M^-1 P G^T) lambda = V* - V(x), one sparse linear
solve (G = grad V, P the per-vertex projector onto the allowed directions). This is the
discrete form of the projection w = grad(phi) with phi = 0 on the free surface and no
normal shift on walls and the axis; w = O(|d|^2) (second order in dt: the motion is
changed only where the linearisation is), the residual left O(|d|^4). The dilation of
a dilating material is kept to first order (it is in grad V . d).

The target is the linearised motion's, not the P2 field's own weak balance int phi_i
tr eps(du): the vertices cannot follow the P2 field's curved edges, and forcing their
patches to its balance changes their motion at first order (on a short column of
revolution it lifted the top on the axis, which must stay still).

The idea is the projection step of Chorin's projection method (A. J. Chorin, Math.
Comp. 22, 1968) applied to the vertex positions instead of the velocity, with the
continuity equation replaced by the patch-volume balance of the linearised step.
"""
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from ..discretisation.fields import vertex_dofs


@dataclass
class VolumeConstraint:
    """The patch volumes a step's moved vertices must keep.

    Attributes
    ----------
    triangles : (n_elements, 3) vertex indices;  orientation : (n_elements,) +-1, the
    sign of each triangle's area at t_n;  start : (n_vertices, 2) the vertices at t_n;
    allowed : (n_vertices, 2, 2) projector onto the directions each vertex may shift;
    axisymmetric : the 2 pi r weight;  growth : every patch's target also grows by this
    fraction of its volume at t_n (:func:`area_growth`; 0: the linearised motion's alone).
    """

    triangles: np.ndarray
    orientation: np.ndarray
    start: np.ndarray
    allowed: np.ndarray
    axisymmetric: bool
    growth: float = 0.0

    def volumes(self, x):
        """Patch volumes V_i at the vertices x."""
        return patch_volumes(x, self.triangles, self.orientation, self.axisymmetric)

    def gradient(self, x):
        """G = dV/dx at the vertices x."""
        return patch_volume_gradient(x, self.triangles, self.orientation, self.axisymmetric)

    def target(self, x):
        """V_i* of the moved vertices x: the patch volumes the linearised motion states
        (each grown by ``growth``)."""
        return ((1.0 + self.growth) * self.volumes(self.start)
                + self.gradient(self.start) @ (x - self.start).ravel())


def area_growth(constraint, volume):
    """The growth that takes the step's domain (the patches' total at t_n) to ``volume``.

    Why. Each remeshing's alpha shape closes the gaps of a broken free surface narrower than
    alpha h (air a splash or a breaking wave traps): the domain gains area that no particle
    carries, an incompressible step keeps it, and it adds up over a run (a fifth of the
    domain in a block sliding into a tank, book/water_and_mud.md). With every material
    isochoric the domain's true area is its first one (times the fraction of the mass
    still in the scene); asking every patch for the same relative growth gives the gain
    back at the next step, spread as the least shift of the vertices
    (:func:`volume_shift`): the free surface is lowered, not one gap closed.
    """
    now = float(constraint.volumes(constraint.start).sum())
    if not (np.isfinite(volume) and volume > 0 and now > 0):
        raise ValueError(f"the target volume and the step's domain must be positive, got "
                         f"{volume!r} and {now!r}")
    return volume / now - 1.0


def _signed_areas(p, t):
    """Signed areas of the triangles t (n, 3) at the points p (n_v, 2)."""
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                  - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1]))


def patch_volumes(p, t, orientation, axisymmetric):
    """V_i = int phi_i dV over the straight triangles t at the points p: a third of each
    area in plane strain; in axisymmetry 2 pi A (2 r_i + r_j + r_k) / 12."""
    area = orientation * _signed_areas(p, t)
    if axisymmetric:
        r = p[t, 0]
        local = 2 * np.pi * area[:, None] * (r + r.sum(axis=1, keepdims=True)) / 12
    else:
        local = np.repeat(area[:, None] / 3, 3, axis=1)
    return np.bincount(t.ravel(), weights=local.ravel(), minlength=len(p))


def patch_volume_gradient(p, t, orientation, axisymmetric):
    """G = dV_i / dx_j, sparse (n_vertices, 2 n_vertices), column 2 j + c for component c."""
    area = orientation * _signed_areas(p, t)
    nxt, prv = t[:, [1, 2, 0]], t[:, [2, 0, 1]]
    # dA/dx_j = (y_next - y_prev, x_prev - x_next) / 2 for a counter-clockwise triangle
    d_area = 0.5 * orientation[:, None, None] * np.stack(
        [p[nxt, 1] - p[prv, 1], p[prv, 0] - p[nxt, 0]], axis=2)       # (n_e, 3 (j), 2)
    if axisymmetric:
        r = p[t, 0]
        factor = (r + r.sum(axis=1, keepdims=True)) * (2 * np.pi / 12)  # (n_e, 3 (i))
        values = factor[:, :, None, None] * d_area[:, None, :, :]      # (n_e, i, j, c)
        hoop = 2 * np.pi / 12 * area[:, None, None] * (1.0 + np.eye(3)[None])  # d r-sum
        values[..., 0] += hoop
    else:
        values = np.repeat(d_area[:, None, :, :] / 3, 3, axis=1)
    rows = np.broadcast_to(t[:, :, None, None], values.shape)
    cols = 2 * np.broadcast_to(t[:, None, :, None], values.shape) + np.arange(2)
    n = len(p)
    return sp.coo_matrix((values.ravel(), (rows.ravel(), cols.ravel())),
                         shape=(n, 2 * n)).tocsr()


def allowed_directions(n_vertices, blocked):
    """(n_vertices, 2, 2) projectors onto the directions left free by the unit normals
    ``blocked`` = [(vertex indices, (k, 2) normals), ...] (a held vertex: both axes)."""
    allowed = np.broadcast_to(np.eye(2), (n_vertices, 2, 2)).copy()
    for vertices, normals in blocked:
        for i, n in zip(vertices, normals):           # a few boundary vertices
            q = allowed[i] @ n
            size = np.linalg.norm(q)
            if size > 1e-8:
                q = q / size
                allowed[i] -= np.outer(q, q)
    return allowed


def step_constraint(disc, *, fixed=(), contacts=None, pressed=None, volume=None,
                    growth_limit=0.0):
    """The :class:`VolumeConstraint` of a step.

    Parameters
    ----------
    disc : the step's Discretisation (mesh at t_n).  fixed : displacement dofs held still
    (a held phase, the radial dofs on the axis): those components are not shifted.
    contacts : the step's ContactSet or None;  pressed : (n_contacts,) bool, the contact
    rows whose node presses on its body: no shift along the body's normal there.
    volume : None, or the volume the moved domain is to have (:func:`area_growth`).
    growth_limit : the largest growth (or shrinking) asked of one step, a fraction of the
    domain's volume (0: none; ``PFEMConfig.keep_area_step``): the rest is left to the
    next steps.
    """
    mesh = disc.mesh
    t = mesh.t[:3].T
    p = mesh.p.T
    orientation = np.sign(_signed_areas(p, t))
    vd = vertex_dofs(disc)
    vertex_of = np.full(disc.n_u, -1)
    vertex_of[vd.ravel()] = np.repeat(np.arange(mesh.nvertices), 2)
    component = np.zeros(disc.n_u, dtype=int)
    component[vd[:, 1]] = 1
    fixed = np.asarray(fixed, dtype=int)
    fixed = fixed[vertex_of[fixed] >= 0]                       # midside dofs: no particle
    blocked = [(vertex_of[fixed], np.eye(2)[component[fixed]])]
    if contacts is not None and pressed is not None and np.any(pressed):
        rows = np.flatnonzero(pressed)
        at = vertex_of[contacts.dofs[rows, 0]]
        blocked.append((at[at >= 0], contacts.normal[rows[at >= 0]]))
    constraint = VolumeConstraint(t, orientation, p.copy(),
                                  allowed_directions(mesh.nvertices, blocked),
                                  disc.geometry.axisymmetric)
    if volume is not None:
        constraint.growth = area_growth(constraint, volume)
        if growth_limit > 0:                     # the rest at the next steps
            constraint.growth = float(np.clip(constraint.growth, -growth_limit, growth_limit))
    return constraint


def volume_shift(constraint, x, regularisation=1e-10):
    """The least shift w (n_vertices, 2) of the moved vertices x that restores the patch
    volumes of ``constraint`` to first order in w (one linear solve).

    The multiplier system G M^-1 P G^T is singular when no vertex can change the total
    volume (a body held all round); ``regularisation`` (relative to its diagonal) keeps
    it solvable, and a multiplier of such a mode shifts nothing (G^T maps it to zero).
    """
    volumes = constraint.volumes(x)
    residual = constraint.target(x) - volumes
    G = constraint.gradient(x)
    weight = np.abs(volumes)
    weight = np.maximum(weight, 1e-12 * weight.max())
    n = len(x)
    blocks = constraint.allowed / weight[:, None, None]                # M^-1 P, per vertex
    rows = 2 * np.arange(n)[:, None, None] + np.arange(2)[None, :, None]
    cols = 2 * np.arange(n)[:, None, None] + np.arange(2)[None, None, :]
    D = sp.coo_matrix((blocks.ravel(), (np.broadcast_to(rows, blocks.shape).ravel(),
                                        np.broadcast_to(cols, blocks.shape).ravel())),
                      shape=(2 * n, 2 * n)).tocsr()
    DGt = D @ G.T
    S = (G @ DGt).tocsc()
    diagonal = S.diagonal()
    floor = regularisation * (diagonal + 1e-6 * diagonal.mean())
    lam = spsolve(S + sp.diags(floor), residual)
    return (DGt @ lam).reshape(n, 2)


def bounded_shift(constraint, x, motion):
    """:func:`volume_shift` of the moved vertices x, refused when larger than ``motion`` (the
    step's largest vertex displacement).

    Why. The shift corrects the second-order rest of the motion, O(|d|^2 / l): far below
    the motion itself. A larger one means the linearisation has failed (triangles the step
    inverted or flattened, as in a pile of particles crowded into a corner: the clay
    block into the tank, book/water_and_mud.md); the step then keeps its unshifted
    positions (``keep_area`` gives the area back at the next step).

    Returns (shift (n_vertices, 2), zero when refused; its largest vertex shift; refused).
    """
    w = volume_shift(constraint, x)
    size = float(np.linalg.norm(w, axis=1).max(initial=0.0))
    refused = not size <= motion                          # NaN is refused too
    return (np.zeros_like(w) if refused else w), size, refused
