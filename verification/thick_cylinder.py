"""Thick-walled cylinder under internal pressure in axisymmetry (thesis Ch 7 formulation).

A long cylinder a <= r <= b (u_z = 0 on its top and bottom: plane strain along the
axis) is expanded by a prescribed radial displacement of its bore; the internal
pressure is the bore's ring reaction over its area, p = R_r / (2 pi a h). This
exercises the hoop strain u_r / r, the 2 pi r weight and which cone is active:
the stress state is triaxial (s_zz between s_rr and s_tt), so Tresca and
Mohr-Coulomb must be the exact three-cone sets of the axisymmetric criteria.

References (closed forms; e.g. Hill, *The Mathematical Theory of Plasticity*, 1950,
ch. V; research notes ``chapters-6-8.md`` section 4.7):

* elastic (Lame, plane strain): s_rr = A - B/r^2, s_tt = A + B/r^2, s_zz = 2 nu A,
  u_r = (1 + nu)/E [(1 - 2 nu) A r + B / r], A = p a^2/(b^2 - a^2), B = A b^2;
* collapse, Tresca (and the plane-strain Drucker-Prager match (A.17) at phi = 0):
  p = 2 c ln(b/a);
* collapse, the Drucker-Prager cone of (7.10) at phi = 0 (von Mises, k = 2c/sqrt3,
  s_zz the mean of s_rr and s_tt): p = (4/sqrt3) c ln(b/a);
* collapse, Mohr-Coulomb (s_tt major, s_rr minor):
  p = c cot(phi) [(b/a)^(2 sin(phi)/(1 + sin(phi))) - 1];
  the same with zero dilation (the scheme of [80]): the radial problem is
  statically determinate, the flow rule does not enter;
* collapse, the (7.10) cone at phi > 0 with zero dilation: the flow potential
  sqrt(J2) keeps s_zz the mean of s_rr and s_tt, where (7.10) reads
  R + 3 alpha s <= k, Mohr-Coulomb with sin(phi') = 3 alpha, c' = k / cos(phi'):
  the formula above with (c', phi') (phi = 30: phi' = 43.85 deg).

Runs: on each mesh (``--nr`` elements across the wall, one layer of square cells
split in two triangles) the rigid-plastic limit analysis (one SOCP, prescribed
bore velocity); on the finest the elastoplastic pressure-displacement curve (3.45)
to its plateau and the zero-dilation limit analyses (fixed-point passes); on
``--nr-elastic`` the elastic range against Lame.

Usage::

    python verification/thick_cylinder.py --quick --json results/thick_cylinder.json
    python verification/thick_cylinder.py --help
"""
import sys
import time

import numpy as np
from skfem import MeshTri

from pfem_skfem.drivers.incremental import displacement_control
from pfem_skfem.materials import (drucker_prager_match, Elastic, MohrCoulombAxisymmetric,
                                  TrescaAxisymmetric)
from pfem_skfem.discretisation.static import assemble_B, assemble_C, boundary_dofs, discretise
from pfem_skfem.problems.axisymmetric import (static_increment_axisymmetric, with_axis,
                                              zero_dilation)
from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, material_options, nonnegative_float, opt,
                                        positive_angle, positive_float, positive_int)
from pfem_skfem.harness.progress import progress_bar
from pfem_skfem.harness.report import Report, script_main


def collapse_pressures(a, b, c, phi):
    """Closed-form collapse pressures: Tresca, (7.10) at phi = 0, Mohr-Coulomb (phi)."""
    sn = np.sin(np.radians(phi))
    mc = c / np.tan(np.radians(phi)) * ((b / a) ** (2 * sn / (1 + sn)) - 1)
    return {"tresca": 2 * c * np.log(b / a),
            "dp_compression_phi0": 4 / np.sqrt(3) * c * np.log(b / a),
            "dp_plane_strain_phi0": 2 * c * np.log(b / a),
            "mohr_coulomb": mc}


def dp_zero_dilation_pressure(a, b, dp):
    """Collapse pressure of a Drucker-Prager cone with zero dilation (s_zz the mean)."""
    sin_phi = 3 * dp.alpha
    if not 0 < sin_phi < 1:
        raise ValueError(f"3 alpha must lie in (0, 1), got {sin_phi!r}")
    c_eq = dp.k / np.sqrt(1 - sin_phi ** 2)
    return c_eq * np.sqrt(1 - sin_phi ** 2) / sin_phi * (
        (b / a) ** (2 * sin_phi / (1 + sin_phi)) - 1)


def zero_dilation_pressure(model, criterion, c, solver="clarabel"):
    """Limit analysis with zero dilation: fixed-point passes of [80]; (p, passes)."""
    res, changes = zero_dilation(lambda cone: limit_pressure(model, cone, solver)[1], criterion,
                                 floor=1e-3 * c,
                                 measure=lambda r: bore_pressure(model, r.reactions))
    return bore_pressure(model, res.reactions), len(changes)


def lame(r, p, a, b, elastic):
    """Lame's plane-strain solution under internal pressure p: u_r, s_rr, s_tt, s_zz."""
    E, nu = elastic.E, elastic.nu
    A = p * a ** 2 / (b ** 2 - a ** 2)
    Bc = A * b ** 2
    u = (1 + nu) / E * ((1 - 2 * nu) * A * r + Bc / r)
    return u, A - Bc / r ** 2, A + Bc / r ** 2, 2 * nu * A * np.ones_like(r)


def cylinder_model(a, b, nr):
    """One layer of nr square cells across the wall; u_z = 0 top and bottom; bore dofs."""
    if not (0 < a < b):
        raise ValueError(f"need 0 < a < b, got a = {a!r}, b = {b!r}")
    if int(nr) != nr or nr < 1:
        raise ValueError(f"nr must be a positive integer, got {nr!r}")
    h = (b - a) / nr
    mesh = MeshTri.init_tensor(np.linspace(a, b, nr + 1), np.array([0.0, h]))
    disc = discretise(mesh, "axisymmetric")
    eps = 1e-9 * b
    ends = lambda x: (x[1] < eps) | (x[1] > h - eps)        # noqa: E731
    bore = boundary_dofs(disc, lambda x: x[0] < a + eps, 0)
    fixed = with_axis(disc, boundary_dofs(disc, ends, 1))
    return dict(disc=disc, B=assemble_B(disc), fixed=fixed, bore=bore, h=h, a=a, nr=nr)


def bore_pressure(model, reactions):
    """Internal pressure: the bore's radial ring reaction over the bore area 2 pi a h."""
    return np.sum(reactions[..., model["bore"]], axis=-1) / (2 * np.pi * model["a"] * model["h"])


def limit_pressure(model, criterion, solver="clarabel"):
    """Rigid-plastic limit analysis: (3.45) with C = 0 and a unit bore velocity."""
    disc = model["disc"]
    res = static_increment_axisymmetric(
        disc, model["B"], None, np.zeros(disc.n_u), np.zeros((disc.n_points, 4)), criterion,
        fixed=model["fixed"], prescribed=(model["bore"], np.ones(model["bore"].size)),
        solver=solver)
    return bore_pressure(model, res.reactions), res


def pressure_curve(model, elastic, criterion, u_bore, n_increments, solver="clarabel"):
    """Elastoplastic pressure against bore displacement (3.45) under displacement control."""
    C = assemble_C(model["disc"], elastic)
    hist = displacement_control(model["B"], C, criterion, fixed=model["fixed"],
                                prescribed=(model["bore"], u_bore * np.ones(model["bore"].size)),
                                n_increments=n_increments, solver=solver)
    return hist.factors * u_bore, bore_pressure(model, hist.reactions), hist


def elastic_check(model, elastic, criterion, u_bore, solver="clarabel"):
    """One elastic increment (3.45) against Lame: errors of p, u_r (nodes), stresses (points)."""
    disc = model["disc"]
    a, b = model["a"], float(disc.mesh.p[0].max())
    C = assemble_C(disc, elastic)
    res = static_increment_axisymmetric(
        disc, model["B"], C, np.zeros(disc.n_u), np.zeros((disc.n_points, 4)), criterion,
        fixed=model["fixed"], prescribed=(model["bore"], u_bore * np.ones(model["bore"].size)), solver=solver)
    p_ref = u_bore / lame(a, 1.0, a, b, elastic)[0]
    radial = np.concatenate([disc.basis_u.nodal_dofs[0], disc.basis_u.facet_dofs[0]])
    r_dof = disc.basis_u.doflocs[0, radial]
    u_ref = lame(r_dof, p_ref, a, b, elastic)[0]
    r = disc.points[:, 0]
    _, s_rr, s_tt, s_zz = lame(r, p_ref, a, b, elastic)
    ref = np.stack([s_rr, s_zz, s_tt, 0 * r], axis=1)          # stored order (rr, zz, tt, rz)
    return dict(p=bore_pressure(model, res.reactions), p_ref=p_ref,
                u_error=np.abs(res.du[radial] - u_ref).max() / np.abs(u_ref).max(),
                sigma_error=np.abs(res.sigma - ref).max() / np.abs(ref).max(),
                yield_ratio=float(criterion.yield_ratio(res.sigma).max()),
                r=r, sigma=res.sigma, sigma_ref=ref)


def criteria(c, phi):
    """The cones of the run, keyed like :func:`collapse_pressures`."""
    return {"tresca": TrescaAxisymmetric(c),
            "dp_compression_phi0": drucker_prager_match(c, 0.0, "compression-meridian"),
            "dp_plane_strain_phi0": drucker_prager_match(c, 0.0, "plane-strain"),
            "mohr_coulomb": MohrCoulombAxisymmetric(c, phi)}


LABELS = {"tresca": "Tresca (3 cones)", "dp_compression_phi0": "DP (7.10), phi = 0",
          "dp_plane_strain_phi0": "DP plane-strain (A.17), phi = 0",
          "mohr_coulomb": "Mohr-Coulomb (3 cones)"}


# 3 alpha < 1 for the (7.10) compression-meridian cone: sin phi < 3 / (2 sqrt3 + 1)
PHI_MAX_ZERO_DILATION = float(np.degrees(np.arcsin(3 / (2 * np.sqrt(3) + 1))))


def check(args):
    """A usage error for an empty wall (--a not below --b), or None."""
    if not args.a < args.b:
        return f"--a must be smaller than --b, got a = {args.a}, b = {args.b}"
    if not 3 * drucker_prager_match(args.c, args.phi).alpha < 1:
        return (f"--phi {args.phi:g}: the (7.10) cone has 3 alpha >= 1, no zero-dilation "
                f"reference; take --phi below {PHI_MAX_ZERO_DILATION:.1f} degrees")
    return None


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    p.add_argument("--a", type=positive_float, default=1.0, help="inner radius [m]")
    p.add_argument("--b", type=positive_float, default=2.0, help="outer radius [m]")
    material_options(p, c=opt(100.0, "cohesion / Su [kPa]"),
                     phi=opt(30.0, "friction angle of the Mohr-Coulomb run [deg]",
                             type=positive_angle("the Mohr-Coulomb closed form has c cot phi; "
                                                 "phi = 0 is the Tresca case, always run")),
                     E=1.0e5, nu=0.3)
    p.add_argument("--nr", type=positive_int, nargs="+", default=[8, 16, 32],
                   help="elements across the wall of the limit-analysis meshes")
    p.add_argument("--nr-elastic", type=positive_int, default=512,
                   help="elements across the wall of the elastic check")
    p.add_argument("--u-bore", type=positive_float, default=0.03,
                   help="final bore displacement of the elastoplastic curves [m]")
    p.add_argument("--increments", type=positive_int, default=20,
                   help="increments of the elastoplastic curves")
    p.add_argument("--tol", type=nonnegative_float, default=0.01,
                   help="tolerance on the collapse pressures (relative)")
    return p


QUICK = dict(nr=[4, 8, 16], increments=10)


def run(args):
    """Limit analysis on each mesh, plateaus on the finest, the elastic check; a Report."""
    t0 = time.perf_counter()
    elastic = Elastic(args.E, args.nu)
    refs = collapse_pressures(args.a, args.b, args.c, args.phi)
    crits = criteria(args.c, args.phi)
    report = Report("thick_cylinder", args)
    meshes = sorted(args.nr)
    limits = {key: [] for key in crits}
    models = {nr: cylinder_model(args.a, args.b, nr) for nr in meshes}
    bar = progress_bar(total=len(meshes) * len(crits) + len(crits), args=args, unit="solve",
                       desc="thick cylinder")
    for nr in meshes:
        bar.set_description(f"thick cylinder, limit analyses, {nr} across")
        for key, crit in crits.items():
            limits[key].append(limit_pressure(models[nr], crit, args.solver)[0])
            bar.update(1)
        bar.set_postfix_str(", ".join(f"{k} {limits[k][-1] / refs[k] - 1:+.1e}" for k in crits))
    src = {"tresca": "2 c ln(b/a)", "dp_compression_phi0": "(4/sqrt3) c ln(b/a)",
           "dp_plane_strain_phi0": "2 c ln(b/a)",
           "mohr_coulomb": "c cot(phi) [(b/a)^(2 sin(phi)/(1+sin(phi))) - 1]"}
    curves, orders = {}, {}
    finest = models[meshes[-1]]
    for key, crit in crits.items():
        ref = refs[key]
        p_lim = np.array(limits[key])
        report.add(f"p_limit_{key}", p_lim[-1], ref,
                   f"{src[key]} ({LABELS[key]}, limit analysis, nr = {meshes[-1]})", args.tol)
        # converging from above: every mesh above the closed form, the error shrinking
        err = (p_lim - ref) / ref
        report.add_interval(f"p_limit_{key}_min_excess", err.min(), 0.0, args.tol,
                            "limit analysis >= closed form on every mesh", 1e-7)
        if len(meshes) > 1:
            shrink = np.max(err[1:] / err[:-1])
            report.add_interval(f"p_limit_{key}_error_ratio", shrink, 0.0, 0.9,
                                "error of the next finer mesh / error (< 1: converging)")
            orders[key] = float(-np.polyfit(np.log(meshes), np.log(np.abs(err)), 1)[0])
        bar.set_description(f"thick cylinder, {LABELS[key]} curve, {meshes[-1]} across")
        s, p, _ = pressure_curve(finest, elastic, crit, args.u_bore, args.increments,
                                 args.solver)
        curves[key] = (s, p)
        bar.update(1)
        bar.set_postfix_str(f"plateau {p[-1] / ref - 1:+.1e}")
        report.add(f"p_plateau_{key}", p[-1], ref,
                   f"{src[key]} (elastoplastic plateau, nr = {meshes[-1]})", args.tol)

    bar.close()
    # zero dilation (the scheme of [80]) on the finest mesh
    mc, dp = crits["mohr_coulomb"], drucker_prager_match(args.c, args.phi)
    p_mc0, passes_mc = zero_dilation_pressure(finest, mc, args.c, args.solver)
    p_dp0, passes_dp = zero_dilation_pressure(finest, dp, args.c, args.solver)
    report.add("p_limit_mohr_coulomb_psi0", p_mc0, refs["mohr_coulomb"],
               f"{src['mohr_coulomb']} (zero dilation, {passes_mc} passes)", args.tol)
    ref_dp0 = dp_zero_dilation_pressure(args.a, args.b, dp)
    report.add(f"p_limit_dp_7_10_phi{args.phi:g}_psi0", p_dp0, ref_dp0,
               f"(7.10) at phi = {args.phi:g}, zero dilation: Mohr-Coulomb with "
               f"sin(phi') = 3 alpha ({passes_dp} passes)", args.tol)
    p_dp_assoc = limit_pressure(finest, dp, args.solver)[0]

    el = elastic_check(cylinder_model(args.a, args.b, args.nr_elastic), elastic,
                       crits["tresca"], 1e-3 * args.u_bore, args.solver)
    el_coarse = elastic_check(cylinder_model(args.a, args.b, args.nr_elastic // 2), elastic,
                              crits["tresca"], 1e-3 * args.u_bore, args.solver)
    report.add_interval("elastic_yield_ratio", el["yield_ratio"], 0.0, 1.0,
                        "the elastic check stays inside the yield surface")
    report.add("p_elastic", el["p"], el["p_ref"], "Lame (plane strain) for the bore displacement",
               1e-6)
    report.add_interval("u_r_elastic_max_rel_error", el["u_error"], 0.0, 1e-6,
                        f"Lame u_r at every node, nr = {args.nr_elastic}")
    # stresses: a linear field per element against 1/r^2 converges as O(h^2) at the points;
    # the wall is one layer of elements (u_z = 0), so 512 across is a 1,024-triangle strip
    # its bound 1e-6 at the default wall (b - a) / a = 1 and nr = 512 (5.6e-7 measured), scaled
    # as the error, O(((b - a) / (a nr))^2): b = 2.5 measured 1.34e-6, b = 4 5.8e-6 (issue 56)
    sigma_bound = 1e-6 * ((args.b - args.a) / args.a * 512 / args.nr_elastic) ** 2
    report.add_interval("sigma_elastic_max_rel_error", el["sigma_error"], 0.0, sigma_bound,
                        f"Lame stresses at every stress point, nr = {args.nr_elastic}: "
                        f"1e-6 ((b - a) / a x 512 / nr)^2")
    report.add_interval("sigma_elastic_order", np.log2(el_coarse["sigma_error"] / el["sigma_error"]),
                        1.5, 3.0, "observed order of the stress error (nr/2 -> nr)")
    report.extra = {
        "meshes": meshes, "limit_pressure": {k: list(map(float, v)) for k, v in limits.items()},
        "reference": refs, "observed_order": orders,
        "dp_7_10_associated_limit_pressure": float(p_dp_assoc),
        "elastic": {k: float(el[k]) for k in ("p", "p_ref", "u_error", "sigma_error")},
        "wall_time_s": time.perf_counter() - t0}
    report.data = dict(report=report, curves=curves, elastic=el)
    return report


def figures(args, report, curves, elastic):
    """Pressure-displacement curves, convergence of the limit pressures, elastic stresses."""
    plt = pyplot()
    out = figure_dir(args, "thick_cylinder")
    refs = report.extra["reference"]
    fig, ax = plt.subplots(1, 3, figsize=(14, 4))
    for i, (key, (s, p)) in enumerate(curves.items()):
        ax[0].plot(s / args.a, p / args.c, f"C{i}-", label=LABELS[key])
        ax[0].axhline(refs[key] / args.c, color=f"C{i}", ls="--", lw=0.8)
    ax[0].set_xlabel("bore displacement / a")
    ax[0].set_ylabel("p / c")
    ax[0].set_title("pressure-expansion curves (dashed: closed forms)")
    ax[0].legend(fontsize=7)
    meshes = report.extra["meshes"]
    for i, (key, p) in enumerate(report.extra["limit_pressure"].items()):
        ax[1].loglog(meshes, np.array(p) / refs[key] - 1, f"C{i}o-", label=LABELS[key])
    ax[1].set_xlabel("elements across the wall")
    ax[1].set_ylabel("limit pressure / closed form - 1")
    ax[1].set_title("limit analysis converging from above")
    ax[1].legend(fontsize=7)
    el = elastic
    order = np.argsort(el["r"])
    for k, name in ((0, "s_rr"), (2, "s_tt"), (1, "s_zz")):
        ax[2].plot(el["r"][order], el["sigma_ref"][order, k], "k-", lw=0.8)
        ax[2].plot(el["r"][order], el["sigma"][order, k], ".", ms=3, label=name)
    ax[2].set_xlabel("r [m]")
    ax[2].set_ylabel("stress [kPa]")
    ax[2].set_title("elastic stresses (lines: Lame)")
    ax[2].legend(fontsize=7)
    save_figure(fig, out / "thick_cylinder.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
