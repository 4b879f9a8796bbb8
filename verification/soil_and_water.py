"""Soil beside water: a clay block sliding into a tank, and the dam break's granular twin.

Beyond the thesis (issue 39, item 6). Two scenes of the PFEM engine:

* **Block into a tank** (two materials in one step, :class:`~pfem_skfem.materials.RegionCones`,
  as Zhang et al. (2019, CMAME) put soil and water in one Lagrangian conic formulation): a
  block of undrained clay (:class:`~pfem_skfem.materials.CohesiveTresca`, a total-stress
  material, rigid-plastic, density rho_c) slides down a slope of angle beta (friction
  mu_slope) into a tank of inviscid water (:class:`~pfem_skfem.materials.NewtonianFluid`,
  mu = 0, density rho_w), depth d, length L, closed by a wall; the water's surface is
  recorded at two gauges. The alpha shape closes the gaps of the broken surface at every
  remeshing (air a splash and the breaking wave trap) and the domain gains area no particle
  carries: 13 % by t = 1.8 s at the quick size, 21 % for a block of water (measured
  without thinning). ``--keep-area on`` (the default, ``PFEMConfig.keep_area``) gives each
  step's gain back at the next (:func:`~pfem_skfem.pfem.volume_projection.area_growth`).
  ``--thin 0.4`` (the default, ``AlphaMesh(thin)``) thins particles crowded closer than
  0.4 h at each remeshing: without it the added surface particles pile into the tank's
  corners, whose massless slivers the step may give any speed (the full size blew up).
  ``--spread-mass on`` (the default, ``PFEMConfig.spread_mass``) spreads each region's
  mass over its particles by their lumped areas at each remeshing: without it the
  masses pile onto few particles (the water's massless particles on the mesh grow from 0
  to 35 by 3 s at the quick size, 69 at 30 s) and the particles' energy measures
  those piles. ``--alpha-advected 3`` (the default, ``PFEMConfig.alpha_advected``): no
  triangle fills a notch of the previous step's moved surface, where the splash's gaps
  were filled and weighed (at the full size the remeshings then add 1,570 J/m of
  potential energy instead of 4,030, and the particles' energy no longer gains 1,830
  J/m through the splash). ``--refine-interior`` (0, the default: off,
  ``PFEMConfig.refine_interior``) adds the midside nodes of stretched interior edges as
  particles: the cloud, which thinning coarsens over a long run (the water's particles
  188 to 76 in 30 s at the quick size), stays finer, and the water then keeps more of
  its motion (book: Water and mud). ``--keep-surface on`` (off by default,
  ``AlphaMesh(keep_surface)``) thins the free surface without moving it: the remeshings
  then take an eighth as much area off (book).
* **Granular twin**: the dam-break column of Martin & Moyce (a wide, 2a high, against a
  smooth wall) released twice, alike: once of water (the viscosity of water, a smooth
  floor), once of a dry granular material (:class:`~pfem_skfem.materials.ZeroDilationMohrCoulomb`,
  phi = 30, on a floor of friction tan phi), to T = t sqrt(2g/a) = 4: the difference a
  strength makes, side by side.

No experiment is asserted here beyond conservation (for the water against Martin & Moyce,
``verification/dam_break.py``; for granular columns against Lube et al.,
``verification/granular_column_plane.py``). Checks: each region's mass to round-off (the
particles carry it); the tank's area (its alpha-shape domain) within --tol-area-tank of
its first; the block in the water and at rest there (its centre of mass slower than
--rest-speed sqrt(g d) at some step after it entered); the block's wave at both gauges
(the surface raised by at least h/2); no vertex faster than --tol-speed sqrt(2 g) (a
fall from the slope's top: a faster one is a blow-up) and at most --tol-refused of the
steps' volume projections refused; each twin's area within --tol-area, and the
water's front ahead of the granular one at T = 4; the particles' largest energy gain
between two instants at most --tol-energy of their peak kinetic energy (an inviscid
implicit step only loses energy; the remeshings' exchanges lift it locally: 0.12 at
the quick size, 0.31 at the full, 0.35 at the quick size run to 30 s; with
--alpha-advected 0, 0.19 to 1.6). Recorded, not checked: the mean level
of the flat tank over the second half of the run beside the still level with the block
in (l with L l + l^2 / (2 tan beta) = the first area; the water still sloshes at
--t-end: inviscid, it is damped only numerically; run to 30 s, ``--quick --t-end 30
--steps 1000``, its kinetic energy falls below 1 % of its peak by 22 s as its cloud
coarsens; at the full size it is 1.5 % of its peak over the last 5 s with dt = 0.005 s,
``--t-end 30 --steps 6000``, and 9.5 % with dt = 0.01 s, which moves the fastest water
more than a spacing a step: book, Water and mud), the
block's speed at the end (the reflected wave moves it again), the clay's own area (the
elements all of whose vertices are clay: the clay is declared first, so an element with
vertices of both is water, and the block's area shrinks as the flow strips particles off
it), and the steps whose volume projection was refused (a shift larger than the step's motion:
:func:`~pfem_skfem.pfem.volume_projection.bounded_shift`), and two energies, the
particles' and the step's own (its element masses), with what the remeshings change of
the latter (potential: the alpha shape fills gaps or drops triangles; kinetic: the map
onto the new mesh) and what the steps change (``keep_area``'s growth lifts water), the water's
massless particles on the mesh, the kinetic energy of the particles flying free and the
fastest particle at each step.

Usage::

    python verification/soil_and_water.py --quick --json results/soil_and_water.json   # 1 minute
    python verification/soil_and_water.py --json book/data/soil_and_water.json         # 5 minutes
    python verification/soil_and_water.py --quick --t-end 30 --steps 1000   # 3 minutes
    # (the tank to 30 s; with --json book/data/soil_and_water_30s.json, the book's data)
    python verification/soil_and_water.py --t-end 30 --steps 6000           # 30 minutes
    # (the full size to 30 s: book/data/soil_and_water_full_30s.json)
    python verification/soil_and_water.py --save-every 5        # VTU/PVD of the three scenes
"""
from dataclasses import dataclass, field
import sys
from pathlib import Path

import numpy as np

from pfem_skfem.harness.figures import figure_dir, labelled, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, checkpoint_options, in_range,
                                        material_options, nonnegative_float, opt, pfem_options,
                                        positive_float, positive_int, slope_angle, time_options)
from pfem_skfem.harness.params import UNKEYED, Parameters, keys_of
from pfem_skfem.harness.report import Report, script_main
from pfem_skfem.pfem.measure import (energy_budget, height_at, mesh_energy, particle_energy,
                                     surface_level)

QUICK = dict(nx=8, twin_steps=40, h=0.08, steps=100, t_end=3.0)
CLAY = 0                # the tank scene's regions: (clay, water)
#: the tank's measures printed beside the checks (all in the JSON's extra "tank")
SHOWN = ("edge", "t_stop", "block_speed_at_end", "largest_rise", "level_mean", "level_expected",
         "shift_refused", "step_motion_over_h", "energy_change_end", "energy_largest_rise",
         "mesh_energy_change_end", "mesh_energy_largest_rise", "remeshing_potential",
         "remeshing_kinetic", "steps_energy")

def tank_scene(*, beta, mu_slope, mu_floor, d, L, block, c, rho_w, rho_c, g, h, dt,
               keep_area=True, thin=0.4, spread_mass=False, alpha_advected=0.0,
               refine_interior=0.0, keep_surface=False, keep_area_step=0.0,
               solver="clarabel"):
    """The slope of height 1 (angle beta, friction mu_slope) into a tank of water d deep
    and L long (its floor of friction mu_floor, a smooth wall), a clay block ``block`` =
    (length, thickness) of cohesion c resting on the slope with its lower end 0.1 above
    the water's edge; particles h apart; particles crowded closer than ``thin`` h are
    thinned at each remeshing (``AlphaMesh(thin)``) and, with ``spread_mass``, each
    region's mass is spread over its particles by their lumped areas
    (``PFEMConfig.spread_mass``); ``alpha_advected``, ``refine_interior``: those of
    :class:`~pfem_skfem.scene.config.PFEMConfig`. Returns (state, scene, geometry: the
    slope's foot and the water's edge)."""
    from pfem_skfem.discretisation import ThetaMethod
    from pfem_skfem.materials import CohesiveTresca, NewtonianFluid
    from pfem_skfem.pfem.remesh import AlphaMesh
    from pfem_skfem.problems.contact import CoulombCones, RigidSegment
    from pfem_skfem.scene import Body, Region, Scene
    from pfem_skfem.scene.config import PFEMConfig

    tb = np.radians(beta)
    top, foot = 1.0, 1.0 / np.tan(tb)                       # the slope from (0, 1) to (foot, 0)
    down = np.array([np.cos(tb), -np.sin(tb)])              # down the slope
    out = np.array([np.sin(tb), np.cos(tb)])                # out of it
    edge = foot * (1 - d / top)                             # the water's edge on the slope
    x0 = np.array([0.0, top]) + (edge / np.cos(tb) - 0.1 - block[0]) * down
    corners = (x0, x0 + block[0] * down, x0 + block[0] * down + block[1] * out,
               x0 + block[1] * out)
    water = Region(((edge, d), (foot, 0.0), (foot + L, 0.0), (foot + L, d)),
                   NewtonianFluid(0.0), rho_w, h, name="water")
    clay = Region(tuple(map(tuple, corners)), CohesiveTresca(c), rho_c, h, name="clay")
    far = 10.0
    bodies = (Body("slope", RigidSegment((-far * np.cos(tb), top + far * np.sin(tb)),
                                         (foot, 0.0), mu_slope)),     # solid below
              Body("floor", RigidSegment((foot, 0.0), (foot + L + h, 0.0), mu_floor)),
              Body("wall", RigidSegment((foot + L, -h), (foot + L, far), 0.0)))
    config = PFEMConfig(theta=ThetaMethod(dt, 1.0, 1.0), contact=CoulombCones(), passes=1,
                        solver=solver, volume_correction=True, keep_area=keep_area,
                        keep_area_step=keep_area_step,
                        spread_mass=spread_mass, alpha_advected=alpha_advected,
                        refine_interior=refine_interior,
                        remesher=AlphaMesh(thin=thin, keep_surface=keep_surface))
    # clay first: an element with vertices of both takes the last declared region, water, so
    # the block is its own particles' elements (buoyancy exact, hydrostatics.py) and clay
    # particles the flow strips off do not make clay of the water around them
    scene = Scene(regions=(clay, water), bodies=bodies, gravity=(0.0, -g), alpha=1.6,
                  length=top, config=config)
    return scene.initial_state(), scene, dict(foot=foot, edge=edge)


@dataclass(frozen=True)
class Tank(Parameters):
    """The block into the tank, its scene (:func:`tank_scene`, dt = t_end / steps) and its
    checkpoint's keys (all but the solver): the options of the same names (block a list,
    keep_area, spread_mass and keep_surface "on" or "off")."""
    beta: float
    mu_slope: float
    mu_floor: float
    d: float
    L: float
    block: list
    c: float
    rho_w: float
    rho_c: float
    g: float
    h: float
    t_end: float
    steps: int
    keep_area: str
    thin: float
    spread_mass: str
    alpha_advected: float
    refine_interior: float
    keep_surface: str
    keep_area_step: float
    solver: str = field(default="clarabel", metadata=UNKEYED)

    def scene(self):
        """(state, scene, geometry) of :func:`tank_scene`."""
        on = {k: getattr(self, k) == "on" for k in ("keep_area", "spread_mass", "keep_surface")}
        return tank_scene(**keys_of(self, omit=("t_end", "steps"), block=tuple(self.block),
                                    dt=self.t_end / self.steps, solver=self.solver, **on))


@dataclass(frozen=True)
class Twins(Parameters):
    """The dam-break twins, water and sand (friction angle phi), each a column a wide, 2a
    high, nx particles across against a smooth wall, to T = t sqrt(2g/a) = 4 in twin_steps:
    their scenes and their checkpoints' keys (all but the solver)."""
    rho: float
    a: float
    nx: int
    phi: float
    g: float
    twin_steps: int
    solver: str = field(default="clarabel", metadata=UNKEYED)

    def scene(self, name="granular"):
        """(state, scene) of the twin ``name``: 'water' on a smooth floor, or 'granular' on
        a floor of friction tan phi."""
        from pfem_skfem.materials import NewtonianFluid, ZeroDilationMohrCoulomb
        from pfem_skfem.scene import Geostatic, column_scene

        a, water = self.a, name == "water"
        material = NewtonianFluid(1e-3) if water else ZeroDilationMohrCoulomb(phi=self.phi)
        return column_scene(material, a, 2 * a, a / (self.nx - 1), rho=self.rho, g=self.g,
                            dt=4.0 * np.sqrt(a / (2 * self.g)) / self.twin_steps,
                            stress=Geostatic(), far=50 * a, passes=2, solver=self.solver,
                            floor_friction=0.0 if water else np.tan(np.radians(self.phi)),
                            volume_correction=True)


def tank_level(area, L, beta):
    """The level l of a still surface over the tank holding ``area``: the area below l
    between the slope (angle beta, its foot at y = 0) and the wall L beyond the foot is
    L l + l^2 / (2 tan beta)."""
    k = 1.0 / (2.0 * np.tan(np.radians(beta)))
    return (-L + np.sqrt(L * L + 4 * k * area)) / (2 * k)


def run_tank(args, out):
    """The block into the tank to --t-end (checkpointed in --checkpoint-dir, and resumed from
    there): the last state, and the series at each step with what they measure: the books,
    the levels, the block's rest, the energies (:func:`~pfem_skfem.pfem.measure.energy_budget`)."""
    from pfem_skfem.drivers.resumable import Bar, Checkpoints, Frames, ResumableRun

    params = Tank.of(args)
    state0, scene, geo = params.scene()
    gauges = geo["foot"] + np.array([0.25, 0.75]) * args.L
    span = (geo["foot"] + args.h, geo["foot"] + args.L - args.h)      # the flat tank
    first = {"t": [0.0], "block_x": [float(state0.x[state0.region == CLAY, 0].mean())],
              "block_speed": [0.0], "gauges": [[args.d, args.d]], "level": [args.d],
              "energy": [particle_energy(state0, scene.gravity)], "mesh_energy": [],
              "water_massless": [0], "flying_energy": [0.0], "fastest": [0.0],
              "water_particles": [int(np.sum(state0.region != CLAY))]}
    run = ResumableRun.open(
        scene, state0, first,
        checkpoints=Checkpoints(directory=args.checkpoint_dir, label="block_into_tank",
                                keys=params.keys(), every=args.checkpoint_every),
        frames=Frames(directory=out / "block_into_tank", name="block_into_tank",
                      every=args.save_every),
        bar=Bar(total=args.steps, desc="block_into_tank", verbose=args.progress))

    def measure(run, more):
        state, record, result, series = run.state, run.record, run.result, run.kept
        clay = state.region == CLAY
        meshed = np.zeros(state.n, dtype=bool)         # not the drops flying free of the mesh
        meshed[state.mesh_particle[state.mesh_particle >= 0]] = True
        water = ~clay & meshed
        series["t"].append(state.time)
        series["block_x"].append(float(state.x[clay, 0].mean()))
        series["block_speed"].append(float(np.linalg.norm(
            state.mass[clay] @ state.v[clay] / state.mass[clay].sum())))
        series["gauges"].append([height_at(state, xg, water, default=np.nan) for xg in gauges])
        series["level"].append(surface_level(state.x, water, args.h, *span))
        series["energy"].append(particle_energy(state, scene.gravity))
        series["mesh_energy"].append(mesh_energy(state, scene, record, result))
        # the water's particles on the mesh without mass (piled onto others: spread_mass)
        series["water_massless"].append(int(np.sum(water & (state.mass == 0))))
        series["water_particles"].append(int(np.sum(~clay)))
        # the kinetic energy of the particles flying free of the mesh, the fastest particle
        series["flying_energy"].append(0.5 * float(state.mass[~meshed] @ np.sum(
            state.v[~meshed] ** 2, axis=1)))
        series["fastest"].append(float(np.linalg.norm(state.v, axis=1).max()))

    run.advance(lambda run: run.state.step >= args.steps or run.state.n == 0, measure)
    state, series = run.state, {k: np.asarray(v) for k, v in run.kept.items()}
    books = region_books(scene, state0, state.history)
    first_area = float(state.history["area"][0])
    stop = np.flatnonzero((series["block_x"] > geo["edge"])
                          & (series["block_speed"] < args.rest_speed * np.sqrt(args.g * args.d)))
    return state, {
        **series, "gauges_x": gauges, "edge": geo["edge"], "foot": geo["foot"], "books": books,
        "first_area": first_area, "level_expected": tank_level(first_area, args.L, args.beta),
        "level_mean": float(np.nanmean(series["level"][series["t"] >= 0.5 * args.t_end])),
        "level_without_block": tank_level(first_area - books["clay"]["area_first"], args.L,
                                          args.beta),
        "largest_rise": np.nanmax(series["gauges"], axis=0) - args.d,
        "t_stop": float(series["t"][stop[0]]) if stop.size else np.nan,
        "block_speed_at_end": float(series["block_speed"][-1]),
        # steps whose volume projection failed (bounded_shift): kept unshifted, counted
        "shift_refused": int(np.sum(state.history["volume_shift_refused"])),
        # the fastest particle's motion in a step (the 99th percentile over the run), in h:
        # a long run needs it below about a half (book: Water and mud, the time step)
        "step_motion_over_h": float(np.percentile(series["fastest"], 99) * args.t_end
                                    / args.steps / args.h),
        **energy_budget(series["energy"], series["mesh_energy"]),           # J/m
        # the particles at the end, for a picture (mm)
        "x_end": np.round(state.x, 3), "clay_end": state.region == CLAY}


def region_books(scene, state0, history):
    """Per region: largest relative change of its mass over the run (the step records'
    ``history``), and of its area (the elements of its region, against the first step's:
    the lattice does not fill a slanted polygon's edges); 'all': the largest change of the
    whole domain's area."""
    from pfem_skfem.pfem.bookkeeping import region_masses

    mass0 = region_masses(scene, state0)
    out = {"all": dict(area=float(np.max(np.abs(history["area_change"]))))}
    for r in scene.regions:
        m = np.array([b[r.name] for b in history["mass_regions"]])
        area = np.array([b[r.name] for b in history["area_regions"]])
        out[r.name] = dict(mass=float(np.max(np.abs(m / mass0[r.name] - 1))),
                           area=float(np.max(np.abs(area / area[0] - 1))),
                           area_first=float(area[0]), area_final=float(area[-1] / area[0] - 1))
    return out


def check(args):
    if args.nx < 4:
        return "--nx must be at least 4 (particles across a column)"
    if args.mu_slope >= np.tan(np.radians(args.beta)):
        return "--mu-slope must be below tan(--beta): the block must slide"
    if args.d >= 1.0:
        return "--d must be below the slope's height 1"
    return None


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    t = p.add_argument_group("the block into the tank")
    t.add_argument("--beta", type=slope_angle, default=30.0, help="slope angle [deg]")
    t.add_argument("--mu-slope", type=nonnegative_float, default=0.2,
                   help="friction coefficient of the slope")
    t.add_argument("--mu-floor", type=nonnegative_float, default=0.0,
                   help="friction coefficient of the tank's floor")
    t.add_argument("--d", type=positive_float, default=0.4,
                   help="water depth [m] (the slope is 1 m high)")
    t.add_argument("--L", type=positive_float, default=2.0,
                   help="tank length beyond the slope's foot [m]")
    t.add_argument("--block", type=positive_float, nargs=2, default=[0.4, 0.2],
                   metavar=("LENGTH", "THICKNESS"), help="clay block [m]")
    material_options(t, units="Pa", c=opt(2000.0, "undrained shear strength of the clay [Pa]"))
    t.add_argument("--rho-w", type=positive_float, default=1000.0, help="water [kg/m3]")
    t.add_argument("--rho-c", type=positive_float, default=1800.0, help="clay [kg/m3]")
    time_options(t, steps=opt(300, "steps to --t-end"), t_end=opt(3.0, "end [s]"))
    pfem_options(t, h=0.04, keep_area="on", thin=0.4, keep_area_step=0.0, keep_surface="off",
                 spread_mass="on",
                 alpha_advected=opt(3.0, why="3: no triangle fills a notch of the moved "
                                             "surface"),
                 refine_interior=0.0)
    t.add_argument("--tol-speed", type=positive_float, default=2.0,
                   help="the fastest vertex of the run at most this x sqrt(2 g) (a fall "
                        "from the slope's top; a splash may focus some energy)")
    t.add_argument("--tol-refused", type=in_range(0, 1), default=0.05,
                   help="at most this fraction of the steps' volume projections refused")
    t.add_argument("--tol-energy", type=positive_float, default=0.5,
                   help="the particles' largest energy gain between two instants, at most this "
                        "x their peak kinetic energy")
    t.add_argument("--rest-speed", type=positive_float, default=0.02,
                   help="the block at rest: its centre of mass slower than this x sqrt(g d)")
    t.add_argument("--tol-area-tank", type=positive_float, default=0.05,
                   help="tolerance of the tank's area change (each remeshing adds some, "
                        "--keep-area gives it back at the next step)")
    w = p.add_argument_group("the granular twin")
    material_options(w, units="Pa",
                     rho=opt(1000.0, why="of both columns (the same: only the strength "
                                         "differs)"),
                     phi=opt(30.0, "the granular twin's friction angle [deg]"))
    w.add_argument("--a", type=positive_float, default=0.05715,
                   help="the twin columns' width [m] (Martin & Moyce's)")
    w.add_argument("--nx", type=positive_int, default=16, help="particles across a twin")
    w.add_argument("--twin-steps", type=positive_int, default=80,
                   help="steps of each twin to T = t sqrt(2g/a) = 4 (the dam break's)")
    material_options(p, units="Pa", g=9.81)
    p.add_argument("--tol-area", type=positive_float, default=0.02,
                   help="tolerance of each twin's area change")
    time_options(p, save_every=opt(0, why="a PVD per scene"))
    checkpoint_options(p, "run")
    return p


def run_twins(args, out):
    """The water column and its granular twin to T = 4: fronts, books, final particles
    (each checkpointed in --checkpoint-dir, and resumed from there)."""
    from pfem_skfem.drivers.resumable import Bar, Checkpoints, Frames, ResumableRun

    t_unit, twins, params = np.sqrt(args.a / (2 * args.g)), {}, Twins.of(args)
    for name in ("water", "granular"):
        s0, sc = params.scene(name)
        label = f"twin_{name}"
        run = ResumableRun.open(
            sc, s0, {"T": [0.0], "Z": [1.0], "speed": [0.0]},
            checkpoints=Checkpoints(directory=args.checkpoint_dir, label=label,
                                    keys=params.keys(), every=args.checkpoint_every),
            frames=Frames(directory=out / label, name=label, every=args.save_every),
            bar=Bar(total=args.twin_steps, desc=label, verbose=args.progress))

        def measure_twin(run, more):
            fronts, state = run.kept, run.state
            fronts["T"].append(state.time / t_unit)
            fronts["Z"].append(float(state.x[:, 0].max() / args.a))
            fronts["speed"].append(float(np.linalg.norm(state.v, axis=1).max()))

        run.advance(lambda run: run.state.step >= args.twin_steps or run.state.n == 0,
                    measure_twin)
        s1, fronts = run.state, run.kept
        twins[name] = dict(fronts, books=region_books(sc, s0, s1.history), points=s1.x.copy())
    return twins


def run(args):
    out = Path(args.outdir) / "soil_and_water"
    state, tank = run_tank(args, out)
    twins = run_twins(args, out)
    report = Report("soil_and_water", args, particles=int(state.n),
                    clay_particles=int(np.sum(state.region == CLAY)))
    books = tank["books"]
    for region in ("water", "clay"):
        report.add_interval(f"tank_{region}_mass_change", books[region]["mass"], 0.0, 1e-12,
                            "the particles carry each region's mass")
    report.add_interval("tank_area_change", books["all"]["area"], 0.0, args.tol_area_tank,
                        "the tank's area (its alpha-shape domain) kept")
    report.add_interval("block_in_water", tank["block_x"][-1] - tank["edge"], 0.0, np.inf,
                        "the block's centre beyond the water's edge [m]")
    report.add_interval("block_stopped", float(np.min(tank["block_speed"][
                            tank["block_x"] > tank["edge"]], initial=np.inf)
                            / np.sqrt(args.g * args.d)), 0.0, args.rest_speed,
                        "the block came to rest in the water: its least speed (of its centre "
                        "of mass) / sqrt(g d)")
    # no particle can outrun a fall from the slope's top (1 m): a faster one is a blow-up
    report.add_interval("fastest_over_free_fall", float(np.max(state.history["max_speed"]))
                        / np.sqrt(2 * args.g * 1.0), 0.0, args.tol_speed,
                        "the fastest vertex of any step against sqrt(2 g) (a fall from the "
                        "slope's top)")
    report.add_interval("projections_refused", tank["shift_refused"] / args.steps, 0.0,
                        args.tol_refused,
                        "the fraction of steps whose volume projection failed (bounded_shift)")
    report.add_interval("wave_at_gauges", float(tank["largest_rise"].min() / args.h), 0.5,
                        np.inf, "the block's wave raised the surface at both gauges, in h")
    gain, peak = tank["energy_largest_gain"], tank["kinetic_peak"]
    report.add_interval("energy_gain_over_peak_kinetic", gain / peak if peak > 0 else np.inf,
                        0.0, args.tol_energy, "the particles' largest energy gain between two "
                        "instants / their peak kinetic energy")
    for name, tw in twins.items():
        report.add_interval(f"{name}_mass_change", tw["books"]["column"]["mass"], 0.0, 1e-12,
                            "the particles carry the column's mass")
        report.add_interval(f"{name}_area_change", tw["books"]["all"]["area"], 0.0,
                            args.tol_area, "the column's area (its alpha-shape domain) kept")
    report.add_interval("water_over_granular_front", twins["water"]["Z"][-1]
                        / twins["granular"]["Z"][-1], 1.0, np.inf,
                        "water (no strength) runs further than phi = 30")
    report.extra = {"tank": tank, "twins": {k: {kk: v[kk] for kk in ("T", "Z", "speed", "books")}
                                            for k, v in twins.items()}}
    report.add_table("the tank", ["measure", "value"],
                     [("block_x at the start, at the end", np.round(tank["block_x"][[0, -1]], 3)),
                      ("clay's own area change at the end", books["clay"]["area_final"]),
                      *((k, tank[k]) for k in SHOWN)])
    report.add_table("the twins at T = 4", ["twin", "front Z"],
                     [(k, tw["Z"][-1]) for k, tw in twins.items()])
    report.data = dict(state=state, tank=tank, twins=twins)
    return report


def figures(args, state, tank, twins):
    """The tank at the end, its surface against time, the twins' fronts and particles."""
    fig, ax = pyplot().subplots(2, 2, figsize=(12, 8))
    ax = ax.ravel()
    clay = state.region == CLAY
    ax[0].plot(state.x[~clay, 0], state.x[~clay, 1], ".", ms=2, label="water")
    ax[0].plot(state.x[clay, 0], state.x[clay, 1], ".", ms=3, color="saddlebrown", label="clay")
    labelled(ax[0], "x [m]", "y [m]", f"block into the tank, t = {args.t_end:g} s"
             ).set_aspect("equal")
    for k, xg in enumerate(tank["gauges_x"]):
        ax[1].plot(tank["t"], tank["gauges"][:, k], lw=0.8, label=f"gauge x = {xg:.2f} m")
    ax[1].plot(tank["t"], tank["level"], "k", label="mean level")
    ax[1].axhline(tank["level_expected"], color="r", ls="--",
                  label="level with the block in (area)")
    ax[1].axhline(args.d, color="grey", ls=":", label="still water before")
    labelled(ax[1], "t [s]", "surface [m]", "the water's surface")
    for name, tw in twins.items():
        ax[2].plot(tw["T"], tw["Z"], label=name)
        ax[3].plot(*(tw["points"] / args.a).T, ".", ms=2, label=name)
    labelled(ax[2], "T = t sqrt(2g/a)", "front Z = z/a", "dam break: water and its granular twin")
    labelled(ax[3], "x / a", "y / a", "the columns at T = 4").set_aspect("equal")
    save_figure(fig, figure_dir(args, "soil_and_water") / "soil_and_water.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
