"""Step 2b, optional: the moved vertices shifted so that every vertex patch keeps the
volume the step's linearised strain gives it.

Why. The particles move by the vertex values of du, so each straight-sided triangle's
area becomes det(I + grad du) times the old one: 1 + div du + det(grad du) in plane
strain (with the hoop stretch in axisymmetry). The conic step states the strain
linearised, tr eps(du), and for psi = 0 keeps it zero in the weak sense of the
element's linear stresses; the quadratic term is not stated and is lost at every
step: O(dt^2) a step, O(dt) over a run, a shrinking of every extensional flow (a
collapsing column, a landslide spreading on its base).

What. The volume of the patch of vertex i (its dual cell, weighted by its hat
function phi_i, in axisymmetry by 2 pi r) is

    V_i(x) = int phi_i dV   over the straight-sided triangles at the vertices x,

and the step states its value after the move (the weak volume balance of the
linearised strain, exact for the zero-dilation flow rule)

    V_i* = V_i(x_n) + int_{Omega_n} phi_i tr eps(du) dV.

The shift w of the moved vertices is the least (patch-volume weighted) one that meets
the constraints linearised at the moved vertices x:

    minimise  1/2 sum_i m_i |w_i|^2   subject to   V_i(x) + grad V_i(x) . w = V_i*,
    w_i in the directions vertex i may move (none for a held vertex, along the axis
    on the axis, tangential to a rigid body it presses on),

so w = M^-1 P G^T lambda with (G M^-1 P G^T) lambda = V* - V(x), one sparse linear
solve (G = grad V, P the per-vertex projector onto the allowed directions). This is
the discrete form of the projection w = grad(phi) with phi = 0 on the free surface and
no normal shift on walls and the axis (the pressure-like multiplier vanishes where
the boundary may move); the residual left is of second order in w, O(dt^4) a step.
The idea is the projection step of Chorin's projection method (A. J. Chorin, Math.
Comp. 22, 1968) applied to the vertex positions instead of the velocity, with the
continuity equation replaced by the step's own patch-volume balance.
"""
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from ..fields import barycentric_at_points, vertex_dofs


@dataclass
class VolumeConstraint:
    """The patch volumes a step's moved vertices must keep.

    Attributes
    ----------
    triangles : (n_elements, 3) vertex indices;  orientation : (n_elements,) +-1, the
    sign of each triangle's area at t_n;  target : (n_vertices,) V_i*;  allowed :
    (n_vertices, 2, 2) projector onto the directions each vertex may shift;
    axisymmetric : the 2 pi r weight.
    """

    triangles: np.ndarray
    orientation: np.ndarray
    target: np.ndarray
    allowed: np.ndarray
    axisymmetric: bool


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


def strain_volume_change(disc, B, du):
    """int_{Omega_n} phi_i tr eps(du) dV at every vertex: the stress-point rows of B du
    (int N_p eps(du) dV, thesis (3.41), (7.25)) summed over the normal components and
    spread to the vertices by phi_i at the stress points (phi_i is linear in the element,
    so this is exact)."""
    trace = (B @ du).reshape(-1, 4)[:, :3].sum(axis=1)
    bary, element = barycentric_at_points(disc)
    vertices = disc.mesh.t[:3, element].T                              # (n_points, 3)
    return np.bincount(vertices.ravel(), weights=(bary * trace[:, None]).ravel(),
                       minlength=disc.mesh.nvertices)


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


def step_constraint(disc, B, du, *, fixed=(), contacts=None, pressed=None):
    """The :class:`VolumeConstraint` of a step.

    Parameters
    ----------
    disc : the step's Discretisation (mesh at t_n);  B : its strain operator (3.41);
    du : (n_u,) the step's displacement.  fixed : displacement dofs held still (a held
    phase, the radial dofs on the axis): those components are not shifted.
    contacts : the step's ContactSet or None;  pressed : (n_contacts,) bool, the contact
    rows whose node presses on its body: no shift along the body's normal there.
    """
    mesh = disc.mesh
    t = mesh.t[:3].T
    p = mesh.p.T
    orientation = np.sign(_signed_areas(p, t))
    axisymmetric = disc.geometry.axisymmetric
    target = patch_volumes(p, t, orientation, axisymmetric) + strain_volume_change(disc, B, du)
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
    return VolumeConstraint(t, orientation, target, allowed_directions(mesh.nvertices, blocked),
                            axisymmetric)


def volume_shift(constraint, x, regularisation=1e-10):
    """The least shift w (n_vertices, 2) of the moved vertices x that restores the patch
    volumes of ``constraint`` to first order in w (one linear solve).

    The multiplier system G M^-1 P G^T is singular when no vertex can change the total
    volume (a body held all round); ``regularisation`` (relative to its diagonal) keeps
    it solvable, and a multiplier of such a mode shifts nothing (G^T maps it to zero).
    """
    t, s, axi = constraint.triangles, constraint.orientation, constraint.axisymmetric
    residual = constraint.target - patch_volumes(x, t, s, axi)
    G = patch_volume_gradient(x, t, s, axi)
    weight = np.abs(patch_volumes(x, t, s, axi))
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


def without_split_bulges(constraint, disc, edges, split):
    """``constraint`` with the targets of the ends of the ``split`` boundary edges lowered
    by the volume the edge's new particle (its P2 midside node) brings back: the triangle
    (a, midside, b), of area L (delta . n) / 2, half to each end (else the bulge would
    be counted twice, once by the shift and once by the particle).

    edges : :func:`~pfem_skfem.pfem.surface.boundary_edges` (a, b, dofs, delta, n) at t_n.
    """
    if not np.any(split):
        return constraint
    a, b, _, delta, n = (e[..., split] if k == 2 else e[split]
                         for k, e in enumerate(edges))
    p = disc.mesh.p.T
    length = np.linalg.norm(p[b] - p[a], axis=1)
    volume = 0.5 * length * np.einsum("id,id->i", delta, n)
    if constraint.axisymmetric:         # 2 pi times the triangle's centroid radius
        volume *= 2 * np.pi * (1.5 * (p[a, 0] + p[b, 0]) + delta[:, 0]) / 3
    target = constraint.target.copy()
    np.add.at(target, a, -0.5 * volume)
    np.add.at(target, b, -0.5 * volume)
    return VolumeConstraint(constraint.triangles, constraint.orientation, target,
                            constraint.allowed, constraint.axisymmetric)
