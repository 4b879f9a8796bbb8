"""The PFEM loop of thesis Section 2.2 (steps 0-2b): one engine for every scene.

One step from the cloud C^n to C^{n+1}, one call per stage, each timed::

    detect   (1a) alpha-shape of the particles          pfem.alpha_shape.alpha_shape
    remesh   (1b) mesh of the detected domain            pfem.remesh (AlphaMesh, QualityRemesh)
    map      (1c) velocities and stresses onto it        pfem.transfer.map_state
    assemble      B, A, D (C), gravity, contacts, holds  operators, problems.contact
    solve    (2a) (4.23) + (5.12), fixed-point passes    problems.nonassociated.lagged_step
    move     (2b) particles moved, surface kept, outlets pfem.surface.move_particles

The problem is a :class:`~pfem_skfem.scene.Scene` (regions, rigid bodies and their
motions, outlets, phases, gravity); :class:`PFEMConfig` holds the numerical choices.
:func:`pfem_step` does not change its input: it returns the new state, the step's
record and what output needs of the step (:class:`StepResult`).
"""
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field, fields, is_dataclass, replace
import time as _time

import numpy as np
from skfem import MeshTri

from ..fields import element_mean, plastic_strain_increment, vertex_dofs
from ..operators import body_force_vector, discretise
from ..operators_dynamic import gravity_vector
from ..pfem import adaptive_alpha, alpha_shape, thin_cloud
from ..pfem.alpha_shape import triangle_areas
from ..pfem.remesh import AlphaMesh, ParticleMesh, QualityRemesh
from ..pfem.state import PFEMState, initial_state, load_checkpoint, save_checkpoint
from ..pfem.surface import move_particles, particle_tags
from ..pfem.transfer import Interpolation, L2Projection, adopt_added_nodes, map_state, \
    old_discretisation
from ..problems.contact import CoulombCones, LaggedFriction, boundary_nodes, \
    potential_contacts, without_nodes
from ..problems.dynamic import BACKENDS, DynamicScales, ThetaMethod, dynamic_operators
from ..problems.nonassociated import lagged_step

__all__ = ["PFEMConfig", "PFEMState", "StepResult", "pfem_step", "run", "run_to_rest",
           "initial_state", "load_checkpoint", "save_checkpoint", "config_summary",
           "step_fields"]

STRESS_MAPPINGS = ("uem_bounded", "uem", "ida", "spr")


@dataclass(frozen=True)
class PFEMConfig:
    """The numerical choices of a PFEM run (the physics is the scene's).

    Attributes
    ----------
    theta : :class:`~pfem_skfem.problems.dynamic.ThetaMethod` (dt, theta1, theta2), held once.
    passes : solves per step when the material or the contact rule is lagged (1: the
        lagged values only).
    contact : contact rule, :class:`~pfem_skfem.problems.contact.CoulombCones` (the
        associated cones of (5.12), the thesis') or
        :class:`~pfem_skfem.problems.contact.LaggedFriction` (no dilation; passes >= 2).
    remesher : :class:`~pfem_skfem.pfem.remesh.AlphaMesh` (the alpha-shape's triangles)
        or :class:`~pfem_skfem.pfem.remesh.QualityRemesh` (Triangle; added nodes become
        particles).
    remesh_interval : remesh every this many steps (between, the mesh moves with the particles).
    stress_mapping : 'uem_bounded', 'uem' (Fig 2.6), 'ida' (2.1)-(2.2) or 'spr'.
    velocity : :class:`~pfem_skfem.pfem.transfer.L2Projection` (no kinetic energy added)
        or :class:`~pfem_skfem.pfem.transfer.Interpolation`.
    search : contact search distance in units of h.
    backend : 'clarabel' (the step assembled directly) or 'cvxpy' (the reference statement).
    bulge : place the boundary particles so that the straight-sided boundary keeps the
        area of the curved P2 one (:func:`~pfem_skfem.pfem.surface.bulge_correction`).
    refine_surface : a boundary edge stretched longer than this many h gets its P2
        midside node as a new particle (0: never).
    """

    theta: ThetaMethod = field(default_factory=lambda: ThetaMethod(0.01, 1.0, 1.0))
    passes: int = 2
    contact: object = field(default_factory=CoulombCones)
    remesher: object = field(default_factory=AlphaMesh)
    remesh_interval: int = 1
    stress_mapping: str = "uem_bounded"
    velocity: object = field(default_factory=L2Projection)
    search: float = 1.0
    backend: str = "clarabel"
    bulge: bool = True
    refine_surface: float = 2.0

    def __post_init__(self):
        if not isinstance(self.theta, ThetaMethod):
            raise ValueError(f"theta must be a ThetaMethod(dt, theta1, theta2), got {self.theta!r}")
        if not isinstance(self.contact, (CoulombCones, LaggedFriction)):
            raise ValueError(f"contact must be CoulombCones() or LaggedFriction(), got "
                             f"{self.contact!r}")
        if int(self.passes) < 1:
            raise ValueError(f"passes must be >= 1, got {self.passes!r}")
        if int(self.passes) < self.contact.passes_needed:
            raise ValueError(f"contact={self.contact!r} needs passes >= "
                             f"{self.contact.passes_needed} (the first pass finds the normal forces)")
        if not isinstance(self.remesher, (AlphaMesh, QualityRemesh)):
            raise ValueError(f"remesher must be AlphaMesh() or QualityRemesh(size), got "
                             f"{self.remesher!r}")
        if int(self.remesh_interval) < 1:
            raise ValueError(f"remesh_interval must be >= 1, got {self.remesh_interval!r}")
        if self.stress_mapping not in STRESS_MAPPINGS:
            raise ValueError(f"stress_mapping must be one of {STRESS_MAPPINGS}, got "
                             f"{self.stress_mapping!r}")
        if not isinstance(self.velocity, (L2Projection, Interpolation)):
            raise ValueError(f"velocity must be L2Projection() or Interpolation(), got "
                             f"{self.velocity!r}")
        if self.backend not in BACKENDS:
            raise ValueError(f"backend must be one of {BACKENDS}, got {self.backend!r}")
        if not (np.isfinite(self.search) and self.search > 0):
            raise ValueError(f"search must be positive, got {self.search!r}")
        if not (self.refine_surface >= 0):
            raise ValueError(f"refine_surface must be >= 0, got {self.refine_surface!r}")

    @property
    def dt(self):
        return self.theta.dt


@dataclass
class StepResult:
    """What output needs of a step besides the state: its mesh, solution and fields.

    Attributes
    ----------
    disc : the step's Discretisation;  pm : its ParticleMesh (particle of each vertex);
    increment : the DynamicIncrement;  plastic_strain : (n_points,) equivalent plastic
    strain increment;  contacts : the ContactSet (None without contacts);  sigma_m :
    (n_vertices,) smoothed mean stress of the solution at the mesh's vertices.
    """

    disc: object
    pm: ParticleMesh
    increment: object
    plastic_strain: np.ndarray
    contacts: object = None
    sigma_m: np.ndarray = None


class StageTimer:
    """Seconds spent in each named stage: ``with timer("detect"): ...``."""

    def __init__(self):
        self.seconds = {}

    @contextmanager
    def __call__(self, name):
        t0 = _time.perf_counter()
        try:
            yield
        finally:
            self.seconds[name] = self.seconds.get(name, 0.0) + _time.perf_counter() - t0


# -- assemble ------------------------------------------------------------------------------
def element_regions(state, pm):
    """Region of each element: that of most of its vertices (the first vertex on a tie)."""
    r = state.region[pm.particle[pm.mesh.t]]                 # (3, m)
    majority = np.where(r[1] == r[2], r[1], r[0])
    return majority


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


class _MultiCone:
    """The step's cone when regions have different materials: one Tresca-type radius per
    stress point from each point's material (materials with a ``radius``)."""

    def __init__(self, materials, point_region):
        self.materials = materials
        self.point_region = point_region

    def cone(self, sigma_m, stress_scale):
        from ..materials import TrescaField
        k = np.empty(len(sigma_m))
        for i, m in enumerate(self.materials):
            mine = self.point_region == i
            k[mine] = m.radius(sigma_m[mine], stress_scale)
        return TrescaField(k)

    def strength_scale(self, sigma_m, stress_scale):
        return float(np.median(self.cone(sigma_m, stress_scale).k)) / 2

    @property
    def lagged(self):
        return any(m.lagged for m in self.materials)


def step_material(scene, disc, regions):
    """The material object of the step (one region's, or a per-point combination)."""
    materials = [r.material for r in scene.regions]
    if len({repr(m) for m in materials}) == 1:
        return materials[0]
    if not all(hasattr(m, "radius") for m in materials):
        raise ValueError("regions of different materials need materials with a radius "
                         "(ZeroDilationMohrCoulomb, CohesiveTresca)")
    return _MultiCone(materials, regions[disc.point_element])


# -- the step ------------------------------------------------------------------------------
def pfem_step(state, scene):
    """One PFEM step C^n -> C^{n+1} (Section 2.2) of ``scene``.

    Returns (new state, step record, :class:`StepResult`). The input state is not changed.
    """
    config = scene.config
    theta = config.theta
    timer = StageTimer()
    t_start = _time.perf_counter()
    h_median = float(np.median(state.h))
    stress_scale = scene.stress_scale
    remesh_now = (state.mesh_p is None or state.step % int(config.remesh_interval) == 0
                  or np.any(state.mesh_particle < 0))    # a vertex's particle has left
    alpha = scene.alpha if not np.isfinite(state.alpha) else state.alpha
    area0 = state.area0
    thinned = 0
    if remesh_now:
        with timer("detect"):
            if config.remesher.thins_cloud:              # keep the spacing near h
                keep = thin_cloud(state.x, state.h, fraction=0.4)
                if not keep.all():
                    state = hand_on_mass(state, keep)
                    thinned = int((~keep).sum())
            shape = alpha_shape(state.x, state.h, alpha)
            area = shape.area
            area0 = area if not np.isfinite(area0) else area0
            if scene.adaptive_alpha:                     # alpha_n = m0 alpha_0 / m_n (Ch 8)
                alpha = float(np.clip(adaptive_alpha(scene.alpha, area0, area),
                                      0.8 * scene.alpha, 1.5 * scene.alpha))
        with timer("remesh"):
            pm = config.remesher(shape)
            source = old_discretisation(state)
            n_before = state.n
            state, pm = adopt_added_nodes(state, pm, source)
            added = state.n - n_before
            disc = discretise(pm.mesh)
        with timer("map"):
            v_dofs, sigma_n = map_state(state, pm, disc, source, config.stress_mapping,
                                        config.velocity)
    else:
        added = 0
        with timer("remesh"):
            mesh = MeshTri(np.ascontiguousarray(state.x[state.mesh_particle].T),
                           np.ascontiguousarray(state.mesh_t.T), sort_t=False)
            pm = ParticleMesh(mesh, state.mesh_particle)
            disc = discretise(mesh)
            area = disc.area
        v_dofs, sigma_n = state.v_dofs, state.sigma
    with timer("assemble"):
        regions = element_regions(state, pm)
        ops, f = assemble_operators(scene, disc, regions, theta)
        bodies = scene.bodies_at(state.time, theta.dt)
        contacts, contact_bodies = contact_set(disc, bodies, config.search * h_median)
        phase = scene.phase_at(state.time)
        fixed = held_dofs(disc, phase, contacts)
        if contacts is not None and fixed.size:      # a held node is a support
            contacts = without_nodes(contacts, fixed)
        material = step_material(scene, disc, regions)
    with timer("solve"):
        scales = step_scales(state.scales, scene, theta.dt)
        solved = lagged_step(ops, f, contacts, disc, material, config.contact, v_dofs,
                             sigma_n, state.sigma_m[pm.particle], scales, passes=config.passes,
                             stress_scale=stress_scale, fixed=fixed, backend=config.backend)
    inc = solved.increment
    with timer("move"):
        bodies_next = [b.at(state.time + theta.dt) for b in scene.bodies
                       if b.present(state.time)]
        holding = phase is not None and phase.hold is not None
        moved, projected = move_particles(
            state, pm, disc, inc, solved.sigma_m, theta=theta, gravity=scene.gravity,
            bodies=bodies_next, refine_surface=config.refine_surface,
            bulge=config.bulge and not holding)     # a held boundary keeps its place exactly
        deps = plastic_strain_increment(disc, ops.B, inc.du)
        free_surface, contact = particle_tags(disc, pm, contacts, inc, moved.n,
                                              stress_scale / scene.length * h_median ** 2)
        # the mesh moved with its vertices (straight sides), for the next map
        new = replace(moved, step=state.step + 1, time=state.time + theta.dt,
                      free_surface=free_surface, contact=contact,
                      mesh_p=moved.x[pm.particle], mesh_t=disc.mesh.t.T.copy(),
                      mesh_particle=pm.particle.copy(), v_dofs=inc.v.copy(),
                      sigma=inc.sigma.copy(), scales=inc.scales, area0=area0, alpha=alpha)
        surface = moved.n - state.n                  # midside nodes of stretched edges
        new, out_now = discharge(new, scene.outlets)
    result = StepResult(disc, pm, inc, deps, contacts, solved.sigma_m)
    record = step_record(scene, new, result, ops, solved, contact_bodies, regions, timer,
                         t_start, area=area, area0=area0, alpha=alpha, projected=projected,
                         added=added, surface=surface, thinned=thinned, phase=phase,
                         held=len(fixed),
                         discharged_now=out_now)
    return new, record, result


def assemble_operators(scene, disc, regions, theta):
    """B, C, A, D, M of (4.23) and the gravity load (3.42), with each element's density."""
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
    'unbounded' (measured: phi = 35, a = 0.5, step 189 of 200). None before the first step."""
    if previous is None:
        return None
    return DynamicScales(previous.stress, max(previous.displacement, scene.g * dt ** 2),
                         max(previous.dynamic_force, scene.rho * scene.g))


def hand_on_mass(state, keep):
    """The state without the particles not kept, each of which hands its mass to the
    nearest kept particle (the material's mass is only ever passed on)."""
    from scipy.spatial import cKDTree
    mass = state.mass.copy()
    gone = np.flatnonzero(~keep)
    kept = np.flatnonzero(keep)
    nearest = kept[cKDTree(state.x[kept]).query(state.x[gone])[1]]
    np.add.at(mass, nearest, mass[gone])
    return replace(state, mass=mass).subset(keep)


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


def region_amounts(scene, state, disc, regions):
    """Mass of the particles of each region, and the area of the elements of each region."""
    area_e = triangle_areas(disc.mesh.p.T, disc.mesh.t.T)
    mass = {r.name: float(state.mass[state.region == k].sum())
            for k, r in enumerate(scene.regions)}
    area = {r.name: float(area_e[regions == k].sum()) for k, r in enumerate(scene.regions)}
    return mass, area


def step_record(scene, new, result, ops, solved, contact_bodies, regions, timer, t_start, *,
                area, area0, alpha, projected, added, surface, thinned, phase, held,
                discharged_now):
    """The step's record for the history: geometry, mass bookkeeping, forces on the
    bodies, energy, solver iterations and status, stage times."""
    disc, pm, inc = result.disc, result.pm, result.increment
    mass_regions, area_regions = region_amounts(scene, new, disc, regions)
    forces, moments = body_loads(scene, result.contacts, contact_bodies, inc,
                                 new.time - scene.config.dt)
    speed = np.linalg.norm(inc.v[vertex_dofs(disc)], axis=1)
    mesh_area = float(triangle_areas(disc.mesh.p.T, disc.mesh.t.T).sum())
    moved_area = float(triangle_areas(new.mesh_p, disc.mesh.t.T).sum())
    return {"step": new.step, "time": new.time, "phase": None if phase is None else phase.name,
            "area": area, "mesh_area": mesh_area, "moved_area": moved_area,
            "area_change": area / area0 - 1, "alpha": alpha,
            "mass": new.total_mass, "mass_regions": mass_regions, "area_regions": area_regions,
            "discharged": {k: v[0] for k, v in new.discharged.items()},
            "discharged_particles": {k: v[1] for k, v in new.discharged.items()},
            "discharged_now": {k: v[1] for k, v in discharged_now.items()},
            "forces": forces, "moments": moments,
            "iterations": solved.iterations, "inaccurate": solved.inaccurate,
            "status": inc.info.status, "elements": int(disc.mesh.nelements),
            "particles": int(new.n), "free_particles": int(new.n - np.sum(new.mesh_particle >= 0)),
            "added": added, "surface_particles": surface, "thinned": thinned, "held_dofs": held, "projected": projected,
            "max_speed": float(speed.max()),
            "kinetic_energy": float(0.5 * inc.v @ (ops.M @ inc.v)),
            "max_plastic_strain_increment": float(result.plastic_strain.max()),
            "seconds": _time.perf_counter() - t_start,
            **{f"t_{k}": v for k, v in timer.seconds.items()},
            "t_compile": solved.compile_time,        # inside t_solve: building the problem
            "t_conic": solved.solve_time}            # inside t_solve: Clarabel itself


# -- output --------------------------------------------------------------------------------
def step_fields(state, result):
    """Points, triangles and fields of a step for VTU output.

    Point data: velocity (3 components, z = 0 for ParaView), speed, smoothed mean stress
    and pressure p = -(sx + sy)/2, the tags free_surface and contact (0/1), region;
    cell data: element mean stress (sx, sy, sxy), equivalent plastic strain increment.
    """
    disc, inc = result.disc, result.increment
    points = state.mesh_p
    mp = state.mesh_particle
    vel = np.zeros((len(points), 3))
    vel[:, :2] = inc.v[vertex_dofs(disc)]               # a discharged vertex: the solution's
    vel[mp >= 0, :2] = state.v[mp[mp >= 0]]             # the particles' (put out of walls)
    sm = result.sigma_m
    tag = lambda a: np.where(mp >= 0, a[np.maximum(mp, 0)], 0).astype(float)  # noqa: E731
    stress = element_mean(disc, inc.sigma)
    point_data = {"velocity": vel, "speed": np.linalg.norm(vel, axis=1),
                  "pressure": -sm, "mean_stress": sm,
                  "free_surface": tag(state.free_surface), "contact": tag(state.contact),
                  "region": tag(state.region)}
    cell_data = {"stress": stress[:, [0, 1, 3]],
                 "plastic_strain_increment": element_mean(disc, result.plastic_strain)}
    return points, disc.mesh.t.T, point_data, cell_data


# -- runs ----------------------------------------------------------------------------------
def run(state, scene, steps, *, checkpoint=None, checkpoint_every=0, series=None,
        save_every=1, on_step=None, verbose=False, snapshots=(), progress=None):
    """Advance ``state`` of ``scene`` by ``steps`` PFEM steps.

    Parameters
    ----------
    state : PFEMState (from ``scene.initial_state()`` or :func:`load_checkpoint`).
    scene : the :class:`~pfem_skfem.scene.Scene`.
    steps : number of steps to take.
    checkpoint : path of the checkpoint file, written every ``checkpoint_every`` steps.
    series : a :class:`pfem_skfem.io.TimeSeries` to write a VTU every ``save_every`` steps.
    on_step : callable(state, record, result) after each step.
    verbose : print one line per step (step, time, area change, iterations, seconds).
    snapshots : step numbers whose particles and fields are kept in the returned dict.
    progress : callable(step, steps, record) after each step (e.g. a progress bar).

    Returns
    -------
    (state, snaps) with snaps {step: dict(x, points, cells, speed, deps)}.
    """
    snaps = {}
    for i in range(int(steps)):
        state, rec, result = pfem_step(state, scene)
        for k, val in rec.items():                     # the history grows by one record
            state.history.setdefault(k, []).append(val)
        if verbose:
            print(f"step {rec['step']:5d}  t = {rec['time']:.4f}  dA = {rec['area_change']:+.3%}"
                  f"  it = {rec['iterations']:3d}  elements = {rec['elements']:5d}"
                  f"  |v|max = {rec['max_speed']:.3g}  {rec['seconds']:.2f} s", flush=True)
        if series is not None and save_every and state.step % save_every == 0:
            series.write(state.time, *step_fields(state, result))
        if state.step in snapshots:
            pts, cells, pd, cd = step_fields(state, result)
            snaps[state.step] = {"x": state.x.copy(), "points": pts, "cells": cells,
                                 "speed": pd["speed"], "deps": cd["plastic_strain_increment"]}
        if checkpoint is not None and checkpoint_every and state.step % checkpoint_every == 0:
            save_checkpoint(checkpoint, state)
        if on_step is not None:
            on_step(state, rec, result)
        if progress is not None:
            progress(i + 1, int(steps), rec)
    return state, snaps


def run_to_rest(state, scene, speed, max_steps, **options):
    """Advance ``state`` one step at a time until every particle is slower than ``speed``,
    for at most ``max_steps`` steps (``options`` go to :func:`run`).

    Returns (state, at_rest, steps taken).
    """
    at_rest = lambda st: bool(np.max(np.linalg.norm(st.v, axis=1)) < speed)   # noqa: E731
    taken = 0
    while not at_rest(state) and taken < max_steps:
        state, _ = run(state, scene, 1, **options)
        taken += 1
    return state, at_rest(state), taken


def _plain(value):
    if is_dataclass(value):
        return {"type": type(value).__name__, **{k: _plain(v) for k, v in asdict(value).items()}}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value if isinstance(value, (int, float, str, bool, type(None), dict)) else repr(value)


def config_summary(scene):
    """The scene as plain JSON-able values (objects by type and fields)."""
    return {f.name: _plain(getattr(scene, f.name)) for f in fields(scene)}
