"""Water and mud films down an incline: the exact profiles of a Newtonian and a Bingham layer.

Beyond the thesis. A layer of depth h on a no-slip plane inclined at theta carries the
shear stress tau(z) = rho g sin(theta) (h - z) at height z in steady uniform flow.

* Newtonian (:class:`~pfem_skfem.materials.NewtonianFluid`), tau = mu du/dz: the
  parabola (Nusselt's film)

      u(z) = rho g sin(theta) (h z - z^2 / 2) / mu,   u(h) = rho g sin(theta) h^2 / (2 mu);

  P2 velocities hold it exactly, so the error is the time stepping's and the solver's.
* Bingham (:class:`~pfem_skfem.materials.BinghamFluid`), tau = tau_y + mu du/dz where it
  flows: sheared below z_y = h - tau_y / (rho g sin(theta)), a rigid plug above,

      u(z) = rho g sin(theta) (z_y z - z^2 / 2) / mu  (z <= z_y),
      u = rho g sin(theta) z_y^2 / (2 mu)             (the plug, z >= z_y);

  no flow at all when rho g h sin(theta) <= tau_y. The yield surface z_y is inside an
  element on every mesh here (z_y / h near 1/3): the profile converges with the mesh, its
  order measured.

The Bingham tolerance, from the elements across the sheared layer m = z_y ny / h: the exact
profile is C^1 with a jump J = rho g sin(theta) / mu of u'' at z_y, so in the element that
holds z_y (length h / ny) no quadratic follows it closer than c J (h / ny)^2, c =
:data:`P2_KINK` = 0.01883 (the P2 interpolant at 0, 1/2, 1 of (x - a)_+^2 / 2 on [0, 1], worst
over a). The plug moves with that node, so relative to u_plug = J z_y^2 / 2 the plug's
velocity and the profile (dominated by the plug) err by

    e <= B(m) = 2 c / m^2,

and the check is e <= --tol x B (default 1.5). Measured: e m^2 up to 0.044 = 1.17 x 2c over
z_y / h = 0.12-0.56 and ny = 4, 8, 16 (the default, m = 5.3: 4.3e-4 against 2.0e-3).

Set-up: the periodic strip of :mod:`pfem_skfem.drivers.strip` (one element wide, no-slip
base, free surface, x along the slope), from rest to steady state in implicit steps.

Checks: the film's surface velocity and profile to 1e-6 on two meshes; the Bingham plug's
velocity and the profile on the finest mesh within --tol x B(m), the profile's convergence order
at least 1.5, the plug's thickness to within a node spacing; no flow (|u| <= 1e-6 of the
film's surface velocity) with tau_y_stop > rho g h sin(theta); rho, tau_y, mu doubled
give the same velocities bit for bit.

Usage::

    python verification/fluid_films.py --quick --json results/fluid_films.json   # 3 seconds
    python verification/fluid_films.py --help                # every option
"""
import sys

import numpy as np

from pfem_skfem.drivers.strip import profile_weights, strip_flow
from pfem_skfem.harness.declare import own_options
from pfem_skfem.harness.figures import figure_dir, labelled, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, material_options, nonnegative_float, opt,
                                        positive_int, slope_angle, time_options)
from pfem_skfem.harness.report import Report, observed_order, script_main
from pfem_skfem.viz import plot_order

QUICK = dict(ny=[4, 8, 16])
#: the worst max error of the P2 interpolant (nodes 0, 1/2, 1) of (x - a)_+^2 / 2 on [0, 1]
#: over 0 <= a <= 1: a jump J of u'' inside an element of length h_e costs P2_KINK J h_e^2
P2_KINK = 0.01883


def kink_bound(h, zy, ny):
    """B(m) = 2 P2_KINK / m^2, m = z_y ny / h the elements across the sheared layer: the
    relative error of the plug's velocity (and of the profile) that the kink of u at z_y
    leaves on ny elements."""
    return 2.0 * P2_KINK / (zy * ny / h) ** 2

def film_velocity(z, h, theta, rho, mu, g):
    """Nusselt's film: u(z) = rho g sin(theta) (h z - z^2/2) / mu."""
    return rho * g * np.sin(np.radians(theta)) * (h * np.asarray(z) - np.asarray(z) ** 2 / 2) / mu


def yield_height(h, theta, rho, tau_y, g):
    """z_y = h - tau_y / (rho g sin(theta)): the plug's base (<= 0: no flow)."""
    return h - tau_y / (rho * g * np.sin(np.radians(theta)))


def bingham_velocity(z, h, theta, rho, tau_y, mu, g):
    """u(z) = rho g sin(theta) (z_y z - z^2/2) / mu below z_y, the plug's speed above."""
    zy = max(yield_height(h, theta, rho, tau_y, g), 0.0)
    zz = np.minimum(np.asarray(z, dtype=float), zy)
    return rho * g * np.sin(np.radians(theta)) * (zy * zz - zz ** 2 / 2) / mu


def exact_profiles(args):
    """The film's and the mud's exact u(z) at the options' h, theta, rho, mu, tau_y and g,
    and the mud's z_y."""
    h, theta, rho, mu, g = args.h, args.theta, args.rho, args.mu, args.g
    return (lambda z: film_velocity(z, h, theta, rho, mu, g),
            lambda z: bingham_velocity(z, h, theta, rho, args.tau_y, mu, g),
            yield_height(h, theta, rho, args.tau_y, g))


def profile_error(z, u, exact):
    """Discrete L2 distance of u from ``exact`` at the sorted heights z (trapezoid weights),
    relative to the L2 norm of ``exact``."""
    w = profile_weights(z)
    return float(np.sqrt(w @ (u - exact) ** 2 / (w @ exact ** 2)))


def plug_base(z, u):
    """The height of the plug's base in a profile u(z) (z sorted): the lowest of the nodes
    from the surface down whose velocity is the surface's to 1e-3."""
    moving = np.flatnonzero(np.abs(u - u[-1]) > 1e-3 * abs(u[-1]))
    return z[moving[-1] + 1 if moving.size else 0]


def check(args):
    """Options that cannot go together (a usage error), or None."""
    load = args.rho * args.g * args.h * np.sin(np.radians(args.theta))
    if not args.tau_y < load:
        return (f"--tau-y must be below rho g h sin(theta) = {load:.4g} Pa (a flowing layer); "
                f"tau_y_stop is the no-flow case")
    if not args.tau_y_stop > load:
        return f"--tau-y-stop must exceed rho g h sin(theta) = {load:.4g} Pa (no flow)"
    return "--ny needs two meshes at least (a convergence order)" if len(args.ny) < 2 else None


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    material_options(p, units="Pa", rho=1000.0, g=9.81)
    time_options(p, steps=opt(40, "steps of each run"))
    return own_options(
        p, theta=opt(10.0, "slope angle [deg]", type=slope_angle), h=opt(0.02, "layer depth [m]"),
        mu=opt(1.0, "viscosity [Pa s] of the film and plastic viscosity of the mud"),
        tau_y=opt(22.7, "yield stress of the mud [Pa] (default: z_y near h/3)",
                  type=nonnegative_float),
        tau_y_stop=opt(42.6, "a yield stress above rho g h sin(theta) [Pa]: no flow"),
        ny=opt([4, 8, 16, 32, 64], "elements through the depth, one Bingham run each",
               type=positive_int, nargs="+"),
        T=opt(10.0, "run time in units of h^2 / nu (nu = mu / rho)"),
        tol=opt(1.5, "the Bingham plug's and profile's tolerance on the finest mesh, as a factor "
                     "on the P2 bound 2 c / m^2 (m = z_y ny / h the elements across the "
                     "sheared layer, c = 0.01883; see the docstring)"))


def flows(args):
    """The steady layers on the strip: the film on the two coarsest meshes ({ny: result}),
    the mud on each, the mud too strong to flow (--tau-y-stop) and the mud of rho, tau_y and
    mu doubled, both on the coarsest."""
    from pfem_skfem.materials import BinghamFluid, NewtonianFluid

    common = dict(steps=args.steps, t_end=args.T * args.h ** 2 * args.rho / args.mu, g=args.g,
                  passes=1, verbose=args.progress, solver=args.solver)

    def layer(fluid, n, rho=args.rho):
        return strip_flow(args.theta, args.h, fluid, rho, ny=n, **common)
    ny, mu, tau_y = sorted(args.ny), args.mu, args.tau_y
    return ({n: layer(NewtonianFluid(mu), n) for n in ny[:2]},
            {n: layer(BinghamFluid(tau_y, mu), n) for n in ny},
            layer(BinghamFluid(args.tau_y_stop, mu), ny[0]),
            layer(BinghamFluid(2 * tau_y, 2 * mu), ny[0], 2 * args.rho))


def run(args):
    """The film and the mud against their exact profiles, the stop, the doubled run."""
    (films, mud, stop, doubled), (film, bingham, zy) = flows(args), exact_profiles(args)
    ny, h, u_film, u_plug = sorted(args.ny), args.h, float(film(args.h)), float(bingham(args.h))
    report = Report("fluid_films", args, z_y=zy, u_film=u_film, u_plug=u_plug)
    for n, r in films.items():
        report.add(f"film_surface_velocity_ny{n}", r["u"][-1], u_film,
                   "rho g sin(theta) h^2 / (2 mu) (Nusselt)", 1e-6)
        report.add_interval(f"film_profile_L2_error_ny{n}", profile_error(r["z"], r["u"],
                            film(r["z"])), 0.0, 1e-6, "the parabola, held exactly by P2 velocities")
    errors = [profile_error(r["z"], r["u"], bingham(r["z"])) for r in mud.values()]
    fine, tol = mud[ny[-1]], args.tol * kink_bound(h, zy, ny[-1])
    layer = f"; tolerance {args.tol:g} x 2 c / m^2, m = {zy * ny[-1] / h:.3g} elements across z_y"
    report.add(f"plug_velocity_ny{ny[-1]}", fine["u"][-1], u_plug,
               "rho g sin(theta) z_y^2 / (2 mu)" + layer, tol)
    report.add_interval(f"bingham_profile_L2_error_ny{ny[-1]}", errors[-1], 0.0, tol,
                        "sheared parabola below z_y, rigid plug above" + layer)
    order = observed_order(ny, errors, counts=True)
    report.add_interval("bingham_profile_order", order, 1.5, np.inf,
                        "L2 error ~ (h/ny)^order, the yield surface inside an element")
    report.add_interval("plug_base_height_error",
                        abs(plug_base(fine["z"], fine["u"]) - zy) / (h / (2 * ny[-1])), 0.0, 3.0,
                        "the plug's base z_y, in node spacings (h / 2 ny); the 1e-3 "
                        "velocity criterion reaches below z_y by O(spacing)")
    report.add_interval("no_flow_speed_ratio", np.abs(stop["u"]).max() / u_film, 0.0, 1e-6,
                        "rho g h sin(theta) <= tau_y: no flow")
    report.add_interval("doubled_density_difference",
                        float(np.abs(doubled["u"] - mud[ny[0]]["u"]).max()), 0.0, 0.0,
                        "rho, tau_y, mu x 2: the same velocities bit for bit")
    profiles = {f"film_ny{ny[0]}": films[ny[0]], **{f"bingham_ny{n}": r for n, r in mud.items()}}
    report.extra = {"ny": ny, "bingham_L2_errors": errors, "order": order, "iterations": {
        f"bingham_ny{n}": float(r["iterations"].mean()) for n, r in mud.items()},
        "profiles": {k: {"z": r["z"], "u": r["u"]} for k, r in profiles.items()}}
    report.add_table("bingham", ["ny", "Bingham L2 error", "iterations/step"],
                     [[n, e, mud[n]["iterations"].mean()] for n, e in zip(ny, errors)],
                     formats={"Bingham L2 error": ".3e", "iterations/step": ".1f"},
                     title=f"bingham (observed order {order:.2f})")
    report.data = dict(films=films, mud=mud, ny=ny, errors=errors, order=order)
    return report


def figures(args, films, mud, ny, errors, order):
    """The profiles beside the exact ones, and the Bingham error against the mesh."""
    fig, ax = pyplot().subplots(1, 2, figsize=(11, 4.2))
    (film, bingham, zy), zz = exact_profiles(args), np.linspace(0.0, args.h, 300)
    for what, exact, n, r, mark in (("Newtonian", film, ny[0], films, "o"),
                                    ("Bingham", bingham, ny[1], mud, "s")):
        ax[0].plot(exact(zz), zz / args.h, "-", label=f"{what}, exact")
        ax[0].plot(r[n]["u"], r[n]["z"] / args.h, mark, ms=4, label=f"{what}, ny = {n}")
    ax[0].axhline(zy / args.h, color="0.6", ls=":", label="plug base z_y")
    labelled(ax[0], "u [m/s]", "z / h", "steady profiles")
    plot_order(ax[1], ny, errors, f"Bingham, order {order:.2f}", slope=-2.0)
    labelled(ax[1], "elements through the depth, ny", "relative L2 error of u",
             "Bingham profile against the mesh")
    save_figure(fig, figure_dir(args, "fluid_films") / "fluid_films.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
