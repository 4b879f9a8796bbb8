"""A published retrogressive slope in sensitive clay: del Castillo et al.'s 5 m slope in the PFEM.

Beyond the thesis (issue 55 item 4: a fully specified slope in place of Saint-Jude). The
source: E. M. del Castillo, R. I. Borja & A. H. Favero Neto (2026), "A coupled u-pw SPH
formulation for hydromechanical modeling of retrogressive landslides ...", IJNAMG,
doi 10.1002/nag.70322, section 5 and 5.1 (pp. 14-17). Their slope (p. 14): 5 m high at
45 deg, 25 m along the base and 20 m along the top, a no-slip base and a free-slip wall
behind it (x = 0 here, the face towards +x: crest at x = 20 m, toe at x = 25 m); von Mises
clay (Drucker-Prager, phi = 0), E = 25 MPa, nu = 0.3, rho = 2150 kg/m3, porosity 0.4,
water table at the surface; exponential softening (their (48), after Zabala & Alonso 2011)
c = c_r + (c_p - c_r) exp(-eta eps_acc), c_p = 15.1 kPa, c_r = 1.5 kPa, eta = 5; the
effective stresses start at K0 = 0.5, and the failure is triggered by eta = 5 and the
cohesion divided by 1.65; 20 s simulated (SPH spacing 0.1 m, 11,275 particles). Their
undrained (penalty) run: run-out about 21.6 m, retrogression 14.0 m (p. 15), three
successive rotational slides (a flowslide) whose debris spreads into horsts and grabens,
arrested by the debris buttressing the back-scarp; their coupled u-pw run: 19.5 m and 20 m
(p. 17).

Here: the library's softening Tresca clay (:class:`~pfem_skfem.materials.SofteningTresca`,
:class:`~pfem_skfem.materials.ExponentialSoftening`) in total stress, the PFEM loop and
step control of ``verification/sensitive_clay.py``. The conversions (book/softening.md,
"A published slope"):

* strength: the paper does not give its Drucker-Prager fit at phi = 0; the library's
  Tresca c = tau_over_c x c / F, tau_over_c the plane-strain shear strength over the
  paper's c: 2 / sqrt(3) for the compression-cone fit q = 2c (the default: with it the
  slope at peak strength stands at the limit, gamma H / c in [6.00, 6.20] by the library's
  bounds, as the paper's gravity loading at peak strength needs), 1 for the plane-strain fit;
* strain: the paper does not define eps_acc; gamma^p = k eps_acc, k = gamma_per_eps:
  sqrt(3) for the equivalent plastic strain int sqrt(2/3) |d eps^p| conjugate to q (the
  default), sqrt(2) for the norm of the plastic strain, 1 for an engineering shear strain.
  Then exp(-eta eps_acc) = exp(-3 gamma^p / gamma_95) exactly with gamma_95 = 3 k / eta;
* stress: the total-stress K0 of effective K0 with water at the surface,
  K0_total = (K0 (rho - rho_w) + rho_w) / rho (0.733).

Measured at t_end: the run-out (the furthest particle beyond the toe), the retrogression
(from the crest back to the furthest particle of the original top surface that has dropped
by more than ``--drop``) and the kinetic energy. The paper defines neither distance in its
text; from the crest and from the toe are read from its u-pw run (retrogression 20 m, "a
lack of more soil material left to fail": the whole 20 m top) and the 8 m slope's ("the
entire 16 m of the top").

Checks, stated before the runs: every run: the exponential law's conversion (the library's
c at gamma^p = k eps equals tau_over_c / F x the paper's c at eps, to 1e-12), the slope fails
(run-out at least a spacing) and the step control halves dt after each step over its cap.
A run to the paper's 20 s or later: the run-out and the retrogression within ``--band``
(25 %) of the undrained run's 21.6 m and 14.0 m, the failure retrogresses (the retrogression
grows by two spacings or more after ``--t-first`` = 2 s, the first slide) and it arrests
(kinetic energy at t_end below 5 % of its peak). The band: the paper's two hydromechanical
models differ by 10 % in run-out and 43 % in retrogression, SPH's run-out and retrogression
fall with refinement (Jin, Yin & Yuan 2020), and the two conversions are inferred. --quick
(the default h = 1 m, to 2 s) checks the first three only.

Options beyond the paper: ``--viscosity`` (the clay's Bingham eta [kPa s], Zhang et al. 2017's
elastoviscoplastic clay: tau = c + eta dgamma^p/dt) and ``--regularisation nonlocal --ell``
(:class:`~pfem_skfem.materials.NonlocalAverage`); each keys its own checkpoint.

Measured (book/softening.md, "A published slope"; 20 s, the step control's exact drop of
2026-12-07): h = 1 m, 800 steps (dt never halved: the largest drop 0.22 of c_p - c_r), 171 s
of CPU (2338 steps and 415 s with the steepest-rate bound of before); the slides come as
theirs (0.7-2.1, 3.9-4.9, 6.5-8.0 s), but the third takes the whole top (retrogression 20.0 m,
their u-pw run's) and the fully remoulded debris runs out 61.2 m. h = 0.5 m: 800 steps,
600 s of CPU, run-out 66.9 m, retrogression 20.0 m. ``--viscosity 0.3`` (of the order of the
paper's SPH artificial viscosity as a shear viscosity, rho alpha c h / 16 = 0.22-1.0 kPa s
with the SI's approach-only switch, h = 0.15 m and its unstated sound speed c): run-out 41.2 m
(21.5 m from 6 to 8 s), 20.0 m, and it arrests. The run-out and retrogression checks fail in
every run.

Why (book/softening.md, "Why the debris runs three times as far", 2026-12-08): no conversion or
boundary of the paper's was found mis-read (c_r undivided by F: 37.7 m; eps_acc as gamma^p:
62.6 m; the plane-strain fit: 71.1 m). At 20 s nearly all the clay that moved is within 10 %
of c_r (the extras' ``remoulded``), and a heap wholly at c_r cannot rest short of Nye's
profile y^2 = 2 c_r s / (rho g): 40.9 m beyond the toe (``remoulded_heap_runout``, in the
table). The paper's deposits hold 2-3 c_r at rest: their debris keeps intact horsts and
grabens between 0.1-0.3 m bands, which this PFEM at h = 0.5-1 m does not.

Usage::

    python verification/retrogressive_slope.py --quick --json results/retrogressive_slope.json
    python verification/retrogressive_slope.py --checkpoint-dir results/retrogressive_slope_ckpt
    python verification/retrogressive_slope.py --h 0.5 \\
        --checkpoint-dir results/retrogressive_slope_ckpt
    python verification/retrogressive_slope.py --viscosity 0.3 \\
        --checkpoint-dir results/retrogressive_slope_ckpt
"""
from dataclasses import dataclass, field
import math
import sys

import numpy as np

from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, checkpoint_options, in_range,
                                        material_options, nonnegative_float, opt,
                                        pfem_options, positive_float, softening_options,
                                        time_options)
from pfem_skfem.harness.params import UNKEYED, Parameters, keys_of
from pfem_skfem.harness.report import Report, script_main

QUICK = dict(t_end=2.0)
#: del Castillo et al. 2026: the undrained run (p. 15) and the coupled u-pw run (p. 17) [m]
PAPER = dict(runout=21.6, retrogression=14.0, runout_upw=19.5, retrogression_upw=20.0)
#: their simulated time [s] (p. 15): the run-out and retrogression are checked from it on
T_PAPER = 20.0
#: the kinetic energy at t_end over its peak below which the slide has arrested
ARREST = 0.05


def paper_strength(eps, c_p, c_r, eta):
    """The paper's (48): c = c_r + (c_p - c_r) exp(-eta eps_acc)."""
    return c_r + (c_p - c_r) * np.exp(-eta * np.asarray(eps, dtype=float))


def gamma_95_of(eta, k):
    """gamma_95 of the library's exp(-3 gamma^p / gamma_95) that is the paper's
    exp(-eta eps_acc) when gamma^p = k eps_acc: 3 k / eta (not ln(20) k / eta: the library's
    '95 %' is exp(-3) = 0.0498)."""
    return 3.0 * k / eta


def remoulded_heap_runout(area, c, rho, g, base):
    """The shortest run-out beyond the toe (at ``base`` from the wall) at which ``area`` of clay
    can rest as a thin heap of strength c on the rough base against the smooth wall: Nye's
    perfectly plastic profile y^2 = 2 c s / (rho g), s back from the front, holds
    (2/3) sqrt(2 c / (rho g)) L^1.5 over a length L; a shorter heap needs more than c
    somewhere (thin-layer estimate). The whole slope fully remoulded: 40.9 m by default."""
    length = (1.5 * area / math.sqrt(2.0 * c / (rho * g))) ** (2.0 / 3.0)
    return length - base


def remoulded_fraction(state, x0, law, moved, tol=0.1):
    """The area fraction of the clay that moved more than ``moved`` (its elements' mean
    vertex displacement) whose strength is within ``tol`` (c_p - c_r) of c_r."""
    from pfem_skfem.pfem.alpha_shape import triangle_areas

    p, t = state.mesh_p, state.mesh_t
    g = np.asarray(state.gamma_p).reshape(len(t), -1).mean(axis=1)
    c = law.strength(g)
    area = np.abs(triangle_areas(p, t))
    mp = np.asarray(state.mesh_particle)
    clay = (mp >= 0) & (mp < len(x0))                  # the clay's particles, not the bodies'
    disp = np.where(clay, np.linalg.norm(p - x0[np.where(clay, mp, 0)], axis=1), 0.0)
    failed = disp[t].sum(axis=1) > moved * np.maximum(clay[t].sum(axis=1), 1)
    rem = failed & (c < law.c_r + tol * (law.c_p - law.c_r))
    return float(area[rem].sum() / area[failed].sum()) if failed.any() else 0.0


def total_k0(K0, rho, rho_w):
    """sigma_h / sigma_v in total stress of an effective K0, water at the surface:
    (K0 (rho - rho_w) + rho_w) / rho."""
    return (K0 * (rho - rho_w) + rho_w) / rho


@dataclass(frozen=True)
class Slope(Parameters):
    """The slope, its clay and its run (the options of the same names); ``scene()`` builds it,
    its fields but t_end are its checkpoint's keys."""
    height: float
    base: float
    top: float
    h: float
    c_p: float
    c_r: float
    eta: float
    F: float
    tau_over_c: float
    gamma_per_eps: float
    E: float
    nu: float
    rho: float
    rho_w: float
    g: float
    K0: float
    mu: float
    dt: float
    max_drop: float
    viscosity: float = 0.0
    regularisation: str = "none"
    ell: float = None
    t_end: float = field(default=None, metadata=UNKEYED)

    def keys(self):
        """The checkpoint's keys; a slope without viscosity or regularisation keeps those of
        before it had them (its checkpoints are found again)."""
        omit = (("viscosity",) if self.viscosity == 0 else ()) + \
            (("regularisation", "ell") if self.regularisation == "none" else ())
        return keys_of(self, omit=omit)

    def material_regularisation(self):
        """The material's ``regularisation``: None or ``NonlocalAverage(ell)``."""
        from pfem_skfem.materials import NonlocalAverage
        return None if self.regularisation == "none" else NonlocalAverage(self.ell)

    def polygon(self):
        """The clay: its back on the wall x = 0, its face from the crest down to the toe."""
        return ((0.0, 0.0), (self.base, 0.0), (self.top, self.height), (0.0, self.height))

    def law(self):
        """The library's exponential law after the trigger: c_p and c_r times tau_over_c / F,
        gamma_95 = 3 k / eta."""
        from pfem_skfem.materials import ExponentialSoftening
        s = self.tau_over_c / self.F
        return ExponentialSoftening(s * self.c_p, s * self.c_r,
                                    gamma_95_of(self.eta, self.gamma_per_eps))

    def scene(self):
        """(state, scene): the triggered slope from its geostatic K0 state."""
        from pfem_skfem.discretisation.theta import ThetaMethod
        from pfem_skfem.materials import Elastic, SofteningTresca
        from pfem_skfem.problems.contact import RigidSegment
        from pfem_skfem.scene import Body, Geostatic, Region, Scene
        from pfem_skfem.scene.config import PFEMConfig

        far = 50.0 * self.base
        material = SofteningTresca(self.law(), Elastic(self.E, self.nu),
                                   self.material_regularisation(), eta=self.viscosity)
        clay = Region(self.polygon(), material, self.rho, self.h, name="clay",
                      stress=Geostatic(k0=total_k0(self.K0, self.rho, self.rho_w), top=self.height))
        bodies = (Body("base", RigidSegment((-far, 0.0), (far, 0.0), self.mu)),
                  Body("wall", RigidSegment((0.0, far), (0.0, -self.h), 0.0)))
        scene = Scene(regions=(clay,), bodies=bodies, gravity=(0.0, -self.g), alpha=1.6,
                      length=self.height,
                      config=PFEMConfig(theta=ThetaMethod(self.dt, 1.0, 1.0), passes=2))
        return scene.initial_state(), scene


def conversion_error(params, eps=np.linspace(0.0, 2.0, 41)):
    """The largest relative difference between the library's c at gamma^p = k eps and
    tau_over_c / F x the paper's c at eps."""
    ours = params.law().strength(params.gamma_per_eps * eps)
    theirs = params.tau_over_c / params.F * paper_strength(eps, params.c_p, params.c_r,
                                                           params.eta)
    return float(np.max(np.abs(ours - theirs) / theirs))


def failure(args):
    """The slope of the options run to t_end: its measurements (a dict)."""
    from pfem_skfem.drivers.resumable import Bar, Checkpoints, ResumableRun, StepClock
    from pfem_skfem.drivers.time_step import SofteningTimeStep
    from pfem_skfem.pfem.measure import failure_extent, ground_particles

    clock = StepClock()
    params = Slope.of(args)
    state, scene = params.scene()
    x0 = state.x.copy()
    ground = ground_particles(x0, params.height - 0.25 * params.h, behind=params.top)

    def measures(x):
        """(run-out beyond the toe, retrogression behind the crest) of the particles at x."""
        return failure_extent(x, x0, ground, toe=params.base, crest=params.top,
                              drop=args.drop)

    policy = SofteningTimeStep(scene.config.dt, max_drop=args.max_drop, halvings=4)
    run = ResumableRun.open(
        scene, state, {"t": [], "runout": [], "retrogression": [], "kinetic": [], "dt": [],
                       "cpu_seconds": []},
        checkpoints=Checkpoints(args.checkpoint_dir, "retrogressive_slope", params.keys(),
                                args.checkpoint_every),
        bar=Bar(int(np.ceil(args.t_end / args.dt)), "retrogressive slope", args.progress),
        time_step=policy)

    def observe(run, snapshots):
        s, kept = run.state, run.kept
        runout, retro = measures(s.x)
        kept["t"].append(float(s.time))
        kept["runout"].append(runout)
        kept["retrogression"].append(retro)
        kept["kinetic"].append(float(0.5 * np.sum(s.mass * np.sum(s.v ** 2, axis=1))))
        kept["dt"].append(float(run.step_scene.config.dt))
        clock.record(kept)

    run.advance(lambda run: run.state.time >= args.t_end * (1 - 1e-9), observe)
    state, kept = run.state, run.kept
    drops = np.asarray(state.history["softening_drop"])
    dts = np.asarray(kept["dt"])
    runout, retro = measures(state.x)
    t = np.asarray(kept["t"])
    first = np.asarray(kept["retrogression"])[t <= args.t_first + 1e-9]
    kinetic = np.asarray(kept["kinetic"])
    return dict(runout=runout, retrogression=retro, params=params, steps=state.step,
                retrogression_first=float(first[-1]) if first.size else 0.0,
                kinetic_ratio=float(kinetic[-1] / kinetic.max()) if kinetic.max() > 0
                else float("nan"),
                halved=policy.halved_after_cap(drops, dts),
                remoulded=remoulded_fraction(state, x0, params.law(), args.drop),
                cpu_seconds=float(np.sum(kept["cpu_seconds"])), particles=len(x0),
                largest_drop=float(drops.max()), history={k: np.asarray(v)
                                                          for k, v in kept.items()},
                x=state.x, x0=x0, mesh=(state.mesh_p, state.mesh_t), gamma_p=state.gamma_p)


def run(args):
    params = Slope.of(args)
    h = args.h
    report = Report("retrogressive_slope", args)
    report.add_interval("conversion_error", conversion_error(params), 0.0, 1e-12,
                        f"the library's c at gamma^p = {args.gamma_per_eps:g} eps is "
                        f"{args.tau_over_c:.4g} / {args.F:g} x the paper's (48) at eps "
                        f"(gamma_95 = 3 k / eta = {params.law().gamma_95:.4g})")
    c = failure(args)
    report.add_interval("runout_over_h", c["runout"] / h, 1.0, np.inf,
                        "the triggered slope fails: run-out at least a spacing (its gamma H / c "
                        f"= {args.rho * args.g * args.height / params.law().c_p:.2f}, above the "
                        "slope's limit 6.0-6.2)")
    report.add_interval("halved_after_cap", float(c["halved"]), 1.0, 1.0,
                        "after each step over the cap the next dt was halved")
    band = args.band
    if args.t_end >= T_PAPER:
        for key in ("runout", "retrogression"):
            ref = PAPER[key]
            report.add_interval(f"{key}_vs_paper", c[key], (1 - band) * ref, (1 + band) * ref,
                                f"del Castillo et al. 2026 undrained run: {ref:g} m, within "
                                f"{band:.0%} (their u-pw run: {PAPER[key + '_upw']:g} m)",
                                reference=ref)
        report.add_interval("retrogression_growth_over_h",
                            (c["retrogression"] - c["retrogression_first"]) / h, 2.0, np.inf,
                            f"the failure retrogresses: the retrogression grows by two "
                            f"spacings or more after t = {args.t_first:g} s (the first slide)")
        report.add_interval("kinetic_ratio", c["kinetic_ratio"], 0.0, ARREST,
                            f"it arrests: the kinetic energy at t_end below {ARREST:.0%} of "
                            f"its peak (the paper: near zero after the third slide)")
    heap = remoulded_heap_runout(0.5 * (args.base + args.top) * args.height,
                                 params.law().c_r, args.rho, args.g, args.base)
    report.add_table("slope", ["", "run-out [m]", "retrogression [m]"],
                     [["this run", c["runout"], c["retrogression"]],
                      ["at rest, all at c_r (Nye): at least", heap, args.top],
                      ["paper, undrained", PAPER["runout"], PAPER["retrogression"]],
                      ["paper, u-pw", PAPER["runout_upw"], PAPER["retrogression_upw"]]],
                     title=f"\nat t = {args.t_end:g} s, h = {h:g} m ({c['particles']} "
                           f"particles, {c['steps']} steps, {c['cpu_seconds']:.0f} s CPU)")
    report.extra = {k: c[k] for k in ("runout", "retrogression", "retrogression_first",
                                      "kinetic_ratio", "steps", "largest_drop", "particles",
                                      "remoulded")}
    report.extra["remoulded_heap_runout"] = heap
    every = max(1, len(c["history"]["t"]) // 400)        # about 400 entries of each
    report.extra["history"] = {k: c["history"][k][::every] for k in ("t", "runout",
                                                                     "retrogression", "kinetic")}
    report.extra["deposit"] = {"x0": np.round(c["x0"], 3),
                               "x": np.round(c["x"][:len(c["x0"])], 3)}
    report.data = dict(case=c)
    return report


def check(args):
    """A usage error, or None: the face leans back from the toe to the crest
    (0 < top < base), and the crest's ground lies behind it."""
    if not args.top < args.base:
        return (f"--top {args.top:g}: below --base {args.base:g} (the face runs from the "
                "toe x = base up to the crest x = top)")
    if args.regularisation == "fracture-energy":
        return "--regularisation fracture-energy: not offered here (none or nonlocal)"
    if args.regularisation == "nonlocal" and not (args.ell and args.ell > args.h):
        return (f"--regularisation nonlocal needs --ell above the spacing --h {args.h:g} "
                f"(got {args.ell})")
    if args.regularisation == "none" and args.ell is not None:
        return "--ell without --regularisation nonlocal: it would be ignored"
    return None


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    p.add_argument("--height", type=positive_float, default=5.0, help="slope height H [m]")
    p.add_argument("--base", type=positive_float, default=25.0,
                   help="length along the base, wall to toe [m]")
    p.add_argument("--top", type=positive_float, default=20.0,
                   help="length along the top, wall to crest [m] (45 deg: base - H)")
    softening_options(p, c_p=opt(15.1, "the paper's peak cohesion c_p [kPa]"),
                      c_r=opt(1.5, "the paper's residual cohesion c_r [kPa]"),
                      max_drop=opt(0.5, "cap on a step's strength drop, a fraction of c_p - c_r "
                                        "(the next step's dt is halved above it)"),
                      regularisation=opt("none", "the clay's regularisation: none (local "
                                                 "softening) or nonlocal (NonlocalAverage: "
                                                 "each step's Delta gamma^p averaged over "
                                                 "--ell)"),
                      ell=opt(None, "the nonlocal averaging length ell [m] (above --h)"))
    p.add_argument("--viscosity", type=nonnegative_float, default=0.0,
                   help="Bingham viscosity of the clay [kPa s] (SofteningTresca's eta: "
                        "tau = c + eta dgamma^p/dt in simple shear; 0: rate-independent)")
    p.add_argument("--eta", type=positive_float, default=5.0,
                   help="the paper's softening coefficient eta in exp(-eta eps_acc)")
    p.add_argument("--F", type=in_range(1.0), default=1.65,
                   help="the trigger's strength reduction factor: c_p and c_r divided by F")
    p.add_argument("--tau-over-c", type=positive_float, default=2 / math.sqrt(3),
                   help="the plane-strain shear strength over the paper's c: 2/sqrt(3) the "
                        "compression-cone fit (q = 2c), 1 the plane-strain fit")
    p.add_argument("--gamma-per-eps", type=positive_float, default=math.sqrt(3),
                   help="k = gamma^p / eps_acc: sqrt(3) for eps_acc = int sqrt(2/3)|d eps^p|, "
                        "sqrt(2) for int |d eps^p|, 1 for an engineering shear strain")
    p.add_argument("--K0", type=nonnegative_float, default=0.5,
                   help="effective earth pressure coefficient at rest K0 (water at the surface)")
    p.add_argument("--rho-w", type=positive_float, default=1.0, help="water density [t/m3]")
    p.add_argument("--mu", type=nonnegative_float, default=2.0,
                   help="base friction mu (the paper's no-slip base: mu rho g t > c_r under "
                        "debris t = 0.03 m thick or more)")
    material_options(p, units="kPa", rho=2.15, g=9.81, E=25000.0, nu=0.3)
    pfem_options(p, h=opt(1.0, "particle spacing [m] (the paper's SPH: 0.1)"))
    time_options(p, dt=opt(0.025, "time step [s] (halved by the cap)"),
                 t_end=opt(T_PAPER, "end time [s] (the paper: 20; the paper's checks from it)"))
    p.add_argument("--t-first", type=positive_float, default=2.0,
                   help="end of the first slide [s] (the paper: its band surfaces at 0.6 s, "
                        "the second slide starts at 3.5 s)")
    p.add_argument("--drop", type=positive_float, default=0.5,
                   help="a surface particle that dropped by more than this has failed [m]")
    p.add_argument("--band", type=in_range(0, 1, low_open=True, high_open=True), default=0.25,
                   help="the checks' band on the paper's run-out and retrogression (fraction)")
    checkpoint_options(p, "slope", every=20)
    return p


def figures(args, case):
    """The deposit at t_end (gamma^p shaded over the initial particles) and the run-out,
    retrogression and kinetic energy in time."""
    plt = pyplot()
    fig, (ax, cax, bx) = plt.subplots(3, 1, figsize=(9, 6.5),
                                      gridspec_kw={"height_ratios": [1, 0.06, 1.2]})
    p, t = case["mesh"]
    shade = ax.tripcolor(p[:, 0], p[:, 1], t, facecolors=np.log10(
        1e-3 + case["gamma_p"].reshape(-1, 3).mean(axis=1)), cmap="viridis", vmin=-3, vmax=1)
    ax.plot(case["x0"][:, 0], case["x0"][:, 1], ",", color="0.6")
    par = case["params"]
    for x, label in ((par.top - PAPER["retrogression"], "paper's scarp"),
                     (par.base + PAPER["runout"], "paper's front")):
        ax.axvline(x, color="C3", ls="--", lw=1)
        ax.text(x, par.height * 1.05, label, color="C3", fontsize=8, ha="center")
    ax.set_aspect("equal")
    ax.set(xlim=(-0.5, max(case["x"][:, 0].max(), par.base + PAPER["runout"]) + 1),
           xlabel="x [m]", ylabel="y [m]",
           title=f"t = {args.t_end:g} s: run-out {case['runout']:.1f} m, retrogression "
                 f"{case['retrogression']:.1f} m (paper: {PAPER['runout']:g}, "
                 f"{PAPER['retrogression']:g})")
    fig.colorbar(shade, cax=cax, orientation="horizontal", label="log10(1e-3 + gamma^p)")
    fig.subplots_adjust(hspace=0.7)
    hist = case["history"]
    bx.plot(hist["t"], hist["runout"], label="run-out [m]")
    bx.plot(hist["t"], hist["retrogression"], label="retrogression [m]")
    bx.set(xlabel="t [s]", ylabel="distance [m]")
    kx = bx.twinx()
    kx.plot(hist["t"], hist["kinetic"], color="0.5", lw=1, label="kinetic energy")
    kx.set_ylabel("kinetic energy [kJ/m]")
    bx.legend(loc="upper left", fontsize=8)
    kx.legend(loc="upper right", fontsize=8)
    save_figure(fig, figure_dir(args, "retrogressive_slope") / "slope.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
