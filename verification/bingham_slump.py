"""A Bingham slump: a mud column on a rough floor comes to rest on the yield-stress profile of Nye.

Beyond the thesis. A column of mud (L0 wide, H0 high, against a smooth wall x = 0, the
symmetry plane of a column 2 L0 wide) is released on a rough horizontal floor. Where a
shallow deposit is at rest its basal shear stress rho g h |h'| cannot exceed the yield
stress; a slump that has yielded everywhere on its way stops where it just reaches it,
on the shallow yield-stress profile (Nye 1951; Liu & Mei 1989; Balmforth et al. 2006;
the arrested state of a slow slump: Matson & Hogg 2007)

    h(x) = sqrt(2 tau_y (x_f - x) / (rho g)),   x_f = (3 L0 H0 / (2 sqrt(2 k H0)))^(2/3)

(x_f from the area L0 H0 kept), k = tau_y / (rho g H0). The profile is the leading order
in the deposit's aspect ratio eps = h(0) / x_f: the longitudinal stresses it neglects make
a two-dimensional plastic deposit stronger, hence steeper and shorter, by a relative amount
that vanishes with eps (Dubash, Balmforth, Slim & Cochard 2009).

Materials and set-ups (measured, see the book page):

* mud, :class:`~pfem_skfem.materials.BinghamFluid` (tau_y, plastic viscosity --mu): a slow,
  viscous slump (Reynolds number rho sqrt(g H0) H0 / mu about 10 at mu = 10 Pa s) from rest
  to rest, the time step growing as the flow slows (each step moves a particle at most
  --cfl spacings), at rest when every particle is slower than --rest sqrt(g H0). A fast
  slump (mu = 1 Pa s) overshoots: its kinetic energy carries it past the profile, flatter;
* the rigid-plastic :class:`~pfem_skfem.materials.CohesiveTresca` (c = tau_y) has no
  viscosity to slow it: released dynamically it is inertial at any small k and runs far
  past the profile (x_f 1.7 times Nye's at k = 0.02). It is brought down quasi-statically:
  every step starts from rest (the velocities set to zero), so that a step moves the
  deposit only while gravity exceeds what the yield stress can hold, and the deposit is at
  rest when the acceleration of a step from rest is below --rest-a g.

The particle spacing is Nye's height at the wall over --n-h, so that every k has the same
resolution of the deposit; alpha_advected keeps the thinning corner by the wall (without
it 3.5 % of the area was cut off at k = 0.01).

Checks, for each material and each k of --k: at rest; the mean relative excess of the
height over h(x) (x_f the deposit's own front) in the middle, 0.2 x_f < x < 0.8 x_f, in
[0, --tol sqrt(eps)]: a deposit not flatter than Nye's, within a tolerance that shrinks as
h/L does (measured 0.67-0.76 sqrt(eps) for eps = 0.064-0.16: the excess shrinks as
eps^0.44 (Tresca) to eps^0.63 (mud), more slowly than the first-order O(eps) the
longitudinal stresses suggest); the front in [1 - sqrt(eps), 1] of Nye's x_f; the mass to
round-off and the area within 2 %. For each material, the excess at the smallest eps below
that at the largest where the two are a factor TREND = 2 apart (--quick's two k are not:
their excesses differ by less than the discretisation's spread, +-0.04 at n_h = 3.5-5).
The full run adds the studies at --study-k (Tresca): the mesh (n_h x 1.4) and the step
(cfl / 2) change the excess by less than half of it (a deviation from Nye, not from the
discretisation); the fast mud and the dynamic Tresca slump run farther than the slow ones.

How much gravity a heap can carry, as a rigid-plastic Tresca body (c = tau_y) on a floor
without slip against the smooth wall: certified limit bounds alpha_L <= alpha <= alpha_U
(:func:`pfem_skfem.drivers.bounds.adapt`, refined until they are --bound-target-gap apart or
--bound-max-elements). Nye's heap stands in 2D, alpha_L >= 1 (measured alpha_L = 1 + 1.6-1.7
eps, alpha_U = 1 + 1.9-2.1 eps: the longitudinal stresses its shallow theory neglects),
and its excess strength alpha - 1 shrinks with eps (the upper bound at the smaller eps
below the lower bound at the larger). Stretched upright by s = sqrt(alpha) (a shallow
heap's basal shear grows as s^2) it is at its limit: its bounds within --stretch-tol of 1
(measured 0.99-1.07; bounded on the heap's own last mesh stretched with it), so a 2D heap at its limit is about s - 1 = 0.9 eps taller than
Nye's. Each deposit, the heap under its measured surface,
stopped at its limit within --alpha-tol: alpha_U >= 1 - alpha_tol (not steeper than the
continuum can hold; measured alpha 0.80-0.95 at n_h = 3.5-5: the PFEM's step, a few
elements across the deposit, is a little stronger than the continuum, as displacement
elements' collapse loads are) and alpha_L <= 1 + alpha_tol (not flatter than it had to
be).

Usage::

    python verification/bingham_slump.py --quick --json results/bingham_slump.json
    python verification/bingham_slump.py --save-every 10        # VTU/PVD of every slump
"""
from dataclasses import dataclass, field, replace
from pathlib import Path
import sys
import time

import numpy as np

from pfem_skfem.harness.declare import own_options
from pfem_skfem.harness.figures import figure_dir, labelled, pyplot, save_figure
from pfem_skfem.harness.options import (adaptive_options, base_parser, checkpoint_options,
                                        in_range, material_options, nonnegative_float, opt,
                                        pfem_options, positive_float, positive_int, time_options)
from pfem_skfem.harness.params import UNKEYED, Parameters
from pfem_skfem.harness.report import Report, script_main, thinned
from pfem_skfem.harness.sweeps import run_groups

QUICK = dict(k=[0.04, 0.02], n_h=3.5, studies=False, bound_rounds=4,
             bound_elements=3000, deposit_rounds=2)

#: argparse type of a relative tolerance of a gravity multiplier
TOLERANCE = in_range(0, 1, low_open=True, high_open=True, what="a fraction in (0, 1)")

#: the solvers a limit bound is asked of in turn (limit_bracket)
FALLBACK = {"clarabel", "qoco"}

#: the middle of the deposit, in units of its front x_f, where the profile is compared
MIDDLE = (0.2, 0.8)
MATERIALS = ("bingham", "tresca")
#: the excess is checked to shrink between k whose eps are at least this factor apart (closer,
#: the excesses differ by less than the discretisation's spread, +-0.04 measured at
#: n_h = 3.5-5: no trend to check)
TREND = 2.0
#: the time steps are dt0 * LADDER^n (one scene per rung, made once)
LADDER = 2 ** 0.25

yield_number = in_range(0, 1, low_open=True, high_open=True,
                        what="a yield number tau_y / (rho g H0) in (0, 1)")


def nye_front(k, H0, area):
    """x_f of Nye's profile of the given area: (2/3) sqrt(2 k H0) x_f^(3/2) = area."""
    return (1.5 * area / np.sqrt(2 * k * H0)) ** (2 / 3)


def nye_height(x, x_f, k, H0):
    """h(x) = sqrt(2 tau_y (x_f - x) / (rho g)), tau_y / (rho g) = k H0; 0 beyond x_f."""
    return np.sqrt(2 * k * H0 * np.clip(x_f - np.asarray(x, dtype=float), 0.0, None))


def aspect_ratio(k, H0, area):
    """eps = h(0) / x_f of Nye's profile = sqrt(2 k H0 / x_f)."""
    return float(np.sqrt(2 * k * H0 / nye_front(k, H0, area)))


def heap_mesh(x, h, size):
    """A heap on the floor y = 0 against the wall x = 0, its surface the polyline (x, h)
    from the wall (x[0] = 0) to the front (h[-1] = 0), triangulated with elements of about
    ``size``: the surface resampled every size / 2 of its length (a vertical front too)."""
    from pfem_skfem.discretisation.meshes import triangulate_polygon

    length = np.r_[0.0, np.cumsum(np.hypot(np.diff(x), np.diff(h)))]
    s = np.linspace(0.0, length[-1], int(np.ceil(2 * length[-1] / size)) + 1)
    surface = np.c_[np.interp(s, length, x), np.interp(s, length, h)]
    return triangulate_polygon(np.vstack([surface, [[0.0, 0.0]]]), size)


def nye_heap_mesh(eps, size, stretch=1.0):
    """Nye's heap in units of its height at the wall, h(x) = sqrt(1 - eps x) on
    0 <= x <= 1 / eps (tau_y / (rho g) = eps / 2 there), its heights times ``stretch``:
    :func:`heap_mesh`."""
    x = (1 - np.linspace(1, 0, 2001) ** 2) / eps         # dense where the front is steep
    return heap_mesh(x, stretch * np.sqrt(np.clip(1 - eps * x, 0.0, None)), size)


def limit_bracket(mesh, c, args, rounds=None, last=None):
    """alpha_L <= alpha <= alpha_U: the multiplier of gravity that a rigid-plastic body on
    ``mesh`` (unit weight, Tresca c: lengths in a height, order-one data) can carry on a
    floor y = 0 without slip against the smooth wall x = 0, both bounds strict
    (:func:`pfem_skfem.drivers.bounds.adapt`: refined where they differ, ``rounds``
    meshes, --bound-rounds by default). Without slip is the strongest floor: alpha_U
    bounds the body on any floor, alpha_L the rough one.

    A bound that --solver cannot certify is asked of the other of :data:`FALLBACK`
    (measured: Clarabel stalls 'AlmostSolved' on some lower bounds of Nye's long heaps at
    2-5 thousand elements, QOCO on some deposits'). Every round's bounds are strict, so a
    solve that fails in a later round leaves the best of the rounds before it, and its
    error as the status. A dict: lower, upper, elements (of the round that gave the lower
    bound), rounds, seconds, status (the error, or '') and solvers (those that certified
    the bounds); NaN bounds where the first round failed: a failed check, not a number.
    The last mesh bounded is appended to the list ``last`` if one is given."""
    import warnings

    from pfem_skfem.drivers.bounds import adapt
    from pfem_skfem.materials.criteria import Tresca
    from pfem_skfem.problems.bounds import LimitProblem, Support
    from pfem_skfem.problems.conic import AlmostSolvedWarning, SolverError

    floor, wall = 1e-9 * np.ptp(mesh.p, axis=1)[::-1]     # vertices on y = 0 and x = 0
    problem = LimitProblem(mesh, Tresca(c), supports=(Support(lambda x: x[1] < floor, "xy"),
                                                      Support(lambda x: x[0] < wall, "x")),
                           body_live=(0.0, -1.0))
    done, status, t0 = [], "", time.perf_counter()
    try:
        with warnings.catch_warnings():     # AlmostSolved: still a strict bound (checked)
            warnings.simplefilter("ignore", AlmostSolvedWarning)
            adapted = adapt(problem, rounds=rounds or args.bound_rounds,
                            max_elements=args.bound_elements, target_gap=args.bound_gap,
                            progress=done.append, solver=args.solver,
                            fallback=tuple(FALLBACK - {args.solver}))
        mesh = adapted.problem.mesh
    except SolverError as error:
        status = f"round {len(done) + 1}: {error}"
    if last is not None:
        last.append(mesh)
    best = max(done, key=lambda r: r.lower, default=None)
    return dict(lower=best.lower if done else np.nan,
                upper=min(r.upper for r in done) if done else np.nan,
                elements=best.elements if done else mesh.t.shape[1], rounds=len(done),
                seconds=time.perf_counter() - t0, status=status,
                solvers=sorted({name for r in done for name in r.solvers}))


def nye_bracket(k, args):
    """The gravity Nye's heap of yield number ``k`` can carry (:func:`limit_bracket`; eps its
    aspect ratio, c = eps / 2 in its height at the wall), and, as 'stretched', that of the
    heap at its limit: Nye's stretched upright by s = sqrt(alpha), since a shallow heap's basal
    shear rho g h h' grows as s^2 (alpha as s^-2), on the heap's last mesh stretched with it
    (--stretch-rounds meshes: any mesh gives strict bounds, and that one is already refined
    where the heap's bounds differed)."""
    from skfem import MeshTri

    eps, last = aspect_ratio(k, args.H0, args.L0 * args.H0), []
    nye = dict(eps=eps, **limit_bracket(nye_heap_mesh(eps, args.bound_size), eps / 2, args,
                                        last=last))
    s = nye["stretch"] = float(np.sqrt((nye["lower"] + nye["upper"]) / 2))
    nye["stretched"] = (limit_bracket(MeshTri(last[0].p * np.array([[1.0], [s]]), last[0].t),
                                      eps / 2, args, rounds=args.stretch_rounds)
                        if np.isfinite(s) else no_bracket("no bracket of Nye's heap to stretch"))
    return nye


def no_bracket(status):
    """:func:`limit_bracket`'s answer where there is no heap to bound: NaN bounds (a failed
    check, not a number) and why."""
    return dict(lower=np.nan, upper=np.nan, elements=0, rounds=0, seconds=0.0,
                status=status, solvers=[])


def deposit_bracket(r, args):
    """:func:`limit_bracket` of a slump's deposit, the heap under its measured surface h(x)
    (continued flat to the wall, down to the floor at its front x_f) in units of its
    height at the wall, c = k H0 / h(0); elements of --bound-size h(0), --deposit-rounds
    meshes."""
    h0 = r["h"][0]
    x = np.r_[0.0, r["xs"], r["x_f"]] / h0
    h = np.r_[r["h"][0], r["h"], 0.0] / h0
    if not np.all(np.isfinite(h)):              # a gap in the deposit: no heap to bound
        return no_bracket("a gap in the deposit's surface")
    return limit_bracket(heap_mesh(x, h, args.bound_size), r["k"] * args.H0 / h0, args,
                         rounds=args.deposit_rounds)


@dataclass(frozen=True)
class Slump(Parameters):
    """A slump, its scene and its checkpoint's keys (all but the solver): the column (L0 x H0)
    of mud ('bingham': tau_y, mu) or of rigid-plastic Tresca ('tresca': c = tau_y), tau_y =
    k rho g H0, ``n_h`` particles across Nye's height at the wall, against the smooth wall
    x = 0 on the floor y = 0 of friction coefficient mu_f; the others the options'."""
    k: float
    material: str
    n_h: float
    cfl: float
    mu: float
    quasi_static: bool
    L0: float
    H0: float
    rho: float
    g: float
    mu_f: float
    dt0: float
    dt_max: float
    fall_max: float
    alpha_advected: float
    solver: str = field(default="clarabel", metadata=UNKEYED)

    @property
    def spacing(self):
        """The particles' spacing: Nye's height at the wall / n_h."""
        k, H0 = self.k, self.H0
        return float(nye_height(0.0, nye_front(k, H0, self.L0 * H0), k, H0)) / self.n_h

    def scene(self):
        """(state, scene) of the slump, its first step dt0 sqrt(H0 / g)."""
        from pfem_skfem.materials import BinghamFluid, CohesiveTresca
        from pfem_skfem.scene import column_scene

        tau_y, g = self.k * self.rho * self.g * self.H0, self.g
        mud = (BinghamFluid(tau_y, self.mu) if self.material == "bingham"
               else CohesiveTresca(tau_y))
        return column_scene(mud, self.L0, self.H0, self.spacing, rho=self.rho, g=g,
                            dt=self.dt0 * np.sqrt(self.H0 / g), name="mud",
                            floor_friction=self.mu_f, passes=1, solver=self.solver,
                            volume_correction=True, alpha_advected=self.alpha_advected)


def slump(params, args, *, label, save_every=0):
    """One slump (:class:`Slump` ``params``) from release to rest (or to --max-steps /
    --T-max).

    The time step: a dynamic slump's next step moves the fastest particle ``cfl``
    spacings (at most 1.5 times the last step, at least dt0, at most dt_max); a
    quasi-static one (every step from rest, its displacement growing as dt^2) likewise,
    and at most the step in which a particle falls freely ``fall_max`` spacings (a particle
    that left the body falls g dt^2): the driver's
    :class:`~pfem_skfem.drivers.time_step.AdaptiveTimeStep` on rungs dt0 LADDER^n.

    With --checkpoint-dir the slump (its state, time step and front so far) is saved there
    every --checkpoint-every steps and at the end, and goes on from its checkpoint."""
    from pfem_skfem.drivers.resumable import Checkpoints, Frames, ResumableRun
    from pfem_skfem.drivers.time_step import AdaptiveTimeStep
    from pfem_skfem.pfem.measure import front, surface_height

    H0, L0, g, spacing = params.H0, params.L0, params.g, params.spacing
    k, material, n_h, cfl, mu, quasi_static = (params.k, params.material, params.n_h,
                                                params.cfl, params.mu, params.quasi_static)
    area = L0 * H0
    x_nye = nye_front(k, H0, area)
    t_unit = np.sqrt(H0 / g)
    dt0, dt_max = params.dt0 * t_unit, params.dt_max * t_unit
    if quasi_static:
        dt_max = min(dt_max, np.sqrt(params.fall_max * spacing / g))
    state, scene0 = params.scene()
    # the next step moves the fastest particle cfl spacings (at most 1.5 x the last step)
    time_step = AdaptiveTimeStep(dt0, dt_max, move=cfl, spacing=spacing,
                                 quasi_static=quasi_static, ladder=LADDER, growth=1.5)
    run = ResumableRun.open(
        scene0, state, {"T": [0.0], "X": [L0], "rest_measure": np.inf},
        checkpoints=Checkpoints(directory=args.checkpoint_dir, label=f"slump_{label}",
                                keys=params.keys(), every=args.checkpoint_every),
        frames=Frames(directory=Path(args.outdir) / "bingham_slump" / label, name="slump",
                      every=save_every),
        time_step=time_step)
    kept, rest = run.kept, args.rest_a if quasi_static else args.rest
    t0 = time.perf_counter()

    def observe(run, more):
        state = run.state
        speed = float(np.linalg.norm(state.v, axis=1).max())
        kept["T"].append(state.time / t_unit)
        kept["X"].append(front(state) if state.mesh_p is not None else np.nan)
        # at rest: a step from rest that barely accelerates (quasi-static), every particle
        # slow (dynamic)
        kept["rest_measure"] = (speed / (g * run.step_scene.config.dt) if quasi_static
                                else speed / np.sqrt(g * H0))

    def still(run):
        return run.state.step > 3 and kept["rest_measure"] < rest

    run.advance(lambda run: (run.state.step >= args.max_steps
                             or run.state.time >= args.T_max * t_unit or still(run)),
                observe)
    seconds = time.perf_counter() - t0
    state, series, T, X = run.state, run.series, kept["T"], kept["X"]
    at_rest, rest_measure = still(run), kept["rest_measure"]
    hist = state.history
    x_f = front(state)
    xs = np.linspace(0.0, x_f, 201)[1:-1]
    h = surface_height(state, xs)
    nye = nye_height(xs, x_f, k, H0)
    mid = (xs > MIDDLE[0] * x_f) & (xs < MIDDLE[1] * x_f)
    ratio = h[mid] / nye[mid] - 1
    # -d(h^2/2)/dx / (k H0) over the middle: 1 on Nye's profile (h |h'| = tau_y / (rho g))
    slope = -np.polyfit(xs[mid], h[mid] ** 2 / 2, 1)[0] / (k * H0) if np.all(
        np.isfinite(h[mid])) else np.nan
    return dict(label=label, k=k, material=material, n_h=n_h, cfl=cfl, mu=mu,
                quasi_static=quasi_static, spacing=spacing, particles0=int(hist["particles"][0]),
                at_rest=at_rest, rest_measure=rest_measure, steps=int(state.step),
                T_rest=state.time / t_unit, seconds=seconds, x_f=x_f, x_nye=x_nye,
                eps=aspect_ratio(k, H0, area), h_over_L=float(np.max(h) / x_f),
                excess=float(np.mean(ratio)), rms=float(np.sqrt(np.mean(ratio ** 2))),
                largest=float(np.max(np.abs(ratio))), basal_stress_ratio=float(slope),
                mass_error=float(np.max(np.abs(np.asarray(hist["mass"]) / hist["mass"][0] - 1))),
                area_change=float(np.max(np.abs(hist["area_change"]))),
                iterations=float(np.mean(hist["iterations"])), xs=xs, h=h, T=np.array(T),
                x_front=np.array(X), points=state.x.copy(),
                pvd=str(series.pvd_path) if series is not None else None)


def check(args):
    if args.study_k not in args.k and args.studies:
        return f"--study-k ({args.study_k:g}) must be one of --k {args.k}"
    return None


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    material_options(p, units="Pa", rho=1000.0, g=9.81)
    pfem_options(p, alpha_advected=3.0)
    adaptive_options(p, "bound", what="the limit bounds, drivers.bounds.adapt", rounds=6,
                     max_elements=opt(8000, dest="bound_elements"),
                     target_gap=opt(0.01, dest="bound_gap"),
                     size=opt(0.25, "first element size of a heap's limit-bound mesh, in "
                                    "its height at the wall"))
    time_options(p, save_every=opt(0, why="of every slump, and a PVD"))
    own_options(
        p, L0=(positive_float, 0.1, "column width [m] (half of a column against its symmetry "
                                    "plane)"),
        H0=(positive_float, 0.1, "column height [m]"),
        k=opt([0.04, 0.02, 0.01], "yield numbers k = tau_y / (rho g H0), one slump each (tau_y "
              "= k rho g H0): Nye's aspect ratio eps = 0.16, 0.10, 0.064", type=yield_number,
              nargs="+"),
        mu=(positive_float, 10.0, "plastic viscosity of the mud [Pa s] (the slow slump)"),
        mu_fast=(nonnegative_float, 1.0, "plastic viscosity of the fast mud of the studies "
                                         "[Pa s]"),
        mu_f=(nonnegative_float, 5.0, "Coulomb friction coefficient of the rough floor"),
        materials=opt(list(MATERIALS), "bingham: the slow viscous slump; tresca: quasi-static, "
                      "c = tau_y", type=MATERIALS, nargs="+"),
        n_h=(in_range(2, None, what="a number of particles >= 2"), 5.0,
             "particles across Nye's height at the wall (spacing)"),
        cfl=(in_range(0, 2, low_open=True, what="a fraction of a spacing in (0, 2]"), 0.5,
             "largest particle displacement per step, in spacings"),
        dt0=(positive_float, 0.05, "first (and least) time step, in units of sqrt(H0 / g)"),
        dt_max=(positive_float, 50.0, "largest time step, in units of sqrt(H0 / g)"),
        fall_max=(positive_float, 16.0, "quasi-static: the step in which a free particle falls "
                                        "this many spacings is the largest"),
        rest=(positive_float, 1e-6, "a dynamic slump is at rest below this speed / sqrt(g H0)"),
        rest_a=(positive_float, 1e-4, "a quasi-static one below this acceleration of a step "
                                      "from rest / g"),
        max_steps=(positive_int, 2000, "steps at most"),
        T_max=(positive_float, 1e4, "time at most, in units of sqrt(H0 / g)"),
        tol=(positive_float, 1.0, "the height excess in the middle may reach tol sqrt(eps)"),
        alpha_tol=(TOLERANCE, 0.2, "a deposit's certified gravity multiplier may miss 1 by "
                                   "this much"),
        stretch_tol=(TOLERANCE, 0.05, "Nye's heap stretched upright by sqrt(alpha) carries 1 "
                                      "within this"),
        deposit_rounds=(positive_int, 6, "meshes of a deposit's bounds (fewer: a wider bracket, "
                                         "so the --alpha-tol checks only harder to pass)"),
        stretch_rounds=(positive_int, 1, "meshes of the stretched heap's bounds, the first the "
                                         "last of the heap's own, stretched"),
        studies=(bool, True, "at --study-k: the mesh and step twins, the fast and dynamic "
                             "slumps"),
        study_k=(yield_number, 0.02, "k of the studies"))
    checkpoint_options(p, "slump")
    return p


def run(args):
    runs = run_groups(slump, {f"{m}_k{k:g}": dict(
        params=Slump.of(args, k=k, material=m, mu=args.mu if m == "bingham" else 0.0,
                        quasi_static=m == "tresca"),
        args=args, label=f"{m}_k{k:g}", save_every=args.save_every)
        for m in args.materials for k in args.k}, desc="slumps")
    tresca = Slump.of(args, k=args.study_k, material="tresca", mu=0.0, quasi_static=True)
    studies = run_groups(slump, {name: dict(params=replace(tresca, **change), args=args,
                                            label=label) for name, label, change in (
        ("tresca 1.4 n_h", "tresca_mesh", dict(n_h=1.4 * args.n_h)),
        ("tresca cfl/2", "tresca_step", dict(cfl=args.cfl / 2)),
        ("fast mud", "bingham_fast", dict(material="bingham", mu=args.mu_fast,
                                          quasi_static=False)),
        ("dynamic tresca", "tresca_dynamic", dict(quasi_static=False)),
    )} if args.studies else {}, desc="studies")
    # the deposits and Nye's heaps, how much gravity each can carry (certified bounds)
    for r in [*runs.values(), *studies.values()]:
        r["alpha"] = deposit_bracket(r, args)
    nye = {k: nye_bracket(k, args) for k in args.k}
    report = Report("bingham_slump", args,
                    Reynolds=args.rho * np.sqrt(args.g * args.H0) * args.H0 / args.mu)
    for k, b in nye.items():
        report.add_interval(f"nye_k{k:g}_alpha_lower", b["lower"], 1.0, np.inf,
                            f"Nye's heap (eps = {b['eps']:.3f}) stands in 2D: the lower bound "
                            f"of the gravity it carries >= 1 ({b['elements']} elements"
                            + (f"; {b['status']}" if b["status"] else "") + ")")
        report.add_interval(f"nye_k{k:g}_stretched_alpha_lower", b["stretched"]["lower"], 0.0,
                            1 + args.stretch_tol, f"Nye's heap x {b['stretch']:.4f} upright "
                            "is at its limit (alpha ~ s^-2 of a shallow heap): lower bound <= "
                            f"1 + {args.stretch_tol:g}")
        report.add_interval(f"nye_k{k:g}_stretched_alpha_upper", b["stretched"]["upper"],
                            1 - args.stretch_tol, np.inf, f"Nye's heap x {b['stretch']:.4f} "
                            f"upright: upper bound >= 1 - {args.stretch_tol:g}")
    thin, wide = (f(nye.values(), key=lambda b: b["eps"]) for f in (min, max))
    if thin is not wide:
        report.add_interval("nye_strength_excess_ratio",
                            (thin["upper"] - 1) / (wide["lower"] - 1), 0.0, 1.0,
                            "the 2D excess strength alpha - 1 of Nye's heap shrinks with h/L:"
                            f" upper bound at eps {thin['eps']:.3f} over the lower "
                            f"bound at {wide['eps']:.3f}")
    for label, r in runs.items():
        eps, a, quasi = r["eps"], r["alpha"], r["quasi_static"]
        report.add_interval(f"{label}_at_rest", r["rest_measure"], 0.0,
                            args.rest_a if quasi else args.rest, "at rest: " + (
                                "acceleration of a step from rest / g" if quasi else
                                "largest speed / sqrt(g H0)") + f" (after {r['steps']} steps)")
        report.add_interval(f"{label}_height_excess", r["excess"], 0.0, args.tol * np.sqrt(eps),
                            f"Nye: mean h / sqrt(2 tau_y (x_f - x) / (rho g)) - 1 over "
                            f"{MIDDLE[0]:g}-{MIDDLE[1]:g} x_f, within {args.tol:g} sqrt(eps), "
                            f"eps = {eps:.3f}")
        report.add_interval(f"{label}_front_over_nye", r["x_f"] / r["x_nye"],
                            1 - np.sqrt(eps), 1.0, "x_f / Nye's x_f of the same area: "
                            "not longer (a 2D deposit is stronger), within sqrt(eps)")
        report.add_interval(f"{label}_alpha_upper", a["upper"], 1 - args.alpha_tol, np.inf,
                            "the deposit not steeper than it can stand: the upper bound of "
                            f"the gravity it carries >= 1 - {args.alpha_tol:g}"
                            + (f" ({a['status']})" if a["status"] else ""))
        report.add_interval(f"{label}_alpha_lower", a["lower"], 0.0, 1 + args.alpha_tol,
                            "the deposit not flatter than it had to be: the lower bound of "
                            f"the gravity it carries <= 1 + {args.alpha_tol:g}"
                            + (f" ({a['status']})" if a["status"] else ""))
        report.add_interval(f"{label}_mass_error", r["mass_error"], 0.0, 1e-12,
                            "particles carry the mass")
        report.add_interval(f"{label}_area_change", r["area_change"], 0.0, 0.02,
                            "incompressible: the domain's area kept")
    for material in args.materials:
        mine = [r for r in runs.values() if r["material"] == material]
        thin, wide = (f(mine, key=lambda r: r["eps"]) for f in (min, max))
        if wide["eps"] >= TREND * thin["eps"]:
            report.add_interval(f"{material}_excess_ratio", thin["excess"] / wide["excess"],
                                0.0, 1.0, f"the excess shrinks as h/L does: eps "
                                f"{thin['eps']:.3f} over {wide['eps']:.3f}")
    if studies:
        if (base := runs.get(f"tresca_k{args.study_k:g}")) is None:       # --materials bingham
            base = studies["tresca"] = slump(tresca, args, label="tresca_base")
        report.add_interval("excess_discretisation_spread",
                            max(abs(studies[s]["excess"] - base["excess"]) for s in (
                                "tresca 1.4 n_h", "tresca cfl/2")) / base["excess"], 0.0, 0.5,
                            "n_h x 1.4 and cfl / 2 change the height excess by less than "
                            "half of it")
        slow_mud = runs.get(f"bingham_k{args.study_k:g}", base)
        report.add_interval("fast_mud_runout", studies["fast mud"]["x_f"] / slow_mud["x_f"],
                            1.0, np.inf, f"mu = {args.mu_fast:g} Pa s: inertia carries the "
                            "mud farther than the slow slump")
        report.add_interval("dynamic_tresca_runout", studies["dynamic tresca"]["x_f"]
                            / base["x_f"], 1.0, np.inf, "Tresca released dynamically: "
                            "farther than quasi-statically")
    report.extra = {name: {k: thinned(r, drop=("label", "points")) for k, r in rs.items()}
                    for name, rs in (("runs", runs), ("studies", studies))}
    report.extra["nye"] = {f"{k:g}": b for k, b in nye.items()}
    report.add_table(
        "runs", ["run", "k", "n_h", "mu", "eps", "h/L", "excess", "rms", "x_f/Nye", "hh`/kH0",
                 "rest", "T_rest", "steps", "s"],
        [[label, r["k"], r["n_h"], r["mu"], r["eps"], r["h_over_L"], r["excess"], r["rms"],
          r["x_f"] / r["x_nye"], r["basal_stress_ratio"], "yes" if r["at_rest"] else "no",
          r["T_rest"], r["steps"], r["seconds"]] for label, r in {**runs, **studies}.items()],
        formats={"k": ".3f", "n_h": ".1f", "mu": ".1f", "eps": ".3f", "h/L": ".3f",
                 "excess": "+.3f", "rms": ".3f", "x_f/Nye": ".3f", "hh`/kH0": ".3f",
                 "T_rest": ".1f", "s": ".0f"})
    carried = [*((f"Nye k{k:g}", b) for k, b in nye.items()),
               *((f"Nye k{k:g} x {b['stretch']:.3f}", {**b["stretched"], "eps": b["eps"]})
                 for k, b in nye.items()),
               *((label, {**r["alpha"], "eps": r["eps"]})
                 for label, r in {**runs, **studies}.items())]
    report.add_table(
        "gravity carried", ["gravity carried", "eps", "alpha_L", "alpha_U", "elements", "s",
                            "solvers", "status"],
        [[label, b["eps"], b["lower"], b["upper"], b["elements"], b["seconds"],
          "+".join(b["solvers"]), b["status"]] for label, b in carried],
        formats={"eps": ".3f", "alpha_L": ".4f", "alpha_U": ".4f", "s": ".0f"})
    report.data = dict(runs=runs, studies=studies, nye=nye)
    return report


def figures(args, runs, studies, nye):
    """The deposits beside Nye's profiles, the height excess against eps, and the gravity
    each heap carries (its certified bounds)."""
    fig, ax = pyplot().subplots(1, 3, figsize=(17, 4.4))
    for r in runs.values():
        scale = float(nye_height(0.0, r["x_nye"], r["k"], args.H0))
        ax[0].plot(r["xs"] / r["x_nye"], r["h"] / scale,
                   "-" if r["material"] == "bingham" else "--",
                   label=f"{r['material']}, k = {r['k']:g}")
    x = np.linspace(0.0, 1.0, 200)
    ax[0].plot(x, np.sqrt(1 - x), "k:", label="Nye, the same area (every k)")
    for r in [r for r in studies.values() if not r["quasi_static"] or r["material"] == "bingham"]:
        scale = float(nye_height(0.0, r["x_nye"], r["k"], args.H0))
        ax[0].plot(r["xs"] / r["x_nye"], r["h"] / scale, "-.", lw=1,
                   label=f"{r['label']} (inertia), k = {r['k']:g}")
    labelled(ax[0], "x / x_f (Nye)", "h / h_Nye(0)", "deposits at rest")
    eps = np.array([r["eps"] for r in runs.values()])
    for material in args.materials:
        mine = [r for r in runs.values() if r["material"] == material]
        ax[1].loglog([r["eps"] for r in mine], [max(r["excess"], 1e-4) for r in mine], "o-",
                     label=f"{material}: mean height excess over Nye")
    grid = np.geomspace(eps.min() / 1.3, eps.max() * 1.3, 20)
    ax[1].loglog(grid, args.tol * np.sqrt(grid), "k:", label=f"tolerance {args.tol:g} sqrt(eps)")
    ax[1].loglog(grid, grid, color="0.6", ls="--", label="eps")
    labelled(ax[1], "aspect ratio eps = h(0) / x_f (Nye)", "excess of h over Nye, 0.2-0.8 x_f",
             "the profile against h/L")
    heaps = {"Nye's heap": list(nye.values()),
             **{f"{m} deposits": [{**r["alpha"], "eps": r["eps"]} for r in runs.values()
                                  if r["material"] == m] for m in args.materials}}
    for shift, (name, bs) in zip((1.0, 0.97, 1.03), heaps.items()):
        e = np.array([b["eps"] for b in bs]) * shift           # side by side at one eps
        lo, hi = np.array([b["lower"] for b in bs]), np.array([b["upper"] for b in bs])
        ax[2].errorbar(e, (lo + hi) / 2, yerr=(hi - lo) / 2, fmt="o", capsize=3, label=name)
    ax[2].axhline(1.0, color="k", ls=":", label="at its limit")
    labelled(ax[2], "aspect ratio eps = h(0) / x_f (Nye)", "gravity carried, alpha_L to alpha_U",
             "rigid-plastic heaps: certified limit bounds")
    save_figure(fig, figure_dir(args, "bingham_slump") / "bingham_slump.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
