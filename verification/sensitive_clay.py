"""A sensitive-clay slope in the PFEM: the failure grows with the clay's sensitivity.

Beyond the thesis (issue 55 item 4, its first part; the mechanism of Zhang, Sheng, Sloan &
Bleyer, IJNME 112 (2017) 963-989, and of Zhang, Wang, Krabbenhoft & Tinti, Landslides 17
(2020) 1117-1127, whose geometries and parameters are not reproduced here). A bank of
undrained clay H high and W long stands on a rough floor (friction mu) against a smooth
wall x = 0, its face x = W vertical and free; it starts geostatic (K0 = 1). Its Tresca
strength softens linearly with the plastic shear strain (:mod:`pfem_skfem.materials.
softening`) from c_p to c_r = c_p / S_t at gamma^p = gamma_r, S_t the sensitivity, the
strength of each step read from the gamma^p the particles' mesh carries
(:mod:`pfem_skfem.pfem.softening`). The peak strength is set by the stability number
N = rho g H / c_p, above the critical one of a vertical cut (rigorous bounds 3.772-3.786,
Pastor et al. 2000, ``verification/limit_bounds.py``): the face fails at any sensitivity.
With S_t = 1 the slid mass keeps its strength and buttresses the new scarp; as S_t grows
the slid mass is remoulded, runs out, and unloads the scarp.

Measured at t_end: the run-out (the furthest particle beyond the face), the
retrogression distance (from the face back to the furthest particle of the original
ground surface that has dropped by more than a tenth of H) and the mobilised mass (the
fraction of the mass whose particles moved by more than a tenth of H).

Checks: the bank fails at S_t = 1 (its run-out at least a particle spacing: N above the
cut's bounds); the run-out grows with S_t (by 5 % or more from one S_t to the next); at
the largest S_t the bank retrogresses further than at S_t = 1 (by a spacing or more:
checked above half of one) and moves more mass (5 % or more); the step control acted
(after each step whose strength drop exceeds the cap, the next step's dt is halved:
``SofteningTimeStep``). Between two sensitive clays (S_t = 3 and 10 at the default size)
the retrogression and the mobilised mass are not checked: they are not monotone there
(book/softening.md).

Usage::

    python verification/sensitive_clay.py --quick --json results/sensitive_clay.json
"""
from dataclasses import dataclass, field
import sys

import numpy as np

from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, checkpoint_options, in_range,
                                        material_options, nonnegative_float, opt,
                                        positive_float, softening_options, time_options)
from pfem_skfem.harness.params import UNKEYED, Parameters
from pfem_skfem.harness.report import Report, script_main

QUICK = dict(n=5, sensitivities=[1.0, 10.0])
#: the cut's rigorous upper bound on rho g H / c (Pastor et al. 2000)
CUT_UPPER = 3.786


@dataclass(frozen=True)
class Bank(Parameters):
    """The bank of sensitivity S_t, its scene and its checkpoint's keys (all but t_end: a run
    goes on to a later one); the other fields are the options of the same names."""
    S_t: float
    height: float
    width: float
    n: int
    N: float
    gamma_r: float
    E_over_c: float
    nu: float
    mu: float
    rho: float
    g: float
    dt: float
    max_drop: float
    t_end: float = field(default=None, metadata=UNKEYED)

    def scene(self):
        """(state, scene) of the bank."""
        from pfem_skfem.materials import Elastic, LinearSoftening, SofteningTresca
        from pfem_skfem.scene import Geostatic
        from pfem_skfem.scene.columns import column_scene

        H = self.height
        c_p = self.rho * self.g * H / self.N
        soil = SofteningTresca(LinearSoftening(c_p, c_p / self.S_t, self.gamma_r),
                               Elastic(self.E_over_c * c_p, self.nu))
        return column_scene(soil, self.width, H, H / self.n, rho=self.rho, g=self.g,
                            dt=self.dt * np.sqrt(H / self.g), stress=Geostatic(),
                            floor_friction=self.mu, wall_friction=0.0,
                            far=50.0 * (self.width + H), passes=2)


def failure(S_t, args):
    """The bank of sensitivity ``S_t`` (:class:`Bank`) run to t_end: its measurements (a
    dict)."""
    from pfem_skfem.drivers.resumable import Bar, Checkpoints, ResumableRun
    from pfem_skfem.drivers.time_step import SofteningTimeStep

    params = Bank.of(args, S_t=S_t)
    state, scene = params.scene()
    H, W = args.height, args.width
    x0 = state.x.copy()
    ground = np.flatnonzero(x0[:, 1] > H * (1 - 0.25 / args.n))   # the original surface
    t_end = args.t_end * np.sqrt(H / args.g)
    policy = SofteningTimeStep(scene.config.dt, max_drop=args.max_drop, halvings=4)
    run = ResumableRun.open(
        scene, state, {"gamma_max": [], "dt": []},
        checkpoints=Checkpoints(args.checkpoint_dir, f"sensitive_clay_St{S_t:g}", params.keys(),
                                args.checkpoint_every),
        bar=Bar(int(np.ceil(args.t_end / args.dt)), f"sensitive clay, S_t = {S_t:g}",
                args.progress), time_step=policy)

    def observe(run, snapshots):
        run.kept["gamma_max"].append(float(run.state.gamma_p.max()))
        run.kept["dt"].append(float(run.step_scene.config.dt))

    run.advance(lambda run: run.state.time >= t_end * (1 - 1e-9), observe)
    state, kept = run.state, run.kept
    dropped = ground[x0[ground, 1] - state.x[ground, 1] > 0.1 * H]
    drops = np.asarray(state.history["softening_drop"])
    dts = np.asarray(kept["dt"])
    over = np.flatnonzero(drops[:-1] > args.max_drop)
    floor = scene.config.dt / 2 ** policy.halvings
    moved = np.linalg.norm(state.x[:len(x0)] - x0, axis=1) > 0.1 * H   # x0's stay first
    return dict(runout=float(state.x[:, 0].max() - W),
                mobilised=float(np.sum(state.mass[:len(x0)][moved]) / state.total_mass),
                retrogression=float(W - x0[dropped, 0].min()) if dropped.size else 0.0,
                gamma_max=np.asarray(kept["gamma_max"]), steps=state.step,
                largest_drop=float(drops.max()),
                halved=bool(np.all(np.isclose(dts[over + 1], np.maximum(dts[over] / 2, floor),
                                              rtol=1e-12))),
                x=state.x, x0=x0, mesh=(state.mesh_p, state.mesh_t), gamma_p=state.gamma_p)


def ratio(a, b):
    """b / a, NaN (a failed check) where a is not positive."""
    return b / a if a > 0 else float("nan")


def check(args):
    """Options that cannot go together (a usage error), or None: the checks compare each
    sensitivity with S_t = 1, so two at least, increasing from 1."""
    s = args.sensitivities
    if len(s) < 2 or s[0] != 1.0 or any(b <= a for a, b in zip(s, s[1:])):
        return (f"--sensitivities {' '.join(f'{v:g}' for v in s)}: two or more, increasing, "
                "the first 1 (no softening): the checks compare each with the one before")
    return None


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    p.add_argument("--height", type=positive_float, default=1.0, help="bank height H [m]")
    p.add_argument("--width", type=positive_float, default=6.0,
                   help="bank length W behind its face [m]")
    p.add_argument("--n", type=in_range(2, integer=True), default=6,
                   help="particles across the height")
    p.add_argument("--N", type=in_range(CUT_UPPER, low_open=True), default=6.0,
                   help="stability number rho g H / c_p (above the cut's 3.786: it fails)")
    softening_options(p, sensitivities=opt([1.0, 3.0, 10.0], "sensitivities S_t = c_p / c_r, "
                                           "the first 1 (no softening)", nargs="+"),
                      gamma_r=0.2,
                      max_drop=opt(0.5, "cap on a step's strength drop, a fraction of c_p - c_r "
                                        "(the next step's dt is halved above it)"))
    p.add_argument("--E-over-c", type=positive_float, default=500.0,
                   help="Young's modulus over c_p")
    p.add_argument("--mu", type=nonnegative_float, default=0.5, help="floor friction mu")
    material_options(p, units="kPa", rho=2.0, g=9.8, nu=0.45)
    time_options(p, dt=opt(0.05, "time step, in units of sqrt(H / g)"),
                 t_end=opt(5.0, "end time, in units of sqrt(H / g)"))
    checkpoint_options(p, "bank", every=20)
    return p


def run(args):
    cases = {S_t: failure(S_t, args) for S_t in args.sensitivities}
    spacing = args.height / args.n
    report = Report("sensitive_clay", args)
    first = cases[args.sensitivities[0]]
    report.add_interval("runout_St1_over_h", first["runout"] / spacing, 1.0, np.inf,
                        f"N = {args.N:g} > {CUT_UPPER} (the vertical cut's upper bound): the "
                        f"bank fails without softening")
    runouts = [cases[s]["runout"] for s in args.sensitivities]
    report.add_interval("runout_growth", min(ratio(a, b) for a, b in zip(runouts, runouts[1:])),
                        1.05, np.inf, "the run-out grows with S_t, by 5 % or more (least ratio)")
    last = cases[args.sensitivities[-1]]
    report.add_interval("retrogression_gain",
                        (last["retrogression"] - first["retrogression"]) / spacing, 0.5, np.inf,
                        "the largest S_t retrogresses further than S_t = 1 (in spacings: the "
                        "ground's particles lie a spacing apart, so a gain is a whole one)")
    report.add_interval("mobilised_gain", ratio(first["mobilised"], last["mobilised"]), 1.05, np.inf,
                        "the largest S_t moves 5 % more mass or more than S_t = 1 (ratio)")
    report.add_interval("halved_after_cap", float(all(c["halved"] for c in cases.values())),
                        1.0, 1.0, "after each step over the cap the next dt was halved")
    report.add_table("sensitivity", ["S_t", "run-out / H", "retrogression / H", "mobilised",
                                     "steps", "largest drop", "gamma^p max"],
                     [[s, c["runout"] / args.height, c["retrogression"] / args.height,
                       c["mobilised"], c["steps"], c["largest_drop"], c["gamma_max"][-1]]
                      for s, c in cases.items()])
    report.extra = {f"St{s:g}_{k}": cases[s][k] for s in cases
                    for k in ("runout", "retrogression", "mobilised", "steps", "largest_drop")}
    report.data = dict(cases=cases)
    return report


def figures(args, cases):
    """The deposits at t_end, gamma^p shaded, one panel per sensitivity."""
    plt = pyplot()
    n = len(cases)
    fig, axes = plt.subplots(n + 1, 1, figsize=(8, 2.2 * n + 1.2),
                             gridspec_kw={"height_ratios": [1.0] * n + [0.08]})
    for ax, (S_t, c) in zip(axes[:n], cases.items()):
        p, t = c["mesh"]
        shade = ax.tripcolor(p[:, 0], p[:, 1], t, facecolors=np.log10(
            1e-3 + c["gamma_p"].reshape(-1, 3).mean(axis=1)), cmap="viridis", vmin=-3, vmax=2)
        ax.plot(c["x0"][:, 0], c["x0"][:, 1], ",", color="0.6")
        ax.set_aspect("equal")
        ax.set_xlim(-0.2, max(d["x"][:, 0].max() for d in cases.values()) + 0.2)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_title(f"S_t = {S_t:g}: run-out {c['runout']:.2f} m, "
                     f"retrogression {c['retrogression']:.2f} m")
    fig.colorbar(shade, cax=axes[n], orientation="horizontal",
                 label="log10(1e-3 + gamma^p) at t_end")
    save_figure(fig, figure_dir(args, "sensitive_clay") / "deposits.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
