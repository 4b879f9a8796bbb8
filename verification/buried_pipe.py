"""Deeply buried smooth pipe pushed through undrained clay (thesis 5.4.2, Fig 5.4-5.5).

A rigid pipe of radius r in a rigid-plastic Tresca soil (Su, unit weight rho g) is
moved by a prescribed displacement; half of the domain (a 10 m x 15 m column, the
pipe centred on the symmetry axis) is modelled. The pipe is a rigid circle with a
smooth contact (5.12): the soil may slide along it and separate from it, never
penetrate it. The resistance is normalised as Nc = F / (r Su) with F the force on
the half pipe, i.e. F_full / (D Su).

The soil's weight adds a buoyancy rho g pi r^2 / 2 to the force on the half pipe
(the pipe displaces its own volume of soil upwards; for Tresca the weight does
nothing else once the soil stays in contact). The weightless flow-around
references are therefore compared with Nc = (F - rho g pi r^2 / 2) / (r Su); the
raw F / (r Su) is reported too.

References
----------
* 9.14: Randolph & Houlsby (1984), smooth pile, lower bound.
* 9.20: the smooth upper bound quoted by the thesis ([114, 149]; Martin & Randolph
  2006 close the gap at 9.20).
* 9.29: the thesis with 2,812 elements (theta1 = theta2 = 1).

The problem solved here is the quasi-static rigid-plastic step: (3.45) without C,
with the contact cones of (5.12) and the pipe's motion entering through the gaps.
With theta1 = theta2 = 1 and a pipe starting from rest, the dynamic step (4.23)
differs from it only by the inertia of the soil over one step: the pipe's step 0.01 r
taken in dt from rest accelerates the soil by 0.01 r / dt^2, which adds to Nc about 3 I,
I = rho (0.01 r / dt^2) r / Su (measured at 700 elements: +0.030 at I = 0.01, dt = 0.1 s;
+0.019 at I = 0.0064; +1.83 at I = 1, dt = 0.01 s). The flow-around references are
quasi-static, so ``--dt`` is refused below r sqrt(rho / Su) (I > 0.01; 0.1 s at the
defaults).

Usage::

    python verification/buried_pipe.py --quick --json results/buried_pipe.json   # seconds
    python verification/buried_pipe.py --help                                # every option

``--quick`` and ``--json PATH`` (and ``--outdir``, ``--no-figures``, ``--quiet``)
come from :func:`pfem_skfem.harness.options.base_parser`.
"""
import sys
import time

import numpy as np

from pfem_skfem.materials import Tresca
from pfem_skfem.discretisation.meshes import fit_element_count, pipe_half_domain
from pfem_skfem.discretisation.static import assemble_B, body_force_vector, boundary_dofs, discretise
from pfem_skfem.problems.contact import RigidCircle, potential_contacts, resultants
from pfem_skfem.problems.static import static_increment
from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, element_count, material_options,
                                        nonnegative_float, opt, positive_float, time_options)
from pfem_skfem.harness.progress import progress_bar
from pfem_skfem.harness.report import Report, script_main

QUICK = dict(elements=[700])
LOWER_RH, UPPER, THESIS = 9.14, 9.20, 9.29


def pipe_model(n_elements, *, width=10.0, height=15.0, depth=7.5, r=0.5, ratio=30.0,
               growth=0.25):
    """Curved P2 mesh of the half column with about ``n_elements`` elements, and its supports."""
    best = fit_element_count(
        lambda h: pipe_half_domain(width, height, depth, r, h_min=h / ratio, h_max=h,
                                   growth=growth),
        n_elements, first_size=1.5 * np.sqrt(2.3 * width * height / n_elements))
    disc = discretise(best)
    eps = 1e-9 * width
    axis = lambda x: x[0] < eps                                  # noqa: E731 symmetry
    side = lambda x: x[0] > width - eps                          # noqa: E731
    base = lambda x: x[1] < -height + eps                        # noqa: E731
    fixed = np.unique(np.concatenate([
        boundary_dofs(disc, axis, 0), boundary_dofs(disc, side, 0),
        boundary_dofs(disc, base, 0), boundary_dofs(disc, base, 1)]))
    return dict(disc=disc, B=assemble_B(disc), fixed=fixed, n_elements=best.t.shape[1],
                center=(0.0, -depth), r=r)


def pipe_resistance(model, *, su, rho, g, mu=0.0, step=None, dt=None, solver="clarabel"):
    """Force on the half pipe moved down by ``step``: rigid-plastic, quasi-static, or,
    with a time step ``dt``, one step of the dynamic problem (4.23) + (5.12) with
    theta1 = theta2 = 1 from rest (as in the thesis)."""
    disc, r = model["disc"], model["r"]
    step = step or 0.01 * r
    pipe = RigidCircle(model["center"], r, mu=mu)
    contacts = potential_contacts(disc, [pipe], search_distance=0.02 * r,
                                  motions=[(0.0, -step)])
    f = body_force_vector(disc, (0.0, -rho * g))
    zero_stress = np.zeros((disc.n_points, 4))
    if dt is None:
        res = static_increment(model["B"], None, f, zero_stress, Tresca(su),
                               fixed=model["fixed"], contacts=contacts, solver=solver)
    else:
        from pfem_skfem.discretisation import ThetaMethod, dynamic_operators
        from pfem_skfem.problems.backends import cvxpy_solver
        from pfem_skfem.problems.dynamic import dynamic_increment
        from pfem_skfem.problems.step_terms import Contact
        ops = dynamic_operators(disc, rho, ThetaMethod(dt, 1.0, 1.0), elastic=None)
        res = dynamic_increment(ops, f, f, zero_stress, np.zeros(disc.n_u), Tresca(su),
                                fixed=model["fixed"], terms=[Contact(contacts)],
                                solver=cvxpy_solver(solver))
    force_on_pipe = resultants(contacts, res.p, res.q)[0]
    return force_on_pipe[1], res, contacts      # the soil pushes the pipe up


def check(args):
    """The pipe inside the column (a usage error naming the options), or None."""
    if not (args.r < args.depth < args.height - args.r) or args.r >= args.width:
        return (f"the pipe (--r {args.r:g} at --depth {args.depth:g}) must lie inside the "
                f"column (--height {args.height:g}, --width {args.width:g})")
    shortest = args.r * np.sqrt(args.rho / args.su)
    if args.dt is not None and args.dt < shortest:
        return (f"--dt {args.dt:g} s is below r sqrt(rho / Su) = {shortest:.4g} s: one step "
                f"from rest adds the soil's inertia, about 3 rho (0.01 r / dt^2) r / Su = "
                f"{3 * args.rho * 0.01 * args.r ** 2 / (args.dt ** 2 * args.su):.3g} to Nc, "
                f"against quasi-static references")
    return None


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    p.add_argument("--r", type=positive_float, default=0.5, help="pipe radius [m]")
    material_options(p, su=50.0, rho=2.0, g=opt(9.8, type=nonnegative_float))
    p.add_argument("--mu", type=nonnegative_float, default=0.0, help="pipe-soil friction (0: smooth)")
    p.add_argument("--width", type=positive_float, default=10.0, help="half width [m]")
    p.add_argument("--height", type=positive_float, default=15.0, help="column [m]")
    p.add_argument("--depth", type=positive_float, default=7.5,
                   help="depth of the pipe centre [m]")
    time_options(p, dt=opt(None, "solve one dynamic step (4.23) of this length [s] (theta1 = "
                                 "theta2 = 1, from rest) instead of the quasi-static step; "
                                 "at least r sqrt(rho / Su), 0.1 s at the defaults (the "
                                 "inertia, see the docstring)"))
    p.add_argument("--elements", type=element_count, nargs="+", default=[700, 1400, 2812],
                   help="approximate element counts (a mesh-convergence table)")
    return p


def run(args):
    """Pipe resistance on each mesh, net of the buoyancy, against the bounds and the thesis."""
    report = Report("buried_pipe", args)
    buoyancy = args.rho * args.g * np.pi * args.r ** 2 / 2 / (args.r * args.su)
    rows, last = [], None
    bar = progress_bar(sorted(args.elements), args=args, unit="mesh", desc="buried pipe")
    for n in bar:
        bar.set_description(f"buried pipe, about {n} elements")
        t0 = time.perf_counter()
        model = pipe_model(n, width=args.width, height=args.height, depth=args.depth, r=args.r)
        F, res, contacts = pipe_resistance(model, su=args.su, rho=args.rho, g=args.g,
                                           mu=args.mu, dt=args.dt, solver=args.solver)
        nc_raw = F / (args.r * args.su)
        rows.append((model["n_elements"], nc_raw, nc_raw - buoyancy, time.perf_counter() - t0))
        bar.set_postfix_str(f"F/(r Su) = {nc_raw:.4f}, net of buoyancy {nc_raw - buoyancy:.4f}")
        last = (model, res, contacts)
    report.add_table("convergence", ["elements", "F/(r Su)", "Nc (net)", "vs 9.20"],
                     [[n_el, raw, net, net / UPPER - 1] for n_el, raw, net, _ in rows],
                     formats={"F/(r Su)": ".4f", "Nc (net)": ".4f", "vs 9.20": "+.2%"})
    nc = rows[-1][2]
    if args.mu == 0:
        report.add_interval("Nc", nc, LOWER_RH, 9.40,
                            "smooth flow-around: 9.14 (Randolph & Houlsby 1984) - 9.20 "
                            "(upper bound); thesis 9.29; accepted up to 9.40",
                            reference=UPPER)
        report.add("Nc_vs_thesis", nc, THESIS, "thesis 5.4.2 (2,812 elements)",
                   0.03 if args.quick else 0.015)
    # the contact forces never pull (p >= 0) and the buoyancy is the weight's only effect
    model, res, contacts = last
    report.add_interval("min_contact_pressure", res.p.min() / (args.su * args.r), -1e-6,
                        np.inf, "contact law (5.5): p >= 0")
    report.extra = {"convergence": [dict(elements=a, nc_raw=b, nc_net=c, seconds=d)
                                    for a, b, c, d in rows], "buoyancy_term": buoyancy}
    report.data = dict(rows=rows, last=last)
    return report


def figures(args, rows, last):
    """Mesh convergence and the failure mode (Fig 5.5: mechanism speed, plastic zone)."""
    from matplotlib.tri import Triangulation
    model, res, contacts = last
    disc = model["disc"]
    m = disc.mesh
    ux, uy = disc.basis_u.nodal_dofs                   # x and y dofs of each vertex
    xy = disc.basis_u.doflocs[:, ux]
    speed = np.hypot(res.du[ux], res.du[uy]) / (0.01 * args.r)
    fig, ax = pyplot().subplots(1, 2, figsize=(11, 5))
    tri = Triangulation(xy[0], xy[1], m.t.T)
    tp = ax[0].tripcolor(tri, speed, shading="gouraud", cmap="magma")
    ax[0].set_xlim(0, 2.5)
    ax[0].set_ylim(-args.depth - 1.5, -args.depth + 1.5)
    ax[0].set_aspect("equal")
    ax[0].set_title(f"Fig 5.5: mechanism around the pipe ({model['n_elements']} elements)")
    ax[0].set_xlabel("x [m]")
    ax[0].set_ylabel("y [m]")
    fig.colorbar(tp, ax=ax[0], label="speed / pipe speed")
    n_el = [r[0] for r in rows]
    nc = [r[2] for r in rows]
    ax[1].plot(n_el, nc, "o-", ms=7, zorder=3, label="ours (net of buoyancy)")
    ax[1].axhspan(LOWER_RH, UPPER, color="g", alpha=0.2,
                  label="9.14 (Randolph & Houlsby) - 9.20 (upper bound)")
    ax[1].axhline(THESIS, color="r", ls="--", label="thesis 9.29 (2,812 elements)")
    ax[1].set_xlim(0, 1.15 * max(n_el))
    ax[1].set_ylim(min(8.6, min(nc) - 0.3), max(9.6, max(nc) + 0.1))
    ax[1].set_xlabel("elements")
    ax[1].set_ylabel("Nc = F / (r Su)")
    ax[1].set_title("pipe resistance against the mesh")
    ax[1].legend(loc="lower right", fontsize=8)
    save_figure(fig, figure_dir(args, "buried_pipe") / "buried_pipe.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
