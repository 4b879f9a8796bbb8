"""The PFEM loop of thesis Section 2.2 (steps 0-2b): one engine for every scene.

One step from the cloud C^n to C^{n+1}, one call per stage, each timed::

    detect   (1a) alpha-shape of the particles          pfem.alpha_shape.alpha_shape
    remesh   (1b) mesh of the detected domain            pfem.remesh (AlphaMesh, QualityRemesh)
    map      (1c) velocities and stresses onto it        pfem.transfer.map_state
                  (and a softening material's gamma^p    pfem.softening)
    assemble      B, A, D (C), gravity, contacts, holds  pfem.assemble
    solve    (2a) (4.23) + (5.12), fixed-point passes    problems.nonassociated.lagged_step
    move     (2b) particles moved, surface kept, outlets pfem.surface, pfem.bookkeeping

The problem is a :class:`~pfem_skfem.scene.Scene` (regions, rigid bodies and their
motions, outlets, phases, gravity, the geometry: plane strain or axisymmetry);
:class:`PFEMConfig` holds the numerical choices. In axisymmetry (thesis Ch 7) every
mesh is discretised with the 2 pi r weight, u_r = 0 on the axis, the area of the
records is the volume of revolution and the mean-stress lag is the material's.
:func:`pfem_step` does not change its input: it returns the new state, the step's
record and what output needs of the step (:class:`StepResult`).
"""
from contextlib import contextmanager
from dataclasses import asdict, dataclass, fields, is_dataclass, replace
import time as _time

import numpy as np
from skfem import MeshTri

from ..discretisation.fields import plastic_strain_increment
from ..io import step_fields
from ..discretisation.geometry import as_geometry
from ..discretisation.static import axis_dofs, discretise
from ..pfem import adaptive_alpha, alpha_shape, thin_cloud
from ..pfem.alpha_shape import measure
from ..pfem.assemble import (assemble_operators, contact_set, element_regions, held_dofs,
                             step_material, step_scales)
from ..pfem.bookkeeping import (StepFacts, discharge, free_flight_record, hand_on_mass,
                               spread_mass, step_record)
from ..pfem.pore import carried, pore_pressure_term
from ..pfem import softening
from ..pfem.remesh import ParticleMesh
from ..pfem.state import PFEMState, save_checkpoint
from ..pfem.surface import fly_free, move_particles, particle_tags
from ..pfem.transfer import adopt_added_nodes, map_state, old_discretisation
from ..pfem.volume_projection import step_constraint
from ..problems.contact import without_nodes
from ..problems.nonassociated import lagged_step, StepStart
from ..scene.bodies import check_motion_over
from ..scene.loads import check_ramp_over, surface_loads

__all__ = ["StepResult", "pfem_step", "run", "run_to_rest", "check_run", "config_summary"]


@dataclass
class StepResult:
    """What output needs of a step besides the state: its mesh, solution and fields.

    Attributes
    ----------
    disc : the step's Discretisation;  pm : its ParticleMesh (particle of each vertex);
    increment : the DynamicIncrement;  plastic_strain : (n_points,) equivalent plastic
    strain increment;  contacts : the ContactSet (None without contacts);  sigma_m :
    (n_vertices,) smoothed mean stress of the solution at the mesh's vertices;
    pore_pressure, excess_pore_pressure : (n_vertices,) p at t_{n+1} and p less the
    hydrostatic (None without water).
    strength : (n_points,) a softening material's strength c(gamma^p) the step used (None
    without one).
    """

    disc: object
    pm: ParticleMesh
    increment: object
    plastic_strain: np.ndarray
    contacts: object = None
    sigma_m: np.ndarray = None
    pore_pressure: np.ndarray = None
    excess_pore_pressure: np.ndarray = None
    strength: np.ndarray = None


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


# -- the step ------------------------------------------------------------------------------
def detect_domain(state, alpha, alpha_advected=0.0):
    """The domain of the particles as a step detects it: their alpha-shape, which with
    ``alpha_advected`` > 0 (:class:`PFEMConfig`) also reads the state's mesh moved to
    t_n (None before the first step)."""
    advected = None if state.mesh_p is None else (state.mesh_p, state.mesh_t)
    return alpha_shape(state.x, state.h, alpha, advected=advected,
                       alpha_advected=alpha_advected)


def kept_area(state, scene, area0, meshed):
    """The area (volume in axisymmetry) the moved domain is to have with
    ``config.keep_area``: the first detected one, less the volume m / rho of the
    particles outside the step's mesh (``meshed``: (n,) bool; a splash's drops fly free)
    and times the fraction of the scene's mass still inside; None without it.

    Why the drops: the domain holds the particles of the mesh only; asking it for its
    first area while some of its water flies free would inflate the rest by the drops'
    volume and lift its surface."""
    if not scene.config.keep_area:
        return None
    rho = np.array([r.rho for r in scene.regions], dtype=float)
    flying = float(np.sum(state.mass[~meshed] / rho[state.region[~meshed]]))
    gone = sum(float(m) for m, _ in state.discharged.values())
    inside = 1.0 - gone / (state.total_mass + gone) if gone else 1.0
    return area0 * inside - flying


def pfem_step(state, scene):
    """One PFEM step C^n -> C^{n+1} (Section 2.2) of ``scene``.

    Returns (new state, step record, :class:`StepResult`). The input state is not changed.
    A step whose particles form no element (after the first) moves them all as free
    particles and returns None for the StepResult; a step that discharges every particle
    returns an empty state, which cannot be stepped.
    """
    if state.n == 0:
        raise ValueError(f"the state has no particle left (all discharged by t = "
                         f"{state.time:.6g}): there is nothing to step")
    config = scene.config
    theta = config.theta
    geometry = as_geometry(scene.geometry)
    timer = StageTimer()
    t_start = _time.perf_counter()
    h_median = float(np.median(state.h))
    stress_scale = scene.stress_scale
    softens = any(r.material.softening for r in scene.regions)
    remesh_now = (state.mesh_p is None or state.step % int(config.remesh_interval) == 0
                  or np.any(state.mesh_particle < 0))    # a vertex's particle has left
    alpha = scene.alpha if not np.isfinite(state.alpha) else state.alpha
    area0 = state.area0
    thinned = 0
    if remesh_now:
        with timer("detect"):
            if config.remesher.thin_fraction > 0:        # keep the spacing near h
                surface = state.free_surface if config.remesher.keep_surface else None
                keep = thin_cloud(state.x, state.h, fraction=config.remesher.thin_fraction,
                                  prefer=surface)
                if not keep.all():
                    state = hand_on_mass(state, keep, stay=surface)
                    thinned = int((~keep).sum())
            shape = detect_domain(state, alpha, config.alpha_advected)
        if len(shape.triangles) == 0 and state.step > 0:  # the last few of a discharge
            return free_flight(state, scene, timer, t_start, alpha, thinned)
        with timer("detect"):
            area = (float(measure(shape.points, shape.triangles, True).sum())
                    if geometry.axisymmetric else shape.area)       # the volume, 2 pi r dA
            area0 = area if not np.isfinite(area0) else area0
            if scene.adaptive_alpha:                     # alpha_n = m0 alpha_0 / m_n (Ch 8)
                alpha = float(np.clip(adaptive_alpha(scene.alpha, area0, area),
                                      0.8 * scene.alpha, 1.5 * scene.alpha))
        with timer("remesh"):
            pm = config.remesher(shape)
            source = old_discretisation(state, geometry)
            n_before = state.n
            state, pm = adopt_added_nodes(state, pm, source)
            added = state.n - n_before
            if config.spread_mass:               # the masses follow the mesh's areas
                state = spread_mass(state, pm, geometry.axisymmetric)
            disc = discretise(pm.mesh, geometry)
        with timer("map"):
            v_dofs, sigma_n = map_state(state, pm, disc, source, config.stress_mapping,
                                        config.velocity)
            gamma_n = (softening.carried_strain(state, disc, source, config.stress_mapping)
                       if softens else None)
    else:
        added = 0
        with timer("remesh"):
            mesh = MeshTri(np.ascontiguousarray(state.x[state.mesh_particle].T),
                           np.ascontiguousarray(state.mesh_t.T), sort_t=False)
            pm = ParticleMesh(mesh, state.mesh_particle)
            disc = discretise(mesh, geometry)
            area = disc.area
        v_dofs, sigma_n = state.v_dofs, state.sigma
        gamma_n = softening.carried_strain(state, disc, False, None) if softens else None
    with timer("assemble"):
        regions = element_regions(state, pm)
        ops, f = assemble_operators(scene, disc, regions, theta)
        if scene.loads:                              # the surface loads on this mesh
            f_loads, load_resultants = surface_loads(scene, disc, state.time, theta)
            f = f + f_loads
        bodies = scene.bodies_at(state.time, theta.dt)
        contacts, contact_bodies = contact_set(disc, bodies, config.search * h_median)
        phase = scene.phase_at(state.time)
        fixed = held_dofs(disc, phase, contacts)
        if contacts is not None and fixed.size:      # a held node is a support
            contacts = without_nodes(contacts, fixed)
        if geometry.axisymmetric:                    # u_r = 0 on the axis r = 0
            fixed = np.union1d(fixed, axis_dofs(disc))
        material = step_material(scene, disc, regions)
        pore = pore_pressure_term(scene, disc, pm, state, contacts, regions)   # None: dry
        if softens:                                  # the strength at the carried gamma^p
            softening_material, material = material, softening.step_material(
                material, gamma_n, disc)
    with timer("solve"):
        scales = step_scales(state.scales, scene, theta.dt)
        start = StepStart(v_dofs, sigma_n, state.sigma_m[pm.particle], scales)
        solved = lagged_step(ops, f, contacts, disc, material, start, config=config,
                             stress_scale=stress_scale, fixed=fixed,
                             terms=() if pore is None else (pore,))
    inc = solved.increment
    p_start = None if pore is None else state.pore_pressure[pm.particle]
    state, p_vertices = carried(state, pm, inc)        # the particles' p at t_{n+1}
    gamma_p = drop = None
    if softens:                                      # gamma^p after the step (lags one step)
        gamma_p, drop = softening.strain_update(softening_material, ops, inc, sigma_n, disc,
                                                gamma_n)
    with timer("move"):
        bodies_next = [b.at(state.time + theta.dt) for b in scene.bodies
                       if b.present(state.time)]
        holding = phase is not None and phase.hold is not None
        volume = None
        if config.volume_correction:        # held and axis dofs stay, pressed nodes slide
            meshed = np.zeros(state.n, dtype=bool)
            meshed[pm.particle] = True
            volume = step_constraint(disc, fixed=fixed, contacts=contacts,
                                     pressed=None if contacts is None else
                                     inc.p > 1e-6 * stress_scale / scene.length * h_median ** 2,
                                     volume=kept_area(state, scene, area0, meshed),
                                     growth_limit=config.keep_area_step)
        moved, projected, shift = move_particles(
            state, pm, disc, inc, solved.sigma_m, theta=theta, gravity=scene.gravity,
            bodies=bodies_next, refine=(config.refine_surface, config.refine_interior),
            bulge=config.bulge and not holding,     # a held boundary keeps its place exactly
            volume=volume)
        deps = plastic_strain_increment(disc, ops.B, inc.du)
        free_surface, contact = particle_tags(disc, pm, contacts, inc, moved.n,
                                              stress_scale / scene.length * h_median ** 2)
        # the mesh moved with its vertices (straight sides), for the next map
        new = replace(moved, step=state.step + 1, time=state.time + theta.dt,
                      free_surface=free_surface, contact=contact,
                      mesh_p=moved.x[pm.particle], mesh_t=disc.mesh.t.T.copy(),
                      mesh_particle=pm.particle.copy(), v_dofs=inc.v.copy(),
                      sigma=inc.sigma.copy(), scales=inc.scales, area0=area0, alpha=alpha,
                      gamma_p=gamma_p)
        surface = moved.n - state.n                  # midside nodes of stretched edges
        new, out_now = discharge(new, scene.outlets)
    result = StepResult(disc, pm, inc, deps, contacts, solved.sigma_m,
                        strength=material.strength() if softens else None)
    if p_vertices is not None:                      # at the vertices moved to t_{n+1}
        result.pore_pressure = p_vertices
        result.excess_pore_pressure = p_vertices - scene.water.hydrostatic(new.mesh_p)
    facts = StepFacts(result=result, ops=ops, solved=solved, contact_bodies=contact_bodies,
                      regions=regions, v_start=v_dofs, area=area, area0=area0, alpha=alpha,
                      phase=phase, projected=projected, added=added, surface=surface,
                      thinned=thinned, held=len(fixed), discharged_now=out_now, shift=shift)
    record = step_record(scene, new, facts, timer, t_start)
    if scene.loads:                  # each load's resultant in the step (theta-weighted)
        record["loads"] = load_resultants
    if p_vertices is not None:       # consolidating: not at rest while p still changes
        record["pore_pressure_max"] = float(np.abs(p_vertices).max())
        record["pore_pressure_rate_max"] = float(np.abs(p_vertices - p_start).max() / theta.dt)
    if softens:                    # the step control's measure and the largest gamma^p
        record["softening_drop"], record["gamma_p_max"] = drop, float(gamma_p.max())
    return new, record, result


def free_flight(state, scene, timer, t_start, alpha, thinned):
    """The step of a cloud that forms no element: every particle flies free (gravity and
    friction on the bodies), then the outlets; (new state, record, None)."""
    theta = scene.config.theta
    phase = scene.phase_at(state.time)
    with timer("move"):
        bodies_next = [b.at(state.time + theta.dt) for b in scene.bodies
                       if b.present(state.time)]
        moved, projected = fly_free(state, theta=theta, gravity=scene.gravity,
                                    bodies=bodies_next,
                                    axisymmetric=as_geometry(scene.geometry).axisymmetric)
        moved_over_h = (np.linalg.norm(moved.x - state.x, axis=1).max()
                        / np.median(state.h))
        n = moved.n
        new = replace(moved, step=state.step + 1, time=state.time + theta.dt,
                      free_surface=np.ones(n, dtype=bool), contact=np.zeros(n, dtype=bool),
                      mesh_p=None, mesh_t=None, mesh_particle=None, v_dofs=None, sigma=None,
                      stress0=None, alpha=alpha, gamma_p=None)
        new, out_now = discharge(new, scene.outlets)
    record = free_flight_record(scene, new, timer, t_start, alpha=alpha, projected=projected,
                                moved_over_h=moved_over_h, thinned=thinned, phase=phase,
                                discharged_now=out_now, start=state)
    if scene.loads:                  # no mesh, no surface: no load
        record["loads"] = {load.name: [0.0, 0.0] for load in scene.loads}
    return new, record, None


# -- runs ----------------------------------------------------------------------------------
def run(state, scene, steps, *, checkpoint=None, checkpoint_every=0, series=None,
        save_every=1, on_step=None, verbose=False, snapshots=(), progress=None):
    """Advance ``state`` of ``scene`` by ``steps`` PFEM steps.

    Parameters
    ----------
    state : PFEMState (from ``scene.initial_state()`` or
        :func:`~pfem_skfem.pfem.state.load_checkpoint`).
    scene : the :class:`~pfem_skfem.scene.Scene`.
    steps : number of steps to take, an int >= 0 (0: the input state itself is returned).
    checkpoint : path of the checkpoint file, written every ``checkpoint_every`` steps.
    series : a :class:`pfem_skfem.io.TimeSeries` to write a VTU every ``save_every`` steps.
    on_step : callable(state, record, result) after each step.
    verbose : print one line per step (step, time, area change, iterations, seconds).
    snapshots : step numbers whose particles and fields are kept in the returned dict.
    progress : callable(step, steps, record) after each step (e.g. a progress bar).

    Notes
    -----
    The input state is not changed (the returned one has its own history), and it must be
    a state of ``scene`` (:func:`check_run`), and each prescribed motion finite at every
    step time of the run (ValueError naming the body).
    The run ends early when every particle has been discharged (the state is then empty).
    A step whose particles form no element has no mesh: it writes no VTU and keeps no
    snapshot.

    Returns
    -------
    (state, snaps) with snaps {step: dict(x, points, cells, speed, deps)}.
    """
    steps = check_run(state, scene, steps)
    snaps = {}
    for i in range(steps):
        state, rec, result = pfem_step(state, scene)
        # each state owns its history (new lists, the old state's untouched), complete
        # before any output: a stop in a VTU write leaves the last state's consistent
        history = {k: list(v) for k, v in state.history.items()}
        for k, val in rec.items():
            history.setdefault(k, []).append(val)
        state.history = history                       # state is pfem_step's new object
        if verbose:
            print(f"step {rec['step']:5d}  t = {rec['time']:.4f}  dA = {rec['area_change']:+.3%}"
                  f"  it = {rec['iterations']:3d}  elements = {rec['elements']:5d}"
                  f"  |v|max = {rec['max_speed']:.3g}  {rec['seconds']:.2f} s", flush=True)
        meshed = result is not None
        if series is not None and meshed and save_every and state.step % save_every == 0:
            series.write(state.time, *step_fields(state, result))
        if state.step in snapshots and meshed:
            pts, cells, pd, cd = step_fields(state, result)
            snaps[state.step] = {"x": state.x.copy(), "points": pts, "cells": cells,
                                 "speed": pd["speed"], "deps": cd["plastic_strain_increment"]}
        if checkpoint is not None and checkpoint_every and state.step % checkpoint_every == 0:
            save_checkpoint(checkpoint, state)
        if on_step is not None:
            on_step(state, rec, result)
        if progress is not None:
            progress(i + 1, steps, rec)
        if state.n == 0:                               # all discharged
            break
    return state, snaps


def check_run(state, scene, steps):
    """The number of steps of :func:`run` as an int, after checking that ``steps`` is a
    non-negative int (TypeError, ValueError naming it) and that ``state`` can be a state
    of ``scene`` (ValueError): its region indices are the scene's and its mass (with what
    has been discharged) is the scene's mass (to 1e-6), so a state of another scene
    (a resumed checkpoint, a branched study) is refused before any step; so is a body's
    prescribed motion that fails or is not finite at a step time of the run
    (:func:`~pfem_skfem.scene.bodies.check_motion_over`: the scene checks t_end, or its
    first 1000 steps, and a run may go past both)."""
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)):
        raise TypeError(f"steps must be a non-negative int, got {steps!r}")
    if steps < 0:
        raise ValueError(f"steps must be >= 0, got {steps!r}")
    if not isinstance(state, PFEMState):
        raise TypeError(f"state must be a PFEMState (scene.initial_state() or "
                        f"load_checkpoint()), got {type(state).__name__}")
    if not hasattr(scene, "regions") or not hasattr(scene, "config"):
        raise TypeError(f"scene must be a Scene, got {type(scene).__name__}")
    n_regions = len(scene.regions)
    if state.n and (state.region.min() < 0 or state.region.max() >= n_regions):
        raise ValueError(f"the state does not belong to the scene: its particles name region "
                         f"{int(state.region.max())}, the scene has {n_regions} region(s)")
    expected = scene.mass
    held = state.total_mass + sum(float(m) for m, _ in state.discharged.values())
    if state.total_mass > 0 and not abs(held - expected) <= 1e-6 * expected:
        raise ValueError(f"the state does not belong to the scene: it holds mass {held:.6g} "
                         f"(with the discharged), the scene's regions {expected:.6g}")
    for body in scene.bodies:       # the scene checked to t_end, or its first 1000 steps
        check_motion_over(body, scene.config.dt, start=state.time, first=state.step,
                          steps=int(steps))
    for load in scene.loads:        # a ramp, likewise
        check_ramp_over(load, scene.config.dt, start=state.time, steps=int(steps))
    return int(steps)


def run_to_rest(state, scene, speed, max_steps, **options):
    """Advance ``state`` one step at a time until every particle is slower than ``speed``,
    for at most ``max_steps`` steps (``options`` go to :func:`run`); an empty cloud (all
    discharged) is at rest.

    Returns (state, at_rest, steps taken).
    """
    at_rest = lambda st: bool(st.n == 0 or np.max(np.linalg.norm(st.v, axis=1)) < speed)  # noqa
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
    return {f.name: _plain(getattr(scene, f.name)) for f in fields(scene)
            if f.name != "max_particles"                 # a guard, not the problem
            and not (f.name == "water" and scene.water is None)}    # as before it
