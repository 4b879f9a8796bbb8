"""Step 2b of the PFEM loop (Section 2.2): the particles moved, and the free surface kept.

The particles are the vertices of the six-node triangles (Section 2.3.1), so two
things lose area although the psi = 0 flow is isochoric in each P2 element: moving
only the vertices drops the bulge of every curved boundary edge, and the alpha-shape
deletes the boundary triangles that a stretching free surface makes too large. The
remedies: :func:`bulge_correction` shifts the boundary vertices so that the chords
keep the area of the curved edges, and a boundary edge stretched beyond
``refine_surface`` h hands its P2 midside node to the cloud as a new particle
(:func:`move_particles`). :func:`particle_tags` sets the free-surface and contact tags.
"""
from dataclasses import replace

import numpy as np

from ..discretisation.fields import vertex_dofs
from ..problems.particle import free_particles_step
from .volume_projection import bounded_shift


def boundary_edges(disc, du):
    """Boundary edges: end vertices a, b, midside dofs, the midside deviation
    delta = du_mid - (du_a + du_b)/2 and the outward unit normal at t_n."""
    mesh = disc.mesh
    f = mesh.boundary_facets()
    a, b = mesh.facets[:, f]
    vd = vertex_dofs(disc)
    fd = disc.basis_u.facet_dofs[:, f]
    delta = du[fd].T - 0.5 * (du[vd[a]] + du[vd[b]])
    p = mesh.p.T
    t = p[b] - p[a]
    n = np.column_stack([t[:, 1], -t[:, 0]]) / np.linalg.norm(t, axis=1)[:, None]
    centroid = p[mesh.t[:, mesh.f2t[0, f]]].mean(axis=0)
    n[np.einsum("id,id->i", n, 0.5 * (p[a] + p[b]) - centroid) < 0] *= -1   # outward
    return a, b, fd, delta, n


def axis_vertices(disc):
    """(n_vertices,) bool: vertices on the axis r = 0 of an axisymmetric discretisation
    (to round-off, as :func:`~pfem_skfem.discretisation.static.axis_dofs`); all False in plane strain."""
    p = disc.mesh.p
    if not disc.geometry.axisymmetric:
        return np.zeros(p.shape[1], dtype=bool)
    scale = float(np.ptp(p, axis=1).max()) or 1.0
    return np.abs(p[0]) <= 1e-12 * scale


def bulge_correction(disc, du, skip=None, regularisation=0.01, edges=None, axis=None):
    """Shift of the boundary vertices that keeps the area the P2 displacement gives the body.

    The particles are the vertices only, so moving them drops the bulge of each boundary
    edge, the area (2/3) L (delta . n) between the curved P2 edge and its chord, with
    delta = du_mid - (du_a + du_b)/2 and n the outward unit normal. The flow of the psi = 0
    scheme is exactly isochoric in each P2 element (div du is linear and orthogonal to
    the linear stresses), so the dropped bulge is a loss of area at every step, of first
    order in du and independent of dt.

    Each end of an edge puts back half of its bulge: a shift w_a of vertex a adds
    (L_e / 2) (w_a . n_e) to edge e, so w_a should satisfy w_a . n_e = c_e with
    c_e = (2/3) (delta_e . n_e) for both boundary edges e at a. Solved per vertex in the
    least-squares sense with a small Tikhonov term (``regularisation``), which on a
    straight boundary gives w_a = (c_1 + c_2)/2 n (the two equations coincide) and at a
    corner the shift that leaves the edge without bulge unchanged: the crest of a slope
    below a flat top moves along the top, not up. ``skip`` : (n_boundary_edges,) bool,
    edges left out (those whose midside node becomes a particle); ``edges`` : the
    :func:`boundary_edges` of (disc, du), if already computed; ``axis`` : (n_vertices,)
    bool, vertices on the axis of an axisymmetric body, whose radial shift is zero (they
    stay on the axis; an edge along the axis has no bulge, u_r = 0 on it).

    Returns (n_vertices, 2) shifts (zero at interior vertices). The shifts keep the area
    of the meridian section; in axisymmetry (``disc.geometry``) they keep the volume
    2 pi r dA instead (:func:`_bulge_correction_axisymmetric`).
    """
    a, b, _, delta, n = boundary_edges(disc, du) if edges is None else edges
    if disc.geometry.axisymmetric:
        return _bulge_correction_axisymmetric(disc, du, a, b, delta, n, skip,
                                              regularisation, axis)
    c = 2.0 / 3.0 * np.einsum("id,id->i", delta, n)
    if skip is not None:
        c = np.where(skip, 0.0, c)
    nv = disc.mesh.nvertices
    normal_matrix = np.zeros((nv, 2, 2))                  # sum_e n_e n_e^T at each vertex
    rhs = np.zeros((nv, 2))                               # sum_e c_e n_e
    nn = n[:, :, None] * n[:, None, :]
    for end in (a, b):
        np.add.at(normal_matrix, end, nn)
        np.add.at(rhs, end, c[:, None] * n)
    on = np.unique(np.concatenate([a, b]))
    # the Tikhonov term in units of the vertex's own normal matrix (trace = edges at it)
    lam = _tikhonov(normal_matrix[on], regularisation)
    shift = np.zeros((nv, 2))
    shift[on] = np.linalg.solve(normal_matrix[on] + lam[:, None, None] * np.eye(2),
                                rhs[on][..., None])[..., 0]
    return shift


def _tikhonov(normal_matrix, regularisation):
    """The Tikhonov term of :func:`bulge_correction` at every vertex."""
    return regularisation * np.trace(normal_matrix, axis1=1, axis2=2) / 2


def _bulge_correction_axisymmetric(disc, du, a, b, delta, n_start, skip, regularisation, axis):
    """:func:`bulge_correction` for a body of revolution: the shifts that put back each
    boundary edge's bulge *volume*, stated on the moved chords.

    The moved P2 edge is x(s) = chord(s) + 4 s (1 - s) delta, so between it and its moved
    chord (length L, outward normal n, midpoint radius r_mid) lies the volume
    2 pi L (delta . n) ((2/3) r_mid + (4/15) delta_r) exactly. A shift w of end a turns the
    chord about b and adds 2 pi (L/2) r_bar_a (w . n), r_bar_a = (2 r_a + r_b)/3. Each end
    puts back half: w . n_e = c_e with c_e = (2/3) (delta . n_e) ((r_mid + 0.4 delta_r) /
    r_bar_a), solved at each vertex in the least-squares sense weighted by the edges'
    volume weights L_e r_bar_e (so that on a straight boundary the volume put back is the
    two halves', whatever the edge lengths), with the Tikhonov term of the plane case. The
    chords at t_n (the plane case's) leave a residual of second order in du that is
    10-15 % of the dropped bulges at dt / sqrt(h0/g) = 0.02 on a collapsing column.
    Vertices on the axis (``axis``) move along it only.
    """
    vd = vertex_dofs(disc)
    p = disc.mesh.p.T + du[vd]                      # the vertices moved, chords at t_{n+1}
    tangent = p[b] - p[a]
    length = np.linalg.norm(tangent, axis=1)
    n = np.column_stack([tangent[:, 1], -tangent[:, 0]]) / np.maximum(length, 1e-300)[:, None]
    n[np.einsum("id,id->i", n, n_start) < 0] *= -1     # outward, as at t_n
    mesh = disc.mesh
    delta_n = np.einsum("id,id->i", delta, n)
    if skip is not None:
        delta_n = np.where(skip, 0.0, delta_n)
    r = p[:, 0]
    r_bulge = 0.5 * (r[a] + r[b]) + 0.4 * delta[:, 0]    # (3/2) int r over the bulge / area
    nv = mesh.nvertices
    normal_matrix = np.zeros((nv, 2, 2))                  # sum_e w_e n_e n_e^T
    rhs = np.zeros((nv, 2))                               # sum_e w_e c_e n_e
    nn = n[:, :, None] * n[:, None, :]
    scale = float(np.ptp(p, axis=0).max()) or 1.0
    for end, other in ((a, b), (b, a)):
        r_bar = np.maximum((2 * r[end] + r[other]) / 3, 1e-12 * scale)
        weight = length * r_bar                           # the volume of a unit normal shift
        c_end = 2.0 / 3.0 * delta_n * r_bulge / r_bar
        np.add.at(normal_matrix, end, weight[:, None, None] * nn)
        np.add.at(rhs, end, (weight * c_end)[:, None] * n)
    on = np.unique(np.concatenate([a, b]))
    lam = _tikhonov(normal_matrix, regularisation)
    shift = np.zeros((nv, 2))
    shift[on] = np.linalg.solve(normal_matrix[on] + lam[on, None, None] * np.eye(2),
                                rhs[on][..., None])[..., 0]
    if axis is not None:                # on the axis: the shift along it only
        on_axis = np.flatnonzero(axis)
        shift[on_axis, 0] = 0.0
        shift[on_axis, 1] = rhs[on_axis, 1] / np.maximum(
            normal_matrix[on_axis, 1, 1] + lam[on_axis], 1e-300)
    return shift


def project_out_of_bodies(x, v, bodies, h):
    """Particles found inside a rigid body put back on its surface, their normal velocity
    (into the body) removed; returns x, v and the number that were deeper than 1e-3 h."""
    projected = 0
    for body in bodies:
        g0, n = body.gap(x)
        inside = g0 < 0
        if inside.any():
            x[inside] -= g0[inside, None] * n[inside]
            vn = np.einsum("id,id->i", v[inside], n[inside])
            v[inside] -= np.minimum(vn, 0)[:, None] * n[inside]
            projected += int(np.sum(g0 < -1e-3 * h))
    return x, v, projected


def move_particles(state, pm, disc, inc, sigma_m_vertices, *, theta, gravity, bodies,
                   refine=(2.0, 0.0), bulge=True, volume=None):
    """Step 2b: particles of the mesh move by du (vertex dofs) and take v_{n+1}; particles
    in no element fly ballistically (theta-method free fall) and slide with friction on the
    rigid bodies (:func:`~pfem_skfem.problems.particle.free_particles_step`).

    Parameters
    ----------
    state : PFEMState at t_n;  pm, disc : the step's ParticleMesh and Discretisation;
    inc : its DynamicIncrement;  sigma_m_vertices : the smoothed mean stress of the solution.
    theta : ThetaMethod;  gravity : (2,) acceleration;  bodies : rigid bodies at t_{n+1}.
    refine : (surface, interior): a boundary edge longer than ``surface`` h gets its P2
        midside node as a new particle (0: never); an interior edge longer than ``interior``
        h likewise (0, the default: never; the new particle takes the region of the edge's
        first vertex), so that a cloud that thinning merges keeps its spacing where the
        flow stretches it.
    bulge : apply :func:`bulge_correction`.
    volume : a :class:`~pfem_skfem.pfem.volume_projection.VolumeConstraint` of the step, or
        None: after the bulge correction the vertices are shifted so that every vertex
        patch keeps the volume their linearised motion states
        (:func:`~pfem_skfem.pfem.volume_projection.bounded_shift`).

    In axisymmetry (``disc.geometry``) the particles on the axis stay on it exactly (u_r = 0
    there, no radial bulge shift), and a particle that would cross the axis (a free one, or
    a vertex by round-off) is put on it with its radial velocity removed.

    Returns the moved state (new particles appended: midside nodes of stretched boundary
    edges, then of stretched interior edges, with no mass), the number of particles found
    inside a rigid body by more than 1e-3 h (put back on its surface), and the volume
    shift's record: its largest vertex shift (0 without ``volume``) and whether it was
    refused (larger than the step's largest vertex motion: the linearisation failed, the
    positions are left unshifted).
    """
    refine_surface, refine_interior = refine
    vd = vertex_dofs(disc)
    x, v = state.x.copy(), state.v.copy()
    sm = state.sigma_m.copy()
    on_mesh = np.zeros(len(x), dtype=bool)
    on_mesh[pm.particle] = True
    x[pm.particle] += inc.du[vd]
    # stretched boundary edges: their P2 midside node becomes a particle, so the free
    # surface is not torn open by the alpha-shape (its triangles would be deleted)
    edges = boundary_edges(disc, inc.du)
    a, b, fd, _, _ = edges
    pa, pb = pm.particle[a], pm.particle[b]
    h_edge = 0.5 * (state.h[pa] + state.h[pb])
    split = np.zeros(len(a), dtype=bool)
    if refine_surface > 0:
        split = np.linalg.norm(x[pa] - x[pb], axis=1) > refine_surface * h_edge
    axis = axis_vertices(disc)
    if bulge:
        x[pm.particle] += bulge_correction(disc, inc.du, skip=split, edges=edges,
                                           axis=axis if axis.any() else None)
    shift = {"volume_shift": 0.0, "volume_shift_refused": False}
    if volume is not None:
        motion = np.linalg.norm(x[pm.particle] - state.x[pm.particle], axis=1).max(initial=0.0)
        w, size, refused = bounded_shift(volume, x[pm.particle], motion)
        x[pm.particle] += w
        shift = {"volume_shift": size, "volume_shift_refused": refused}
    new_x = disc.basis_u.doflocs[:, fd[0, split]].T + inc.du[fd[:, split]].T
    new_v = inc.v[fd[:, split]].T
    inner = np.empty(0, dtype=int)
    if refine_interior > 0:         # stretched interior edges at the moved positions
        inner = np.flatnonzero(disc.mesh.f2t[1] >= 0)      # facets of two triangles
        ia, ib = pm.particle[disc.mesh.facets[:, inner]]
        h_inner = 0.5 * (state.h[ia] + state.h[ib])
        stretched = np.linalg.norm(x[ia] - x[ib], axis=1) > refine_interior * h_inner
        inner, ia, ib, h_inner = (a[stretched] for a in (inner, ia, ib, h_inner))
    v[pm.particle] = inc.v[vd]
    sm[pm.particle] = sigma_m_vertices
    free = ~on_mesh
    if free.any():              # gravity and frictional contact with the walls, (5.2)
        x[free], v[free] = free_particles_step(x[free], v[free], gravity, theta.dt,
                                               theta.theta2, bodies)
        sm[free] = 0.0
    moved = replace(state, x=x, v=v, sigma_m=sm)
    if split.any():
        new_sm = 0.5 * (sm[pa[split]] + sm[pb[split]])
        moved = moved.appended(new_x, new_v, h_edge[split], new_sm, state.region[pa[split]],
                               pore_pressure=_midpoint(state.pore_pressure, pa[split],
                                                       pb[split]))
    if inner.size:
        fi = disc.basis_u.facet_dofs[:, inner]
        moved = moved.appended(disc.basis_u.doflocs[:, fi[0]].T + inc.du[fi].T, inc.v[fi].T,
                               h_inner, 0.5 * (sm[ia] + sm[ib]), state.region[ia],
                               pore_pressure=_midpoint(state.pore_pressure, ia, ib))
    # no particle inside a rigid body: a node that was outside the contact search (or a
    # free particle) and crossed a wall is put back on it with its normal velocity removed
    x, v, projected = project_out_of_bodies(moved.x, moved.v, bodies, np.median(state.h))
    if disc.geometry.axisymmetric:
        x[pm.particle[axis], 0] = 0.0              # on the axis, exactly
        keep_off_axis(x, v)
    return replace(moved, x=x, v=v), projected, shift


def _midpoint(values, a, b):
    """A P1 field (the pore pressure) at the midpoints of edges (a, b): the mean of their
    ends, exactly; None without one."""
    return None if values is None else 0.5 * (values[a] + values[b])


def keep_off_axis(x, v):
    """In axisymmetry a particle that would cross the axis r = 0 is put on it with its
    inward radial velocity removed (in place)."""
    crossed = x[:, 0] < 0
    x[crossed, 0] = 0.0
    v[crossed, 0] = np.maximum(v[crossed, 0], 0.0)


def fly_free(state, *, theta, gravity, bodies, axisymmetric=False):
    """Step 2b when the particles form no element (the last few of a discharge, a spray):
    every particle flies free and slides on the bodies, as the free particles of a meshed
    step do. Returns the moved state (no lagged stress left) and the number of particles
    put back out of a body."""
    x, v = free_particles_step(state.x, state.v, gravity, theta.dt, theta.theta2, bodies)
    x, v, projected = project_out_of_bodies(x, v, bodies, np.median(state.h))
    if axisymmetric:
        keep_off_axis(x, v)
    return replace(state, x=x, v=v, sigma_m=np.zeros(state.n)), projected


def particle_tags(disc, pm, contacts, inc, n, weight):
    """The tags of :class:`~pfem_skfem.pfem.Particles` after a step, for n particles.

    free_surface : a vertex of a boundary edge of the step's mesh (in axisymmetry not an
    edge along the axis), or a particle in no element (flying free, or new: the midside node of a stretched boundary edge);
    contact : a vertex pressed against a rigid body, normal force p above 1e-6 ``weight``
    (a particle's weight, rho g h^2).
    """
    free_surface = np.ones(n, dtype=bool)
    free_surface[pm.particle] = False
    if disc.geometry.axisymmetric:               # the axis is no free surface
        axis = axis_vertices(disc)
        ends = disc.mesh.facets[:, disc.mesh.boundary_facets()]
        ends = ends[:, ~(axis[ends[0]] & axis[ends[1]])]
        free_surface[pm.particle[np.unique(ends)]] = True
    else:
        free_surface[pm.particle[disc.mesh.boundary_nodes()]] = True
    contact = np.zeros(n, dtype=bool)
    if contacts is not None:
        vertex_of = np.full(disc.n_u, -1)
        vertex_of[vertex_dofs(disc)[:, 0]] = np.arange(disc.mesh.nvertices)
        vertex = vertex_of[contacts.dofs[:, 0]]          # -1: a midside node
        pressed = (vertex >= 0) & (inc.p > 1e-6 * weight)
        contact[pm.particle[vertex[pressed]]] = True
    return free_surface, contact
