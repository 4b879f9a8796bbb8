"""Rigid circular footing on a weightless Tresca soil in axisymmetry (thesis Ch 7 formulation).

A footing of radius R is pushed into the soil by a prescribed vertical
displacement of the surface under it: smooth by default (radial motion free),
rough with ``--rough`` (the soil under the footing moves with it: u_r = 0 there).
The domain r <= W, -D <= z <= 0 is a graded Triangle mesh refined at the footing
edge; u_r = 0 on the axis and on r = W, the base is fixed. The mobilised bearing
capacity is Nc = F / (pi R^2 c), F the footing's ring reaction (the force on the
whole footing). Runs: the rigid-plastic limit analysis on each mesh (smooth and
rough, exact three-cone Tresca and the (7.10) Drucker-Prager cone at phi = 0),
elastoplastic Nc-settlement curves like Fig 3.4 on each mesh, the plastic zone at
collapse, and Mohr-Coulomb footings for a few phi (reported, not gated).

References
----------
* Smooth footing, Tresca: Nc = 5.69 (Shield 1955; Cox, Eason & Hopkins 1961),
  checked on the finest mesh within 2 %, the three meshes converging from above.
* Rough footing, Tresca: a rough footing restrains the soil, so on the same mesh
  Nc_rough >= Nc_smooth (a smaller set of mechanisms). The value 6.05 usually
  quoted (Eason & Shield 1960) is reported beside ours, not gated: it was not
  verified for this project.
* The (7.10) cone at phi = 0 is von Mises with k = 2c/sqrt3, which contains the
  Tresca hexagon of c and lies inside the Tresca hexagon of 2c/sqrt3, so on every
  mesh Nc_T <= Nc_DP <= (2/sqrt3) Nc_T, and for the exact solution
  5.69 <= Nc_DP <= 6.57 (research notes, chapters-6-8.md section 4.7): only a bound.
* Mohr-Coulomb, phi > 0: no table of circular-footing factors was verified for
  this project; the values are reported (JSON ``extra``) with the strip-footing
  factor (3.49) for scale.

Usage::

    python verification/circular_footing.py --quick --json results/circular_footing.json
    python verification/circular_footing.py --rough
    python verification/circular_footing.py --help
"""
import sys
import time

import numpy as np
from skfem import MeshTri

from pfem_skfem.drivers.incremental import displacement_control
from pfem_skfem.materials import (drucker_prager_match, Elastic, MohrCoulombAxisymmetric,
                                  TrescaAxisymmetric)
from pfem_skfem.discretisation.meshes import graded_rectangle_with_elements
from pfem_skfem.discretisation.static import assemble_B, assemble_C, boundary_dofs, discretise
from pfem_skfem.problems.axisymmetric import static_increment_axisymmetric, with_axis
from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, element_count, material_options,
                                        nonnegative_float, opt, positive_angle, positive_float,
                                        positive_int)
from pfem_skfem.harness.progress import progress_bar
from pfem_skfem.harness.report import Report, script_main

NC_SMOOTH = 5.69       # Shield 1955; Cox, Eason & Hopkins 1961
NC_ROUGH = 6.05        # Eason & Shield 1960 (quoted, not verified here)


def strip_nc(phi):
    """Prandtl-Reissner strip-footing factor (3.49), for scale only."""
    ph = np.radians(phi)
    if ph == 0:
        return 2 + np.pi
    return (np.tan(np.pi / 4 + ph / 2) ** 2 * np.exp(np.pi * np.tan(ph)) - 1) / np.tan(ph)


def domain_size(R, phi):
    """Radius and depth of the domain: 5 R, grown with phi like Prandtl's mechanism."""
    ph = np.radians(phi)
    r0 = R / np.cos(np.pi / 4 + ph / 2)
    r1 = r0 * np.exp(0.5 * np.pi * np.tan(ph))
    extent = R + 2 * r1 * np.cos(np.pi / 4 - ph / 2)
    return max(5.0 * R, 1.6 * extent), max(5.0 * R, 1.2 * r1)


def footing_model(n_elements, *, R=0.5, phi=0.0, rough=False, ratio=40.0, growth=0.3):
    """Graded mesh of r <= W, -D <= z <= 0, refined at the footing edge; supports; footing dofs.

    Returns a dict with the discretisation, B, fixed dofs (axis u_r included), the
    prescribed dofs and their unit motion (u_z = -1 under the footing; u_r = 0 there
    too if ``rough``), and the footing's vertical dofs.
    """
    # the mesh is made for R = 1 and scaled by R: Triangle's meshes are not scale-invariant
    # in floating point (another R gave another mesh, whose Nc differs by the mesh-to-mesh
    # scatter, 0.3 % at 400 elements), so Nc is the same at every R, as it must be
    unit = graded_rectangle_with_elements(*domain_size(1.0, phi), (1.0, 0.0), n_elements,
                                          ratio=ratio, growth=growth)
    mesh = MeshTri(unit.p * R, unit.t)
    width, depth = (R * v for v in domain_size(1.0, phi))
    disc = discretise(mesh, "axisymmetric")
    eps = 1e-9 * width
    under = lambda x: (np.abs(x[1]) < eps) & (x[0] < R + eps)   # noqa: E731
    side = lambda x: x[0] > width - eps                          # noqa: E731
    base = lambda x: x[1] < -depth + eps                         # noqa: E731
    footing = boundary_dofs(disc, under, 1)
    prescribed, motion = footing, -np.ones(footing.size)
    if rough:
        radial = boundary_dofs(disc, under, 0)
        prescribed = np.concatenate([footing, radial])
        motion = np.concatenate([motion, np.zeros(radial.size)])
    fixed = np.unique(np.concatenate([boundary_dofs(disc, side, 0), boundary_dofs(disc, base, 0),
                                      boundary_dofs(disc, base, 1)]))
    fixed = with_axis(disc, np.setdiff1d(fixed, prescribed), prescribed)
    return dict(disc=disc, B=assemble_B(disc), fixed=fixed, prescribed=prescribed,
                motion=motion, footing=footing, R=R, n_elements=mesh.nelements,
                width=width, depth=depth)


def bearing_factor(model, reactions, c):
    """Nc = F / (pi R^2 c), F the footing's ring reaction (compression positive)."""
    return -np.sum(reactions[..., model["footing"]], axis=-1) / (np.pi * model["R"] ** 2 * c)


def nc_limit(model, criterion, c, solver="clarabel"):
    """Limit-analysis Nc: rigid-plastic (3.45) with a unit footing velocity."""
    disc = model["disc"]
    res = static_increment_axisymmetric(
        disc, model["B"], None, np.zeros(disc.n_u), np.zeros((disc.n_points, 4)), criterion,
        fixed=model["fixed"], prescribed=(model["prescribed"], model["motion"]),
        solver=solver)
    return bearing_factor(model, res.reactions, c), res


def nc_curve(model, elastic, criterion, settlement, n_increments, c, solver="clarabel"):
    """Elastoplastic Nc-settlement curve (3.45) under displacement control."""
    C = assemble_C(model["disc"], elastic)
    hist = displacement_control(model["B"], C, criterion, fixed=model["fixed"],
                                prescribed=(model["prescribed"], settlement * model["motion"]),
                                n_increments=n_increments, solver=solver)
    return hist.factors * settlement, bearing_factor(model, hist.reactions, c), hist


def check(args):
    """Options that cannot go together (a usage error), or None."""
    if len(set(args.elements)) < 2:
        return ("--elements needs at least two distinct counts: the refinement checks "
                "compare the meshes")
    return None


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    p.add_argument("--R", type=positive_float, default=0.5, help="footing radius [m]")
    material_options(p, c=opt(100.0, "cohesion / Su [kPa]"), E=1.0e5, nu=0.49,
                     phi=opt([10, 20, 30], nargs="*",
                             help="friction angles of the Mohr-Coulomb footings [deg] (none "
                                  "to skip)",
                             type=positive_angle("the Mohr-Coulomb reference has cot phi; "
                                                 "phi = 0 is the Tresca case, always run")))
    p.add_argument("--rough", action="store_true",
                   help="rough footing: the soil under it moves with it (u_r = 0)")
    p.add_argument("--elements", type=element_count, nargs="+", default=[300, 1000, 3000],
                   help="approximate element counts of the three graded meshes")
    p.add_argument("--settlement", type=positive_float, default=0.03,
                   help="final footing displacement of the Nc-settlement curves [m]")
    p.add_argument("--increments", type=positive_int, default=20,
                   help="increments of each Nc-settlement curve")
    p.add_argument("--mc-elements", type=element_count, default=1000,
                   help="elements of the Mohr-Coulomb meshes")
    p.add_argument("--tol", type=nonnegative_float, default=None,
                   help="tolerance on the smooth Nc (default 2%%, 3%% with --quick)")
    return p


QUICK = dict(elements=[200, 400, 800], increments=8, phi=[20], mc_elements=400)


def run(args):
    """Limit analysis on every mesh, the curves, the Mohr-Coulomb footings; a Report."""
    t0 = time.perf_counter()
    c, elastic = args.c, Elastic(args.E, args.nu)
    tresca, dp = TrescaAxisymmetric(c), drucker_prager_match(c, 0.0, "compression-meridian")
    report = Report("circular_footing", args)
    meshes = sorted(args.elements)
    lim = {key: [] for key in ("smooth", "rough", "dp_smooth")}
    models, curves = {}, {}
    bar = progress_bar(total=len(meshes) + len(args.phi or []), args=args, unit="mesh",
                       desc="circular footing")
    for n in meshes:
        bar.set_description(f"circular footing, {n} elements: limit analyses and the curve")
        smooth = footing_model(n, R=args.R)
        rough = footing_model(n, R=args.R, rough=True)
        models[n] = rough if args.rough else smooth
        lim["smooth"].append(nc_limit(smooth, tresca, c, args.solver)[0])
        lim["rough"].append(nc_limit(rough, tresca, c, args.solver)[0])
        lim["dp_smooth"].append(nc_limit(smooth, dp, c, args.solver)[0])
        s, nc, hist = nc_curve(models[n], elastic, tresca, args.settlement, args.increments, c,
                               args.solver)
        curves[n] = (s, nc, hist)
        bar.update(1)
        bar.set_postfix_str(f"Nc smooth {lim['smooth'][-1]:.4f}, rough {lim['rough'][-1]:.4f}, "
                            f"(7.10) {lim['dp_smooth'][-1]:.4f}; curve end {nc[-1]:.4f}")
    n_el = [models[n]["n_elements"] for n in meshes]
    tol = args.tol if args.tol is not None else (0.03 if args.quick else 0.02)
    smooth_nc, rough_nc = np.array(lim["smooth"]), np.array(lim["rough"])
    src = "Shield 1955; Cox, Eason & Hopkins 1961: smooth Nc = 5.69"
    report.add("Nc_smooth_limit", smooth_nc[-1], NC_SMOOTH, f"{src} ({n_el[-1]} elements)", tol)
    report.add_interval("Nc_smooth_limit_min_excess", (smooth_nc / NC_SMOOTH - 1).min(), 0.0,
                        0.10, "limit analysis above 5.69 on every mesh", 1e-9)
    report.add_interval("Nc_smooth_limit_refinement_ratio",
                        np.max(smooth_nc[1:] / smooth_nc[:-1]), 0.0, 1.0,
                        "Nc(finer) / Nc(coarser) < 1: decreasing with every refinement")
    main = rough_nc if args.rough else smooth_nc
    plateau = curves[meshes[-1]][1][-1]
    if args.rough:
        report.add_interval("Nc_rough_plateau", plateau, main[-1] * (1 - tol), main[-1],
                            "elastoplastic plateau below the limit analysis of its mesh, "
                            f"within {tol:.0%}")
    else:
        report.add("Nc_smooth_plateau", plateau, NC_SMOOTH, f"{src} (elastoplastic, "
                   f"{n_el[-1]} elements, {args.increments} increments)", tol)
    report.add_interval("Nc_rough_over_smooth", np.min(rough_nc / smooth_nc), 1.0, 2.0,
                        "rough >= smooth on the same mesh (fewer mechanisms)")
    dp_nc = np.array(lim["dp_smooth"])
    report.add_interval("Nc_dp_7_10_over_tresca", np.max(dp_nc / smooth_nc), 1.0, 2 / np.sqrt(3),
                        "Tresca(c) in von Mises(2c/sqrt3) in Tresca(2c/sqrt3), same mesh")
    report.add_interval("Nc_dp_7_10", dp_nc[-1], NC_SMOOTH, 2 / np.sqrt(3) * NC_SMOOTH,
                        "bound 5.69 <= Nc <= 6.57 for the (7.10) cone at phi = 0", tol)

    mc = {}
    for phi in args.phi or []:
        bar.set_description(f"circular footing, Mohr-Coulomb phi = {phi:g}")
        model = footing_model(args.mc_elements, R=args.R, phi=phi, rough=args.rough)
        value = nc_limit(model, MohrCoulombAxisymmetric(c, phi), c, args.solver)[0]
        mc[f"{phi:g}"] = dict(Nc=float(value), strip_3_49=float(strip_nc(phi)),
                              elements=model["n_elements"])
        bar.update(1)
        bar.set_postfix_str(f"Nc = {value:.3f} (strip (3.49): {strip_nc(phi):.3f})")
    bar.close()
    report.extra = {
        "elements": n_el, "Nc_limit_smooth": smooth_nc.tolist(),
        "Nc_limit_rough": rough_nc.tolist(), "Nc_limit_dp_7_10": dp_nc.tolist(),
        "Nc_rough_literature_unverified": NC_ROUGH,
        "curves": {f"{models[n]['n_elements']}el": {"settlement": curves[n][0].tolist(),
                                                    "Nc": curves[n][1].tolist()}
                   for n in meshes},
        "mohr_coulomb_limit": mc, "wall_time_s": time.perf_counter() - t0}
    report.data = dict(models=models, curves=curves)
    return report


def figures(args, models, curves):
    """Nc-settlement curves (like Fig 3.4), the meshes' detail, the plastic zone at collapse."""
    plt = pyplot()
    out = figure_dir(args, "circular_footing")
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for n, (s, nc, _) in curves.items():
        ax.plot(s, nc, "o-", ms=3, label=f"{models[n]['n_elements']} elements")
    ref = NC_ROUGH if args.rough else NC_SMOOTH
    ax.axhline(ref, color="k", ls="--", lw=1,
               label="6.05 (Eason & Shield, rough)" if args.rough else "5.69 (Shield, smooth)")
    ax.set_xlabel("footing settlement [m]")
    ax.set_ylabel("Nc = F / (pi R^2 c)")
    ax.set_ylim(0, 1.25 * ref)
    ax.set_title(f"{'rough' if args.rough else 'smooth'} circular footing, Tresca")
    ax.legend(fontsize=8)
    save_figure(fig, out / "nc_settlement.png")

    n = max(models)
    model, hist = models[n], curves[n][2]
    disc = model["disc"]
    ratio = TrescaAxisymmetric(args.c).yield_ratio(hist.sigma)
    per_element = np.zeros(disc.mesh.nelements)
    np.maximum.at(per_element, disc.point_element, ratio)
    from pfem_skfem import io, viz
    points, cells = io.mesh_arrays(disc.mesh)
    vtu = out / "plastic_zone.vtu"
    io.write_vtu(vtu, points, cells, cell_data={"yield_ratio": np.minimum(per_element, 1.0)})
    fig, a = plt.subplots(figsize=(6, 4.5))
    viz.plot_field(a, points, cells, np.minimum(per_element, 1.0), label="yield ratio")
    a.set_xlim(0, 4 * args.R)
    a.set_ylim(-3 * args.R, 0)
    a.set_aspect("equal")
    a.set_xlabel("r [m]")
    a.set_ylabel("z [m]")
    a.set_title("plastic zone at collapse (yield ratio 1 = plastic)")
    save_figure(fig, out / "plastic_zone.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
