"""Step 1c of the PFEM loop (Section 2.2): the state of the old mesh carried to the new one.

The source of every map is the last mesh moved to t_n with its P2 velocities and
stresses (:func:`old_discretisation`); :func:`map_state` carries the velocities (L2
projection or interpolation) and the stresses (a scheme of :mod:`.mapping`) to the
new mesh, and :func:`adopt_added_nodes` turns nodes a remesher added into particles.
"""
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree
from skfem import Basis, ElementTriP1, MeshTri

from ..discretisation.fields import collapsed, vertex_dofs, vertex_to_points
from ..discretisation.geometry import PLANE_STRAIN
from ..discretisation.static import discretise
from .mapping import interpolate, locate, map_nodal, map_stress, project_nodal
from .remesh import ParticleMesh, last_declared_region


@dataclass(frozen=True)
class L2Projection:
    """Velocities by the L2 projection of the old P2 field onto the new mesh
    (:func:`~pfem_skfem.pfem.mapping.project_nodal`): momentum kept, no kinetic energy added."""


@dataclass(frozen=True)
class Interpolation:
    """Velocities by interpolating the old P2 field at the new nodes; the vertices take their
    particles' velocities, a midside node outside the old mesh the mean of its edge's ends."""


def _mesh(p, t):
    return MeshTri(np.ascontiguousarray(p.T), np.ascontiguousarray(t.T), sort_t=False)


def old_discretisation(state, geometry=PLANE_STRAIN):
    """The last mesh, moved to t_n, with its P2 velocities and stresses: the source of a map.

    A step may collapse a triangle of the moved mesh (zero area); it is left out, its
    values living on in its neighbours (vertex and midside dofs are shared), so that the
    map sees a valid mesh. Returns (Discretisation, v_dofs, sigma), or None before the
    first mesh. ``geometry`` : that of the scene (plane strain by default).
    """
    if state.mesh_p is None:
        return None
    p, t = state.mesh_p, state.mesh_t
    bad = collapsed(p, t)
    if not bad.any():
        return discretise(_mesh(p, t), geometry), state.v_dofs, state.sigma
    full = _mesh(p, t)
    disc = discretise(_mesh(p, t[~bad]), geometry)
    # P2 vector dofs (scikit-fem): vertex v -> 2v + c, facet f -> 2 nv + 2f + c, with
    # nv = mesh.nvertices (the largest vertex index in t, plus one)
    nv, nv_red = full.nvertices, disc.mesh.nvertices
    key = lambda f: f[0] * nv + f[1]                       # noqa: E731 (facets are sorted)
    index = dict(zip(key(full.facets), range(full.facets.shape[1])))
    f_full = np.array([index[k] for k in key(disc.mesh.facets)])
    v = np.zeros(disc.n_u)
    v[disc.basis_u.nodal_dofs] = state.v_dofs[np.arange(2 * nv_red).reshape(nv_red, 2).T]
    v[disc.basis_u.facet_dofs] = state.v_dofs[2 * nv + 2 * f_full + np.arange(2)[:, None]]
    sigma = state.sigma.reshape(-1, 3, 4)[~bad].reshape(-1, 4)
    return disc, v, sigma


def old_regions(state):
    """The region of each element of the map source's mesh (:func:`old_discretisation`):
    the last declared among its vertices' particles, as in the step that used it
    (:func:`~pfem_skfem.pfem.assemble.element_regions`; a particle thinned away since
    counts for none). For the bounded UEM's patch fits, region by region."""
    t = state.mesh_t[~collapsed(state.mesh_p, state.mesh_t)]
    return last_declared_region(state.region, state.mesh_particle[t])


def stress_options(state, stress_mapping):
    """The options of :func:`~pfem_skfem.pfem.mapping.map_stress` for the scheme: the old
    elements' regions for the bounded UEM, none for the others."""
    return {"regions": old_regions(state)} if stress_mapping == "uem_bounded" else {}


def adopt_added_nodes(state, pm, source):
    """Nodes a remesher added (``pm.particle < 0``) become particles: velocity and mean
    stress from the map ``source`` (:func:`old_discretisation`; at rest on the first mesh),
    region and initial stress of the nearest particle, no mass. Returns (state, pm)."""
    added = pm.particle < 0
    if not added.any():
        return state, pm
    xa = pm.mesh.p.T[added]
    if source is None:
        va, sa = np.zeros((len(xa), 2)), np.zeros(len(xa))
    else:
        old_disc, v_old, _ = source
        va = interpolate(old_disc.basis_u, v_old, xa).T
        sa = _vertex_field(state, state.sigma_m, old_disc, xa)
    nearest = cKDTree(state.x).query(xa)[1]
    pa = None
    if state.pore_pressure is not None:        # the old P1 field there (first mesh: nearest)
        pa = (state.pore_pressure[nearest] if source is None
              else _vertex_field(state, state.pore_pressure, source[0], xa))
    particle = pm.particle.copy()
    particle[added] = state.n + np.arange(len(xa))
    # the initial stress (read on the first mesh only): the nearest particle's
    s0 = None if state.stress0 is None else state.stress0[nearest]
    new = state.appended(xa, va, np.full(len(xa), np.median(state.h)), sa, state.region[nearest],
                         pore_pressure=pa, stress0=s0)
    return new, ParticleMesh(pm.mesh, particle)


def _vertex_field(state, values, old_disc, xa):
    """A particle field (the mean stress, the pore pressure) as P1 on the old mesh, at xa."""
    p1 = Basis(old_disc.mesh, ElementTriP1())
    mp = state.mesh_particle                  # -1: a particle thinned away since
    vals = values[np.maximum(mp, 0)]
    if (mp < 0).any():
        vals[mp < 0] = vals[mp >= 0].mean()
    # a vertex only a collapsed triangle used is not in the map source's mesh (the
    # last ones: its vertices keep their numbers)
    return interpolate(p1, vals[:old_disc.mesh.nvertices], xa)


def map_state(state, pm, disc, source, stress_mapping="uem_bounded", velocity=L2Projection()):
    """Step 1c: velocities and stresses on the new mesh (the mean stress is carried by the
    particles and needs no map).

    Parameters
    ----------
    state : the PFEMState (its particles' velocities set the vertex values).
    pm, disc : the new ParticleMesh and its Discretisation.
    source : the map source from :func:`old_discretisation` (None: first mesh, where the
        velocities are the particles', linear in each element, and the stresses the
        initial ``state.stress0`` interpolated, or zero).
    stress_mapping : 'uem_bounded', 'uem' (Fig 2.6), 'ida' (2.1)-(2.2) or 'spr'.
    velocity : :class:`L2Projection` or :class:`Interpolation`.

    Returns v_dofs (n_u,), sigma (n_points, 4).
    """
    vd = vertex_dofs(disc)
    if source is None:
        v = np.zeros(disc.n_u)
        v[vd] = state.v[pm.particle]
        a, b = disc.mesh.facets
        v[disc.basis_u.facet_dofs] = 0.5 * (v[vd[a]] + v[vd[b]]).T
        sigma = np.zeros((disc.n_points, 4))
        if state.stress0 is not None:
            for k in range(4):
                sigma[:, k] = vertex_to_points(disc, state.stress0[pm.particle, k])
        return v, sigma
    old, v_old, sigma_old = source
    sigma = map_stress(old, sigma_old, disc, stress_mapping,
                       **stress_options(state, stress_mapping))
    if isinstance(velocity, L2Projection):
        return project_nodal(old.basis_u, v_old, disc.basis_u,
                             vertex_values=state.v[pm.particle]), sigma
    v = map_nodal(old.basis_u, v_old, disc.basis_u)
    v[vd] = state.v[pm.particle]
    # a midside node outside the old mesh would take the old quadratic extrapolated, which
    # can be far off near the free surface (book/pfem_large_deformation.md); there the
    # velocity is the mean of the edge's two particles
    ends = disc.mesh.facets
    _, inside, _ = locate(old.mesh, disc.mesh.p[:, ends].mean(axis=1).T)
    out = ~inside
    if out.any():
        fd = disc.basis_u.facet_dofs[:, out]
        v[fd] = 0.5 * (v[vd[ends[0, out]]] + v[vd[ends[1, out]]]).T
    return v, sigma
