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
fraction of the mass whose particles moved by more than a tenth of H); in the mesh study also
the remoulded fraction (of the area at the residual strength c_r).

Checks: the bank fails at S_t = 1 (its run-out at least a particle spacing: N above the
cut's bounds); the run-out grows with S_t (by 5 % or more from one S_t to the next); at
the largest S_t the bank retrogresses further than at S_t = 1 (by a spacing or more:
checked above half of one) and moves more mass (5 % or more); the step control acted
(after each step whose strength drop exceeds the cap, the next step's dt is halved:
``SofteningTimeStep``). Between two sensitive clays (S_t = 3 and 10 at the default size)
the retrogression and the mobilised mass are not checked: they are not monotone there
(book/softening.md).

Regularisation (``--regularisation``, default none: local softening): a fracture energy
(``fracture-energy``: gamma_r is that of a band ``--ell`` thick, scaled by ell / h in an
element of size h, :class:`~pfem_skfem.materials.FractureEnergy`) or a nonlocal average of
each step's Delta gamma^p over ``--ell`` (``nonlocal``,
:class:`~pfem_skfem.materials.NonlocalAverage`). ell must be at least the particle spacing
H / n of every bank (a band thinner than an element: a law steeper than the local one, or
an average over nothing).

Mesh study (``--mesh-study N ...``, off by default; issue 55 item 4, "the retrogression's
convergence"): the bank of each ``--study-sensitivities`` S_t at each particle count N across
H, with each of ``--study-regularisations`` (ell: ``--ell``), tabled. Checks, stated before
the runs: with each regularisation the retrogression changes by at most ``--convergence``
(10 %) between the two finest counts (relative to the finest), and without one it changes by
more than with it. Measured (book/softening.md, "The retrogression's convergence"; S_t = 10,
ell = 0.25 m, n = 6, 12, 24): the nonlocal average passes (4.2 %), the fracture energy
fails (11.1 %), and the local bank changes by 3.6 %, less than either.

Usage::

    python verification/sensitive_clay.py --quick --json results/sensitive_clay.json
    python verification/sensitive_clay.py --sensitivities 1 10 --mesh-study 6 12 24 \\
        --ell 0.25 --checkpoint-dir results/sensitive_clay_ckpt   # the study (1.6 h of CPU)
"""
from dataclasses import dataclass, field
import sys

import numpy as np

from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, checkpoint_options, in_range,
                                        material_options, nonnegative_float, opt, option_name,
                                        positive_float, softening_options, time_options)
from pfem_skfem.harness.params import UNKEYED, Parameters, keys_of
from pfem_skfem.harness.report import Report, script_main

QUICK = dict(n=5, sensitivities=[1.0, 10.0])
#: the cut's rigorous upper bound on rho g H / c (Pastor et al. 2000)
CUT_UPPER = 3.786
#: --regularisation's choices: None (local softening) or the material's regularisation class
REGULARISATIONS = ("none", "fracture-energy", "nonlocal")
#: options added after the quick JSON was first recorded, with their defaults: left out of
#: the JSON's params at their defaults (a run without them is the run of before)
LATER_OPTIONS = dict(regularisation="none", ell=None, mesh_study=[], study_sensitivities=[10.0],
                     study_regularisations=list(REGULARISATIONS), convergence=0.1)


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
    regularisation: str = "none"
    ell: float = None
    t_end: float = field(default=None, metadata=UNKEYED)

    def keys(self):
        """The checkpoint's keys; a bank without regularisation keeps those of before it had
        one (its checkpoints are found again)."""
        return keys_of(self, omit=("regularisation", "ell") if self.regularisation == "none"
                       else ())

    def material_regularisation(self):
        """The material's ``regularisation``: None, ``FractureEnergy(ell)`` or
        ``NonlocalAverage(ell)``."""
        from pfem_skfem.materials import FractureEnergy, NonlocalAverage
        kind = {"none": None, "fracture-energy": FractureEnergy,
                "nonlocal": NonlocalAverage}[self.regularisation]
        return None if kind is None else kind(self.ell)

    def scene(self):
        """(state, scene) of the bank."""
        from pfem_skfem.materials import Elastic, LinearSoftening, SofteningTresca
        from pfem_skfem.scene import Geostatic
        from pfem_skfem.scene.columns import column_scene

        H = self.height
        c_p = self.rho * self.g * H / self.N
        soil = SofteningTresca(LinearSoftening(c_p, c_p / self.S_t, self.gamma_r),
                               Elastic(self.E_over_c * c_p, self.nu),
                               self.material_regularisation())
        return column_scene(soil, self.width, H, H / self.n, rho=self.rho, g=self.g,
                            dt=self.dt * np.sqrt(H / self.g), stress=Geostatic(),
                            floor_friction=self.mu, wall_friction=0.0,
                            far=50.0 * (self.width + H), passes=2)


def remoulded_fraction(state, material):
    """The fraction of the body's area at the residual strength c_r at ``state`` (the
    material's strength at its gamma^p and element sizes, a fracture energy's ell / h
    included; collapsed triangles left out)."""
    from pfem_skfem.discretisation.fields import collapsed
    from pfem_skfem.materials.softening import point_sizes
    from pfem_skfem.pfem.alpha_shape import triangle_areas

    area = np.abs(triangle_areas(state.mesh_p, state.mesh_t))
    kept = ~collapsed(state.mesh_p, state.mesh_t)
    area, gamma = area[kept], state.gamma_p.reshape(-1, 3)[kept]
    c = material.strength(gamma.ravel(), point_sizes(np.repeat(area / 3, 3))).reshape(-1, 3)
    at_residual = np.mean(c <= material.law.c_r * (1 + 1e-9), axis=1)   # of its 3 points
    return float(np.sum(area * at_residual) / np.sum(area))


def failure(S_t, args, **given):
    """The bank of sensitivity ``S_t`` (:class:`Bank` of the options, ``given`` replacing
    them: ``n``, ``regularisation``) run to t_end: its measurements (a dict)."""
    from pfem_skfem.drivers.resumable import Bar, Checkpoints, ResumableRun, StepClock
    from pfem_skfem.drivers.time_step import SofteningTimeStep
    from pfem_skfem.pfem.measure import failure_extent, ground_particles

    clock = StepClock()      # each step's CPU seconds, kept in the checkpoints
    params = Bank.of(args, S_t=S_t, **given)
    state, scene = params.scene()
    H, W = args.height, args.width
    x0 = state.x.copy()
    ground = ground_particles(x0, H * (1 - 0.25 / params.n))   # the original surface
    t_end = args.t_end * np.sqrt(H / args.g)
    policy = SofteningTimeStep(scene.config.dt, max_drop=args.max_drop, halvings=4)
    label = f"S_t = {S_t:g}" + (f", n = {params.n}, {params.regularisation}" if given else "")
    run = ResumableRun.open(
        scene, state, {"gamma_max": [], "dt": [], "cpu_seconds": []},
        checkpoints=Checkpoints(args.checkpoint_dir, f"sensitive_clay_St{S_t:g}", params.keys(),
                                args.checkpoint_every),
        bar=Bar(int(np.ceil(args.t_end / args.dt)), f"sensitive clay, {label}",
                args.progress), time_step=policy)

    def observe(run, snapshots):
        run.kept["gamma_max"].append(float(run.state.gamma_p.max()))
        run.kept["dt"].append(float(run.step_scene.config.dt))
        clock.record(run.kept)

    run.advance(lambda run: run.state.time >= t_end * (1 - 1e-9), observe)
    state, kept = run.state, run.kept
    runout, retrogression = failure_extent(state.x, x0, ground, toe=W, crest=W, drop=0.1 * H,
                                           originals=False)   # the bank's face at x = W
    drops = np.asarray(state.history["softening_drop"])
    dts = np.asarray(kept["dt"])
    moved = np.linalg.norm(state.x[:len(x0)] - x0, axis=1) > 0.1 * H   # x0's stay first
    cpu = kept.get("cpu_seconds", [])
    return dict(runout=runout, n=params.n,
                remoulded=remoulded_fraction(state, scene.regions[0].material),
                regularisation=params.regularisation,
                cpu_seconds=float(np.sum(cpu)) if len(cpu) == len(dts) else float("nan"),
                mobilised=float(np.sum(state.mass[:len(x0)][moved]) / state.total_mass),
                retrogression=retrogression,
                gamma_max=np.asarray(kept["gamma_max"]), steps=state.step,
                largest_drop=float(drops.max()),
                halved=policy.halved_after_cap(drops, dts),
                x=state.x, x0=x0, mesh=(state.mesh_p, state.mesh_t), gamma_p=state.gamma_p)


def ratio(a, b):
    """b / a, NaN (a failed check) where a is not positive."""
    return b / a if a > 0 else float("nan")


def uses_ell(args):
    """The particle counts of the banks that read --ell (a regularised one): the sensitivity
    banks' n (with --regularisation) and the mesh study's (with a regularised study)."""
    counts = [args.n] if args.regularisation != "none" else []
    if args.mesh_study and set(args.study_regularisations) - {"none"}:
        counts += list(args.mesh_study)
    return counts


def check(args):
    """Options that cannot go together (a usage error), or None: the checks compare each
    sensitivity with S_t = 1, so two at least, increasing from 1; --ell where a bank is
    regularised only, at least the particle spacing of each such bank; a mesh study of two
    counts or more, increasing, with the local bank and a regularised one (its checks compare
    them); the study's options only with it."""
    s = args.sensitivities
    if len(s) < 2 or s[0] != 1.0 or any(b <= a for a, b in zip(s, s[1:])):
        return (f"--sensitivities {' '.join(f'{v:g}' for v in s)}: two or more, increasing, "
                "the first 1 (no softening): the checks compare each with the one before")
    m, regs = args.mesh_study, args.study_regularisations
    if m and (len(m) < 2 or any(b <= a for a, b in zip(m, m[1:]))):
        return (f"--mesh-study {' '.join(map(str, m))}: two counts or more, increasing (the "
                "checks compare the two finest)")
    if not m:
        for name, default in LATER_OPTIONS.items():
            if name.startswith("study_") or name == "convergence":
                if getattr(args, name) != default:
                    return f"{option_name(name)}: used by the mesh study only (--mesh-study)"
    if "none" not in regs or len(set(regs)) < 2 or len(set(regs)) != len(regs):
        return (f"--study-regularisations {' '.join(regs)}: none and one regularisation or "
                "more, each once (the checks compare them)")
    counts = uses_ell(args)
    if counts and args.ell is None:
        return "--ell: a regularised bank needs its length ell [m]"
    if not counts and args.ell is not None:
        return (f"--ell {args.ell:g}: no bank is regularised (--regularisation none and no "
                "regularised mesh study): it would do nothing")
    if counts and args.ell < args.height / min(counts):
        return (f"--ell {args.ell:g}: below the particle spacing H / n = "
                f"{args.height / min(counts):g} of n = {min(counts)} (a band thinner than an "
                "element: a law steeper than the local one, or an average over nothing)")
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
                                        "(the next step's dt is halved above it)"),
                      regularisation="none",
                      ell=opt(None, "the regularisation's length ell [m] (FractureEnergy's and "
                                    "NonlocalAverage's length): needed by a regularised bank, "
                                    "at least its particle spacing H / n", type=positive_float))
    p.add_argument("--mesh-study", type=in_range(2, integer=True), nargs="+", default=[],
                   metavar="N", help="the mesh study (off by default): particle counts across "
                                     "H, increasing, e.g. 6 12 24")
    p.add_argument("--study-sensitivities", type=in_range(1.0, low_open=True), nargs="+",
                   default=[10.0], help="the mesh study's sensitivities S_t (> 1)")
    p.add_argument("--study-regularisations", choices=REGULARISATIONS, nargs="+",
                   default=list(REGULARISATIONS),
                   help="the mesh study's regularisations: none and one or more others")
    p.add_argument("--convergence", type=in_range(0, 1, low_open=True), default=0.1,
                   help="the mesh study's check: with a regularisation the retrogression "
                        "changes by at most this fraction between the two finest counts")
    p.add_argument("--E-over-c", type=positive_float, default=500.0,
                   help="Young's modulus over c_p")
    p.add_argument("--mu", type=nonnegative_float, default=0.5, help="floor friction mu")
    material_options(p, units="kPa", rho=2.0, g=9.8, nu=0.45)
    time_options(p, dt=opt(0.05, "time step, in units of sqrt(H / g)"),
                 t_end=opt(5.0, "end time, in units of sqrt(H / g)"))
    checkpoint_options(p, "bank", every=20)
    return p


def report_params(args):
    """The JSON's params: the options but those added later at their defaults
    (:data:`LATER_OPTIONS`), so that a run without them records the inputs of before."""
    return {k: v for k, v in vars(args).items()
            if k not in LATER_OPTIONS or v != LATER_OPTIONS[k]}


def relative_change(coarse, fine):
    """abs(fine - coarse) / fine, NaN (a failed check) where fine is not positive."""
    return abs(fine - coarse) / fine if fine > 0 else float("nan")


def mesh_study(args, report):
    """The banks of --mesh-study (each S_t, regularisation and count), their table and the
    convergence checks of the two finest counts; the banks' measurements (a list)."""
    rows = [failure(S_t, args, n=n, regularisation=reg,
                    ell=None if reg == "none" else args.ell)
            | dict(S_t=S_t) for S_t in args.study_sensitivities
            for reg in args.study_regularisations for n in args.mesh_study]
    H, (coarse, fine) = args.height, args.mesh_study[-2:]
    for S_t in args.study_sensitivities:
        of = {(r["regularisation"], r["n"]): r for r in rows if r["S_t"] == S_t}
        change = {reg: relative_change(of[reg, coarse]["retrogression"],
                                       of[reg, fine]["retrogression"])
                  for reg in args.study_regularisations}
        for reg in args.study_regularisations:
            if reg == "none":
                continue
            report.add_interval(
                f"St{S_t:g}_{reg}_retrogression_change", change[reg], 0.0, args.convergence,
                f"with {reg} (ell = {args.ell:g} m) the retrogression changes by at most "
                f"{args.convergence:.0%} from n = {coarse} to {fine} (of the finest)")
            report.add_interval(
                f"St{S_t:g}_{reg}_over_none_change", ratio(change["none"], change[reg]), 0.0,
                np.nextafter(1.0, 0.0), f"without a regularisation the retrogression changes "
                f"more from n = {coarse} to {fine} than with {reg}: the ratio of the changes, "
                f"{reg}'s over none's, strictly below 1")
    report.add_table(
        "mesh study", ["n", "regularisation", "S_t", "retrogression / H", "run-out / H",
                       "mobilised", "remoulded", "steps", "CPU s"],
        [[r["n"], r["regularisation"], r["S_t"], r["retrogression"] / H, r["runout"] / H,
          r["mobilised"], r["remoulded"], r["steps"], r["cpu_seconds"]] for r in rows],
        formats={"retrogression / H": ".3f", "run-out / H": ".3f", "mobilised": ".3f",
                 "remoulded": ".3f", "CPU s": ".0f"},
        title=f"\nmesh study (ell = {args.ell:g} m for the regularised banks)")
    return rows


def run(args):
    cases = {S_t: failure(S_t, args) for S_t in args.sensitivities}
    spacing = args.height / args.n
    report = Report("sensitive_clay", report_params(args))
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
    study = mesh_study(args, report) if args.mesh_study else []
    if study:
        report.extra["mesh_study"] = [
            {k: r[k] for k in ("S_t", "n", "regularisation", "retrogression", "runout",
                               "mobilised", "remoulded", "steps", "largest_drop",
                               "cpu_seconds")}
            for r in study]
    report.data = dict(cases=cases) | (dict(study=study) if study else {})
    return report


def figures(args, cases, study=()):
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
    if study:
        fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
        for k, (key, name) in enumerate((("retrogression", "retrogression / H"),
                                         ("runout", "run-out / H"),
                                         ("mobilised", "mobilised mass"))):
            for (S_t, reg), color in zip(sorted({(r["S_t"], r["regularisation"])
                                                 for r in study}), ("C0", "C1", "C2", "C3",
                                                                    "C4", "C5")):
                runs = [r for r in study if r["S_t"] == S_t and r["regularisation"] == reg]
                axes[k].plot([r["n"] for r in runs],
                             [r[key] / (1 if key == "mobilised" else args.height)
                              for r in runs], "o-", color=color, label=f"S_t = {S_t:g}, {reg}")
            axes[k].set(xlabel="particles across H", ylabel=name, xscale="log")
            axes[k].set_xticks(args.mesh_study, [str(n) for n in args.mesh_study])
            axes[k].minorticks_off()
        axes[0].legend(fontsize=8)
        save_figure(fig, figure_dir(args, "sensitive_clay") / "mesh_study.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
