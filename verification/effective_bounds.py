"""Effective-stress limit analysis: strict bounds and factors of safety with a water table.

Beyond the thesis (issue 54, item 4). The criterion holds for the effective stress
sigma' = sigma + p I, equilibrium for the total stress, the pore pressure p a given field
(:mod:`pfem_skfem.problems.effective_stress`: in the lower bound a body force -grad p, in
the upper bound the power of p on the volumetric strain rate, free boundaries carrying the
water's pressure p). Cases:

1. Griffiths & Lane's slope (2:1, phi' = 20 deg, c' / (gamma H) = 0.05) under water, the
   table above the crest: p = gamma_w (h - y) is linear, its gradient turns gamma_sat into
   gamma' = gamma_sat - gamma_w and the water on the slope's surface cancels the pore
   pressure there, so the problem is the dry slope of gamma': the multiplier of gravity
   (both bounds) and F_L, F_U equal the dry gamma' slope's to 1e-6; gravity the only load,
   alpha gamma is the collapse weight: alpha gamma' = alpha_dry gamma_sat to 1e-6;
2. the slope with a water table below the crest at y_w (horizontal behind the slope, down
   the face below y_w: a seepage face, p = 0 on the whole face; hydrostatic below it):
   F_L <= F_U for each y_w, beside the dry slope's, and both fall as y_w rises
   (associated flow dilates, so the pore pressure's power int p div v >= 0 grows with p);
3. steady seepage up through the submerged slope (a Laplace solve for the head: the
   slope's face and crest under water at the level of case 1; an aquifer below, the base
   higher by Delta h x / (5H), the back wall by Delta h (1 - y / H), continuous): with
   Delta h = 0 the solve is hydrostatic and F_L, F_U are case 1's to 1e-6; as Delta h
   rises the pore pressure rises everywhere inside (maximum principle) and stays the
   water's on the free boundary, so both bounds of F fall;
4. the undrained strip footing, Tresca in effective stress (c' = s_u, phi' = 0), a water
   table at h_w below, at and above the ground: Tresca bounds the deviator only and its
   flow is isochoric, so p changes the footing's force only by the water's pressure on
   it: (F - p(0) B) / (s_u B) brackets Prandtl's 2 + pi, and both bounds equal the dry
   footing's of the same mesh to 1e-6.

The slope's friction angle: at or above the slope's atan(1/2) = 26.57 deg no multiple of
gravity collapses it, and short of that the upper bound's mechanisms lock on the mesh (no
mechanism past tan(phi') = 1/2 - (0.07 to 0.26) s for an element size s H, the bound a pole
towards it, and nearer it its solves end 'AlmostSolved' short of case 1's 1e-6): --phi is
refused above 23 deg (:data:`PHI_MAX`) and above tan(phi') = 1/2 - max(s, 0.1) / 4
(:func:`locking_tan`, which binds on meshes coarser than 0.3 H).

References
----------
* Prandtl: Nc = 2 + pi.  Terzaghi's principle: sigma = sigma' - p I.
* Griffiths & Lane (1999), Geotechnique 49(3), example 1: the dry slope, F = 1.38
  (Bishop & Morgenstern's charts; limit equilibrium, not a bound), as in
  ``verification/limit_bounds.py``: checked inside the dry slope's [F_L, F_U] where the
  slope is theirs, c' / (gamma H) = 0.05 and phi' = 20 deg (the dry F depends on these
  alone), at any H, gamma and c' of that ratio; not elsewhere (:func:`griffiths_lane`).

Usage::

    python verification/effective_bounds.py --quick --json results/effective_bounds.json
"""
import sys
import time
import warnings
from dataclasses import replace

import numpy as np

from pfem_skfem.discretisation.meshes import (graded_rectangle_with_elements,
                                              triangulate_polygon)
from pfem_skfem.drivers.bounds import factor_of_safety
from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (adaptive_options, base_parser, in_range,
                                        material_options, opt, positive_float, saturated_options)
from pfem_skfem.harness.progress import progress_bar
from pfem_skfem.harness.report import Report, script_main
from pfem_skfem.materials import MohrCoulomb, Tresca
from pfem_skfem.problems.bounds import LimitProblem, Punch, Support, lower_bound, upper_bound
from pfem_skfem.problems.conic import AlmostSolvedWarning
from pfem_skfem.problems.effective_stress import PorePressure, Seepage, WaterTable

QUICK = dict(slope_size=0.2, fos_tol=1e-2, y_w=[0.4, 0.8], Delta_h=[0.5], elements=300)
SLOPE_CHARTS = 1.38               # Griffiths & Lane (1999) ex. 1: Bishop-Morgenstern charts
EPS = 1e-9                        # relative tolerance of the boundary selections
#: Clarabel's retry settings of the bounds (problems/bounds.py) from the start: the
#: identities of case 1 hold for the mesh's optimum, which an 'AlmostSolved' end may miss
EXACT = dict(equilibrate_enable=False, static_regularization_constant=1e-7)
#: the upper bound's mechanisms lock short of the slope's angle (book, "Options away from
#: their defaults"): the P2 velocities with the flow rule at the vertices have no mechanism
#: past tan(phi') = 1/2 - k s on a mesh of element size s H, the bound growing as a pole
#: towards it (alpha_U = 38 / (25.0 deg - phi') at s = 0.2); the lock measured at 25.73,
#: 25.64, 25.39, 25.25, 25.48, 24.92, 25.05, 24.93, 24.92, 24.31, 23.17, 23.73, 23.15, 22.08,
#: 24.57 deg for s = 0.07, 0.1, 0.125, 0.15, ..., 0.3, 0.35, 0.4, 0.45, 0.5, 0.6: k = 0.07
#: to 0.21 from s = 0.1, 0.26 at 0.07 (s = 0.05: certified at 25.41 deg, alpha_U 68.7).
#: --phi is refused above k = LOCKING, s taken at least LOCKING_SIZE
LOCKING, LOCKING_SIZE = 0.25, 0.1
#: and nearer the lock the upper bound's solves lose the accuracy of case 1's identities (to
#: 1e-6): at the default size (0.1 H) every one ends 'AlmostSolved', the identities holding
#: to 0.4e-7-4.0e-7 at 20-23 deg and off by 1.7e-6, 2.7e-6, 1.2e-5, 1.5e-5 at 24, 24.5,
#: 25.2, 25.4 deg (the submerged bound not certified at 25.0): --phi is refused above this
PHI_MAX = 23.0


def locking_tan(slope_size):
    """The largest tan(phi') accepted on a slope mesh of element size ``slope_size`` x H:
    1/2 - :data:`LOCKING` x max(``slope_size``, :data:`LOCKING_SIZE`), short of the mesh's
    measured locking (25.41 deg from s = 0.1 down, 24.23 at the quick 0.2, 23.03 at 0.3,
    20.56 at 0.5; below :data:`PHI_MAX` from 0.3 up)."""
    return 0.5 - LOCKING * max(slope_size, LOCKING_SIZE)


def slope_problem(args, gamma, pore=None):
    """The 2:1 slope of height H (toe at the origin, crest from x = 2H): rough base, smooth
    back at x = 5H; gravity (0, -gamma) the live load."""
    H, e = args.H, EPS * args.H
    poly = [(0, 0), (5 * H, 0), (5 * H, H), (2 * H, H)]
    return LimitProblem(triangulate_polygon(poly, args.slope_size * H),
                        MohrCoulomb(args.c, args.phi),
                        supports=(Support(lambda x: x[1] < e, "xy"),
                                  Support(lambda x: x[0] > 5 * H - e, "x")),
                        body_live=(0.0, -gamma), pore_pressure=pore)


def phreatic(args, y_w):
    """A water table at y_w behind the slope and down its face below y_w, scaled with
    gravity (live: the water's weight is part of it)."""
    H = args.H
    return PorePressure(WaterTable([(0.0, 0.0), (2 * y_w, y_w), (5 * H, y_w)], args.gamma_w),
                        live=True)


def seepage(args, problem, dh):
    """``problem`` with the pore pressure of steady seepage (live): face and crest at the
    head 2H (under water, as case 1); an aquifer below, the base at 2H + dh x / (5H), and
    the back wall at 2H + dh (1 - y / H): continuous, no singular exit gradient."""
    H, e = args.H, EPS * args.H
    heads = ((lambda x: (x[1] > e) & (x[0] < 5 * H - e), 2 * H),
             (lambda x: x[1] < e, lambda x: 2 * H + dh * x[0] / (5 * H)),
             (lambda x: x[0] > 5 * H - e, lambda x: 2 * H + dh * (1 - x[1] / H)))
    field = Seepage.solve(problem.mesh, heads, args.gamma_w)
    return replace(problem, pore_pressure=PorePressure(field, live=True))


def footing_problem(args, h_w=None):
    """Half model of a smooth strip footing B on Tresca soil s_u of unit weight gamma (a dead
    load): smooth sides, rough base; a water table at h_w above the ground (dead)."""
    W, D, B, e = args.W, args.D, args.B, EPS * args.W
    pore = None if h_w is None else WaterTable(h_w, args.gamma_w)
    return LimitProblem(graded_rectangle_with_elements(W, D, (B / 2, 0.0), args.elements,
                                                       ratio=args.ratio),
                        Tresca(args.su),
                        supports=(Support(lambda x: (x[0] < e) | (x[0] > W - e), "x"),
                                  Support(lambda x: x[1] < -D + e, "xy")),
                        punch=Punch(lambda x: (np.abs(x[1]) < e) & (x[0] < B / 2 + e)),
                        body_dead=(0.0, -args.gamma), pore_pressure=pore)


def griffiths_lane(args):
    """Whether the dry slope is Griffiths & Lane's example 1 (c' / (gamma H) = 0.05, phi' =
    20 deg, to 1e-9), the one slope whose F the charts' :data:`SLOPE_CHARTS` is: a dry slope's
    F is a function of c' / (gamma H) and phi' alone (the mesh scales with H)."""
    return (abs(args.c / (args.gamma * args.H) - 0.05) <= 1e-9 * 0.05
            and abs(args.phi - 20.0) <= 1e-9 * 20.0)


def check(args):
    if not args.B < 2 * args.W:
        return f"--B ({args.B:g}) must be below twice --W ({args.W:g}): the footing in the domain"
    if not np.tan(np.radians(args.phi)) < 0.5:
        return (f"--phi ({args.phi:g}) must be below the slope's angle atan(1/2) = 26.57 deg: "
                "at or above it no multiple of gravity collapses the slope (the upper bound "
                "has no mechanism; the multiplier grows without bound towards it)")
    if args.phi > PHI_MAX:
        return (f"--phi ({args.phi:g}) must be at most {PHI_MAX:g} deg: towards the slope's "
                "26.57 deg the upper bound's mechanisms lock on the mesh (a pole: on the quick "
                "mesh alpha_U = 38 / (25.0 deg - phi'), no mechanism from 25.0 deg, where "
                "Culmann's wedge bounds alpha by 217; at the default size from 25.64 deg), and "
                "nearer the lock its solves end 'AlmostSolved' short of the 1e-6 of case 1's "
                "identities (default size: 1.7e-6 at 24 deg, 1.5e-5 at 25.4, a bound not "
                f"certified at 25.0; 4.0e-7 at most up to {PHI_MAX:g})")
    if not np.tan(np.radians(args.phi)) <= locking_tan(args.slope_size):
        return (f"--phi ({args.phi:g}) at --slope-size {args.slope_size:g}: tan(phi') must be "
                f"at most 1/2 - {LOCKING:g} x max(slope size, {LOCKING_SIZE:g}) = "
                f"{locking_tan(args.slope_size):.4g} (phi' <= "
                f"{np.degrees(np.arctan(locking_tan(args.slope_size))):.2f} deg): the upper "
                "bound's mechanisms lock on the mesh short of the slope's 26.57 deg, the "
                "coarser the sooner (measured: none past tan(phi') = 1/2 - (0.07 to 0.26) x "
                "slope size, sizes 0.07 to 0.6; 22.08 deg at 0.5): a smaller --phi or a finer "
                "--slope-size")
    if not args.gamma > args.gamma_w:
        return (f"--gamma ({args.gamma:g}) must exceed --gamma-w ({args.gamma_w:g}): a "
                "positive submerged unit weight")
    if any(b <= a for a, b in zip(args.y_w, args.y_w[1:])):
        return f"--y-w must increase, got {args.y_w}"
    if any(b <= a for a, b in zip(args.Delta_h, args.Delta_h[1:])):
        return f"--Delta-h must increase, got {args.Delta_h}"
    return None


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    g = p.add_argument_group("slope (cases 1-3)")
    g.add_argument("--H", type=positive_float, default=10.0, help="slope height H [m]")
    g.add_argument("--gamma", type=positive_float, default=20.0,
                   help="saturated unit weight gamma_sat of slope and footing soil [kN/m3]")
    saturated_options(g, gamma_w=9.81)
    material_options(g, c=opt(10.0, "effective cohesion c' of the slope (c' / (gamma H) = "
                                    "0.05: Griffiths & Lane)"),
                     phi=opt(20.0, "effective friction angle phi' of the slope"),
                     su=opt(20.0, "undrained strength s_u = c' of the Tresca footing"))
    g.add_argument("--y-w", type=in_range(0, 1, low_open=True, high_open=True,
                                          what="a fraction of H in (0, 1)"),
                   nargs="+", default=[0.25, 0.5, 0.75],
                   help="water-table heights y_w / H below the crest, increasing (case 2)")
    g.add_argument("--Delta-h", type=in_range(0, 1, low_open=True,
                                              what="a fraction of H in (0, 1] (measured: at "
                                                   "2 the slope has no positive F)"),
                   nargs="+", default=[0.25, 0.5, 1.0],
                   help="excess head of the aquifer below at the corner (5H, 0) over the "
                        "reservoir's, Delta h / H, increasing (case 3)")
    adaptive_options(g, "slope", what="the slope",
                     size=opt(0.1, "element size of the slope mesh over H (uniform)"))
    g.add_argument("--fos-tol", type=positive_float, default=1e-3,
                   help="relative tolerance of each F's root search")
    g = p.add_argument_group("footing (case 4)")
    g.add_argument("--B", type=positive_float, default=2.0, help="footing width B [m]")
    g.add_argument("--W", type=positive_float, default=6.0, help="half-domain width [m]")
    g.add_argument("--D", type=positive_float, default=4.0, help="domain depth [m]")
    g.add_argument("--h-w", type=in_range(-100, 100, what="a height in [-100, 100] m"),
                   nargs="+", default=[-1.0, 0.0, 1.0],
                   help="water-table heights h_w above the ground [m] (negative: below)")
    adaptive_options(g, what="the footing", elements=800, ratio=80.0)
    return p


def bracket(problem, settings):
    """(alpha_L, alpha_U) of ``problem``."""
    return (lower_bound(problem, **settings).load, upper_bound(problem, **settings).load)


def safety(problem, tol, settings):
    """(F_L, F_U) of ``problem``."""
    lo = factor_of_safety(problem, "lower", tol=tol, **settings).F
    return lo, factor_of_safety(problem, "upper", tol=tol, start=lo, **settings).F


def run(args):
    """The four cases; Clarabel's certified 'AlmostSolved' ends are counted, not printed."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", AlmostSolvedWarning)
        report = _run(args)
    report.extra["almost_solved_accepted"] = sum(
        issubclass(w.category, AlmostSolvedWarning) for w in caught)
    return report


def _run(args):
    t_start = time.perf_counter()
    report = Report("effective_bounds", args)
    # the identities (cases 1, 4 and 3 at Delta h = 0) with EXACT; the rest as the library
    # solves (an EXACT solve is one try: it fails where the retries would not)
    settings = dict(solver=args.solver)
    exact = dict(settings, **(EXACT if args.solver == "clarabel" else {}))
    gamma, gamma_w = args.gamma, args.gamma_w
    gamma_sub = gamma - gamma_w
    bar = progress_bar(total=6 + len(args.y_w) + len(args.Delta_h) + len(args.h_w), args=args,
                       desc="effective bounds", unit="case")

    # -- 1. submerged slope against the dry slope of gamma' --------------------------------
    submerged = slope_problem(args, gamma,
                              PorePressure(WaterTable(2 * args.H, gamma_w), live=True))
    dry_sub = replace(submerged, body_live=(0.0, -gamma_sub), pore_pressure=None)
    dry = replace(submerged, pore_pressure=None)
    alpha = {name: bracket(pr, exact) for name, pr in
             (("submerged", submerged), ("dry_sub", dry_sub), ("dry", dry))}
    bar.update(1)
    F = {}
    for name, pr in (("submerged", submerged), ("dry_sub", dry_sub), ("dry", dry)):
        F[name] = safety(pr, args.fos_tol, exact)
        bar.update(1)
    src = "the submerged slope is the dry slope of gamma' = gamma_sat - gamma_w"
    for k, kind in enumerate(("lower", "upper")):
        report.add(f"submerged_alpha_{kind}", alpha["submerged"][k], alpha["dry_sub"][k],
                   f"{src}: the {kind} bound of the gravity multiplier, to 1e-6", 1e-6)
        report.add(f"submerged_alpha_{kind}_scaling", alpha["submerged"][k] * gamma_sub,
                   alpha["dry"][k] * gamma, "gravity the only load: alpha gamma' = "
                   "alpha_dry gamma_sat, to 1e-6", 1e-6)
        report.add(f"submerged_F_{kind}", F["submerged"][k], F["dry_sub"][k],
                   f"{src}: F_{kind[0].upper()} by strength reduction, to 1e-6", 1e-6)
        report.add_interval(f"submerged_F_{kind}_above_dry", F["submerged"][k] - F["dry"][k],
                            0.0, np.inf, "under water the slope is safer: on one mesh each "
                            "bound of alpha is proportional to 1 / gamma, and gamma' < "
                            "gamma_sat", reference=0.0)
    n_slope = submerged.mesh.t.shape[1]

    # -- 2. a water table below the crest -----------------------------------------------------
    rows = [("dry", 0.0, *F["dry"], *alpha["dry"])]
    for y in args.y_w:
        pr = slope_problem(args, gamma, phreatic(args, y * args.H))
        rows.append((f"y_w = {y:g} H", y, *safety(pr, args.fos_tol, settings),
                     *bracket(pr, settings)))
        bar.update(1)
    if griffiths_lane(args):
        report.add_interval("dry_F_charts_in_bracket", SLOPE_CHARTS, *F["dry"],
                            f"Griffiths & Lane ex. 1: Bishop & Morgenstern's 1.38 (not a "
                            f"bound) inside [F_L, F_U] of the dry slope ({n_slope} elements)",
                            reference=SLOPE_CHARTS)
    else:
        report.extra["dry_F_charts"] = (
            f"not checked: the charts' 1.38 is the slope of c' / (gamma H) = 0.05, phi' = 20 "
            f"deg; here {args.c / (args.gamma * args.H):.4g}, {args.phi:g} deg")
    for (prev, _, fl0, fu0, *_), (name, y, fl, fu, *_) in zip(rows, rows[1:]):
        report.add_interval(f"F_order_y_w{y:g}", fu - fl, 0.0, np.inf,
                            "F_U - F_L >= 0: the bracket is ordered", reference=0.0)
        for kind, a, b in (("lower", fl0, fl), ("upper", fu0, fu)):
            report.add_interval(f"F_{kind}_falls_y_w{y:g}", a - b, 0.0, np.inf,
                                f"F_{kind[0].upper()} below that of {prev}: a higher table, "
                                "more pore pressure on a dilating mechanism", reference=0.0)
    report.add_table("slope", ["water table", "y_w / H", "F_L", "F_U", "alpha_L", "alpha_U"],
                     [list(r) for r in rows],
                     formats={k: ".4f" for k in ("F_L", "F_U", "alpha_L", "alpha_U")},
                     title=f"slope 2:1, phi' = {args.phi:g}, c' = {args.c:g}, "
                           f"{n_slope} elements")

    # -- 3. steady seepage towards the submerged slope -------------------------------------------
    flow = [("Delta h = 0", 0.0, *safety(seepage(args, dry, 0.0), args.fos_tol, exact))]
    bar.update(1)
    for k, kind in enumerate(("lower", "upper")):
        report.add(f"seepage_none_F_{kind}", flow[0][2 + k], F["submerged"][k],
                   "no head difference: the Laplace solve is hydrostatic, case 1's "
                   f"F_{kind[0].upper()}, to 1e-6", 1e-6)
    for dh in args.Delta_h:
        flow.append((f"Delta h = {dh:g} H", dh, *safety(seepage(args, dry, dh * args.H),
                                                        args.fos_tol, settings)))
        bar.update(1)
    for (prev, _, fl0, fu0), (name, dh, fl, fu) in zip(flow, flow[1:]):
        report.add_interval(f"seepage_F_order_dh{dh:g}", fu - fl, 0.0, np.inf,
                            "F_U - F_L >= 0: the bracket is ordered", reference=0.0)
        for kind, a, b in (("lower", fl0, fl), ("upper", fu0, fu)):
            report.add_interval(f"seepage_F_{kind}_falls_dh{dh:g}", a - b, 0.0, np.inf,
                                f"F_{kind[0].upper()} below that of {prev}: a higher head "
                                "behind, more pore pressure inside, the same on the face",
                                reference=0.0)
    report.add_table("seepage", ["aquifer", "Delta h / H", "F_L", "F_U"],
                     [list(r) for r in flow], formats={"F_L": ".4f", "F_U": ".4f"})

    # -- 4. the undrained Tresca footing ------------------------------------------------------
    nc = 2.0 / (args.su * args.B)               # Nc of the half model's force
    pi2 = 2 + np.pi
    dry_f = footing_problem(args)
    lo_d, up_d = bracket(dry_f, exact)
    bar.update(1)
    foot_rows = [("dry", np.nan, lo_d * nc, up_d * nc)]
    for h_w in args.h_w:
        lo, up = bracket(footing_problem(args, h_w), exact)
        surcharge = gamma_w * max(h_w, 0.0) * args.B / 2    # the water's pressure on it
        nl, nu = (lo - surcharge) * nc, (up - surcharge) * nc
        foot_rows.append((f"h_w = {h_w:g} m", h_w, nl, nu))
        tag = f"h_w{h_w:g}"
        report.add_interval(f"footing_Nc_lower_{tag}", nl, -np.inf, pi2,
                            "Prandtl 2 + pi: (F - p(0) B) / (s_u B), a lower bound",
                            reference=pi2)
        report.add_interval(f"footing_Nc_upper_{tag}", nu, pi2, np.inf,
                            "Prandtl 2 + pi: (F - p(0) B) / (s_u B), an upper bound",
                            reference=pi2)
        for kind, a, b in (("lower", nl, lo_d * nc), ("upper", nu, up_d * nc)):
            report.add(f"footing_{kind}_vs_dry_{tag}", a, b, "Tresca: p changes the force "
                       "only by the water's pressure on the footing; the dry bound of the "
                       "same mesh, to 1e-6", 1e-6)
        bar.update(1)
    report.add_table("footing", ["water table", "h_w [m]", "Nc_L", "Nc_U"],
                     [list(r) for r in foot_rows], formats={"Nc_L": ".4f", "Nc_U": ".4f"},
                     title=f"Tresca footing, {dry_f.mesh.t.shape[1]} elements")
    bar.close()
    report.extra = {"slope": dict(elements=n_slope, rows=[list(r) for r in rows],
                                  alpha=alpha, F={k: list(v) for k, v in F.items()}),
                    "seepage": [list(r) for r in flow],
                    "footing": dict(elements=dry_f.mesh.t.shape[1],
                                    rows=[list(r) for r in foot_rows]),
                    "wall_time_s": time.perf_counter() - t_start}
    report.data = dict(rows=rows, flow=flow, foot_rows=foot_rows)
    return report


def figures(args, rows, flow, foot_rows):
    """The slope's F bracket against the water table's height and against the head
    difference of the seepage, the footing's Nc bracket."""
    plt = pyplot()
    fig, ax = plt.subplots(1, 3, figsize=(15, 4))
    y = [r[1] for r in rows]
    ax[0].fill_between(y, [r[2] for r in rows], [r[3] for r in rows], color="C0", alpha=0.3,
                       label="[F_L, F_U]")
    ax[0].plot(y, [r[2] for r in rows], "o-", color="C0", label="F_L (safe)")
    ax[0].plot(y, [r[3] for r in rows], "s-", color="C3", label="F_U (unsafe)")
    ax[0].set_xlabel("water table y_w / H (0: dry)")
    ax[0].set_ylabel("factor of safety F")
    ax[0].set_title(f"slope 2:1, phi' = {args.phi:g}: water table below the crest",
                    fontsize=9)
    ax[0].legend(fontsize=8)
    d = [r[1] for r in flow]
    ax[1].fill_between(d, [r[2] for r in flow], [r[3] for r in flow], color="C0", alpha=0.3)
    ax[1].plot(d, [r[2] for r in flow], "o-", color="C0", label="F_L (safe)")
    ax[1].plot(d, [r[3] for r in flow], "s-", color="C3", label="F_U (unsafe)")
    ax[1].set_xlabel("excess head at the base's far corner, Delta h / H")
    ax[1].set_ylabel("factor of safety F")
    ax[1].set_title("submerged slope, steady seepage from below", fontsize=9)
    ax[1].legend(fontsize=8)
    h = np.arange(len(foot_rows))
    ax[2].errorbar(h, [0.5 * (r[2] + r[3]) for r in foot_rows],
                   yerr=[[0.5 * (r[3] - r[2]) for r in foot_rows]] * 2, fmt="o", capsize=4,
                   label="[Nc_L, Nc_U]")
    ax[2].axhline(2 + np.pi, color="k", ls="--", lw=1, label="2 + pi")
    ax[2].set_xticks(h, [r[0] for r in foot_rows])
    ax[2].set_xlabel("water table")
    ax[2].set_ylabel("(F - p(0) B) / (s_u B)")
    ax[2].set_title("undrained Tresca footing (c' = s_u, phi' = 0)", fontsize=9)
    ax[2].legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, figure_dir(args, "effective_bounds") / "brackets.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
