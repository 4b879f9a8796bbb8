"""Yangbaodi landslide (thesis Ch 8): held initial stress, release, adaptive alpha, friction back-analysis.

A fill slope of decomposed granite failed on 18 September 2002 after prolonged
rainfall and flowed onto the flat ground below (Li et al. 2012, the thesis' [92]). The
thesis models it in plane strain: the slip surface, known from in-situ evidence, is a
rigid frictional boundary (friction coefficient mu, back-analysed); the sliding mass is
rigid-plastic Mohr-Coulomb with phi = 28 deg, c = 0, psi = 0 (the zero-dilation scheme
of [80]) and rho = 1.25 t/m3; about 2,000 P2 triangles; dt = 0.05 s with
theta1 = theta2 = 1; the displacements of every surface node are held zero for the
first 10 s to build the initial stress, then released; the alpha-shape parameter is
adapted, alpha_n = m0 alpha_0 / m_n, to keep the mass ("within 2 %").

Here the slide is a scene of the PFEM engine (:mod:`pfem_skfem.drivers.pfem_loop`):
one region (the mass between the slip surface and the ground surface of a profile), one
rigid polyline body (the slip surface, contact cones (5.12) of friction mu), a held
phase ``Phase(until=t_hold, hold="boundary")`` (every boundary node of the mesh held
still), then free motion until the kinetic energy is below ``--rest`` times its peak (once the centre
of mass has moved a spacing: the release transient's own peak does not count).
The move stage's volume projection (``PFEMConfig(volume_correction=True)``,
:mod:`pfem_skfem.pfem.volume_projection`) is on by default (``--volume-correction off``):
without it every step loses the second-order part of its area change, O(dt) over a run.
So is the detection with the advected domain (``PFEMConfig(alpha_advected=3)``,
``--alpha-advected 0`` for the plain alpha-shape): the thinning front keeps its
flattened triangles instead of losing them to the alpha test.

The profile. The thesis' geometry exists only in its Fig 8.3, whose text keeps nothing
but the axes: ``data/yangbaodi_profile.csv`` is a profile *reconstructed* from what the
text states (failure between 130 and 199 m, flat ground below, its provenance at its top),
not digitised. ``--profile PATH`` reads any other profile of the same format (x,
z_slip, z_surface; x increasing), checked before any work
(:class:`~pfem_skfem.scene.slope_profile.Profile`).

Checks
------
* mass (the detected area, density constant): its largest change after release within
  2 % with adaptive alpha (the thesis' claim); the change without it is reported beside;
* the held phase keeps every particle still (largest displacement below 1e-9 h);
* energy bound: once at rest, the travel angle of the centre of mass, atan(H_cm / L_cm)
  from its start to its end, is not below atan(mu): basal friction dissipates
  mu m g per unit of horizontal travel on a concave profile (the normal force is at
  least the weight's component there) and plastic work and numerical damping only add;
  for every mu of the sweep (the ratio tan(travel angle) / mu >= 1);
* the run-out (the front's largest x) decreases as mu grows (thesis Fig 8.4);
* density invariance (c = 0): every force scales with rho, so rho = 2.5 gives the front
  history of rho = 1.25 bit for bit (a factor of two scales every floating-point number
  exactly) and rho = 0.5 within 2 % of the front's travel (round-off grows through
  remeshing); the thesis finds "little difference";
* the motion ends (kinetic energy below 1e-3 of its peak, the centre of mass moved at least
  one spacing h) within the run; a mass that does not move fails this and the energy bound
  (undefined: no travel angle), it never passes them.

Reported beside the thesis, not gated (the geometry is reconstructed): the front's
largest reach and its time (thesis: about 325 m, about 20 s after release) and the end
of motion (about 25 s after release).

Usage::

    python verification/landslide_yangbaodi.py --quick --json results/landslide.json
        # 3 coarse slides (h = 4 m): about a minute on an idle core pair
    python verification/landslide_yangbaodi.py --h 2.5 --dt 0.125 --t-hold 1 --save-every 8
        # the six slides at a medium size, VTU/PVD per slide (32 min on a shared machine)
    python verification/landslide_yangbaodi.py --save-every 10
        # the thesis' size, about 2,000 triangles: about 2 h a slide here
    python verification/landslide_yangbaodi.py --profile my_slope.csv --mu-study 8 12
    python verification/landslide_yangbaodi.py --help                        # every option
"""
import os
import pickle
import sys
import time
from pathlib import Path

import numpy as np

if __package__ in (None, ""):                     # run as a file: the repository's root
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from pfem_skfem.scene.config import PFEMConfig           # noqa: E402
from pfem_skfem.drivers.pfem_loop import config_summary           # noqa: E402
from pfem_skfem.materials import ZeroDilationMohrCoulomb                      # noqa: E402
from pfem_skfem.pfem.measure import centre_of_mass, front                      # noqa: E402
from pfem_skfem.problems.contact import RigidPolyline                         # noqa: E402
from pfem_skfem.discretisation import ThetaMethod                           # noqa: E402
from pfem_skfem.drivers.resumable import Bar, Checkpoints, Frames, ResumableRun  # noqa: E402
from pfem_skfem.harness.declare import keywords_of, own_options  # noqa: E402
from pfem_skfem.harness.figures import (figure_dir, labelled, pyplot,  # noqa: E402
                                        save_figure, write_summary)
from pfem_skfem.harness.options import (base_parser, checkpoint_options,  # noqa: E402
                                        in_range, material_options, nonnegative_float, opt,
                                        pfem_options, positive_angle, positive_float,
                                        time_options)
from pfem_skfem.harness.report import Report, script_main, thinned  # noqa: E402
from pfem_skfem.harness.sweeps import run_groups  # noqa: E402
from pfem_skfem.harness.options import workers as worker_count  # noqa: E402
from pfem_skfem.scene import Body, Phase, Region, Scene                       # noqa: E402
from pfem_skfem.scene.slope_profile import read_profile                      # noqa: E402
from pfem_skfem.viz import plot_ground, plot_histories, snapshot_grid  # noqa: E402

PROFILE = Path(__file__).resolve().parent / "data" / "yangbaodi_profile.csv"
# A coarse mass (about 4 particles through its thickness) on the same profile; dt in
# proportion to h (the same displacement per step in spacings); a hold of four steps
# (the held stress settles in three, see the book); rougher slip surfaces than the
# thesis' (shorter runs), the density doubled beside, no run with alpha fixed.
QUICK = dict(h=4.0, dt=0.2, t_hold=0.8, t_after=40.0, mu_deg=14.0, mu_study=[14.0, 18.0],
             no_alpha_study=True, rho_study=[2.5])
THESIS_FRONT = 325.0            # m, the front's largest horizontal position (Fig 8.5)
THESIS_FRONT_TIME = 20.0        # s after release
THESIS_END = 25.0               # s after release: "the entire sliding process is finished"
MASS_TOLERANCE = 0.02           # thesis 8.3: "always within 2 %"
DENSITY_TOLERANCE = 0.02        # rho = 0.5 against 1.25, relative to the front's travel
HOLD_STILL = 1e-9               # largest displacement in the held phase, in spacings h
WARNING = ("the profile is reconstructed from the thesis' text and axes (not digitised): "
           "compare reach and times with the thesis' only as an indication")
#: the base run beside the thesis (Fig 8.5, Section 8.3): reach [m], its time, the end [s]
THESIS = {"front_max": THESIS_FRONT, "t_front_max": THESIS_FRONT_TIME, "t_rest": THESIS_END}
#: a run's histories, thinned to about 200 entries in the JSON; what the JSON leaves out
HISTORIES = ("t", "front", "ke", "area_change", "alpha")
LEFT_OUT = ("cm", "points", "track_x", "track_v", "x_end", "x0", "snapshots", "profile", "config")


# -- the scene -----------------------------------------------------------------------------
def landslide(profile, *, h=0.95, rho=1.25, phi=28.0, c=0.0, mu=np.tan(np.radians(10.0)),
              g=9.8, dt=0.05, theta1=1.0, theta2=1.0, alpha=1.6, adaptive_alpha=True,
              t_hold=10.0, hold="boundary", floor=0.005, passes=2, volume_correction=False,
              alpha_advected=0.0, solver="clarabel"):
    """The slide as a scene, and its initial state.

    The mass fills the :meth:`~pfem_skfem.scene.slope_profile.Profile.mass_polygon` of
    ``profile`` (a :class:`~pfem_skfem.scene.slope_profile.Profile`) on a square lattice of
    spacing ``h``, with no initial stress: the held phase (``hold`` until ``t_hold``) builds
    it. The slip surface is a fixed rigid polyline through the whole profile, friction ``mu``.
    ``floor`` is the least cone radius in units of rho g L, L the mass's largest thickness
    (the scene's length), so that no stress is absolute.

    Returns (state, scene).
    """
    soil = ZeroDilationMohrCoulomb(c=c, phi=phi, k_min=floor)
    mass = Region(profile.mass_polygon(), soil, rho, h, name="mass")
    slip = Body("slip_surface", RigidPolyline(tuple(zip(profile.x, profile.z_slip)), mu))
    n_hold = int(round(t_hold / dt))        # steps held; the phase ends between two steps
    phases = (Phase(until=(n_hold - 0.5) * dt, hold=hold, name="hold"),) if n_hold else ()
    scene = Scene(regions=(mass,), bodies=(slip,), phases=phases, gravity=(0.0, -g),
                  alpha=alpha, adaptive_alpha=adaptive_alpha, length=profile.thickness,
                  config=PFEMConfig(theta=ThetaMethod(dt, theta1, theta2), passes=passes,
                                    volume_correction=volume_correction,
                                    alpha_advected=alpha_advected, solver=solver))
    return scene.initial_state(), scene


def material_points(state, profile, fractions=(0.15, 0.5, 0.85)):
    """Indices of the particles nearest the mass's mid-depth at the given fractions of its
    horizontal extent, crown to toe: the rear (A), middle (B) and front (C) points."""
    i0, i1 = profile.mass_range
    x0, x1 = profile.x[i0], profile.x[i1]
    out = []
    for f in fractions:
        xp = x0 + f * (x1 - x0)
        zp = 0.5 * (np.interp(xp, profile.x, profile.z_slip)
                    + np.interp(xp, profile.x, profile.z_surface))
        out.append(int(np.argmin(np.linalg.norm(state.x - (xp, zp), axis=1))))
    return out


def came_to_rest(ke, peak, ke_first, travel, h, rest):
    """Whether a slide is at rest: its kinetic energy ``ke`` below ``rest`` times its
    ``peak`` and below its first value after release, once its centre of mass has travelled
    ``travel`` >= one spacing ``h``. The release transient (the held stress settling into
    the free mass) has a kinetic energy peak of its own: a mass that never moves, or one
    that starts to slide only slowly, fell below ``rest`` of that peak within a few steps
    and was called at rest. A mass that never moves runs to ``--t-after`` and is reported
    not at rest (and its travel angle undefined)."""
    return bool(peak > 0 and ke < rest * peak and ke < ke_first and travel >= h)


def energy_ratio(H, L, mu, travel, h):
    """tan(travel angle of the centre of mass) / mu = H / (mu L); NaN (undefined: a failed
    check, never a pass) when the centre of mass moved less than one spacing ``h`` or not
    forwards (L <= 0), or mu = 0."""
    if not (travel >= h and L > 0 and mu > 0):
        return np.nan
    return float(H / (mu * L))


def run_case(args, *, mu_deg, rho=None, adaptive_alpha=True, snapshot_every=0.0):
    """One slide of the options ``args`` (profile, mesh, material, steps, ``--rest``,
    output, checkpoints) at the basal friction angle ``mu_deg``, the density ``rho``
    (None: ``--rho``) and with or without adaptive alpha: the held phase, then free motion
    until the kinetic energy is below ``--rest`` times its peak (after the peak) or
    ``--t-after`` after release; snapshots every ``snapshot_every`` seconds (0: none).
    Its label (its checks, checkpoint and frames) says what differs from a base slide:
    ``mu10``, ``mu10_rho2.5``, ``mu10_fixed_alpha``.

    With ``--checkpoint-dir`` the state and the measurements so far are saved there every
    ``--checkpoint-every`` steps and at the end
    (:class:`~pfem_skfem.drivers.resumable.ResumableRun`),
    under the label and a digest of the slide's parameters and profile; a run finds its own
    checkpoint and goes on from it, the same steps bit for bit (a slide of the thesis'
    size takes hours here). Snapshots are taken only in the steps run this time."""
    profile, h, dt = read_profile(args.profile), args.h, args.dt
    label = (f"mu{mu_deg:g}" + (f"_rho{rho:g}" if rho is not None else "")
             + ("" if adaptive_alpha else "_fixed_alpha"))
    rho = args.rho if rho is None else rho
    mu = float(np.tan(np.radians(mu_deg)))
    scene_keys = keywords_of(landslide, args, profile=profile, mu=mu, rho=rho,
                             adaptive_alpha=adaptive_alpha,
                             volume_correction=args.volume_correction == "on")
    state, scene = landslide(**scene_keys)
    x0, n0 = state.x.copy(), state.n
    points = material_points(state, profile)
    n_hold = int(round(args.t_hold / dt))
    n_after = int(round(args.t_after / dt))
    snap_every = int(round(snapshot_every / dt)) if snapshot_every else 0
    t_release = n_hold * dt
    cm0 = centre_of_mass(state)
    # how the held stress settles (hold_changes): the largest change of the lagged mean
    # stress from one held step to the next, in units of the stress scale rho g L
    loop = dict(rec={k: [] for k in ("t", "front", "ke", "area_change", "alpha", "cm",
                                     "sigma_m_min")},
                track={"x": [], "v": []}, snaps={0.0: {"x": x0, "speed": np.zeros(n0)}},
                hold_moved=0.0, hold_changes=[], sigma_m_held=None, at_rest=False, peak=0.0)
    keys = {k: v for k, v in scene_keys.items() if k not in ("mu", "solver")} | dict(
        mu_deg=mu_deg, profile=[profile.x.tolist(), profile.z_slip.tolist(),
                                profile.z_surface.tolist()])
    t0 = time.perf_counter()
    run = ResumableRun.open(
        scene, state, loop,
        checkpoints=Checkpoints(directory=args.checkpoint_dir, label=f"landslide_{label}",
                                keys=keys, every=args.checkpoint_every),
        frames=Frames(directory=Path(args.outdir) / "landslide_yangbaodi" / label
                      if args.save_every else None, name="landslide", every=args.save_every),
        bar=Bar(total=n_hold + n_after, desc=f"landslide ({label})", verbose=args.progress))
    loop = run.kept
    rec, track, snaps = loop["rec"], loop["track"], loop["snaps"]

    def observe(run, more):
        state, hist = run.state, run.state.history
        if np.any(np.asarray(hist["thinned"])) or state.n < n0:
            raise RuntimeError("particles were removed: the material points are lost")
        if state.step <= n_hold:                     # the held phase
            loop["hold_moved"] = max(loop["hold_moved"],
                                     float(np.max(np.abs(state.x[:n0] - x0))))
            if loop["sigma_m_held"] is not None:
                loop["hold_changes"].append(
                    float(np.max(np.abs(state.sigma_m[:n0] - loop["sigma_m_held"])))
                    / scene.stress_scale)
            loop["sigma_m_held"] = state.sigma_m[:n0].copy()
            return
        rec["t"].append(state.time - t_release)
        rec["front"].append(front(state))
        rec["ke"].append(hist["kinetic_energy"][-1])
        rec["area_change"].append(hist["area_change"][-1])
        rec["alpha"].append(hist["alpha"][-1])
        rec["cm"].append(centre_of_mass(state))
        rec["sigma_m_min"].append(float(state.sigma_m.min()))
        track["x"].append(state.x[points].copy())
        track["v"].append(state.v[points].copy())
        k = state.step - n_hold
        if snap_every and k % snap_every == 0:
            snaps[k * dt] = {"x": state.x.copy(), "speed": np.linalg.norm(state.v, axis=1)}
        loop["peak"] = max(loop["peak"], rec["ke"][-1])
        travel = float(np.linalg.norm(rec["cm"][-1] - cm0))
        loop["at_rest"] = came_to_rest(rec["ke"][-1], loop["peak"], rec["ke"][0], travel, h,
                                       args.rest)

    run.advance(lambda run: run.state.step >= n_hold + n_after or loop["at_rest"], observe,
                postfix=lambda run: f"t = {run.state.time:.2f} s, "
                                    f"front {front(run.state):.1f} m")
    state, series = run.state, run.series
    hold_changes, sigma_m_held = loop["hold_changes"], loop["sigma_m_held"]
    hold_moved, at_rest = loop["hold_moved"], loop["at_rest"]
    seconds = time.perf_counter() - t0
    t = np.asarray(rec["t"])
    fr = np.asarray(rec["front"])
    ke = np.asarray(rec["ke"])
    cm = np.asarray(rec["cm"]) if rec["cm"] else cm0[None]
    cm_end = cm[-1]
    H, L = float(cm0[1] - cm_end[1]), float(cm_end[0] - cm0[0])
    travel = float(np.hypot(H, L))
    k_peak = int(np.argmax(fr)) if len(fr) else 0
    hist = state.history
    return {
        "label": label, "mu_deg": mu_deg, "mu": mu, "rho": rho, "h": h, "dt": dt,
        "adaptive_alpha": adaptive_alpha, "t_hold": n_hold * dt, "hold": args.hold,
        "particles0": n0, "elements0": int(hist["elements"][0]),
        "elements_mean": float(np.mean(hist["elements"])),
        "area0": float(scene.regions[0].area), "stress_scale": scene.stress_scale,
        "hold_max_displacement_over_h": hold_moved / h,
        "hold_sigma_m_changes": hold_changes,
        "hold_sigma_m_last_change": hold_changes[-1] if hold_changes else np.nan,
        "hold_sigma_m_min": float(sigma_m_held.min()) if sigma_m_held is not None else np.nan,
        "steps_after_release": len(t), "at_rest": at_rest,
        "t_rest": float(t[-1]) if at_rest else np.nan,
        "front0": float(np.max(x0[:, 0])), "front_max": float(fr.max()) if len(fr) else np.nan,
        "t_front_max": float(t[k_peak]) if len(t) else np.nan,
        # a NaN front is not on the profile (NaN > x is False)
        "front_beyond_profile": bool(len(fr) and not fr.max() <= profile.x[-1]),
        "ke_peak": float(ke.max()) if len(ke) else 0.0,
        "ke_end_over_peak": float(ke[-1] / ke.max()) if len(ke) and ke.max() > 0 else np.nan,
        "mass_change_max": float(np.max(np.abs(rec["area_change"]))) if len(t) else 0.0,
        "mass_change_end": float(rec["area_change"][-1]) if len(t) else 0.0,
        "cm0": cm0.tolist(), "cm_end": cm_end.tolist(), "H_cm": H, "L_cm": L,
        "cm_travel": travel,
        "travel_angle_deg": float(np.degrees(np.arctan2(H, L))) if travel >= h else np.nan,
        "energy_ratio": energy_ratio(H, L, mu, travel, h),
        "concave_profile": profile.concave,
        "seconds": seconds, "seconds_per_step": float(np.mean(hist["seconds"])),
        "t": t, "front": fr, "ke": ke, "area_change": np.asarray(rec["area_change"]),
        "alpha": np.asarray(rec["alpha"]), "cm": cm,
        "points": points, "track_x": np.asarray(track["x"]), "track_v": np.asarray(track["v"]),
        "x_end": state.x.copy(), "x0": x0, "snapshots": snaps,
        "profile": {"x": profile.x, "z_slip": profile.z_slip, "z_surface": profile.z_surface},
        "config": config_summary(scene),
        "pvd": str(series.pvd_path) if series is not None else None,
    }


# -- options -------------------------------------------------------------------------------
def check(args):
    try:
        profile = read_profile(args.profile)
    except ValueError as err:
        return f"--profile: {err}"
    if args.h > profile.thickness / 2:
        return (f"--h {args.h:g} leaves fewer than two spacings through the mass "
                f"({profile.thickness:g} m thick at most)")
    if args.t_hold > 0 and args.t_hold < args.dt:
        return f"--t-hold {args.t_hold:g} is shorter than one step --dt {args.dt:g}"
    if args.t_after < 2 * args.dt:
        return f"--t-after {args.t_after:g} is shorter than two steps --dt {args.dt:g}"
    if args.snapshot_every and args.snapshot_every < args.dt:
        return f"--snapshot-every {args.snapshot_every:g} is shorter than one step --dt"
    return ("--phi 0 with --c 0 is a material without strength: give --c > 0 or --phi > 0"
            if args.phi == 0 and args.c == 0 else None)


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    material_options(p, rho=1.25, phi=28.0, c=opt(0.0, type=nonnegative_float), g=9.8)
    time_options(p, dt=0.05, theta1=1.0, theta2=1.0,
                 save_every=opt(0, why="of each run, and a PVD per run"))
    pfem_options(p, h=opt(0.95, why="0.95: about 2,000 elements on the default profile"),
                 alpha=opt(1.6, "alpha-shape parameter alpha_0"),
                 k_min=opt(0.005, dest="floor",
                           why="a fraction of rho g L (L: the mass's thickness)"),
                 passes=2, volume_correction="on",
                 alpha_advected=opt(3.0, why="3: the thin front keeps its triangles (medium "
                                             "size, mass change 0.27-0.65 %% against "
                                             "1.2-5.9 %% with 0; see the book)"))
    friction = positive_angle("the energy bound divides by mu")
    own_options(p, profile=(str, str(PROFILE), "slope profile CSV (x,z_slip,z_surface; "
                            "comments '#'); the default is the reconstruction of Fig 8.3"),
        mu_deg=(friction, 10.0, "basal friction angle [deg] of the main run, mu = tan(mu_deg) "
                                "(thesis: tan 10 deg)"),
        mu_study=opt([8.0, 10.0, 12.0], "basal friction angles [deg] of the back-analysis "
                     "(Fig 8.4)", type=friction, nargs="*"),
        rho_study=opt([0.5, 2.5], "further densities [t/m3] at --mu-deg (Fig 8.5-8.6)",
                      type=positive_float, nargs="*"),
        no_alpha_study=(bool, False, "skip the run without adaptive alpha (mass change reported "
                                     "beside)"),
        t_hold=(nonnegative_float, 10.0, "held phase [s]: every boundary node held still (builds "
                                         "the stress)"),
        hold=(("boundary", "free_surface"), "boundary", "what the held phase holds: every "
              "boundary node, or those not on the slip surface"),
        t_after=(positive_float, 30.0, "longest time [s] after release (600 steps of 0.05 s)"),
        rest=(in_range(0, 1, low_open=True, high_open=True), 1e-3, "at rest when the kinetic "
              "energy is below this fraction of its peak and the centre of mass has moved at "
              "least --h (a mass that never moves runs to --t-after)"),
        snapshot_every=(nonnegative_float, 5.0, "snapshots every this many seconds after "
                                                "release (Fig 8.9-8.10)"),
        keep_runs=(bool, False, "pickle every run's histories to "
                                "OUTDIR/landslide_yangbaodi/runs.pkl"),
        workers=(worker_count, min(2, os.cpu_count() or 1), "parallel processes for the runs"))
    checkpoint_options(p, "slide")
    return p


def _cases(args):
    """Main run first (it has the snapshots), then the friction sweep, the densities and
    the run without adaptive alpha, as run_case keywords: the groups of run_groups."""
    mu = dict(args=args, mu_deg=args.mu_deg)
    return dict(main=[dict(mu, snapshot_every=args.snapshot_every)],
                sweep=[dict(args=args, mu_deg=m) for m in args.mu_study if m != args.mu_deg],
                rhos=[dict(mu, rho=r) for r in args.rho_study if r != args.rho],
                fixed=[] if args.no_alpha_study else [dict(mu, adaptive_alpha=False)])


def density_twin(base, r):
    """How run ``r``, at another density, repeats ``base`` (c = 0: every force scales with
    rho): 'exact', whether the densities' ratio is a power of two (then every floating-point
    number scales exactly, and the run must be the same bit for bit); 'same', whether its
    front history and its last positions are; 'difference', the largest |front_r - front_base|
    over the common steps, over the front's travel in ``base``."""
    ratio = r["rho"] / base["rho"]
    n = min(len(base["front"]), len(r["front"]))
    travel = max(float(np.max(base["front"]) - base["front0"]), 1e-300)
    return dict(exact=np.log2(ratio) == round(np.log2(ratio)),
                same=(len(r["front"]) == len(base["front"])
                      and np.array_equal(r["front"], base["front"])
                      and np.array_equal(r["x_end"], base["x_end"])),
                difference=float(np.max(np.abs(base["front"][:n] - r["front"][:n]))) / travel)


def run(args):
    """The slides of ``args`` in parallel; their checks."""
    res = run_groups(run_case, _cases(args), args.workers, desc="landslides")
    results = [r for group in res.values() for r in group]
    if args.keep_runs:                             # every history, to draw again later
        (figure_dir(args, "landslide_yangbaodi") / "runs.pkl").write_bytes(pickle.dumps(results))
    base, rho_runs, fixed_run = res["main"][0], res["rhos"], (res["fixed"] or [None])[0]
    mu_runs = sorted([base] + res["sweep"], key=lambda r: r["mu"])
    report = Report("landslide_yangbaodi", args, particles=base["particles0"],
                    elements=base["elements0"])
    report.add_table(
        "cases", {"case": "label", "mu": "mu", "rho": "rho",
                  "alpha": lambda r: "adapt" if r["adaptive_alpha"] else "fixed",
                  "n0": "particles0", "elem": "elements0", "front max": "front_max",
                  "at t": "t_front_max", "t rest": "t_rest", "mass chg": "mass_change_max",
                  "travel": "travel_angle_deg", "ratio": "energy_ratio",
                  "steps": "steps_after_release", "s/step": "seconds_per_step"}, results,
        formats={"mu": ".4f", "rho": ".2f", "front max": ".1f", "at t": ".2f", "t rest": ".2f",
                 "mass chg": ".2%", "travel": ".2f", "ratio": ".3f", "s/step": ".2f"})
    report.add_interval("hold_max_displacement_over_h", base["hold_max_displacement_over_h"],
                        0.0, HOLD_STILL, "the held phase keeps every particle still")
    for r in results:
        if r["adaptive_alpha"]:
            report.add_interval(f"{r['label']}_mass_change_max", r["mass_change_max"], 0.0,
                                MASS_TOLERANCE, "thesis 8.3: adaptive alpha keeps the mass "
                                "within 2 %")
        report.add_interval(f"{r['label']}_at_rest", float(r["at_rest"]), 1.0, 1.0,
                            f"moved a spacing, then kinetic energy below {args.rest:g} of "
                            f"its peak within the run")
        report.add_interval(f"{r['label']}_front_on_profile",
                            float(not r["front_beyond_profile"]), 1.0, 1.0,
                            "the mass stays on the profile's slip surface")
    for r in mu_runs:
        report.add_interval(f"{r['label']}_energy_ratio",
                            r["energy_ratio"] if r["at_rest"] else np.nan, 1.0, np.inf,
                            "energy bound: tan(travel angle of the centre of mass) / mu >= 1 "
                            "(at rest; undefined, a failure, if not at rest or not moved)"
                            + ("" if r["concave_profile"] else
                                           "; the profile is not concave: a soft bound"))
    if len(mu_runs) >= 2:
        reach = np.array([r["front_max"] for r in mu_runs])
        report.add_interval("runout_decrease_with_mu", float(np.max(np.diff(reach))),
                            -np.inf, -1e-9 * reach.max(),
                            "thesis Fig 8.4: the deposit is shorter as mu grows "
                            "(largest change of the reach between neighbouring mu, < 0)",
                            reference=-1.0)
    for r in rho_runs:
        twin = density_twin(base, r)
        if twin["exact"]:
            report.add_interval(f"rho{r['rho']:g}_bit_identical", float(twin["same"]), 1.0, 1.0,
                                "c = 0: a density 2^k times gives the same run bit for bit")
        report.add_interval(f"rho{r['rho']:g}_front_difference", twin["difference"], 0.0,
                            0.0 if twin["exact"] else DENSITY_TOLERANCE,
                            "c = 0: the front history does not depend on rho (thesis Fig 8.5: "
                            "little difference); relative to the front's travel")
    if fixed_run is not None:              # its mass change beside adaptive alpha's: "cases"
        report.extra["mass_change_max_fixed_alpha"] = fixed_run["mass_change_max"]
    report.extra["thesis_comparison"] = {"warning": WARNING} | {
        k: [base[k], thesis] for k, thesis in THESIS.items()}
    report.add_table("beside the thesis", ["base run", "ours", "thesis"],
                     [(k, base[k], thesis) for k, thesis in THESIS.items()],
                     formats={"ours": ".2f"}, title=f"warning: {WARNING}")
    report.extra["cases"] = [thinned(r, HISTORIES, LEFT_OUT, entries=200) for r in results]
    report.data = dict(base=base, mu_runs=mu_runs, rho_runs=rho_runs, fixed_run=fixed_run,
                       cases=report.extra["cases"])
    return report


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


# -- figures -------------------------------------------------------------------------------
def figures(args, base, mu_runs, rho_runs, fixed_run, cases):
    """Snapshots coloured by speed (Fig 8.9-8.10); the front and the kinetic energy against
    time (Fig 8.5); the material points A, B, C (Fig 8.7-8.8); the final deposits of the
    friction sweep (Fig 8.4); the mass change with and without adaptive alpha."""
    plt, out, p = pyplot(), figure_dir(args, "landslide_yangbaodi"), base["profile"]
    xmax = max(350.0, 10 * np.ceil(max(np.max(r["x_end"][:, 0])
                                       for r in [base] + mu_runs + rho_runs) / 10 + 1))
    ground = lambda ax: plot_ground(ax, p["x"], p["z_slip"], p["z_surface"],  # noqa: E731
                                    xlim=(0, xmax))
    fig, _ = snapshot_grid({f"t = {t:g} s after release": (s["x"], s["speed"]) for t, s in
                            sorted(base["snapshots"].items())}, label="speed [m/s]",
                           title=f"Landslide, mu = tan {base['mu_deg']:g} deg: particles "
                           "coloured by speed (cf. Fig 8.9-8.10); dashed: the ground before "
                           "failure", size=(9, 1.9), axes=None, draw=ground)
    save_figure(fig, out / "snapshots.png")
    fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(11, 4))
    plot_histories(ax0, [base] + rho_runs, "t", "front", "rho = {rho:g} t/m3")
    plot_histories(ax0, [r for r in mu_runs if r is not base], "t", "front",
                   "mu = tan {mu_deg:g} deg", style=":")
    ax0.plot([THESIS_FRONT_TIME], [THESIS_FRONT], "k*", ms=10,
             label="thesis: ~325 m at ~20 s (other geometry)")
    labelled(ax0, "time after release [s]", "front's horizontal position [m]",
             "the front against time (cf. Fig 8.5)", title_size=9)
    plot_histories(ax1, mu_runs, "t", "ke", "mu = tan {mu_deg:g} deg", floor=1e-30, log=True)
    ax1.axhline(args.rest * base["ke_peak"], color="k", lw=0.6, ls="--",
                label=f"{args.rest:g} of the peak (mu = tan {base['mu_deg']:g})")
    ax1.axvline(THESIS_END, color="0.5", lw=0.8, ls=":", label="thesis: ended ~25 s")
    ax1.set_ylim(max(1e-6 * base["ke_peak"], 1e-30), 3 * base["ke_peak"])
    labelled(ax1, "time after release [s]", "kinetic energy [kJ/m]",
             "kinetic energy against time", title_size=9)
    save_figure(fig, out / "front_and_energy.png")
    fig, axes = plt.subplots(3, 2, figsize=(11, 8.5))
    for k, (name, (ax, av)) in enumerate(zip(("A (rear)", "B (middle)", "C (front)"), axes)):
        xs, vs = base["track_x"][:, k], base["track_v"][:, k]
        ground(ax)
        for x, shade in ((base["x0"], "0.6"), (base["x_end"], "0.4")):
            ax.plot(x[:, 0], x[:, 1], ".", color=shade, ms=1)
        ax.plot(xs[:, 0], xs[:, 1], "r-", lw=1)
        ax.plot(*base["x0"][base["points"][k]], "ro", ms=4)
        ax.set_title(f"point {name}: its trace (red), the mass at start and at rest", fontsize=9)
        av.plot(xs[:, 0], vs, label=["v_x", "v_y"])
        av.axhline(0, color="k", lw=0.5)
        av.set_xlim(0, xmax)
        labelled(av, "x of the point [m]", "velocity [m/s]",
                 f"point {name}: velocity against its x (cf. Fig 8.7-8.8)", title_size=9)
    save_figure(fig, out / "material_points.png")
    fig, _ = snapshot_grid(
        {f"mu = tan {r['mu_deg']:g} deg: reach {r['front_max']:.0f} m, travel angle "
         f"{r['travel_angle_deg']:.1f} deg (bound {r['mu_deg']:g} deg)": (r["x_end"], None)
         for r in mu_runs}, label=None, size=(9, 2.1), axes=None, dots="C3",
        title="final deposits of the friction back-analysis (cf. Fig 8.4)", draw=ground)
    save_figure(fig, out / "deposits.png")
    fig, ax = plt.subplots(figsize=(6.5, 4))
    plot_histories(ax, [base] + [fixed_run] * (fixed_run is not None), "t", "area_change",
                   lambda r: "adaptive alpha" if r["adaptive_alpha"] else
                   f"alpha fixed at {args.alpha:g}", scale=100)
    ax.axhspan(-100 * MASS_TOLERANCE, 100 * MASS_TOLERANCE, color="k", alpha=0.08,
               label="thesis: within 2 %")
    labelled(ax, "time after release [s]", "mass change [%]",
             "mass (detected area) change, alpha_n = m0 alpha0 / m_n", title_size=9)
    save_figure(fig, out / "mass_change.png")
    write_summary(out, cases)


if __name__ == "__main__":
    sys.exit(main())
