"""Bookkeeping of a PFEM step: where the material's mass goes, the forces on the bodies,
and the step's record for the history (thesis Ch 8: the mass is watched; 6.4.1: the
force on the cylinder).

A particle's mass is only ever passed on (:func:`hand_on_mass`), spread over its region's
particles (:func:`spread_mass`) or discharged through an outlet (:func:`discharge`), so
the material inside plus the material discharged is the initial mass at every step; the
area of the mesh is reported beside it.
"""
import time as _time

import numpy as np
from dataclasses import dataclass, replace

from ..discretisation.fields import vertex_dofs
from .alpha_shape import measure, triangle_areas


def hand_on_mass(state, keep, stay=None):
    """The state without the particles not kept, each merged into the nearest kept
    particle of its own region (of any region if none of its own is kept): the kept one
    takes the sum of their masses, at their centre of mass, with their momentum. Each
    region's mass, the momentum and the centre of mass (so the potential energy) are
    kept; a merge loses only the kinetic energy of the pair's relative motion.

    stay : None, or (n,) bool: kept particles that take the merged masses and momentum
    where they stand (the free surface of ``AlphaMesh(keep_surface=True)``): the domain's
    boundary does not recede, and the centre of mass moves by the merged masses' offsets.

    Why the centre of mass: handing a removed particle's mass to its neighbour where the
    neighbour stands moves that mass; where particles crowd against a floor the kept
    neighbour stands above, and the mass climbs (the clay block into the tank,
    book/water_and_mud.md)."""
    from scipy.spatial import cKDTree
    into = np.arange(state.n)
    for region in np.unique(state.region[~keep]):
        gone = np.flatnonzero(~keep & (state.region == region))
        kept = np.flatnonzero(keep & (state.region == region))
        if kept.size == 0:
            kept = np.flatnonzero(keep)
        into[gone] = kept[cKDTree(state.x[kept]).query(state.x[gone])[1]]
    mass = np.zeros(state.n)
    np.add.at(mass, into, state.mass)
    moment = np.zeros((state.n, 2))
    np.add.at(moment, into, state.mass[:, None] * state.x)
    momentum = np.zeros((state.n, 2))
    np.add.at(momentum, into, state.mass[:, None] * state.v)
    merged = np.flatnonzero(np.bincount(into, minlength=state.n) > 1)
    merged = merged[mass[merged] > 0]              # massless pairs: the kept one stays
    moved = merged if stay is None else merged[~np.asarray(stay, dtype=bool)[merged]]
    x, v = state.x.copy(), state.v.copy()
    x[moved] = moment[moved] / mass[moved, None]
    v[merged] = momentum[merged] / mass[merged, None]
    return replace(state, mass=mass, x=x, v=v).subset(keep)


def spread_mass(state, pm, axisymmetric=False):
    """The state with each region's mass on the mesh ``pm`` spread over its particles there
    in proportion to their lumped areas (a third of each triangle's area, or volume of
    revolution in axisymmetry, to each vertex): m_i = M_r A_i / sum_{j in r} A_j. The
    particles no triangle holds (drops flying free) keep theirs.

    Each region's mass is kept to round-off; its momentum and centre of mass become those of
    the mesh's lumped masses (the step weighs its elements by density and area, not by the
    particles' masses). Why: thinning merges masses into kept particles and the particles
    made of midside nodes start massless, so over a long run the masses pile up on a few
    particles and the particles' energy no longer measures the material's (the clay block
    into the tank, book/water_and_mud.md).
    """
    p, t = pm.mesh.p.T, pm.mesh.t.T
    lumped = np.zeros(state.n)
    np.add.at(lumped, pm.particle[t].ravel(),
              np.repeat(np.abs(measure(p, t, axisymmetric)) / 3.0, 3))
    meshed = np.zeros(state.n, dtype=bool)
    meshed[pm.particle] = True
    mass = state.mass.copy()
    for region in np.unique(state.region[meshed]):
        mine = meshed & (state.region == region)
        if lumped[mine].sum() > 0:
            mass[mine] = state.mass[mine].sum() * lumped[mine] / lumped[mine].sum()
    return replace(state, mass=mass)


def discharge(state, outlets):
    """Particles inside an outlet's zone leave the cloud; returns the state without them
    and {outlet: [mass, particles]} discharged in this step (added to state.discharged)."""
    totals = {name: list(v) for name, v in state.discharged.items()}
    now = {}
    keep = np.ones(state.n, dtype=bool)
    for outlet in outlets:
        out = keep & outlet.zone.contains(state.x)
        now[outlet.name] = [float(state.mass[out].sum()), int(out.sum())]
        total = totals.setdefault(outlet.name, [0.0, 0])
        total[0] += now[outlet.name][0]
        total[1] += now[outlet.name][1]
        keep &= ~out
    if keep.all():
        return replace(state, discharged=totals), now
    return replace(state.subset(keep), discharged=totals), now


def body_loads(scene, contacts, contact_bodies, inc, t_n):
    """Force (Fx, Fy) and moment about its reference point that the material exerts on
    each body of the scene in the step (per unit length in plane strain; zero if apart)."""
    forces = {b.name: [0.0, 0.0] for b in scene.bodies}
    moments = {b.name: 0.0 for b in scene.bodies}
    if contacts is None:
        return forces, moments
    on_body = -(contacts.normal * inc.p[:, None] + contacts.tangent * inc.q[:, None])
    for j, k in enumerate(contact_bodies):
        mine = contacts.body == j
        body = scene.bodies[k]
        arm = contacts.x[mine] - body.reference_at(t_n)
        F = on_body[mine]
        forces[body.name] = [float(F[:, 0].sum()), float(F[:, 1].sum())]
        moments[body.name] = float(np.sum(arm[:, 0] * F[:, 1] - arm[:, 1] * F[:, 0]))
    return forces, moments


def region_masses(scene, state):
    """Mass of the particles of each region."""
    return {r.name: float(state.mass[state.region == k].sum())
            for k, r in enumerate(scene.regions)}


def region_areas(scene, disc, regions):
    """Area of the elements of each region (:func:`~pfem_skfem.pfem.assemble.element_regions`;
    in axisymmetry their volume of revolution): the area the step weighs with the region's
    density, so a region's mass over its area is its density while its elements hold its
    drawn polygon."""
    if disc.geometry.axisymmetric:
        area_e = measure(disc.mesh.p.T, disc.mesh.t.T, True)
    else:
        area_e = triangle_areas(disc.mesh.p.T, disc.mesh.t.T)
    return {r.name: float(area_e[regions == k].sum()) for k, r in enumerate(scene.regions)}


def books(scene, new, timer, t_start, *, phase, alpha, discharged_now):
    """What every step record holds, meshed or not: time, phase, the mass inside and
    discharged, the particles, the stage times."""
    return {"step": new.step, "time": new.time, "phase": None if phase is None else phase.name,
            "alpha": alpha, "mass": new.total_mass, "mass_regions": region_masses(scene, new),
            "discharged": {k: v[0] for k, v in new.discharged.items()},
            "discharged_particles": {k: v[1] for k, v in new.discharged.items()},
            "discharged_now": {k: v[1] for k, v in discharged_now.items()},
            "particles": int(new.n),
            "seconds": _time.perf_counter() - t_start,
            **{f"t_{k}": v for k, v in timer.seconds.items()}}


@dataclass
class StepFacts:
    """What a meshed PFEM step knows of itself beside its moved state, for its record.

    result : its :class:`~pfem_skfem.drivers.pfem_loop.StepResult`;  ops : its
    DynamicOperators;  solved : its LaggedStep;  contact_bodies, regions : the bodies of its
    contacts and the regions of its particles;  v_start : the velocities the step starts
    from on its mesh (mapped at a remeshing: their kinetic energy, ``start_kinetic_energy``,
    less the previous step's ``kinetic_energy`` is what the remeshing's map added);
    area, area0 : its domain's area and the first step's;  alpha : its alpha;  phase : its
    phase;  projected, added, surface, thinned, held : the particles put back out of
    bodies, added, on the surface, thinned, and the held dofs;  discharged_now : the mass
    its outlets took;  shift : the volume projection's record.
    """

    result: object
    ops: object
    solved: object
    contact_bodies: object
    regions: object
    v_start: np.ndarray
    area: float
    area0: float
    alpha: float
    phase: object
    projected: int
    added: int
    surface: int
    thinned: int
    held: int
    discharged_now: object
    shift: dict


def step_record(scene, new, facts, timer, t_start):
    """The step's record for the history: geometry, mass bookkeeping, forces on the
    bodies, energy, solver iterations and status, stage times (``facts``: a
    :class:`StepFacts`).

    In axisymmetry every 'area' of the record (area, mesh_area, moved_area, area_change,
    area_regions) is a volume, the integral of 2 pi r dA, and the forces are ring forces
    (the z-component the whole body's; the r-component has no resultant).
    """
    f = facts
    result, ops, solved, area, area0 = f.result, f.ops, f.solved, f.area, f.area0
    disc, inc = result.disc, result.increment
    h_median = float(np.median(new.h)) if new.n else np.nan    # nan: all discharged
    area_regions = region_areas(scene, disc, f.regions)
    forces, moments = body_loads(scene, result.contacts, f.contact_bodies, inc,
                                 new.time - scene.config.dt)
    speed = np.linalg.norm(inc.v[vertex_dofs(disc)], axis=1)   # of the step's mesh
    du_max = np.linalg.norm(inc.du[vertex_dofs(disc)], axis=1).max()
    if disc.geometry.axisymmetric:               # volumes of revolution, 2 pi r dA
        mesh_area = float(measure(disc.mesh.p.T, disc.mesh.t.T, True).sum())
        moved_area = float(measure(new.mesh_p, disc.mesh.t.T, True).sum())
    else:
        mesh_area = float(triangle_areas(disc.mesh.p.T, disc.mesh.t.T).sum())
        moved_area = float(triangle_areas(new.mesh_p, disc.mesh.t.T).sum())
    return {"area": area, "mesh_area": mesh_area, "moved_area": moved_area,
            "area_change": area / area0 - 1, "area_regions": area_regions,
            "forces": forces, "moments": moments,
            "iterations": solved.iterations, "inaccurate": solved.inaccurate,
            "passes": solved.passes, "pass_changes": list(solved.changes),
            "status": inc.info.status, "elements": int(disc.mesh.nelements),
            "free_particles": int(new.n - np.sum(new.mesh_particle >= 0)),
            "added": f.added, "surface_particles": f.surface, "thinned": f.thinned,
            "held_dofs": f.held, "projected": f.projected,
            # the volume projection's largest vertex shift / h, and whether it was refused
            "volume_shift_over_h": float(f.shift["volume_shift"] / h_median),
            "volume_shift_refused": bool(f.shift["volume_shift_refused"]),
            "max_speed": float(speed.max()),
            # a step that moves material by many spacings is a collapse within one step
            # (dt too long for the mechanism), however 'optimal' its solve
            "max_displacement_over_h": float(du_max / h_median),
            "kinetic_energy": float(0.5 * inc.v @ (ops.M @ inc.v)),
            "start_kinetic_energy": float(0.5 * f.v_start @ (ops.M @ f.v_start)),
            "max_plastic_strain_increment": float(result.plastic_strain.max()),
            "t_compile": solved.compile_time,        # inside t_solve: building the problem
            "t_conic": solved.solve_time,            # inside t_solve: Clarabel itself
            **books(scene, new, timer, t_start, phase=f.phase, alpha=f.alpha,
                    discharged_now=f.discharged_now)}


def particle_kinetic_energy(state):
    """sum m |v|^2 / 2 of the particles."""
    return float(0.5 * np.sum(state.mass * np.sum(state.v ** 2, axis=1)))


def free_flight_record(scene, new, timer, t_start, *, alpha, projected, moved_over_h,
                       thinned, phase, discharged_now, start):
    """The record of a step in which the particles formed no element (every one flew
    free, :func:`~pfem_skfem.pfem.surface.fly_free`): the keys of :func:`step_record`,
    with no mesh, no solve and no force on the bodies; ``start`` : the state at t_n."""
    speed = np.linalg.norm(new.v, axis=1) if new.n else np.zeros(1)
    return {"area": 0.0, "mesh_area": 0.0, "moved_area": 0.0, "area_change": -1.0,
            "area_regions": {r.name: 0.0 for r in scene.regions},
            "forces": {b.name: [0.0, 0.0] for b in scene.bodies},
            "moments": {b.name: 0.0 for b in scene.bodies},
            "iterations": 0, "inaccurate": 0, "passes": 0, "pass_changes": [],
            "status": "no element: every particle free",
            "elements": 0, "free_particles": int(new.n),
            "added": 0, "surface_particles": 0, "thinned": thinned, "held_dofs": 0,
            "projected": projected, "volume_shift_over_h": 0.0,
            "volume_shift_refused": False, "max_speed": float(speed.max()),
            "max_displacement_over_h": float(moved_over_h),
            "kinetic_energy": particle_kinetic_energy(new),
            "start_kinetic_energy": particle_kinetic_energy(start),
            "max_plastic_strain_increment": 0.0,
            "t_compile": 0.0, "t_conic": 0.0,
            **books(scene, new, timer, t_start, phase=phase, alpha=alpha,
                    discharged_now=discharged_now)}
