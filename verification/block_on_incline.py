"""A block on a rough incline in the PFEM: it slides at g (sin beta - mu cos beta), or sticks.

Beyond the thesis; the benchmark recipe of CONTRIBUTING.md tried on the smallest PFEM
scene. A block (W x H, an undrained clay far stronger than its stresses: it moves as a
rigid body) rests on a rough floor with Coulomb friction mu, gravity tilted by the slope
angle beta, g (sin beta, -cos beta): the incline in its own frame. The contact rule is
``LaggedFriction`` (5.12) without dilation (a smooth pass, then the friction bounded by mu
times its normal force), remeshed every step. Above the friction angle (tan beta > mu) the
block slides; backward Euler (theta1 = theta2 = 1) integrates a constant force exactly:

    v_n = a n dt,   x_n = a dt^2 n (n + 1) / 2,   a = g (sin beta - mu cos beta),

and the block presses on the floor with its weight's normal part m g cos beta and drags it
along with the friction mu m g cos beta.
Below it (beta_stick < atan mu) the block stays at rest: its friction is m g sin beta.

Checks (each against the closed form): the travel of the sliding block's centre of mass after
--steps steps, to 1e-6; the floor's normal force and its friction, to 1e-6; the sticking
block's largest speed, below 1e-6 g dt, and its friction m g sin beta_stick, to 1e-6.

Usage::

    python verification/block_on_incline.py --quick --json results/block_on_incline.json
"""
import sys

import numpy as np

from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, friction_angle, material_options, opt,
                                        nonnegative_float, positive_float, positive_int,
                                        time_options)
from pfem_skfem.harness.report import Report, script_main

QUICK = dict(steps=5, n=3)


def incline_scene(beta, *, mu, width, height, n, rho, c, g, dt):
    """The block (``n`` particles across its height) on the floor y = 0, gravity tilted by the
    slope angle ``beta`` [deg]: scene and initial state."""
    from pfem_skfem.discretisation import ThetaMethod
    from pfem_skfem.materials import CohesiveTresca
    from pfem_skfem.problems.contact import LaggedFriction, RigidSegment
    from pfem_skfem.scene import Body, Region, Scene
    from pfem_skfem.scene.config import PFEMConfig

    h = height / n
    block = Region(((0.0, 0.0), (width, 0.0), (width, height), (0.0, height)),
                   CohesiveTresca(c), rho, h, name="block")
    far = 1e3 * width
    floor = Body("floor", RigidSegment((-far, 0.0), (far, 0.0), mu))       # block above
    b = np.radians(beta)
    config = PFEMConfig(theta=ThetaMethod(dt, 1.0, 1.0), contact=LaggedFriction(), passes=2)
    scene = Scene(regions=(block,), bodies=(floor,), gravity=(g * np.sin(b), -g * np.cos(b)),
                  alpha=1.6, length=height, config=config)
    return scene.initial_state(), scene


def slide(beta, steps, **parameters):
    """``steps`` steps of the block from rest: the centre of mass's travel, the largest speed
    and the floor's force (along, normal) after each step."""
    from pfem_skfem.drivers.resumable import ResumableRun

    state, scene = incline_scene(beta, **parameters)
    x0 = np.average(state.x[:, 0], weights=state.mass)
    kept = {"travel": [0.0], "speed": [0.0], "force": [[0.0, 0.0]]}

    def observe(run, snapshots):
        s = run.state
        kept["travel"].append(float(np.average(s.x[:, 0], weights=s.mass) - x0))
        kept["speed"].append(float(np.abs(s.v).max()))
        kept["force"].append(list(run.record["forces"]["floor"]))

    ResumableRun.open(scene, state, kept).advance(lambda run: run.state.step >= steps, observe)
    return {k: np.array(v) for k, v in kept.items()}


def check(args):
    if np.tan(np.radians(args.beta)) <= args.mu:
        return f"--beta {args.beta:g}: the block must slide, tan(beta) > --mu {args.mu:g}"
    if np.tan(np.radians(args.beta_stick)) >= args.mu:
        return f"--beta-stick {args.beta_stick:g}: the block must stick, tan < --mu {args.mu:g}"
    return None


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    p.add_argument("--beta", type=friction_angle, default=30.0,
                   help="slope angle of the sliding block [deg]")
    p.add_argument("--beta-stick", type=friction_angle, default=10.0,
                   help="slope angle of the sticking block [deg]")
    p.add_argument("--mu", type=nonnegative_float, default=0.3, help="floor friction mu")
    p.add_argument("--width", type=positive_float, default=1.0, help="block width W [m]")
    p.add_argument("--height", type=positive_float, default=0.5, help="block height H [m]")
    p.add_argument("--n", type=positive_int, default=4, help="particles across the height")
    material_options(p, units="Pa", rho=2000.0, g=9.81,
                     c=opt(1e6, "the block's strength [Pa] (Tresca: far above its stresses)"))
    time_options(p, dt=0.02, steps=20)
    return p


def run(args):
    common = dict(mu=args.mu, width=args.width, height=args.height, n=args.n, rho=args.rho,
                  c=args.c, g=args.g, dt=args.dt)
    sliding = slide(args.beta, args.steps, **common)
    sticking = slide(args.beta_stick, args.steps, **common)
    b, bs = np.radians(args.beta), np.radians(args.beta_stick)
    a = args.g * (np.sin(b) - args.mu * np.cos(b))
    n = np.arange(args.steps + 1)
    exact = a * args.dt ** 2 * n * (n + 1) / 2
    weight = args.rho * args.width * args.height * args.g
    report = Report("block_on_incline", args)
    report.add("travel", sliding["travel"][-1], exact[-1],
               "backward Euler of a constant force: a dt^2 n (n + 1) / 2, "
               "a = g (sin beta - mu cos beta)", 1e-6)
    # the block's force on the floor (the record's): normal (down) and along the slope
    report.add("normal_force", -sliding["force"][-1][1], weight * np.cos(b),
               "m g cos beta", 1e-6)
    report.add("friction_force", sliding["force"][-1][0], args.mu * weight * np.cos(b),
               "mu m g cos beta, dragged along the motion", 1e-6)
    report.add_interval("sticking_speed", sticking["speed"].max() / (args.g * args.dt), 0.0,
                        1e-6, "at rest below the friction angle: largest speed / (g dt)")
    report.add("sticking_friction", sticking["force"][-1][0], weight * np.sin(bs),
               "m g sin beta_stick", 1e-6)
    report.add_table("travel", ["step", "travel [m]", "exact [m]", "relative error"],
                     [[int(k), t, e, abs(t / e - 1) if e else 0.0]
                      for k, t, e in zip(n, sliding["travel"], exact)][1:],
                     formats={"relative error": ".1e"})
    report.extra = {"travel": sliding["travel"], "exact": exact,
                    "sticking_speed": sticking["speed"]}
    report.data = dict(n=n, sliding=sliding, exact=exact)
    return report


def figures(args, n, sliding, exact):
    """The sliding block's travel against the closed form."""
    fig, ax = pyplot().subplots(figsize=(6, 4))
    ax.plot(n * args.dt, exact, "-", color="0.4", label="a dt^2 n (n + 1) / 2")
    ax.plot(n * args.dt, sliding["travel"], "o", label="PFEM, centre of mass")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("travel along the slope [m]")
    ax.set_title(f"block on a {args.beta:g} deg incline, mu = {args.mu:g}")
    ax.legend()
    save_figure(fig, figure_dir(args, "block_on_incline") / "travel.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
