"""The pore pressure in a PFEM step of a saturated scene (issue 54, item 5).

A scene with ``water`` (:class:`~pfem_skfem.scene.water.Water`) adds to each step the
pore pressure p as :class:`~pfem_skfem.problems.pore_term.PorePressureTerm`: continuous P1
on the step's mesh, whose vertices are particles. Its values at t_n are the particles'
(``state.pore_pressure[pm.particle]``) and its solution at t_{n+1} goes back to them, so
remeshing carries p with the particles as it carries their velocities at the vertices,
without a projection (a node a remesher adds takes the old field's value:
:func:`~pfem_skfem.pfem.transfer.adopt_added_nodes`; a node added at the middle of a
stretched edge the mean of its ends, exact for P1). The drained faces are found on each
mesh anew: its boundary vertices in a face's zone, or those that touch no rigid body; and
the vertices of a free-draining region's elements (a region outside ``Water.regions``)
are held at its free drainage, which drains the saturated ones beside it.
"""
from dataclasses import replace

import numpy as np

from ..discretisation.pressure import pressure_field
from ..problems.consolidation import Hydraulic
from ..problems.pore_term import PorePressureTerm


def drained_vertices(water, disc, contacts, h, dry=None):
    """(vertices, p_bar) held by the drained faces of ``water`` on the mesh of ``disc``: its
    boundary vertices in each face's zone (within 1e-6 h of it), or, for a face without a
    zone, those that touch no rigid body (no potential contact of ``contacts`` with a gap
    below 1e-3 h: the search distance reaches further); p_bar the hydrostatic pressure plus
    the face's excess (a vertex in two faces: the last face's). Every vertex of a ``dry``
    element (a boolean per element: a free-draining region's) is held too, at
    ``water.free_draining`` (over a face's value: the region drains it)."""
    mesh = disc.mesh
    boundary = np.unique(mesh.facets[:, mesh.boundary_facets()])
    held = {}
    for face in water.drained:
        if face.zone is None:
            touching = (np.zeros(0, dtype=int) if contacts is None else np.flatnonzero(
                np.isin(disc.basis_u.nodal_dofs[0],
                        contacts.dofs[contacts.gap <= 1e-3 * h, 0])))
            vertices = np.setdiff1d(boundary, touching)
        else:
            vertices = boundary[face.zone.contains(mesh.p[:, boundary].T, tol=1e-6 * h)]
        p_bar = water.hydrostatic(mesh.p[:, vertices].T) + face.p
        held.update(zip(vertices.tolist(), p_bar.tolist()))
    if dry is not None and dry.any():
        vertices = np.unique(mesh.t[:3, dry])
        held.update(zip(vertices.tolist(),
                        water.free_draining(mesh.p[:, vertices].T).tolist()))
    vertices = np.array(sorted(held), dtype=int)
    return vertices, np.array([held[v] for v in vertices.tolist()], dtype=float)


def pore_pressure_term(scene, disc, pm, state, contacts, regions):
    """The step's :class:`~pfem_skfem.problems.pore_term.PorePressureTerm` (None for a scene
    without water): the P1 field on the step's mesh (Darcy and storage on the elements of
    saturated regions, ``regions`` the region of each element), p_n the particles' values,
    the drained faces of this mesh and the vertices of free-draining elements."""
    water = scene.water
    if water is None:
        return None
    if state.pore_pressure is None:
        raise ValueError("the scene is saturated (scene.water) and the state carries no pore "
                         "pressure: start from scene.initial_state()")
    wet = water.saturated(scene.regions)[regions]
    pressure = pressure_field(disc, wet)            # dof i is vertex i
    h = float(np.median(state.h))
    drained = drained_vertices(water, disc, contacts, h, ~wet)
    return PorePressureTerm(water.soil(), pressure, state.pore_pressure[pm.particle],
                            Hydraulic(drained))


def carried(state, pm, increment):
    """The state with the step's pore pressures at its mesh's particles (the others keep
    theirs), and the vertex values; (state, None) without a pore pressure."""
    if "pore_pressure" not in increment.parts:
        return state, None
    p = increment.parts["pore_pressure"]
    values = state.pore_pressure.copy()
    values[pm.particle] = p
    return replace(state, pore_pressure=values), p
