"""A softening layer in simple shear: the exact post-peak curve, with and without regularisation.

Beyond the thesis (issue 55; the closed form of ``shared/research/saturated-softening-3d.md``
3.4, W1). A layer of height L (shear modulus G) rests on a fixed base and is sheared by its
top (displacement delta, no vertical motion: u_y = 0 everywhere). Its Tresca strength softens
with the plastic shear strain gamma^p by the linear law c = max(c_r, c_p + H gamma^p),
H = -(c_p - c_r) / gamma_r < 0 (:mod:`pfem_skfem.materials.softening`). One row of height h
(mid-height) starts a fraction epsilon of the way down the law (gamma^p_0 = epsilon gamma_r):
its peak is c_w = c_p - epsilon (c_p - c_r), and only it yields. The shear stress tau is the
same at every height, so the elastic rows carry tau L / G of the top's displacement and the
band its plastic slip h (gamma^p - gamma^p_0), tau = c(gamma^p):

    delta(tau) = tau L / G + h (c_w - tau) / abs(H)                 (post-peak, exact)
    delta_r = c_r L / G + h (c_w - c_r) / abs(H)                     (full softening)
    D = h (c_w^2 - c_r^2) / (2 abs(H))                               (dissipated, per unit width)

with no snap-back while h / abs(H) > L / G. The band is one row: without regularisation its
slip, delta_r - c_r L / G, halves when h halves. With the fracture-energy regularisation of
length ell (gamma_r scaled by ell / h: H(h) = H h / ell) h / abs(H(h)) = ell / abs(H), and delta_r
and D do not depend on h. The exponential law c = c_r + (c_p - c_r) exp(-3 gamma^p /
gamma_95) has the same form, h (gamma^p(tau) - gamma^p_0) with gamma^p(tau) its inverse.
The nonlocal average of gamma^p over a length (--ell-nonlocal) has no closed form here: its
band is as wide as the average, and delta_r must converge as h shrinks.

The mesh: one column of P2 triangles (width h, rows of height h: element size sqrt(2 A) = h),
every x-dof of a height tied to one (u = u(y)) and each mid-row dof the mean of its row's ends
(u linear in each row: the uniform band of the closed form; P2 alone lets the plastic strain
gather to one side of the row, a band thinner than h). Static increments of (3.45) with the
strength of the start of each increment, updated after it
(:func:`pfem_skfem.drivers.softening.softening_control`), an increment re-solved at half its
size while it drops a strength by more than --max-drop (c_p - c_r).

Checks: the elastic slope G / L and the peak c_w (to 1e-6); at the finest cap the computed
points (delta, tau) from the exact curve, within 2 % of delta_r, on every mesh, regularised
or not, and for the exponential law (within 2 % of the displacement at 95 % softening);
delta_r and D within 2 %; the local slip ratio h_min / h_max (2 %); the regularised delta_r
independent of h within 5 %; the nonlocal delta_r within 5 % on the two finest meshes; the
error shrinking with the cap; with fixed-point passes (each increment solved again with the
strength at its trial end until gamma^p stops changing) every point on the exact curve to
1e-5 of delta_r at the coarsest cap.

Usage::

    python verification/softening_layer.py --quick --json results/softening_layer.json
"""
import sys

import numpy as np
import scipy.sparse as sp
from skfem import MeshTri

from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, in_range, material_options, opt,
                                        pfem_options, positive_float, softening_options)
from pfem_skfem.harness.report import Report, script_main

QUICK = dict(rows=[10, 20, 40], max_drop=[0.04, 0.01])

#: tau within this fraction of c_r: the band has reached the residual strength
AT_RESIDUAL = 1e-6


def layer_model(rows, L, G, nu, kinematics="linear"):
    """The layer's operators: B T, C of one column of ``rows`` rows of P2 triangles, T tying
    the x-dofs of each height into one (u = u(y); the y-dofs have no column: u_y = 0), each
    mid-row dof the mean of its row's ends where ``kinematics`` is 'linear' (u linear in each
    row), free where it is 'p2'; and the stress points' heights, weights and element sizes.
    Column 0 is the base, the last column the top."""
    from pfem_skfem.discretisation.static import assemble_B, assemble_C, discretise
    from pfem_skfem.drivers.softening import point_sizes
    from pfem_skfem.materials import Elastic

    h = L / rows
    disc = discretise(MeshTri.init_tensor(np.array([0.0, h]), np.linspace(0.0, L, rows + 1)))
    elastic = Elastic(2 * G * (1 + nu), nu)
    x_dofs = np.concatenate([disc.basis_u.nodal_dofs[0], disc.basis_u.facet_dofs[0]])
    level = disc.basis_u.doflocs[1, x_dofs] / h         # k at row ends, k + 1/2 mid-row
    if kinematics == "p2":
        half = np.rint(2 * level).astype(int)           # one column per height
        T = sp.csr_matrix((np.ones(len(x_dofs)), (x_dofs, half)), shape=(disc.n_u, 2 * rows + 1))
    else:
        lower = np.minimum(np.floor(level + 1e-9).astype(int), rows - 1)
        upper_share = level - lower                     # 0 or 1 at an end, 1/2 mid-row
        T = sp.csr_matrix((np.concatenate([1 - upper_share, upper_share]),
                           (np.concatenate([x_dofs, x_dofs]), np.concatenate([lower, lower + 1]))),
                          shape=(disc.n_u, rows + 1))
    weights = disc.weights
    return dict(B=(assemble_B(disc) @ T).tocsr(), C=assemble_C(disc, elastic), h=h,
                elastic=elastic, points=disc.points, y=disc.points[:, 1], weights=weights,
                size=point_sizes(weights), top=T.shape[1] - 1)


def exact_delta(tau, law, scale, *, L, G, h, c_w):
    """delta(tau) = tau L / G + h (gamma^p(tau) - gamma^p(c_w)) on the post-peak branch."""
    return tau * L / G + h * (law.strain_at(tau, scale) - law.strain_at(c_w, scale))


def end_strength(law):
    """Full softening: c_r for the linear law, 95 % of c_p - c_r spent for the exponential."""
    from pfem_skfem.materials.softening import ExponentialSoftening
    spent = 0.95 if isinstance(law, ExponentialSoftening) else 1.0
    return law.c_p - spent * (law.c_p - law.c_r)


def exact_dissipation(law, scale, h, c_w, c_end):
    """h int c dgamma^p as c falls from c_w to c_end: h (c_w^2 - c_end^2) / (2 abs(H)) (linear);
    h [c_r dgamma + (c_w - c_end) gamma_95 / 3] (exponential: dc = -3 (c - c_r) dgamma /
    gamma_95)."""
    from pfem_skfem.materials.softening import LinearSoftening
    if isinstance(law, LinearSoftening):
        H = (law.c_p - law.c_r) / (law.gamma_r * scale)
        return h * (c_w ** 2 - c_end ** 2) / (2 * H)
    slip = law.strain_at(c_end, scale) - law.strain_at(c_w, scale)
    return h * (law.c_r * slip + (c_w - c_end) * law.gamma_95 * scale / 3)


def shear(rows, law, ell, max_drop, args, average_length=0.0, passes=1):
    """The layer of ``rows`` rows sheared to --delta-end times its delta_r: (delta, tau) after
    each accepted increment, the dissipation, and the closed form's delta_r, D and c_w.
    ``average_length`` > 0: gamma^p averaged over that length (no closed form: the band's width is
    the average's; the run goes to --delta-end times the delta_r of a band 1.5 x as wide);
    ``passes`` > 1: each increment's fixed point (:class:`StepControl`)."""
    from pfem_skfem.drivers.softening import StepControl, softening_control
    from pfem_skfem.materials.softening import (FractureEnergy, SofteningTresca,
                                                nonlocal_average)

    m = layer_model(rows, args.L, args.G, args.nu, args.row_kinematics)
    material = SofteningTresca(law, m["elastic"], ell and FractureEnergy(ell))
    h, scale = m["h"], float(material.scale(m["h"]))
    c_w = law.c_p - args.epsilon * (law.c_p - law.c_r)
    weak = (m["y"] > (rows // 2) * h) & (m["y"] < (rows // 2 + 1) * h)
    gamma0 = np.where(weak, law.strain_at(c_w, scale), 0.0)
    c_end = end_strength(law)
    closed = dict(L=args.L, G=args.G, h=h, c_w=c_w)
    delta_r = exact_delta(c_end, law, scale, **closed)
    dissipated = exact_dissipation(law, scale, h, c_w, c_end)
    average, end = None, args.delta_end * delta_r
    if average_length:
        average = nonlocal_average(m["points"], m["weights"], average_length)
        wider = dict(closed, h=1.5 * average_length)
        end = args.delta_end * exact_delta(c_end, law, scale, **wider)
        delta_r = dissipated = np.nan
    run = softening_control(m["B"], m["C"], material, fixed=[0], prescribed=([m["top"]],
                            [end]), n_increments=args.increments, size=m["size"],
                            weights=m["weights"], gamma0=gamma0,
                            control=StepControl(max_drop, passes, average), solver=args.solver)
    delta = run.factors * end
    tau = run.reactions[:, m["top"]] / h                       # per unit width of the column
    post = np.arange(len(tau)) >= np.argmax(tau)
    softening = post & (tau > c_end * (1 + AT_RESIDUAL))
    error = np.abs(delta[softening] - exact_delta(tau[softening], law, scale, **closed)).max() \
        / delta_r
    at_r = np.flatnonzero(post & (tau <= c_end * (1 + AT_RESIDUAL)))
    i_r = at_r[0] if at_r.size else len(tau) - 1
    band = m["y"][run.gamma_p >= 0.5 * run.gamma_p.max()]
    width = band.max() - band.min()
    return dict(rows=rows, h=h, ell=ell, max_drop=max_drop, delta=delta, tau=tau, c_w=c_w,
                error=error, delta_r=delta[i_r], delta_r_exact=delta_r,
                dissipation=run.dissipation[i_r] / h, dissipation_exact=dissipated,
                reached=bool(at_r.size), width=width,
                slope=tau[1] / delta[1], solves=run.solves, uncapped=run.uncapped,
                scale=scale, law=law)


def laws(args):
    """The linear law of --H and the exponential law of --gamma-95."""
    from pfem_skfem.materials.softening import ExponentialSoftening, LinearSoftening
    return (LinearSoftening(args.c_p, args.c_r, (args.c_p - args.c_r) / -args.H),
            ExponentialSoftening(args.c_p, args.c_r, args.gamma_95))


def check(args):
    """Snap-back (h / abs(H) <= L / G on the finest mesh, or ell / abs(H) <= L / G) has no
    displacement-controlled answer: refused."""
    if args.c_r >= args.c_p:
        return f"--c-r {args.c_r:g} must be below --c-p {args.c_p:g}"
    h_min = args.L / max(args.rows)
    if h_min / -args.H <= args.L / args.G:
        return (f"--rows {max(args.rows)}: h / abs(H) = {h_min / -args.H:g} <= L / G = "
                f"{args.L / args.G:g}, the layer snaps back; fewer rows or a smaller --H")
    if args.ell / -args.H <= args.L / args.G:
        return f"--ell {args.ell:g}: ell / abs(H) <= L / G, the regularised layer snaps back"
    h_max = args.L / min(args.rows)
    if h_max * args.gamma_95 / (3 * (args.c_p - args.c_r)) <= args.L / args.G:
        return f"--gamma-95 {args.gamma_95:g}: the exponential layer snaps back"
    if len(args.rows) < 2 or len(set(args.rows)) < len(args.rows):
        return "--rows: two different meshes at least (the h-dependence)"
    return None


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    p.add_argument("--L", type=positive_float, default=1.0, help="layer height L [m]")
    material_options(p, G=2000.0, nu=0.3)
    softening_options(p, c_p=20.0, c_r=5.0,
                      H=opt(-20.0, "softening modulus H = dc/dgamma^p of the linear law [kPa]"),
                      gamma_95=opt(2.0, "gamma_95 of the exponential law (run on the coarsest "
                                        "mesh)"),
                      ell=opt(0.2, "regularisation length ell [m]: gamma_r holds for a band ell "
                                   "thick", type=positive_float),
                      ell_nonlocal=0.2,
                      epsilon=opt(0.01, "the weak row starts this fraction down the law"),
                      max_drop=opt([0.04, 0.02, 0.01, 0.005], nargs="+",
                                   help="caps on the strength drop of an increment, "
                                        "/ (c_p - c_r); the finest serves every mesh"),
                      increments=10)
    p.add_argument("--rows", type=in_range(2, integer=True), nargs="+", default=[10, 20, 40],
                   help="rows of the meshes (h = L / rows)")
    pfem_options(p, passes=opt(20, "most fixed-point passes of an increment in the "
                                   "fixed-point run (strength at the trial end)"))
    p.add_argument("--delta-end", type=in_range(1, low_open=True), default=1.2,
                   help="the run's end, a multiple of its delta_r")
    p.add_argument("--row-kinematics", choices=("linear", "p2"), default="linear",
                   help="u linear in each row (the closed form's uniform band), or the P2 "
                        "field (the band may narrow inside the row: the checks then fail)")
    return p


def run(args):
    linear, exponential = laws(args)
    finest, caps = min(args.max_drop), sorted(set(args.max_drop), reverse=True)
    rows = sorted(args.rows)
    report = Report("softening_layer", args)
    local = [shear(n, linear, None, finest, args) for n in rows]
    regular = [shear(n, linear, args.ell, finest, args) for n in rows]
    expo = shear(rows[0], exponential, None, finest, args)
    spread = [shear(n, linear, None, finest, args, average_length=args.ell_nonlocal)
              for n in rows]
    study = [next((r for r in local if r["rows"] == rows[0]), None) if c == finest
             else shear(rows[0], linear, None, c, args) for c in caps]
    fixed_point = shear(rows[0], linear, None, caps[0], args, passes=args.passes)
    first = local[0]
    report.add("elastic_slope", first["slope"], args.G / args.L, "tau / delta = G / L", 1e-6)
    report.add("peak_tau", first["tau"].max(), first["c_w"],
               "the weak row's strength c_w = c_p - epsilon (c_p - c_r)", 1e-6)
    for name, runs, band in (("local", local, "h"), ("regularised", regular, "ell")):
        for r in runs:
            key = f"{name}_rows{r['rows']}"
            report.add_interval(f"{key}_curve_error", r["error"], 0.0, 0.02,
                                f"max |delta - delta(tau)| / delta_r, delta(tau) = tau L / G + "
                                f"{band} (c_w - tau) / abs(H)")
            report.add(f"{key}_delta_r", r["delta_r"], r["delta_r_exact"],
                       f"c_r L / G + {band} (c_w - c_r) / abs(H)", 0.02)
            report.add(f"{key}_dissipation", r["dissipation"], r["dissipation_exact"],
                       f"{band} (c_w^2 - c_r^2) / (2 abs(H))", 0.02)
    report.add_interval("exponential_curve_error", expo["error"], 0.0, 0.02,
                        "max |delta - delta(tau)| / delta_95, delta(tau) = tau L / G + "
                        "h (gamma^p(tau) - gamma^p(c_w))")
    elastic_part = args.c_r * args.L / args.G
    slip = [r["delta_r"] - elastic_part for r in (local[0], local[-1])]
    report.add("local_slip_ratio", slip[1] / slip[0], rows[0] / rows[-1],
               "the band is one row: its slip scales with h", 0.02)
    report.add_interval("regularised_delta_r_ratio", regular[-1]["delta_r"] /
                        regular[0]["delta_r"], 0.95, 1.05,
                        "fracture energy: delta_r independent of h (exactly 1)")
    change = [r["delta_r"] if r["reached"] else np.nan for r in spread[-2:]]
    report.add_interval("nonlocal_delta_r_change", abs(change[1] / change[0] - 1), 0.0, 0.05,
                        "nonlocal average: delta_r converges with h (its two finest meshes)")
    errors = [r["error"] for r in study]
    order = (np.polyfit(np.log(caps), np.log(errors), 1)[0] if len(caps) > 1 else np.nan)
    report.add_interval("cap_order", order, 0.5, np.inf,
                        "the explicit update's lag: the error falls with the cap")
    report.add_interval("fixed_point_curve_error", fixed_point["error"], 0.0, 1e-5,
                        f"fixed-point passes at the cap {caps[0]:g}: every point on "
                        f"delta(tau) (the linear law's branch is straight)")
    report.add_table("meshes", ["law", "rows", "h", "delta_r", "exact", "curve error / delta_r",
                                "D", "D exact", "solves"],
                     [[name, r["rows"], r["h"], r["delta_r"], r["delta_r_exact"], r["error"],
                       r["dissipation"], r["dissipation_exact"], r["solves"]]
                      for name, runs in (("local", local), ("ell", regular),
                                         ("exponential", [expo])) for r in runs],
                     formats={"curve error / delta_r": ".2e"})
    report.add_table("nonlocal", ["rows", "h", "delta_r", "band width (gamma^p > max / 2)",
                                  "solves"],
                     [[r["rows"], r["h"], r["delta_r"], r["width"], r["solves"]] for r in spread])
    report.add_table("caps", ["max drop", "passes", "curve error / delta_r", "solves"],
                     [[r["max_drop"], 1, r["error"], r["solves"]] for r in study]
                     + [[caps[0], args.passes, fixed_point["error"], fixed_point["solves"]]],
                     formats={"curve error / delta_r": ".2e"})
    report.extra = {"cap_errors": errors, "caps": caps,
                    "curves": {f"{k}_rows{r['rows']}": {"delta": r["delta"], "tau": r["tau"]}
                               for k, runs in (("local", local), ("regularised", regular),
                                               ("nonlocal", spread))
                               for r in runs}}
    report.data = dict(local=local, regular=regular, expo=expo, study=study, spread=spread)
    return report


def figures(args, local, regular, expo, study, spread):
    """tau - delta against the closed form, local and regularised (the nonlocal runs beside);
    the error against the cap."""
    fig, ax = pyplot().subplots(1, 3, figsize=(15, 4))
    for a, runs, title in ((ax[0], local + [expo], "local softening"),
                           (ax[1], regular, f"regularised: fracture energy, ell = {args.ell:g} m")):
        for k, r in enumerate(runs):
            tau = np.linspace(r["tau"][r["tau"] > 0].min(), r["c_w"], 200)
            peak = r["c_w"] * args.L / args.G
            exact = exact_delta(tau, r["law"], r["scale"], L=args.L, G=args.G, h=r["h"],
                                c_w=r["c_w"])
            label = f"h = {r['h']:g}" + (" (exponential)" if r is expo else "")
            a.plot(np.r_[0, peak, exact[::-1]], np.r_[0, r["c_w"], tau[::-1]], "-",
                   color=f"C{k}", lw=3, alpha=0.4)
            a.plot(r["delta"], r["tau"], ".", color=f"C{k}", ms=3, label=label)
        if a is ax[1]:
            for k, r in enumerate(spread):
                a.plot(r["delta"], r["tau"], "x", color=f"C{k}", ms=3,
                       label=f"nonlocal, ell = {args.ell_nonlocal:g} m, h = {r['h']:g}")
        a.set(xlabel="top displacement delta [m]", ylabel="shear stress tau [kPa]", title=title)
        a.legend(fontsize=8)
    ax[2].loglog([r["max_drop"] for r in study], [r["error"] for r in study], "o-")
    ax[2].set(xlabel="cap on the strength drop / (c_p - c_r)",
              ylabel="max |delta - exact| / delta_r",
              title=f"increment study, h = {study[0]['h']:g}")
    save_figure(fig, figure_dir(args, "softening_layer") / "softening_layer.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
