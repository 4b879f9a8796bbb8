"""Strict lower and upper bounds of limit analysis that meet: footings, a cut, a slope.

The lower bound (linear stresses, admissible everywhere) and the upper bound (P2
velocities, dissipation through the criterion's cone at the vertices) of
:mod:`pfem_skfem.problems.bounds` bracket the true collapse load on every mesh; the
drivers of :mod:`pfem_skfem.drivers.bounds` refine where their gap lies (Doerfler
marking on the local gap) until the bracket is narrow. Cases:

1. smooth rigid strip footing on weightless Tresca soil (half model: smooth sides,
   rough base), Nc = 2 F / (c B) with F the force on the half footing: adaptive
   rounds and a uniform refinement of the same first mesh;
2. the same footing on Mohr-Coulomb soil (phi = 30 deg by default);
3. a vertical cut of height H in Tresca soil under gravity: gamma H / c at collapse;
4. the slope of Griffiths & Lane (1999) example 1: factor of safety F by strength
   reduction, F_L <= F <= F_U;
5. scale checks: c x k (footing), gamma x k and c x k (cut, slope);
6. the thesis' mixed element (kinematic form, not a bound) on the first footing mesh.

References
----------
* Prandtl: Nc = 2 + pi (Tresca); Mohr-Coulomb Nc = (tan^2(pi/4 + phi/2) exp(pi tan phi)
  - 1) cot phi (3.49) (Prandtl 1920, Reissner 1924): 30.14 at phi = 30 deg.
* Vertical cut: rigorous bounds 3.772 <= gamma H / c <= 3.786 (Pastor, Thai & Francescato
  2000, IJNAMG 24(2):165-182). These values are quoted widely; they were not checked
  against the paper's text here.
* Slope 2:1, phi' = 20 deg, c' / (gamma H) = 0.05, no foundation layer: F = 1.4 by
  (non-associated, psi = 0) elasto-plastic FE, 1.38 by Bishop & Morgenstern's charts
  (Griffiths & Lane 1999, Geotechnique 49(3):387-403, example 1). Neither is a bound.
* Scale: a weightless Tresca problem's bounds are proportional to c; gamma H / c and F
  depend on gamma and c only through c / (gamma H).

Usage::

    python verification/limit_bounds.py --quick --json results/limit_bounds.json   # half a minute
    python verification/limit_bounds.py --help                                # every option

``--quick`` and ``--json PATH`` (and ``--outdir``, ``--no-figures``, ``--quiet``)
come from :func:`pfem_skfem.harness.options.base_parser`.
"""
import math
import sys
import time
from dataclasses import replace

import numpy as np

from pfem_skfem.discretisation.meshes import (graded_rectangle_with_elements,
                                              triangulate_polygon)
from pfem_skfem.drivers.bounds import (adapt, bounds_at, bracket, bracket_safety,
                                       refine_uniformly)
from pfem_skfem.harness.declare import own_options
from pfem_skfem.harness.figures import figure_dir, labelled, pyplot, save_figure
from pfem_skfem.harness.options import (adaptive_options, base_parser, friction_angle,
                                        material_options, nonnegative_int, opt, positive_angle)
from pfem_skfem.harness.progress import bar_callback, progress_bar
from pfem_skfem.harness.report import Report, counted_warnings, script_main
from pfem_skfem.materials import MohrCoulomb, Tresca
from pfem_skfem.problems.bounds import LimitProblem, Punch, Support, kinematic
from pfem_skfem.problems.conic import AlmostSolvedWarning
from pfem_skfem.viz import plot_bound_fields, plot_rounds

QUICK = dict(target_gap=0.03, uniform=0, mc_rounds=3, mc_target_gap=0.06, cut_size=0.15,
             cut_rounds=3, tol_cut=0.08, slope_size=0.15, slope_rounds=1,
             slope_target_gap=0.06)
CUT_BOUNDS = (3.772, 3.786)       # Pastor, Thai & Francescato (2000): rigorous bounds
CUT_CENTRE = 3.78
SLOPE_FE, SLOPE_CHARTS = 1.4, 1.38   # Griffiths & Lane (1999) example 1: FE, Bishop-Morgenstern
SLOPE_RANGE = (1.30, 1.48)
EPS = 1e-9                        # relative tolerance of the boundary selections


def prandtl_nc(phi_deg):
    """Nc (3.49), 2 + pi for phi = 0 (as in verification/strip_footing.py)."""
    phi = np.radians(phi_deg)
    if phi == 0:
        return 2 + np.pi
    return (np.tan(np.pi / 4 + phi / 2) ** 2 * np.exp(np.pi * np.tan(phi)) - 1) / np.tan(phi)


def prandtl_extent(phi_deg, B=1.0):
    """Reach from the footing centre and depth of Prandtl's mechanism (as in strip_footing)."""
    phi = np.radians(phi_deg)
    r0 = 0.5 * B / np.cos(np.pi / 4 + phi / 2)
    r1 = r0 * np.exp(0.5 * np.pi * np.tan(phi))
    t = np.linspace(0, np.pi / 2, 200)
    ang = np.pi / 4 + phi / 2 + t
    depth = np.max(r0 * np.exp(t * np.tan(phi)) * np.sin(np.minimum(ang, np.pi - ang)))
    return 0.5 * B + 2 * r1 * np.cos(np.pi / 4 - phi / 2), depth


def footing_problem(criterion, W, D, B, n_elements, ratio):
    """Half model: punch on 0 <= x <= B/2 (smooth, velocity (0, -1)), smooth sides, rough base."""
    e = EPS * W
    mesh = graded_rectangle_with_elements(W, D, (B / 2, 0.0), n_elements, ratio=ratio)
    return LimitProblem(
        mesh, criterion,
        supports=(Support(lambda x: (x[0] < e) | (x[0] > W - e), "x"),
                  Support(lambda x: x[1] < -D + e, "xy")),
        punch=Punch(lambda x: (np.abs(x[1]) < e) & (x[0] < B / 2 + e), (0.0, -1.0), "y"))


def gravity_problem(polygon, size, criterion, gamma, L):
    """Base y = 0 rough, back x = L smooth, the rest free; gravity (0, -gamma) the live load."""
    e = EPS * L
    return LimitProblem(triangulate_polygon(polygon, size), criterion,
                        supports=(Support(lambda x: x[1] < e, "xy"),
                                  Support(lambda x: x[0] > L - e, "x")),
                        body_live=(0.0, -gamma))


def check(args):
    """Conditions between options (None when they hold)."""
    if not args.B < 2 * args.W:
        return f"--B ({args.B:g}) must be below twice --W ({args.W:g}): the footing in the domain"
    for name in ("cut_size", "slope_size"):
        if not getattr(args, name) < 1:
            return f"--{name.replace('_', '-')} must be below 1 (a fraction of --H)"
    return None


def scaling_tolerance(k):
    """The tolerance of a scaling check by ``k``, and its words: every scaled quantity is
    divided by the strength, so a power of two leaves the solver's data, and hence each
    bound (each trial F), the same bit for bit; otherwise to 1e-9."""
    if math.frexp(k)[0] == 0.5:
        return 0.0, "bit for bit (k a power of two)"
    return 1e-9, "to 1e-9"


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    g = p.add_argument_group("footings (cases 1, 2, 5, 6)")
    own_options(g, B=opt(1.0, "footing width"), W=opt(3.0, "half-domain width (Tresca)"),
                D=opt(2.0, "domain depth (Tresca)"))
    material_options(g, units=None, c=opt(1.0, "cohesion of footings and cut"),
                     phi=opt(30.0, "friction angle of the Mohr-Coulomb footing [deg]",
                             type=positive_angle("(3.49) has cot phi; the Tresca footing is "
                                                 "case 1")))
    adaptive_options(g, what="the Tresca footing", elements=500, ratio=80.0, theta=0.5,
                     rounds=5, target_gap=0.005, target_elements=5000,
                     max_elements=opt(20000, "largest adapted mesh of every case"))
    own_options(g, uniform=opt(2, "uniform refinements of the first Tresca mesh (0: none)",
                               type=nonnegative_int),
                uniform_target_gap=opt(0.01, "gap the last uniform mesh must reach (measured: "
                                             "0.79 %% on 8,240 elements)"),
                mc_width=opt(1.2, "half-width over the reach of Prandtl's mechanism "
                                  "(Mohr-Coulomb)"),
                mc_depth=opt(1.5, "depth over the depth of Prandtl's mechanism (Mohr-Coulomb)"))
    adaptive_options(g, "mc", what="the Mohr-Coulomb footing", elements=600,
                     ratio=opt(20.0, why="measured: 80 leaves 2.7 %% after 5 rounds, 20 "
                                         "leaves 1.6 %%"),
                     theta=0.5, rounds=5, target_gap=0.02)
    own_options(g, scale=opt(2.0, "factor k on c (footing) and on gamma and c (cut, slope) of "
                                  "case 5"))
    g = p.add_argument_group("vertical cut (case 3) and slope (case 4)")
    own_options(g, H=opt(1.0, "height of cut and slope"), gamma=opt(1.0, "unit weight"))
    adaptive_options(g, "cut", what="the cut",
                     size=opt(0.08, "element size of the first cut mesh over H"),
                     theta=0.5, rounds=6)
    own_options(g, tol_cut=opt(0.015, "both cut bounds within this of 3.78 (relative)"),
                slope_phi=opt(20.0, "phi' [deg]", type=friction_angle),
                slope_c=opt(0.05, "c' / (gamma H)"))
    adaptive_options(g, "slope", what="the slope",
                     size=opt(0.15, "element size of the first slope mesh over H"),
                     theta=0.5, rounds=opt(4, "rounds of meshes"),
                     target_gap=opt(0.03, "relative width of [F_L, F_U] to reach"))
    own_options(g, fos_tol=opt(1e-3, "relative tolerance of each F's root search"))
    return p


def tresca_footing(args, report, bar):
    """Cases 1, 6 and 5 on the Tresca footing: the adaptive rounds and the uniform
    refinements of the first mesh against Prandtl's 2 + pi, the mixed element between the
    bounds of the first mesh, and the bounds of c x k there."""
    nc, pi2, k = 2.0 / (args.c * args.B), prandtl_nc(0.0), args.scale   # Nc of the half model
    bar.set_description("Tresca footing, adaptive")
    first = footing_problem(Tresca(args.c), args.W, args.D, args.B, args.elements, args.ratio)
    tres = adapt(first, rounds=args.rounds, target_gap=args.target_gap,
                 max_elements=args.max_elements, theta=args.theta, solver=args.solver,
                 progress=bar_callback(bar, lambda r: f"Tresca: {r.elements} el, Nc in "
                                    f"[{r.lower * nc:.4f}, {r.upper * nc:.4f}]"))
    last, src = tres.rounds[-1], "Prandtl Nc = 2 + pi; {bound}"
    report.add_bracket("footing_Nc", last.lower * nc, last.upper * nc, pi2,
                       src + f" ({last.elements} elements)")
    report.add_interval("footing_gap", last.gap, 0.0, args.target_gap,
                        f"--target-gap: reached after {len(tres.rounds)} adaptive round(s) "
                        f"of at most {args.rounds}, elements "
                        + "/".join(str(r.elements) for r in tres.rounds), reference=0.0)
    report.add_interval("footing_elements", last.elements, 0, args.target_elements,
                        "--target-elements: the adapted mesh that reached the gap",
                        reference=0.0)
    bar.set_description("Tresca footing, uniform")
    uniform = refine_uniformly(first, args.uniform, solver=args.solver, progress=bar_callback(
        bar, lambda u: f"uniform: {u.elements} el, gap {100 * u.gap:.2f} %"))
    if args.uniform:
        u = uniform[-1].as_json(nc)
        report.add_interval("footing_uniform_gap", u["gap"], 0.0, args.uniform_target_gap,
                            f"--uniform-target-gap: {args.uniform} uniform refinement(s), "
                            f"{u['elements']} elements", reference=0.0)
        report.add_interval("footing_adaptive_over_uniform_gap", last.gap / u["gap"], 0.0,
                            1.0, f"the adapted mesh ({last.elements} el) narrower than the "
                            f"uniform one ({u['elements']} el)", reference=0.0)
        report.add_bracket("footing_uniform_Nc", u["lower"], u["upper"], pi2,
                           src + " (uniform mesh)")
    bar.set_description("mixed element, first mesh")
    mixed, r0 = kinematic(first, "gauss", solver=args.solver), tres.rounds[0]
    report.add_interval("footing_mixed_Nc", mixed.load * nc, r0.lower * nc, r0.upper * nc,
                        f"the thesis' mixed element (no bound) between the bounds of its "
                        f"mesh ({r0.elements} elements), as issue 38 states", reference=pi2)
    bar.set_description("scale checks")
    scaled = bracket(replace(first, criterion=Tresca(k * args.c)), solver=args.solver)
    bar.update(1)
    for name in ("lower", "upper"):
        report.add(f"footing_{name}_c_scaling", getattr(scaled, name) / getattr(r0, name), k,
                   f"a weightless Tresca bound is proportional to c (x {k:g}): to "
                   "round-off, 1e-6 allowed for the solver's tolerances", 1e-6)
    return tres, uniform, dict(
        rounds=[r.as_json(nc) for r in tres.rounds], uniform=[r.as_json(nc) for r in uniform],
        Nc_lower=last.lower * nc, Nc_upper=last.upper * nc, reference=pi2,
        mixed_Nc_first_mesh=mixed.load * nc, mixed_solve_s=mixed.info.solve_time,
        scaled_Nc=[scaled.lower * nc, scaled.upper * nc])


def mohr_coulomb_footing(args, report, bar):
    """Case 2: the footing on Mohr-Coulomb soil in a domain as large as Prandtl's mechanism
    times --mc-width and --mc-depth, against (3.49)."""
    bar.set_description(f"Mohr-Coulomb footing, phi = {args.phi:g}")
    nc, ref = 2.0 / (args.c * args.B), prandtl_nc(args.phi)
    reach, depth = prandtl_extent(args.phi, args.B)
    mc = adapt(footing_problem(MohrCoulomb(args.c, args.phi), args.mc_width * reach,
                               args.mc_depth * depth, args.B, args.mc_elements, args.mc_ratio),
               rounds=args.mc_rounds, target_gap=args.mc_target_gap,
               max_elements=args.max_elements, theta=args.mc_theta, solver=args.solver,
               progress=bar_callback(bar, lambda r: f"Mohr-Coulomb: {r.elements} el, Nc in "
                                    f"[{r.lower * nc:.3f}, {r.upper * nc:.3f}]"))
    m = mc.rounds[-1]
    report.add_bracket("footing_MC_Nc", m.lower * nc, m.upper * nc, ref,
                       f"(3.49) Prandtl-Reissner, phi = {args.phi:g}; {{bound}} "
                       f"({m.elements} elements)")
    report.add_interval("footing_MC_gap", m.gap, 0.0, args.mc_target_gap,
                        f"--mc-target-gap: {len(mc.rounds)} round(s), elements "
                        + "/".join(str(r.elements) for r in mc.rounds), reference=0.0)
    return mc, dict(rounds=[r.as_json(nc) for r in mc.rounds], phi=args.phi,
                    Nc_lower=m.lower * nc, Nc_upper=m.upper * nc, reference=ref,
                    width=args.mc_width * reach, depth=args.mc_depth * depth)


def vertical_cut(args, report, bar):
    """Case 3 and its case 5: the cut of height H under gravity, gamma H / c against Pastor
    et al.'s bounds, and unchanged by gamma, c x k on its first mesh."""
    bar.set_description("vertical cut")
    k, c, H, gamma = args.scale, args.c, args.H, args.gamma
    n_of = lambda alpha, g=gamma, cc=c: alpha * g * H / cc   # noqa: E731
    first = gravity_problem([(0, 0), (2 * H, 0), (2 * H, H), (0, H)], args.cut_size * H,
                            Tresca(c), gamma, 2 * H)
    cut = adapt(first, rounds=args.cut_rounds, target_gap=1e-6,
                max_elements=args.max_elements, theta=args.cut_theta, solver=args.solver,
                progress=bar_callback(bar, lambda r: f"cut: {r.elements} el, gamma H / c in "
                                    f"[{n_of(r.lower):.4f}, {n_of(r.upper):.4f}]"))
    cl, cu = n_of(cut.rounds[-1].lower), n_of(cut.rounds[-1].upper)
    src = "Pastor, Thai & Francescato 2000 (quoted; not checked in the paper)"
    report.add_interval("cut_N_lower", cl, -np.inf, CUT_BOUNDS[1],
                        f"{src}: a lower bound <= their upper bound 3.786", reference=CUT_CENTRE)
    report.add_interval("cut_N_upper", cu, CUT_BOUNDS[0], np.inf,
                        f"{src}: an upper bound >= their lower bound 3.772", reference=CUT_CENTRE)
    report.add("cut_N_lower_vs_3.78", cl, CUT_CENTRE, f"{src}; --tol-cut", args.tol_cut)
    report.add("cut_N_upper_vs_3.78", cu, CUT_CENTRE, f"{src}; --tol-cut", args.tol_cut)
    scaled = bracket(replace(first, criterion=Tresca(k * c), body_live=(0.0, -k * gamma)),
                     solver=args.solver)
    bar.update(1)
    scaled = [n_of(scaled.lower, k * gamma, k * c), n_of(scaled.upper, k * gamma, k * c)]
    tol, how = scaling_tolerance(k)
    for name, a, b in zip(("lower", "upper"), scaled,
                          (n_of(cut.rounds[0].lower), n_of(cut.rounds[0].upper))):
        report.add(f"cut_{name}_gamma_c_scaling", a, b,
                   f"gamma H / c unchanged by gamma, c x {k:g}: {how}", tol)
    return cut, dict(rounds=[r.as_json(gamma * H / c) for r in cut.rounds], N_lower=cl,
                     N_upper=cu, reference=list(CUT_BOUNDS), scaled_N_first_mesh=scaled)


def griffiths_lane_slope(args, report, bar):
    """Case 4 and its case 5: the slope's F_L <= F <= F_U by strength reduction against
    Griffiths & Lane's values, and unchanged by gamma, c x k on its first mesh."""
    bar.set_description("slope, strength reduction")
    k, H, gamma = args.scale, args.H, args.gamma
    criterion = MohrCoulomb(args.slope_c * gamma * H, args.slope_phi)
    first = gravity_problem([(0, 0), (5 * H, 0), (5 * H, H), (2 * H, H)], args.slope_size * H,
                            criterion, gamma, 5 * H)
    slope, last_mesh = bracket_safety(
        first, rounds=args.slope_rounds, target_gap=args.slope_target_gap,
        max_elements=args.max_elements, theta=args.slope_theta, tol=args.fos_tol,
        solver=args.solver,
        progress=bar_callback(bar, lambda r: f"slope: {r.elements} el, F in [{r.lower:.4f}, "
                                    f"{r.upper:.4f}]"))
    s = slope[-1]
    src = f"Griffiths & Lane 1999 ex. 1 ({s.elements} elements)"
    report.add_interval("slope_F_order", s.upper - s.lower, 0.0, np.inf,
                        "F_U - F_L >= 0: the bracket is ordered", reference=0.0)
    report.add_interval("slope_F_lower", s.lower, *SLOPE_RANGE, f"{src}: the range 1.30-1.48")
    report.add_interval("slope_F_upper", s.upper, *SLOPE_RANGE, f"{src}: the range 1.30-1.48")
    report.add_interval("slope_gap", s.gap, 0.0, args.slope_target_gap,
                        f"--slope-target-gap: {len(slope)} round(s), elements "
                        + "/".join(str(r.elements) for r in slope), reference=0.0)
    report.add_interval("slope_charts_1.38_in_bracket", SLOPE_CHARTS, s.lower, s.upper,
                        "Bishop & Morgenstern's charts (limit equilibrium, not a bound) "
                        "inside [F_L, F_U]", reference=SLOPE_CHARTS)
    report.add("slope_F_mid_vs_FE_1.4", 0.5 * (s.lower + s.upper), SLOPE_FE,
               f"{src}: their FE factor (psi = 0, not a bound), "
               f"{'inside' if s.lower <= SLOPE_FE <= s.upper else 'outside'} [F_L, F_U]", 0.03)
    scaled = bracket_safety(replace(first, criterion=MohrCoulomb(k * criterion.c, args.slope_phi),
                                    body_live=(0.0, -k * gamma)),
                            rounds=1, tol=args.fos_tol, solver=args.solver)[0][0]
    bar.update(1)
    tol, how = scaling_tolerance(k)
    for name in ("lower", "upper"):
        report.add(f"slope_F_{name}_gamma_c_scaling", getattr(scaled, name),
                   getattr(slope[0], name), f"F unchanged by gamma, c x {k:g} (first mesh): {how}",
                   tol)
    return slope, last_mesh, dict(
        rounds=[dict(elements=r.elements, F_lower=r.lower, F_upper=r.upper, gap=r.gap,
                     solves=r.solves, seconds=r.seconds) for r in slope],
        F_lower=s.lower, F_upper=s.upper, references=dict(FE=SLOPE_FE, charts=SLOPE_CHARTS),
        scaled_F_first_mesh=[scaled.lower, scaled.upper])


def run(args):
    """The six cases in turn; each adds its checks to one report. Clarabel's 'AlmostSolved'
    ends accepted by the library (a certified field) are counted, not printed."""
    t_start, report = time.perf_counter(), Report("limit_bounds", args)
    bar = progress_bar(total=args.rounds + args.uniform + 1 + args.mc_rounds + args.cut_rounds
                       + args.slope_rounds + 3, args=args, desc="limit bounds", unit="round")
    with counted_warnings(AlmostSolvedWarning) as accepted:
        tres, uniform, footing = tresca_footing(args, report, bar)
        mc, footing_mc = mohr_coulomb_footing(args, report, bar)
        cut, vertical = vertical_cut(args, report, bar)
        slope, slope_last, slope_json = griffiths_lane_slope(args, report, bar)
    bar.close()
    report.extra = dict(footing_tresca=footing, footing_mohr_coulomb=footing_mc,
                        vertical_cut=vertical, slope=slope_json,
                        wall_time_s=time.perf_counter() - t_start,
                        almost_solved_accepted=accepted.count)
    report.data = dict(tres=tres, mc=mc, cut=cut, slope=slope, slope_last=slope_last,
                       uniform=uniform)
    return report


def figures(args, tres, mc, cut, slope, slope_last, uniform):
    """(a) the footing's fields, (b) the bounds against elements, (c) the slope's fields."""
    plt, out, nc = pyplot(), figure_dir(args, "limit_bounds"), 2.0 / (args.c * args.B)
    fig, axes = plt.subplots(1, 2, figsize=(11, 3.6))
    plot_bound_fields(axes, tres.problem, tres.lower, tres.upper, "Tresca footing")
    save_figure(fig, out / "footing_fields.png")

    fig, axes = plt.subplots(2, 2, figsize=(10, 7))
    for ax, (title, rounds, f, ref, ref_label) in zip(axes.ravel(), [
            ("Tresca footing: Nc", tres.rounds, nc, prandtl_nc(0.0), "Prandtl 2 + pi"),
            (f"Mohr-Coulomb footing, phi = {args.phi:g}: Nc", mc.rounds, nc,
             prandtl_nc(args.phi), "(3.49)"),
            ("vertical cut: gamma H / c", cut.rounds, args.gamma * args.H / args.c, CUT_BOUNDS,
             "3.772-3.786 (Pastor et al.)"),
            ("slope: factor of safety F", slope, 1.0, SLOPE_CHARTS, "1.38 charts")]):
        plot_rounds(ax, rounds, f, reference=ref, label=ref_label)
        if ax is axes[0, 0] and len(uniform) > 1:
            plot_rounds(ax, uniform, f, hollow=True, what=", uniform")
        if ax is axes[1, 1]:
            ax.axhline(SLOPE_FE, color="0.5", ls=":", lw=1, label="1.4 FE (G & L)")
        labelled(ax, "elements", title.split(": ")[1], title, title_size=9)
    save_figure(fig, out / "bounds_vs_elements.png")

    F = 0.5 * (slope[-1].lower + slope[-1].upper)
    fig, axes = plt.subplots(2, 1, figsize=(9, 6))
    with counted_warnings(AlmostSolvedWarning):           # certified: counted in run
        plot_bound_fields(axes, *bounds_at(slope_last, F, solver=args.solver),
                          f"slope at F = {F:.3f}")
    save_figure(fig, out / "slope_fields.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
