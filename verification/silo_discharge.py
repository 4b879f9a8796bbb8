"""Silo discharge (thesis 6.4.4, Fig 6.16-6.19): the rate through an outlet, Beverloo's scaling.

A plane-strain silo, a bin W = 50 cm wide filled H = 100 cm high above a hopper
Hh = 35 cm high that narrows to an outlet B = 8 cm wide, holds cohesionless material
(rho = 1.5 t/m3, c = 0, phi = 31 deg, psi = 0) at rest; the gate under the outlet is
removed at t = 0 and the material flows out under gravity. The walls are smooth
(mu = 0) or rough (mu = tan phi). Thesis: dt = 0.01 s, alpha = 1.6.

Reading of Fig 6.16 (the four dimensions are not labelled in the text): bin width 50,
fill height of the vertical walls 100, hopper height 35, outlet 8 cm. Its area,
50 x 100 + (50 + 8)/2 x 35 = 6015 cm2, is the initial "volume in silo" of Fig 6.19
(about 6 x 1000 cm2 per unit thickness), and the hopper's half-angle from the
vertical, atan(21/35) = 30.96 deg, is phi (research notes, chapters-6-8 section 3).

The silo is a scene of the PFEM engine (:mod:`pfem_skfem.drivers.pfem_loop`): one
region of particles, two rigid polylines (bin and hopper walls) with the contact cones
(5.12), the gate a body removed at t = 0, and an *outlet*: the particles that cross
the outlet plane y = 0 leave the cloud and their mass is counted as discharged, so the
falling jet is never meshed. The volume left in the silo is the mass inside / rho, as
an experimentalist weighs what has come out.

References and checks
---------------------
* Beverloo, Leniger & van de Velde (1961); for a slot (plane flow) the rate per unit
  length is W = C rho sqrt(g) (B - k d)^(3/2); a continuum has no grain size d, so
  **Q ~ B^(3/2)**, and the rate does not depend on the filling height (the hour-glass
  regime). Staron, Lagree & Popinet (2012), Phys. Fluids 24, 103301: a 2D continuum
  with a friction coefficient above about 0.3 discharges at a constant rate and
  recovers Beverloo's scaling (here tan 31 deg = 0.60). Checked: V(t) linear over
  20-80 % discharged (R^2 of a linear fit >= 0.97); on a shorter silo, outlets
  B = 4, 8, 16 cm give a fitted exponent n of Q ~ B^n in [1.3, 1.7].
* The thesis (6.4.4, Fig 6.19): discharge "approximately 5 s for the smooth silo",
  "almost twice that for the rough silo"; ~500 steps of 0.01 s "sufficient".
  Checked at the thesis' geometry: time to V < 2 % V0 in [4, 6.5] s (smooth), the
  rough/smooth ratio in [1.5, 2.5]; the rate at dt = 0.01 s within 10 % of the rate at
  dt = 0.005 s. On another geometry: the smooth silo empties faster than the rough one.
* Exact property of the model: the mass in the silo plus the mass discharged is the
  initial mass (to round-off), and every particle is accounted for (inside, discharged,
  or created on a stretched surface edge).

Not gated: an experimental prefactor C (a rigid-plastic continuum has no grain size, and
its C depends on the wall friction, the hopper angle and psi = 0). C_eff = Q / (sqrt(g)
B^(3/2)) is reported (the thesis' 6015 cm2 in 5 s gives about 1.7).

Usage::

    python verification/silo_discharge.py --quick --json results/silo_discharge.json  # < 1 min
    python verification/silo_discharge.py --h 0.04 --dt 0.02 --dt-study 0.04 0.01 --B-study
        # the thesis' silo, 2 particles across the outlet: both walls, 3 time steps (16 min)
    python verification/silo_discharge.py --walls --dt-study --checkpoint-dir runs/silo
        # the outlet study alone: B = 4, 8, 16 cm on a silo filled 60 cm, 1 cm between
        # particles (some 6 h of one core; stopped, the same command goes on)
    python verification/silo_discharge.py --walls --dt-study --h-study 0.02
        # the same at 2 cm, two spacings across the 4 cm outlet (1.5 h)
    python verification/silo_discharge.py --help                                      # every option

The defaults (h = 1 cm, 6,198 particles; both walls; dt = 0.04 to 0.005 s; the outlet
study at 1 cm) are some 2,300 steps of 12-45 s and 950 of 18-42 s here, about a day
of one core; give --checkpoint-dir to stop and resume (``--h 0.02 --B-study``: the
thesis' silo at 2 cm, 2,100 steps of 4-7 s).
"""
import json
import os
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pfem_skfem.scene.config import PFEMConfig
from pfem_skfem.drivers.pfem_loop import config_summary
from pfem_skfem.materials import ZeroDilationMohrCoulomb
from pfem_skfem.problems.contact import RigidPolyline, RigidSegment
from pfem_skfem.discretisation import ThetaMethod
from pfem_skfem.drivers.resumable import Bar, Checkpoints, Frames, ResumableRun
from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, checkpoint_options, fraction, in_range,
                                        material_options, nonnegative_float, opt, pfem_options,
                                        positive_float, solver_keyword, sweep_options,
                                        time_options)
from pfem_skfem.harness.params import UNKEYED, Parameters
from pfem_skfem.harness.progress import progress
from pfem_skfem.harness.report import Report, thinned, script_main
from pfem_skfem.harness.sweeps import run_cases
from pfem_skfem.scene import Body, Geostatic, HalfPlane, Outlet, Region, Scene

# A coarse, short silo (2 particles across the outlet, dt = 0.04 s as the coarsest of
# Fig 6.19), both walls; no time-step or outlet study.
QUICK = dict(H=0.2, h=0.04, dt=0.04, t_max=4.0, dt_study=[], B_study=[], r2_min=0.9,
             snapshots_smooth=[0.0, 1.0, 2.0], snapshots_rough=[0.0, 1.0, 2.0])
THESIS = dict(W=0.5, H=1.0, Hh=0.35, B=0.08)          # Fig 6.16, as read above [m]
THESIS_T_EMPTY = 5.0            # s, smooth walls (6.4.4: "approximately 5 s")
THESIS_T_EMPTY_BAND = (4.0, 6.5)
THESIS_RATIO_BAND = (1.5, 2.5)  # rough / smooth: "almost twice that"
BEVERLOO_EXPONENT = 1.5         # plane flow, no grain size
EXPONENT_BAND = (1.3, 1.7)
DT_TOLERANCE = 0.10             # thesis Fig 6.19: dt = 0.01 s "sufficient"
LINEAR_WINDOW = (0.2, 0.8)      # discharged fraction over which the rate is fitted
STUDY_SPACINGS = 4              # particle spacings across the outlet study's narrowest outlet
MASS_TOLERANCE = 1e-12          # relative: the bookkeeping is exact up to round-off


def hopper_height(W, B, angle):
    """Height of a hopper of half-angle ``angle`` [rad] from the vertical, from W to B."""
    return 0.5 * (W - B) / np.tan(angle)


def silo_outline(W, H, Hh, B):
    """The material's polygon: outlet [-B/2, B/2] at y = 0, hopper up to y = Hh, bin to Hh + H."""
    return ((-B / 2, 0.0), (B / 2, 0.0), (W / 2, Hh), (W / 2, Hh + H), (-W / 2, Hh + H),
            (-W / 2, Hh))


@dataclass(frozen=True)
class Silo(Parameters):
    """The silo of thesis Fig 6.16, its scene and its checkpoint's keys (all but the solver).

    The material fills the polygon :func:`silo_outline` on a square lattice of spacing
    ``h``; the walls are two rigid polylines (the solid on the material's side, reaching
    half a metre above the fill) of friction ``mu``; the gate under the outlet is a body
    removed at t = 0; the outlet removes the particles below y = -``outlet_depth``.
    The lagged mean stress starts geostatic (K0 = 1 - sin phi); ``floor`` is the least
    cone radius in units of rho g L (L = Hh + H, the scene's length).
    """
    W: float = 0.5
    H: float = 1.0
    Hh: float = 0.35
    B: float = 0.08
    h: float = 0.01
    rho: float = 1.5
    c: float = 0.0
    phi: float = 31.0
    mu: float = 0.0
    g: float = 9.8
    dt: float = 0.01
    alpha: float = 1.6
    floor: float = 0.005
    passes: int = 2
    outlet_depth: float = 0.0
    solver: str = field(default="clarabel", metadata=UNKEYED)

    def scene(self):
        """(state, scene) of the silo."""
        W, H, Hh, B, mu = self.W, self.H, self.Hh, self.B, self.mu
        top = Hh + H + 0.5
        soil = ZeroDilationMohrCoulomb(c=self.c, phi=self.phi, k_min=self.floor)
        fill = Region(silo_outline(W, H, Hh, B), soil, self.rho, self.h, stress=Geostatic(),
                      name="fill")
        left = ((-W / 2, top), (-W / 2, Hh), (-B / 2, 0.0))
        right = ((B / 2, 0.0), (W / 2, Hh), (W / 2, top))
        bodies = (Body("left_wall", RigidPolyline(left, mu)),
                  Body("right_wall", RigidPolyline(right, mu)),
                  Body("gate", RigidSegment((-B, 0.0), (B, 0.0), mu), removed_at=0.0))
        orifice = Outlet("orifice", HalfPlane((0.0, -self.outlet_depth), (0.0, -1.0)))
        scene = Scene(regions=(fill,), bodies=bodies, outlets=(orifice,), gravity=(0.0, -self.g),
                      alpha=self.alpha, config=PFEMConfig(theta=ThetaMethod(self.dt),
                                                          passes=self.passes, solver=self.solver))
        return scene.initial_state(), scene


def discharge_rate(t, V, window=LINEAR_WINDOW):
    """Rate Q = -dV/dt of a least-squares line through (t, V) where the discharged fraction
    1 - V/V0 lies in ``window``; returns (Q, R^2, intercept, points used)."""
    t, V = np.asarray(t, dtype=float), np.asarray(V, dtype=float)
    out = 1 - V / V[0]
    use = (out >= window[0]) & (out <= window[1])
    if use.sum() < 3:
        return np.nan, np.nan, np.nan, int(use.sum())
    slope, intercept = np.polyfit(t[use], V[use], 1)
    resid = V[use] - (slope * t[use] + intercept)
    r2 = 1 - np.sum(resid ** 2) / np.sum((V[use] - V[use].mean()) ** 2)
    return float(-slope), float(r2), float(intercept), int(use.sum())


def emptying_time(t, V, fraction=0.02):
    """First time V < ``fraction`` V0, interpolated between records (nan if never)."""
    t, V = np.asarray(t, dtype=float), np.asarray(V, dtype=float)
    below = np.flatnonzero(V < fraction * V[0])
    if below.size == 0:
        return np.nan
    k = below[0]
    return float(np.interp(fraction * V[0], [V[k], V[k - 1]], [t[k], t[k - 1]]))


def beverloo_exponent(B, Q):
    """Exponent n of Q ~ B^n, least squares in log-log, and its prefactor."""
    n, logC = np.polyfit(np.log(B), np.log(Q), 1)
    return float(n), float(np.exp(logC))


def run_case(*, label, walls, t_max, empty, snapshot_times=(), outdir=None, save_every=0,
             verbose=False, checkpoint_dir=None, checkpoint_every=20, **silo):
    """One discharge (the :class:`Silo` of the keywords ``silo``) from the gate's removal
    until V < ``empty`` V0 or t = ``t_max``.

    With ``checkpoint_dir`` the state and the snapshots taken so far are saved there
    every ``checkpoint_every`` steps and at the end
    (:class:`~pfem_skfem.drivers.resumable.ResumableRun`), under a name made of the
    label and the scene's parameters; a run finds its own
    checkpoint and goes on from it (the same steps, bit for bit: a long study can span
    several sessions). A checkpoint of the state alone (as written before the snapshots
    were kept) is taken too: the snapshots of its earlier steps are then missing."""
    params = Silo(**silo)
    mu, W, H, Hh, B, h, dt, rho, g = (getattr(params, k) for k in "mu W H Hh B h dt rho g".split())
    state, scene = params.scene()
    x0, n0, m0 = state.x.copy(), state.n, state.total_mass
    first = {0: {"x": x0, "speed": np.zeros(n0)}} if 0.0 in snapshot_times else {}
    t0 = time.perf_counter()
    steps = int(np.ceil(t_max / dt - 1e-9))
    run = ResumableRun.open(
        scene, state, {"snaps": first},
        checkpoints=Checkpoints(directory=checkpoint_dir, label=f"silo_{label}", keys=params.keys(),
                                every=checkpoint_every, state_alone=True),
        frames=Frames(directory=None if outdir is None else Path(outdir) / label, name="silo",
                      every=save_every),
        bar=Bar(total=steps, desc=f"silo ({label})", verbose=verbose))
    snaps = run.kept["snaps"] = {**first, **run.kept["snaps"]}
    snap_steps = {int(round(s / dt)) for s in snapshot_times if s > 0}

    def observe(run, more):
        snaps.update({k: {"x": v["x"], "speed": np.linalg.norm(run.state.v, axis=1)}
                      for k, v in more.items()})

    run.advance(lambda run: not (run.state.step < steps and run.state.n > 0   # n = 0: all out
                                 and run.state.total_mass >= empty * m0),       # (or resumed done)
                observe, snapshots=snap_steps,
                postfix=lambda run: f"t = {run.state.time:.2f} s, "
                                    f"V/V0 = {run.state.total_mass / m0:.3f}")
    state, series = run.state, run.series
    seconds = time.perf_counter() - t0
    hist = state.history
    t = np.r_[0.0, hist["time"]]
    mass = np.r_[m0, hist["mass"]]
    out = np.r_[0.0, [d["orifice"] for d in hist["discharged"]]]
    n_out = int(hist["discharged_particles"][-1]["orifice"])
    n_inside = int(state.n)
    V = mass / rho
    Q, r2, intercept, used = discharge_rate(t, V)
    created = int(np.sum(hist["added"]) + np.sum(hist["surface_particles"])
                  - np.sum(hist["thinned"]))
    return {
        "label": label, "walls": walls, "mu": mu, "W": W, "H": H, "Hh": Hh, "B": B, "h": h,
        "dt": dt, "rho": rho, "V0": float(m0 / rho), "area0": float(scene.regions[0].area),
        "particles0": n0, "steps": len(t) - 1, "t_end": float(t[-1]),
        "t_empty": emptying_time(t, V, empty), "Q": Q, "r2": r2, "fit_intercept": intercept,
        "fit_points": used, "C_eff": Q / (np.sqrt(g) * B ** 1.5),
        "mass_error": float(np.max(np.abs(mass + out - m0)) / m0),
        "particles_inside": n_inside, "particles_discharged": n_out,
        "particles_created": created,
        "particle_balance": int(n_inside + n_out - n0 - created),
        "free_particles_max": int(np.max(hist["free_particles"])),
        "inaccurate_passes": int(np.sum(hist["inaccurate"])),
        "seconds": seconds, "seconds_per_step": float(np.mean(hist["seconds"])),
        "t": t.tolist(), "V": V.tolist(), "mesh_area": [float(scene.regions[0].area)]
        + list(hist["area"]),
        "snapshots": {k * dt: v for k, v in sorted(snaps.items())},
        "config": config_summary(scene),
        "pvd": str(series.pvd_path) if series is not None else None,
    }


def check(args):
    if args.phi == 0 and args.c == 0:
        return "--phi 0 with --c 0 is a material without strength: give --c > 0 or --phi > 0"
    if not (args.walls or args.dt_study or args.B_study):
        return "nothing to run: give --walls, --dt-study or --B-study"
    hs = study_spacing(args)
    if args.B_study and hs > min(args.B_study) / 1.5:
        return (f"--h-study {hs:g} leaves fewer than 1.5 spacings across the outlet "
                f"{min(args.B_study):g}")
    if args.B >= args.W or any(b >= args.W for b in args.B_study):
        return "--B (and --B-study) must be narrower than the bin --W"
    if args.h > args.B / 1.5:
        return f"--h {args.h:g} leaves fewer than 1.5 spacings across the outlet --B {args.B:g}"
    if not 0 < args.empty < LINEAR_WINDOW[0]:
        return f"--empty must lie in (0, {LINEAR_WINDOW[0]})"
    return None


def study_spacing(args):
    """The particle spacing of the outlet study: ``--h-study``, by default a quarter of the
    narrowest outlet (with two spacings across it the rate is 13 % above the rate with four)."""
    if args.h_study is not None:
        return args.h_study
    return min(args.B_study) / STUDY_SPACINGS if args.B_study else args.h


# an outlet plane above the orifice lies inside the hopper: it removes material that has not
# flowed out (at --outlet-depth -1, every particle at t = 0)
OUTLET_DEPTH = in_range(0.0, what="a depth >= 0 [m] below the orifice (a negative one puts "
                                  "the outlet plane inside the hopper, where it removes "
                                  "material that has not flowed out)")


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    p.add_argument("--W", type=positive_float, default=THESIS["W"], help="bin width [m]")
    p.add_argument("--H", type=positive_float, default=THESIS["H"],
                   help="fill height of the vertical bin walls above the hopper [m]")
    p.add_argument("--Hh", type=positive_float, default=THESIS["Hh"], help="hopper height [m]")
    p.add_argument("--B", type=positive_float, default=THESIS["B"], help="outlet width [m]")
    material_options(p, rho=1.5, c=opt(0.0, type=nonnegative_float), phi=31.0, g=9.8)
    p.add_argument("--walls", nargs="*", choices=("smooth", "rough"), default=["smooth", "rough"],
                   help="wall-solid interfaces: smooth mu = 0, rough mu = tan phi")
    pfem_options(p, h=opt(0.01, why="0.01: 8 across the outlet, 6,198 particles; at 0.02 the "
                                    "smooth silo empties at 3.96 s, below the thesis' 4-6.5 s"),
                 alpha=1.6, k_min=opt(0.005, dest="floor", why="a fraction of rho g (Hh + H)"),
                 passes=2)
    time_options(p, dt=0.01, save_every=opt(0, why="a PVD per case"))
    p.add_argument("--dt-study", type=positive_float, nargs="*", default=[0.04, 0.02, 0.005],
                   help="further time steps [s] for the smooth silo (Fig 6.19)")
    p.add_argument("--B-study", type=positive_float, nargs="*", default=[0.04, 0.08, 0.16],
                   help="outlet widths [m] of the scaling study (smooth, on the silo of "
                        "--H-study; the hopper keeps its half-angle)")
    p.add_argument("--H-study", type=positive_float, default=0.6,
                   help="fill height [m] of the bin in the outlet study (0.6: a fill of 0.2 "
                        "slows the 16 cm outlet's rate by 11 %%, see the book)")
    p.add_argument("--h-study", type=positive_float, default=None,
                   help=f"particle spacing [m] in the outlet study (default: the narrowest "
                        f"outlet / {STUDY_SPACINGS}; at two spacings across, its rate is 13 %% "
                        f"above the rate at four, see the book)")
    p.add_argument("--outlet-depth", type=OUTLET_DEPTH, default=0.0,
                   help="the outlet plane lies this far below the orifice [m]")
    p.add_argument("--t-max", type=positive_float, default=14.0,
                   help="longest simulated time [s] of a run")
    p.add_argument("--empty", type=positive_float, default=0.02,
                   help="a silo is empty when V < empty V0 (the discharge time)")
    p.add_argument("--r2-min", type=fraction, default=0.97,
                   help="least R^2 of the linear fit of V(t) over 20-80 %% discharged")
    p.add_argument("--snapshots-smooth", type=nonnegative_float, nargs="*",
                   default=[0.0, 1.0, 2.0, 3.5, 4.0, 4.5], help="times [s] (Fig 6.17)")
    p.add_argument("--snapshots-rough", type=nonnegative_float, nargs="*",
                   default=[0.0, 3.0, 5.0, 6.0, 7.0, 8.0], help="times [s] (Fig 6.18)")
    checkpoint_options(p, "run")
    sweep_options(p, default_workers=min(2, os.cpu_count() or 1), what="the runs")
    return p


def _cases(args):
    """(main runs, time-step study, outlet study) as run_case keywords."""
    tan_phi = float(np.tan(np.radians(args.phi)))
    common = dict(W=args.W, H=args.H, Hh=args.Hh, B=args.B, h=args.h, rho=args.rho, c=args.c,
                  phi=args.phi, g=args.g, dt=args.dt, alpha=args.alpha, floor=args.floor,
                  passes=args.passes, outlet_depth=args.outlet_depth, t_max=args.t_max,
                  empty=args.empty, verbose=args.progress, save_every=args.save_every,
                  checkpoint_dir=args.checkpoint_dir, checkpoint_every=args.checkpoint_every,
                  outdir=(Path(args.outdir) / "silo_discharge") if args.save_every else None,
                  **solver_keyword(args))
    main = [dict(common, walls=w, mu=0.0 if w == "smooth" else tan_phi, label=f"{w}_dt{args.dt:g}",
                 snapshot_times=getattr(args, f"snapshots_{w}")) for w in args.walls]
    smooth = dict(common, walls="smooth", mu=0.0, snapshot_times=())
    dts = [dict(smooth, dt=d, label=f"smooth_dt{d:g}") for d in args.dt_study if d != args.dt]
    angle = np.arctan(0.5 * (args.W - args.B) / args.Hh)
    hs = study_spacing(args)
    # only the rate is needed: each stops once 80 % is out (the end of the fitted window)
    outlets = [dict(smooth, B=b, H=args.H_study, Hh=hopper_height(args.W, b, angle), h=hs,
                    empty=1 - LINEAR_WINDOW[1], label=f"outlet_B{b:g}") for b in args.B_study]
    return main, dts, outlets


def run(args):
    """The discharges of ``args`` (walls, time steps, outlets) in parallel; their checks."""
    main, dts, outlets = _cases(args)
    cases = main + dts + outlets
    if args.progress:
        progress(f"{len(cases)} case(s) on "
                 f"{args.scheduler or str(args.workers) + ' worker(s)'}")
    results = run_cases(run_case, cases, args.workers, desc="silos",
                        scheduler=args.scheduler, results_dir=args.results_dir)
    runs = results[:len(main)]
    dt_runs = results[len(main):len(main) + len(dts)]
    outlet_runs = results[len(main) + len(dts):]

    report = Report("silo_discharge", args)
    report.add_table(
        "discharges", ["case", "walls", "B [cm]", "H [cm]", "dt", "n0", "V0 [cm2]", "Q [cm2/s]",
                       "R^2", "C_eff", "t_empty", "mass err", "steps", "s/step", "reduced"],
        [[r["label"], r["walls"], 100 * r["B"], 100 * r["H"], r["dt"], r["particles0"],
          1e4 * r["V0"], 1e4 * r["Q"], r["r2"], r["C_eff"], r["t_empty"], r["mass_error"],
          r["steps"], r["seconds_per_step"], r["inaccurate_passes"]] for r in results],
        formats={"B [cm]": ".1f", "H [cm]": ".1f", "dt": ".3f", "V0 [cm2]": ".0f",
                 "Q [cm2/s]": ".1f", "R^2": ".3f", "C_eff": ".2f", "t_empty": ".2f",
                 "mass err": ".1e", "s/step": ".2f"})
    print("reduced: solver passes that ended 'AlmostSolved' (Clarabel's reduced accuracy, "
          "accepted by the engine and counted)")
    for r in results:                     # exact: mass and particles accounted for
        report.add_interval(f"{r['label']}_mass_balance", r["mass_error"], 0.0, MASS_TOLERANCE,
                            "inside + discharged = initial mass (round-off)")
        report.add(f"{r['label']}_particle_balance", r["particle_balance"], 0,
                   "n inside + n discharged - n0 - n created = 0", 0)
    for r in runs:                        # hour-glass regime: constant rate
        report.add_interval(f"{r['label']}_linearity_R2", r["r2"] if np.isfinite(r["r2"]) else 0,
                            args.r2_min, 1.0, "V(t) linear over 20-80 % discharged (Beverloo; "
                            "Staron, Lagree & Popinet 2012)")
    thesis = all(np.isclose(getattr(args, k), v) for k, v in THESIS.items())
    by_walls = {r["walls"]: r for r in runs}
    if "smooth" in by_walls and thesis:
        report.add_interval("t_empty_smooth", np.nan_to_num(by_walls["smooth"]["t_empty"],
                                                            nan=np.inf),
                            *THESIS_T_EMPTY_BAND, "thesis 6.4.4: approximately 5 s",
                            reference=THESIS_T_EMPTY)
    if len(by_walls) == 2:
        s, r = by_walls["smooth"], by_walls["rough"]
        if thesis and np.isfinite(s["t_empty"]):
            ratio = r["t_empty"] / s["t_empty"] if np.isfinite(r["t_empty"]) else np.inf
            report.add_interval("t_empty_rough_over_smooth", ratio, *THESIS_RATIO_BAND,
                                "thesis 6.4.4: rough almost twice the smooth", reference=2.0)
        report.add_interval("Q_smooth_over_rough", s["Q"] / r["Q"], 1.0, np.inf,
                            "the smooth silo empties faster (thesis 6.4.4)")
    smooth_main = [r for r in runs if r["walls"] == "smooth"]
    finer = [r for r in dt_runs if r["dt"] < args.dt]
    if smooth_main and finer:
        ref = min(finer, key=lambda r: r["dt"])
        report.add(f"Q_dt{args.dt:g}_vs_dt{ref['dt']:g}", smooth_main[0]["Q"], ref["Q"],
                   "thesis Fig 6.19: dt = 0.01 s sufficient", DT_TOLERANCE)
    if len(outlet_runs) >= 2:
        B = np.array([r["B"] for r in outlet_runs])
        Q = np.array([r["Q"] for r in outlet_runs])
        n, C = beverloo_exponent(B, Q) if np.all(np.isfinite(Q)) else (np.nan, np.nan)
        report.add_interval("beverloo_exponent", n if np.isfinite(n) else 0, *EXPONENT_BAND,
                            "Beverloo, plane flow, no grain size: Q ~ B^(3/2)",
                            reference=BEVERLOO_EXPONENT)
        report.extra["beverloo_fit"] = {"exponent": n, "prefactor": C}
    report.extra["cases"] = [_summary(r) for r in results]
    report.data = dict(runs=runs, dt_runs=dt_runs, outlet_runs=outlet_runs)
    return report


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


def _summary(r):
    """A case without its snapshots and configuration, its histories thinned."""
    return thinned(r, ("t", "V", "mesh_area"), drop=("snapshots", "config"), entries=200)


def _walls(ax, r):
    W, H, Hh, B = (100 * r[k] for k in ("W", "H", "Hh", "B"))
    top = Hh + H + 5
    ax.plot([-W / 2, -W / 2, -B / 2], [top, Hh, 0], "k-", lw=1.5)
    ax.plot([B / 2, W / 2, W / 2], [0, Hh, top], "k-", lw=1.5)
    ax.axhline(0.0, color="r", lw=0.6, ls="--")


def figures(args, runs, dt_runs, outlet_runs):
    """Fig 6.17-6.18 (snapshots coloured by speed), Fig 6.19 (volume in the silo against
    time, both walls and the time steps), Q against B with the B^(3/2) line."""
    plt = pyplot()
    out = figure_dir(args, "silo_discharge")
    for r in runs:
        times = sorted(r["snapshots"])
        if not times:
            continue
        fig, axes = plt.subplots(1, len(times), figsize=(2.2 * len(times) + 1, 4.2),
                                 squeeze=False)
        vmax = max(float(np.max(s["speed"])) for s in r["snapshots"].values()) or 1.0
        for ax, tk in zip(axes[0], times):
            s = r["snapshots"][tk]
            sc = ax.scatter(100 * s["x"][:, 0], 100 * s["x"][:, 1], c=s["speed"], s=3,
                            cmap="viridis", vmin=0, vmax=vmax)
            _walls(ax, r)
            ax.set_aspect("equal")
            ax.set_xlim(-100 * r["W"] / 2 - 3, 100 * r["W"] / 2 + 3)
            ax.set_ylim(-8, 100 * (r["H"] + r["Hh"]) + 8)
            ax.set_title(f"{tk:.1f} s", fontsize=9)
            ax.set_xlabel("x [cm]", fontsize=8)
            ax.tick_params(labelsize=7)
        axes[0, 0].set_ylabel("y [cm]")
        fig.suptitle(f"{r['walls']} silo (mu = {r['mu']:.2f}), particles coloured by speed\n"
                     f"dashed: the outlet plane (cf. Fig 6.{17 if r['walls'] == 'smooth' else 18})",
                     fontsize=9)
        fig.tight_layout()
        fig.colorbar(sc, ax=axes[0].tolist(), label="speed [m/s]", shrink=0.8)
        fig.savefig(out / f"snapshots_{r['walls']}.png", dpi=120)
        plt.close(fig)

    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    if not runs + dt_runs:
        plt.close(fig)
    for r in runs + dt_runs:
        ls = "-" if r in runs else ":"
        ax.plot(r["t"], 1e4 * np.asarray(r["V"]) / 1000, ls,
                label=f"{r['walls']}, dt = {r['dt']:g} s (Q = {1e4 * r['Q']:.0f} cm2/s)")
        if np.isfinite(r["Q"]):
            tt = np.linspace(0, r["t"][-1], 2)
            ax.plot(tt, 1e4 * (r["fit_intercept"] - r["Q"] * tt) / 1000, "k-", lw=0.5, alpha=0.5)
    if runs + dt_runs and all(np.isclose((runs + dt_runs)[0][k], v) for k, v in THESIS.items()):
        ax.axvspan(*THESIS_T_EMPTY_BAND, color="C0", alpha=0.1,
                   label="thesis: smooth empty ~5 s (band 4-6.5 s)")
        ax.axvline(2 * THESIS_T_EMPTY, color="C1", ls="--", lw=1, label="thesis: rough ~2 x 5 s")
    if runs + dt_runs:
        ax.set_ylim(0, None)
        ax.set_xlabel("time t [s]")
        ax.set_ylabel("volume in silo [1000 cm2 per unit thickness]")
        ax.set_title("volume in the silo against time (cf. Fig 6.19); thin: linear fits 20-80 %")
        ax.legend(fontsize=7)
        save_figure(fig, out / "volume_vs_time.png")

    if len(outlet_runs) >= 2:
        B = np.array([r["B"] for r in outlet_runs])
        Q = np.array([r["Q"] for r in outlet_runs])
        fig, (ax0, ax) = plt.subplots(1, 2, figsize=(10, 4))
        for r in outlet_runs:
            ax0.plot(r["t"], np.asarray(r["V"]) / r["V0"], label=f"B = {100 * r['B']:g} cm")
        ax0.axhspan(1 - LINEAR_WINDOW[1], 1 - LINEAR_WINDOW[0], color="k", alpha=0.08,
                    label="fitted window (20-80 % out)")
        ax0.set_xlabel("time t [s]")
        ax0.set_ylabel("V / V0")
        ax0.set_title(f"outlet study: silo filled {100 * outlet_runs[0]['H']:g} cm above the "
                      "hopper", fontsize=9)
        ax0.legend(fontsize=8)
        ax.loglog(100 * B, 1e4 * Q, "o", label="PFEM, smooth")
        bb = np.geomspace(B.min() / 1.2, B.max() * 1.2, 20)
        mid = np.exp(np.mean(np.log(Q / B ** 1.5)))
        ax.loglog(100 * bb, 1e4 * mid * bb ** 1.5, "k--", label="Beverloo, Q ~ B^(3/2)")
        n, _ = beverloo_exponent(B, Q) if np.all(np.isfinite(Q)) else (np.nan, 0)
        ax.set_xlabel("outlet width B [cm]")
        ax.set_ylabel("discharge rate Q [cm2/s per unit thickness]")
        ax.set_title(f"outlet-size scaling: fitted n = {n:.2f}")
        ax.legend(fontsize=8)
        save_figure(fig, out / "rate_vs_outlet.png")
    (out / "summary.json").write_text(json.dumps(
        [_summary(r) for r in runs + dt_runs + outlet_runs],
        default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o), indent=1))


if __name__ == "__main__":
    sys.exit(main())
