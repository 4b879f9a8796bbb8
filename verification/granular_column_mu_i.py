"""The granular columns rerun with mu(I), beside rate-independent runs (beyond the thesis).

The thesis' columns run out too far and stand too low, more so the taller they are, and
the thesis names the cure it did not try (6.4.3, 7.2.3): a friction that grows with the
shear rate. This script reruns the plane columns of 6.4.3
(:mod:`verification.granular_column_plane`) and the axisymmetric columns of 7.4
(:mod:`verification.granular_column_axisymmetric`) with the mu(I) rheology of Jop,
Forterre & Pouliquen (2006) (:mod:`pfem_skfem.materials.rate`, the lagged viscosity by
default; ``--lag friction``, all of mu(I) in the lagged cone, is refused with the mu(I) law as
in ``verification/inclined_plane_flow.py``: :data:`LAG_FRICTION`), each beside
rate-independent runs of the same size and resolution:

* ``mu_s``: zero-dilation Mohr-Coulomb (plane) / Drucker-Prager with sqrt(J2) <= mu p
  (axisymmetric) of friction mu_s, the limit mu_2 -> mu_s of the same material;
* ``mu_2``: the same of friction mu_2, the limit of mu(I) at high rates;
* ``thesis``: the rate-independent run of the column scripts (plane phi = 31 deg, the
  cone of [80]; axisymmetric the (7.10) cone, phi_g = 30 deg).

A mu(I) material has a grain size, so a column has a physical size (the normalised deposit
depends on a and on h0 / d, and on the solid fraction rho / rho_s).

* Plane: Lagree, Staron & Popinet (2011), J. Fluid Mech. 686, their continuum parameters
  mu_s = 0.32, mu_2 = mu_s + 0.28, I_0 = 0.40, and their column size, h0 = 65 d (their
  a = 1.42 and 6.26 columns; ``--h0-over-d``), at every a; or a fixed width in grains
  (``--d0-over-d``). The thesis gives no size for its plane columns, and Lube et al.'s
  (2005) channels are not in the research notes. Lagree et al. write I with the continuum
  density, so rho_s defaults to rho.
* Axisymmetric: Jop et al.'s glass beads (mu_s = 0.38, mu_2 = 0.64, I_0 = 0.279,
  d = 0.53 mm, rho_s = 2450 kg/m3, solid fraction 0.6) at the one laboratory size the
  thesis gives, r0 = 3.9 cm (Fig 7.6, Lajeunesse et al.'s glass beads), at every a. The
  rate part acts on the whole deviator, the hoop strain counted in the shear rate
  (:class:`~pfem_skfem.materials.rate.MuIRheologyAxisymmetric`). ``--volume-correction on``
  applies the move stage's volume projection to these columns (off by default, as the
  axisymmetric script).

References: the fits of Lube et al. as the column scripts print them (imported:
``lube_thesis``, ``lube_lagree``, ``lube_2004``, ``lajeunesse_2004``). Lagree et al.'s
own continuum deposits are not in the research notes (only their parameters and that they
ran a = 0.5, 1.42, 6.26): not compared.

Checks (what holds whatever the rheology): final height at most h0 (to 1 % of the
spacing), the deposit at rest, the particle masses summing to rho V (mass is passed on,
never made), and the mu(I) column invariant under one factor on rho and rho_s together
(every stress scales with rho, I with rho_s / rho; a factor on rho alone changes the
solid fraction and so the flow: no invariance, unlike the rate-independent columns). The
volume (plane: area) change, a discretisation error of the engine that the column scripts
gate, is reported beside each deposit and marked where it exceeds their bounds (the
low-friction twins spread into films a few particles thick, where the alpha-shape loses
area). The ordering of the run-outs (mu_2 <= mu(I) <= mu_s, since mu_s <= mu(I) <= mu_2
at every point) is expected but not a theorem for an inertial flow (there is no
comparison principle: friction changes where the mass goes, not only how fast); it is
reported, as is the comparison with the experiments: whether mu(I) closes the gap is the
result, either way.

Usage::

    python verification/granular_column_mu_i.py --quick --json results/granular_column_mu_i.json
    python verification/granular_column_mu_i.py --a 0.5 1 2 3 5 7 --nx 8 --steps 100
    python verification/granular_column_mu_i.py --help          # every option
"""
import argparse
import sys
from pathlib import Path

import numpy as np

from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, cohesionless_angle, in_range,
                                        material_options, nonnegative_float, opt, pfem_options,
                                        positive_float, positive_int, solver_keyword,
                                        sweep_options, time_options)
from pfem_skfem.harness.progress import progress
from pfem_skfem.harness.report import Report, script_main
from pfem_skfem.harness.sweeps import run_cases
from pfem_skfem.viz import plot_groups

if __package__ in (None, ""):                     # run as a file: the repository's root
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from verification import granular_column_axisymmetric as axi  # noqa: E402
from verification import granular_column_plane as plane  # noqa: E402

LAWS = ("mu(I)", "mu_s", "mu_2", "thesis")
# --quick: mu(I) and its rate-independent limit, one plane and one axisymmetric column
QUICK = dict(a=[1.0], nx=6, steps=50, a_axi=[0.5], nr=5, steps_axi=50, laws=["mu(I)", "mu_s"])
HEIGHT_TOLERANCE = 0.01          # of the particle spacing, as the column scripts
DENSITY_TOLERANCE = 1e-9         # relative: the deposit of (f rho, f rho_s) against (rho, rho_s)
#: why --lag friction is refused (as verification/inclined_plane_flow.py refuses it): all of
#: mu(I) in the cone, its radius 2 mu(I_j) p_j fixed by the last pass's shear rate, puts the
#: rate in explicitly, and the shear goes where the friction was lowest, where the material
#: did not shear: the flow bands at about mu_s (the book, "Rate-dependent friction"; on
#: Bagnold's steady layer u_s 8.3 x the exact at that script's --quick, 6.4 x with 10 x the
#: steps). The column's checks (height, rest, mass, density invariance) hold for any friction
#: and cannot tell: at --quick with it all 15 pass, the plane a = 1 run-out 2.237 against the
#: lagged viscosity's 2.142 (+4.4 %; the mu_s twin 3.245), the axisymmetric a = 0.5 0.740
#: against 0.738, heights 0.604 and 0.459 as the lagged viscosity's (2026-12, issue 56).
LAG_FRICTION = ("--lag friction (all of mu(I) in the cone, lagged) is refused with the mu(I) "
                "law: the rate enters explicitly and the flow bands at about mu_s, as "
                "inclined_plane_flow.py measures against Bagnold's layer; the book, "
                "'Rate-dependent friction'")
PARTICLES_ACROSS = in_range(2, integer=True, what="a number of particles across >= 2")
FRICTION = in_range(0, 1, low_open=True, high_open=True, what="a friction coefficient in (0, 1)")


def plane_soil(law, a, *, mu_s, mu_2, I_0, h0_over_d, d0_over_d, rho_s, lag, p_min, k_min,
               phi_thesis, d0=1.0):
    """The material of one plane column: mu(I) with d = h0 / h0_over_d (or d0 / d0_over_d),
    or a rate-independent twin (zero-dilation Mohr-Coulomb, sin phi = mu_s, mu_2, or the
    thesis' phi)."""
    from pfem_skfem.materials import MuIRheology, ZeroDilationMohrCoulomb
    if law == "mu(I)":
        d = a * d0 / h0_over_d if d0_over_d is None else d0 / d0_over_d
        return MuIRheology(mu_s=mu_s, mu_2=mu_2, I_0=I_0, d=d, rho_s=rho_s, p_min=p_min,
                           k_min=k_min, lag=lag)
    phi = {"mu_s": np.degrees(np.arcsin(mu_s)), "mu_2": np.degrees(np.arcsin(mu_2)),
           "thesis": phi_thesis}[law]
    return ZeroDilationMohrCoulomb(c=0.0, phi=float(phi), k_min=k_min)


def axisymmetric_soil(law, *, mu_s, mu_2, I_0, d, rho_s, lag, p_min, k_min, phi_thesis):
    """The material of one axisymmetric column: mu(I) (the full rate), the Drucker-Prager
    cone sqrt(J2) <= mu p of mu_s or mu_2 (zero dilation), or the thesis' (7.10) cone."""
    from pfem_skfem.materials import MuIRheologyAxisymmetric, ZeroDilationDruckerPrager
    if law == "mu(I)":
        return MuIRheologyAxisymmetric(mu_s=mu_s, mu_2=mu_2, I_0=I_0, d=d, rho_s=rho_s,
                                       p_min=p_min, k_min=k_min, lag=lag)
    if law == "thesis":
        return ZeroDilationDruckerPrager(c=0.0, phi=phi_thesis, k_min=k_min)
    mu = mu_s if law == "mu_s" else mu_2          # alpha = sin(phi) / 3: sqrt(J2) <= mu p
    return ZeroDilationDruckerPrager(c=0.0, phi=float(np.degrees(np.arcsin(mu))), k_min=k_min,
                                     match="plane-strain-psi0")


def plane_case(a, law, *, soil, nx, steps, settle, rho, g, mu_w, passes, alpha, verbose=False,
               solver="clarabel"):
    """One plane column (:func:`verification.granular_column_plane.run_case`), summarised."""
    material = plane_soil(law, a, **soil)
    r = plane.run_case(a, nx=nx, steps=steps, phi=material.phi, mu=mu_w, rho=rho, g=g,
                       floor=soil["k_min"], passes=passes, alpha=alpha, settle=settle,
                       soil=material, verbose=verbose, solver=solver)
    return dict(geometry="plane", law=law, a=a, rho=rho, rho_s=soil["rho_s"],
                d=getattr(material, "d", None), runout=r["runout_over_d0"],
                height=r["h_inf_over_d0"], spacing_over_h0=r["spacing_over_h0"],
                at_rest=r["at_rest"], t_rest=r["t_rest"],
                volume_change_max=r["volume_change_max"], mass_error=r["mass_error"],
                elements=r["elements"], seconds=r["seconds"],
                seconds_per_step=r["seconds_per_step"])


def axisymmetric_case(a, law, *, soil, nr, steps, settle, rho, g, r0, mu_w, passes, alpha,
                      volume_correction=False, verbose=False, solver="clarabel"):
    """One column of revolution (:func:`verification.granular_column_axisymmetric.run_case`),
    summarised; ``volume_correction``: the move stage's volume projection."""
    material = axisymmetric_soil(law, **soil)
    r = axi.run_case(a, nr=nr, steps=steps, phi=material.phi,
                     phi_s=float(np.degrees(np.arctan(mu_w))), rho=rho, g=g, r0=r0,
                     passes=passes, alpha=alpha, floor=soil["k_min"], settle=settle,
                     soil=material, volume_correction=volume_correction, verbose=verbose,
                     solver=solver)
    return dict(geometry="axisymmetric", law=law, a=a, rho=rho, rho_s=soil["rho_s"],
                d=getattr(material, "d", None), runout=r["runout_over_r0"],
                height=r["h_inf_over_r0"], spacing_over_h0=r["spacing_over_r0"] / a,
                at_rest=r["at_rest"], t_rest=r["t_rest"],
                volume_change_max=r["volume_change_max"], mass_error=r["mass_error"],
                elements=r["elements"], seconds=r["seconds"],
                seconds_per_step=r["seconds_per_step"])


def power_of_two(text):
    """A factor 2^k (k an integer, 0 for none): scaling by it is exact in floating point, so
    the scaled run is the same arithmetic and its deposit the same to the bit. Another factor
    rounds each scaled stress differently and the collapse amplifies it: at --quick the
    run-out moves by 2.3e-4 (x 2.5) and 8.3e-5 (x 3), the height by 2.7e-6 and 4.6e-6, where
    x 2 and x 4 give 0 (option audit, issue 56)."""
    f = positive_float(text)
    if f != 2.0 ** round(np.log2(f)):
        raise argparse.ArgumentTypeError(
            f"{text}: a power of 2 (1, 2, 4, 0.5, ...): the invariance is checked to "
            f"{DENSITY_TOLERANCE:g}, which only a factor exact in floating point gives (x 2.5 "
            "moves the run-out by 2.3e-4: round-off, amplified by the flow)")
    return f


def check(args):
    """Options that cannot go together (a usage error), or None."""
    if args.lag == "friction" and "mu(I)" in args.laws:
        return LAG_FRICTION
    for suffix in ("", "_axi"):
        if not getattr(args, "mu_2" + suffix) >= getattr(args, "mu_s" + suffix):
            flag = suffix.replace("_", "-")
            return f"--mu-2{flag} must be >= --mu-s{flag}"
    if not args.rho_axi < args.rho_s_axi:
        return "--rho-axi (bulk density) must be below --rho-s-axi (grain density)"
    return None


def cones(args):
    """The cones beyond the second-order ones: mu(I)'s implicit rate term is exponential."""
    return {"exp"} if args.lag == "implicit" and "mu(I)" in args.laws else set()


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check, cones=cones,
                    solver="qoco has no exponential cone: refused with mu(I) and --lag implicit")
    p.add_argument("--a", type=positive_float, nargs="*", default=list(plane.ASPECTS),
                   help="plane aspect ratios h0/d0 (none: no plane sweep)")
    p.add_argument("--a-axi", type=positive_float, nargs="*", default=list(axi.ASPECTS),
                   help="axisymmetric aspect ratios h0/r0 (none: no axisymmetric sweep)")
    p.add_argument("--laws", choices=LAWS, nargs="+", default=list(LAWS),
                   help="mu(I) and the rate-independent twins to run")
    p.add_argument("--lag", choices=("viscosity", "implicit", "friction"), default="viscosity",
                   help="how the rate enters the step (MuIRheology)")
    p.add_argument("--p-min", type=positive_float, default=1e-3,
                   help="least pressure in I, in units of rho g h0")
    material_options(p, g=9.8)
    time_options(p, settle=opt(4.0, "after t/sqrt(h0/g) = 4, go on for at most this long "
                                    "until at rest"))
    pfem_options(p, k_min=opt(0.005, why="in units of rho g h0"), passes=2, alpha=1.6)
    p.add_argument("--density-factor", type=power_of_two, default=2.0,
                   help="factor on rho and rho_s of the invariance run (mu(I), first plane a; "
                        "1: none; a power of 2: the deposit the same to the bit)")
    g = p.add_argument_group("plane columns (Lagree, Staron & Popinet 2011)")
    g.add_argument("--mu-s", type=FRICTION, default=0.32, help="static friction")
    g.add_argument("--mu-2", type=FRICTION, default=0.60, help="limiting friction (mu_s + 0.28)")
    g.add_argument("--I-0", type=positive_float, default=0.40, help="I_0 of mu(I)")
    g.add_argument("--h0-over-d", type=positive_float, default=65.0,
                   help="column height in grain diameters (Lagree et al.: 65)")
    g.add_argument("--d0-over-d", type=positive_float, default=None,
                   help="column width in grain diameters, in place of --h0-over-d")
    material_options(g, rho=opt(2.0, "bulk density [t/m3]"),
                     phi=opt(31.0, "friction angle of the thesis' run [deg]",
                             type=cohesionless_angle))
    g.add_argument("--rho-s", type=positive_float, default=None,
                   help="density in I [t/m3] (default --rho: Lagree et al.'s continuum density)")
    g.add_argument("--mu-w", type=nonnegative_float, default=float(np.tan(np.radians(31.0))),
                   help="base and wall friction (default tan 31 deg, the plane script's)")
    g.add_argument("--nx", type=PARTICLES_ACROSS, default=8, help="particles across d0")
    time_options(g, steps=opt(100, "time steps to t/sqrt(h0/g) = 4"))
    g = p.add_argument_group("axisymmetric columns (Jop et al. 2006 glass beads)")
    g.add_argument("--mu-s-axi", type=FRICTION, default=0.38, help="static friction")
    g.add_argument("--mu-2-axi", type=FRICTION, default=0.64, help="limiting friction")
    g.add_argument("--I-0-axi", type=positive_float, default=0.279, help="I_0 of mu(I)")
    g.add_argument("--d-axi", type=positive_float, default=0.53e-3, help="grain diameter [m]")
    g.add_argument("--rho-s-axi", type=positive_float, default=2.45,
                   help="grain density [t/m3]")
    g.add_argument("--rho-axi", type=positive_float, default=0.6 * 2.45,
                   help="bulk density [t/m3] (solid fraction 0.6)")
    g.add_argument("--r0", type=positive_float, default=0.039,
                   help="column radius [m] (thesis Fig 7.6: 3.9 cm)")
    g.add_argument("--mu-w-axi", type=nonnegative_float, default=float(np.tan(np.radians(30.0))),
                   help="base friction (default tan 30 deg, the axisymmetric script's)")
    g.add_argument("--phi-axi", type=cohesionless_angle, default=30.0,
                   help="friction angle phi_g of the thesis' (7.10) run [deg]")
    g.add_argument("--nr", type=PARTICLES_ACROSS, default=8, help="particles across r0")
    g.add_argument("--steps-axi", type=positive_int, default=100,
                   help="time steps to t/sqrt(h0/g) = 4")
    pfem_options(g, volume_correction=opt("off", why="the axisymmetric columns only"))
    sweep_options(p, what="the columns")
    return p


def _cases(args):
    """The plane and axisymmetric cases, then the density-invariance case."""
    rho_s = args.rho if args.rho_s is None else args.rho_s
    soil = dict(mu_s=args.mu_s, mu_2=args.mu_2, I_0=args.I_0, h0_over_d=args.h0_over_d,
                d0_over_d=args.d0_over_d, rho_s=rho_s, lag=args.lag, p_min=args.p_min,
                k_min=args.k_min, phi_thesis=args.phi)
    common = dict(settle=args.settle, g=args.g, passes=args.passes, alpha=args.alpha,
                  **solver_keyword(args))
    cases = [(plane_case, dict(common, a=a, law=law, soil=soil, nx=args.nx, steps=args.steps,
                                rho=args.rho, mu_w=args.mu_w))
             for a in sorted(args.a) for law in args.laws]
    soil_axi = dict(mu_s=args.mu_s_axi, mu_2=args.mu_2_axi, I_0=args.I_0_axi, d=args.d_axi,
                    rho_s=args.rho_s_axi, lag=args.lag, p_min=args.p_min, k_min=args.k_min,
                    phi_thesis=args.phi_axi)
    cases += [(axisymmetric_case, dict(common, a=a, law=law, soil=soil_axi, nr=args.nr,
                                       steps=args.steps_axi, rho=args.rho_axi, r0=args.r0,
                                       mu_w=args.mu_w_axi,
                                       volume_correction=args.volume_correction == "on"))
              for a in sorted(args.a_axi) for law in args.laws]
    if args.a and args.density_factor != 1.0 and "mu(I)" in args.laws:
        f = args.density_factor
        cases.append((plane_case, dict(cases[0][1], law="mu(I)", rho=f * args.rho,
                                       soil=dict(soil, rho_s=f * rho_s))))
    return cases


def run_column(function, keywords, verbose=False):
    """One case of :func:`_cases` (module level, for the Dask workers); ``verbose``: its
    progress bar."""
    return function(**keywords, verbose=verbose)


def _references(r):
    """Lube et al.'s fits at the case's a: (run-out, height) as the column scripts print them."""
    if r["geometry"] == "plane":
        h_ref, r_ref = (float(v) for v in plane.lube_thesis(r["a"]))
        return {"runout_lube": r_ref, "height_lube": h_ref,
                "runout_lube_lagree": float(plane.lube_lagree(r["a"]))}
    r_ref, h_ref, in_range = (v.item() for v in axi.lube_2004(r["a"]))
    return {"runout_lube": r_ref, "height_lube": h_ref if in_range else float("nan"),
            "height_lajeunesse": float(axi.lajeunesse_2004(r["a"])[1])}


def volume_bound(geometry):
    """The column script's stated bound on the volume (plane: area) change."""
    return plane.VOLUME_BOUND if geometry == "plane" else axi.VOLUME_BOUND


def _dev(value, ref):
    return value / ref - 1 if np.isfinite(ref) else float("nan")


def run(args):
    """The plane and axisymmetric sweeps and the invariance run; the Report of their checks."""
    cases = _cases(args)
    if args.progress:
        progress(f"{len(cases)} column(s) on "
                 f"{args.scheduler or str(args.workers) + ' worker(s)'}")
    results = run_cases(run_column, [dict(function=f, keywords=k, verbose=args.progress)
                                     for f, k in cases],
                        args.workers, desc="columns with mu(I)", scheduler=args.scheduler,
                        results_dir=args.results_dir)
    density = (results[-1] if args.a and args.density_factor != 1.0 and "mu(I)" in args.laws
               else None)
    rows = results[:-1] if density is not None else results
    report = Report("granular_column_mu_i", args)
    for r in rows:
        r["reference"] = _references(r)
        r["deviation"] = {"runout_lube": _dev(r["runout"], r["reference"]["runout_lube"]),
                          "height_lube": _dev(r["height"], r["reference"]["height_lube"])}
        # NaN is over the bound (NaN > bound is False)
        r["volume_change_over_bound"] = not r["volume_change_max"] <= volume_bound(r["geometry"])
    _tables(report, rows)
    for r in rows:
        tag = f"{r['geometry']}_{r['law']}_a{r['a']:g}"
        report.add_interval(f"{tag}_h_inf_over_h0", r["height"] / r["a"], 0.0, 1.0,
                            f"final height at most h0, to {HEIGHT_TOLERANCE:.0%} of the spacing",
                            tolerance=HEIGHT_TOLERANCE * r["spacing_over_h0"])
        report.add_interval(f"{tag}_t_rest", r["t_rest"] if r["at_rest"] else np.inf, 0.0,
                            4.0 + args.settle, "the deposit comes to rest")
        report.add_interval(f"{tag}_mass_error", r["mass_error"], 0.0, 1e-12,
                            "particle masses sum to rho V (passed on, never made)")
    if density is not None:
        base = next(r for r in rows if r["law"] == "mu(I)" and r["geometry"] == "plane"
                    and r["a"] == density["a"])
        for key in ("runout", "height"):
            report.add(f"density_{key}", density[key], base[key],
                       f"mu(I): rho and rho_s times {args.density_factor:g} (every stress "
                       "scales, I does not)", DENSITY_TOLERANCE)
        print(f"\ninvariance, plane a = {base['a']:g}, mu(I): rho, rho_s x "
              f"{args.density_factor:g}: run-out {density['runout']:.6f} against "
              f"{base['runout']:.6f}, height {density['height']:.6f} against {base['height']:.6f}")
    report.extra = {"columns": rows, "density": density}
    report.data = dict(rows=rows)
    return report


def _tables(report, rows):
    """Run-out and height of each law beside Lube et al.'s fits; the laws' order of run-out."""
    report.add_table(
        "deposits", ["geometry", "a", "law", "run-out", "Lube", "dev", "height", "Lube'", "dev'",
                     "t_rest", "|dV|max", "*", "s/step"],
        [[r["geometry"], r["a"], r["law"], r["runout"], r["reference"]["runout_lube"],
          r["deviation"]["runout_lube"], r["height"], r["reference"]["height_lube"],
          r["deviation"]["height_lube"], r["t_rest"], r["volume_change_max"],
          "*" if r["volume_change_max"] > volume_bound(r["geometry"]) else "",
          r["seconds_per_step"]] for r in rows],
        formats={"a": ".3g", "run-out": ".3f", "Lube": ".3f", "dev": "+.1%", "height": ".3f",
                 "Lube'": ".3f", "dev'": "+.1%", "t_rest": ".2f", "|dV|max": ".2%",
                 "s/step": ".2f"},
        title="final deposits (at rest): run-out (d-d0)/d0 or (r-r0)/r0, height h/d0 or h/r0 "
              "(at the wall / on the axis), against Lube et al.'s fits as the column scripts "
              f"print them (*: above the column script's bound on the volume change, plane "
              f"{volume_bound('plane'):.0%}, axisymmetric {volume_bound('axisymmetric'):.0%})")
    order = []
    for geometry in ("plane", "axisymmetric"):
        for a in sorted({r["a"] for r in rows if r["geometry"] == geometry}):
            by = {r["law"]: r for r in rows if r["geometry"] == geometry and r["a"] == a}
            if {"mu(I)", "mu_s", "mu_2"} <= set(by):
                lo, mid, hi = by["mu_2"]["runout"], by["mu(I)"]["runout"], by["mu_s"]["runout"]
                order.append([geometry, a, lo, mid, hi, "holds" if lo <= mid <= hi
                              else "does not hold"])
    if order:
        report.add_table("order", ["geometry", "a", "mu_2", "mu(I)", "mu_s",
                                   "mu_2 <= mu(I) <= mu_s"], order,
                         formats={"a": "g", "mu_2": ".3f", "mu(I)": ".3f", "mu_s": ".3f"},
                         title="run-out")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


MARKS = {"mu(I)": "o", "mu_s": "v", "mu_2": "^", "thesis": "s"}


def figures(args, rows):
    """Run-out and height against a, log-log, each law beside Lube et al.'s fits."""
    plt = pyplot()
    geometries = [g for g in ("plane", "axisymmetric") if any(r["geometry"] == g for r in rows)]
    fig, axes = plt.subplots(len(geometries), 2, figsize=(10, 4 * len(geometries)),
                             squeeze=False)
    for ax, geometry in zip(axes, geometries):
        rs = [r for r in rows if r["geometry"] == geometry]
        a_fit = np.logspace(np.log10(0.3), np.log10(max(r["a"] for r in rs) * 1.3), 200)
        if geometry == "plane":
            h_fit, r_fit = plane.lube_thesis(a_fit)
            curves = [(0, a_fit, r_fit, "k-", "Lube et al. 2005 (thesis 6.6)"),
                      (0, a_fit, plane.lube_lagree(a_fit), "k--", "Lube et al. (Lagree et al.)"),
                      (1, a_fit, h_fit, "k-", "Lube et al. 2005 (thesis 6.5)")]
            unit = "d0"
        else:
            r_fit, h_fit, _ = axi.lube_2004(a_fit)
            curves = [(0, a_fit, r_fit, "k-", "Lube et al. 2004 (7.31)"),
                      (1, a_fit, h_fit, "k-", "Lube et al. 2004 (7.32)"),
                      (1, a_fit, axi.lajeunesse_2004(a_fit)[1], "k--",
                       "Lajeunesse et al. 2004 (7.34)")]
            unit = "r0"
        plot_groups(ax, [(f"PFEM, {law}", [r for r in rs if r["law"] == law], MARKS[law])
                         for law in LAWS], "a", ("runout", "height"), log=True, curves=curves,
                    labels=(f"a = h0 / {unit}", (f"run-out / {unit}", f"final height / {unit}"),
                            f"{geometry} columns"))
    fig.tight_layout()
    save_figure(fig, figure_dir(args, "granular_column_mu_i") / "deposit_vs_a.png")


if __name__ == "__main__":
    sys.exit(main())
