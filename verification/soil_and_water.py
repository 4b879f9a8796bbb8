"""Soil beside water: the dam break's granular twin, one column of water and one of sand.

Beyond the thesis (issue 39, item 6, its first part). The dam-break column of Martin &
Moyce (a wide, 2a high, against a smooth wall) released twice, alike: once of water
(:class:`~pfem_skfem.materials.NewtonianFluid`, the viscosity of water, a smooth floor),
once of a dry granular material (:class:`~pfem_skfem.materials.ZeroDilationMohrCoulomb`,
phi = 30, on a floor of friction tan phi), to T = t sqrt(2g/a) = 4: the difference a
strength makes, side by side.

No experiment is asserted here beyond conservation (for the water against Martin & Moyce,
``verification/dam_break.py``; for granular columns against Lube et al.,
``verification/granular_column_plane.py``). Checks: each column's mass to round-off (the
particles carry it) and its area (its alpha-shape domain) within --tol_area, and the
water's front ahead of the granular one at T = 4. (The scene of a clay block sliding into
a water tank, two materials in one step, is not here yet: its alpha-shape area grew by
28 % in 2 s, which has to be understood first.)

Usage::

    python verification/soil_and_water.py --quick --json results/soil_and_water.json   # 15 seconds
    python verification/soil_and_water.py --save-every 5        # VTU/PVD of both columns
"""
import sys
from pathlib import Path

import numpy as np

from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, friction_angle,
                                        nonnegative_int, positive_float, positive_int)
from pfem_skfem.harness.report import Report, script_main

QUICK = dict(nx=8, twin_steps=40)


def twin_scene(material, rho, a, nx, *, mu_floor, g, dt, solver="clarabel"):
    """The dam-break column (a wide, 2a high, nx particles across) of ``material`` against a
    smooth wall on a floor of friction mu_floor."""
    from pfem_skfem.scene import Geostatic, column_scene

    return column_scene(material, a, 2 * a, a / (nx - 1), rho=rho, g=g, dt=dt,
                        stress=Geostatic(), floor_friction=mu_floor, far=50 * a, passes=2,
                        solver=solver, volume_correction=True)


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
                           area_final=float(area[-1] / area[0] - 1))
    return out


def check(args):
    if args.nx < 4:
        return "--nx must be at least 4 (particles across a column)"
    return None


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    p.add_argument("--rho", type=positive_float, default=1000.0,
                   help="density of both columns [kg/m3] (the same: only the strength differs)")
    p.add_argument("--g", type=positive_float, default=9.81, help="gravity [m/s2]")
    p.add_argument("--a", type=positive_float, default=0.05715,
                   help="the twin columns' width [m] (Martin & Moyce's)")
    p.add_argument("--phi", type=friction_angle, default=30.0,
                   help="the granular twin's friction angle [deg]")
    p.add_argument("--nx", type=positive_int, default=16, help="particles across a twin")
    p.add_argument("--twin_steps", type=positive_int, default=80,
                   help="steps of each twin to T = t sqrt(2g/a) = 4 (the dam break's)")
    p.add_argument("--tol_area", type=positive_float, default=0.02,
                   help="tolerance of each column's area change")
    p.add_argument("--save-every", type=nonnegative_int, default=0,
                   help="write a VTU every this many steps (0: none), a PVD per scene")
    return p


def run(args):
    from pfem_skfem.drivers.pfem_loop import run_measured
    from pfem_skfem.materials import NewtonianFluid, ZeroDilationMohrCoulomb

    out = Path(args.outdir) / "soil_and_water"
    t_unit = np.sqrt(args.a / (2 * args.g))
    dt = 4.0 * t_unit / args.twin_steps
    twins = {}
    for name, material, mu_floor in (
            ("water", NewtonianFluid(1e-3), 0.0),
            ("granular", ZeroDilationMohrCoulomb(phi=args.phi), np.tan(np.radians(args.phi)))):
        s0, sc = twin_scene(material, args.rho, args.a, args.nx, mu_floor=mu_floor, g=args.g,
                            dt=dt, solver=args.solver)
        fronts = {"T": [0.0], "Z": [1.0], "speed": [0.0]}

        def measure_twin(state, record, result, fronts=fronts):
            fronts["T"].append(state.time / t_unit)
            fronts["Z"].append(float(state.x[:, 0].max() / args.a))
            fronts["speed"].append(float(np.linalg.norm(state.v, axis=1).max()))

        label = f"twin_{name}"
        s1, _ = run_measured(s0, sc, args.twin_steps, measure_twin, desc=label,
                             verbose=args.progress, vtu_dir=out / label, vtu_name=label,
                             save_every=args.save_every)
        twins[name] = dict(fronts, books=region_books(sc, s0, s1.history), points=s1.x.copy())

    report = Report("soil_and_water", args)
    for name, tw in twins.items():
        report.add_interval(f"{name}_mass_change", tw["books"]["column"]["mass"], 0.0, 1e-12,
                            "the particles carry the column's mass")
        report.add_interval(f"{name}_area_change", tw["books"]["all"]["area"], 0.0,
                            args.tol_area, "the column's area (its alpha-shape domain) kept")
    granular, water = twins["granular"], twins["water"]
    report.add_interval("water_over_granular_front", water["Z"][-1] / granular["Z"][-1], 1.0,
                        np.inf, "water (no strength) runs further than phi = 30")
    report.extra = {"twins": {k: {kk: v[kk] for kk in ("T", "Z", "speed", "books")}
                              for k, v in twins.items()}}
    print(f"at T = 4: water Z = {water['Z'][-1]:.2f}, granular Z = {granular['Z'][-1]:.2f}")
    report.data = dict(twins=twins)
    return report


def figures(args, twins):
    """The twins' fronts against time, and their particles at T = 4."""
    fig, ax = pyplot().subplots(1, 2, figsize=(11, 4.2))
    for name, tw in twins.items():
        ax[0].plot(tw["T"], tw["Z"], label=name)
        x = tw["points"] / args.a
        ax[1].plot(x[:, 0], x[:, 1], ".", ms=2, label=name)
    ax[0].set_xlabel("T = t sqrt(2g/a)")
    ax[0].set_ylabel("front Z = z/a")
    ax[0].set_title("dam break: water and its granular twin")
    ax[0].legend(fontsize=7)
    ax[1].set_aspect("equal")
    ax[1].set_xlabel("x / a")
    ax[1].set_ylabel("y / a")
    ax[1].set_title("the columns at T = 4")
    ax[1].legend(fontsize=7)
    save_figure(fig, figure_dir(args, "soil_and_water") / "soil_and_water.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
