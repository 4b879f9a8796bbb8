"""The assemble stage of a PFEM step: what the step's cone program is made of.

The operators of (4.23) with each element's density, the gravity load, the potential
contacts (5.12) of the rigid bodies present in the step (with their motion over it), the
dofs a held phase keeps still, the cone of each stress point's material (density and cone
those of the element's region, :func:`element_regions`: the drawn polygon that holds it),
and the scales of the conic problem.
"""
import numpy as np

from ..materials import RegionCones
from ..discretisation.static import body_force_vector
from ..discretisation.dynamic import gravity_vector
from ..problems.contact import boundary_nodes, potential_contacts
from ..discretisation.dynamic import dynamic_operators
from ..problems.step_scaling import DynamicScales
from ..scene.loads import load_acceleration
from .remesh import last_declared_region


def element_regions(state, pm):
    """Region of each element, for its density and its cone: the last declared among its
    vertices' regions.

    :meth:`~pfem_skfem.scene.Scene.particles` gives the particles on an edge two regions
    share to the region declared first, so a triangle with a vertex of a later region lies
    on that region's side of the edge and one with all three of the earlier region inside
    it. The elements then hold each region's drawn polygon and weigh the mass its particles
    carry: exactly for a lattice rectangle declared first; declared after its neighbour, a
    rectangle loses the triangles spanning its convex corners (at most h^2/2 each). The
    majority of the vertices (the rule before) gave the first region a half-spacing layer
    of its neighbour, an error of order h (``verification/hydrostatics.py``: a block's
    buoyant weight 20, 10, 5 % too large at h = h_b/5, /10, /20; now within 5e-11); the
    mean of the vertices' densities weighs that layer as much. Density and cone follow one
    rule: with the majority's cones beside either density, some elements of the water's
    cone carry a heavier density, and the still water of that tank moves (0.09-0.26 g dt in
    one step, against 4e-4).
    """
    return last_declared_region(state.region, pm.particle[pm.mesh.t].T)


def contact_set(disc, bodies, search):
    """The potential contacts (5.12) of the bodies present in the step with a boundary node
    within ``search``: (ContactSet or None, scene index of each body in it)."""
    if not bodies:
        return None, []
    _, xb = boundary_nodes(disc)
    near = [(k, shape, d) for k, shape, d in bodies if (shape.gap(xb)[0] <= search).any()]
    if not near:
        return None, []
    contacts = potential_contacts(disc, [s for _, s, _ in near], search,
                                  motions=np.array([d for _, _, d in near]))
    return contacts, [k for k, _, _ in near]


def held_dofs(disc, phase, contacts):
    """Displacement dofs held still in a held phase (none otherwise)."""
    if phase is None or phase.hold is None:
        return np.zeros(0, dtype=int)
    dofs, _ = boundary_nodes(disc)
    if phase.hold == "free_surface" and contacts is not None:
        dofs = dofs[~np.isin(dofs[:, 0], contacts.dofs[:, 0])]
    return np.unique(dofs.ravel())


def step_material(scene, disc, regions):
    """The material of the step: one region's, or each point's
    (:class:`~pfem_skfem.materials.RegionCones`)."""
    materials = [r.material for r in scene.regions]
    if len({repr(m) for m in materials}) == 1:
        return materials[0]
    RegionCones.check(materials)                  # before the step's points are known
    return RegionCones(materials, regions[disc.point_element])


def assemble_operators(scene, disc, regions, theta):
    """B, C, A, D, M of (4.23) and the gravity load (3.42), each element with the density of
    its region in ``regions`` (:func:`element_regions`); one region: its density in the
    constant-density forms, whatever ``regions`` says."""
    if len(scene.regions) == 1:
        rho = scene.regions[0].rho
        f = body_force_vector(disc, rho * np.asarray(scene.gravity))
    else:
        rho = np.array([r.rho for r in scene.regions])[regions]
        f = (gravity_vector(disc, rho, scene.g, np.asarray(scene.gravity) / scene.g)
             if scene.g > 0 else np.zeros(disc.n_u))
    return dynamic_operators(disc, rho, theta, elastic=scene.elastic), f


def step_scales(previous, scene, dt):
    """The scales of the step: the previous step's magnitudes, but not below those of a
    free-fall step. As a body comes to rest the displacement scale would otherwise shrink
    step by step, the scaled gaps g0 / u_ref of (5.12) grow as much, and Clarabel reports
    'unbounded' (book/dynamics.md, "Scaling"). None before the first step.

    A saturated scene's steps are as long as consolidation asks (c_v dt / h^2 near one:
    minutes to days), and g dt^2 is then millions of times the step's displacement, which
    a solver's tolerance of that unit leaves undetermined. With an elastic skeleton its
    floor is the smaller of g dt^2 and the oedometric settlement of the scene's stress over
    its length, sigma_s L / E_oed, and its first step is scaled by these (not None). A
    rigid-plastic skeleton has no settlement of its own: what moves it in a step is the
    water that Darcy lets out, k dt sigma_s / (gamma_w L) over the length (a gradient of
    the scene's stress over its length); without that floor the column of
    ``tests/test_consolidation_pfem.py`` under a load moved 4e-4-2e-3 of its height a
    step (the solver's 1e-8 of g dt^2 = 2e4 m) and its pore pressure was that noise's.

    Surface loads (:mod:`pfem_skfem.scene.loads`) count as an acceleration q / (rho L) beside
    g: a body pressed still by a load without gravity would otherwise have no floor at all
    (a zero displacement scale, and Clarabel reports 'unbounded' in its second step)."""
    accel = max(scene.g, load_acceleration(scene))  # g without loads
    floor = accel * dt ** 2
    water = scene.water
    if water is not None and (scene.elastic is not None or water.k > 0):
        elastic = scene.elastic
        settlement = (scene.stress_scale * scene.length / (elastic.lame_lambda
                                                           + 2 * elastic.shear_modulus)
                      if elastic is not None else
                      water.k * dt * scene.stress_scale / (water.gamma_w * scene.length))
        floor = min(floor, settlement) if floor > 0 else settlement
        if previous is None:
            return DynamicScales(scene.stress_scale, floor,
                                 max(scene.rho * scene.g, scene.stress_scale / scene.length))
    if previous is None:
        return None
    return DynamicScales(previous.stress, max(previous.displacement, floor),
                         max(previous.dynamic_force, scene.rho * accel))
