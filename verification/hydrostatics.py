"""Archimedes in the PFEM step: a Tresca block on the floor of a water tank.

Beyond the thesis (issue 39, item 3, its second half; the first, water at rest against a
gate, is ``verification/dam_break.py``'s held column). A block b wide and h_b high of
undrained clay (:class:`~pfem_skfem.materials.CohesiveTresca`, density rho_s, strength
c) stands in the middle of the floor of a tank L wide filled with inviscid water
(:class:`~pfem_skfem.materials.NewtonianFluid`, mu = 0, density rho_w) to the depth H;
floor and walls are smooth rigid segments (5.12). One step of (4.23) from rest.

The step is single-phase and in total stresses: no water gets under the block, so the
floor under it carries the block's weight and the water standing on its top, more than
its weight. Archimedes' statement is about the *effective* force, the floor's reaction
less the water pressure p_f = rho_w g H at the floor's depth:

    R_i - p_f t_i = 0                         at a floor node under water only,
    sum over the nodes under the block = (rho_s - rho_w) g V     (per unit thickness),

t_i the node's share of a unit pressure on the floor (the P2 consistent load: h/6 at a
vertex per edge, 2h/3 at a midside). The reaction's distribution under a rigid(-plastic)
block is not unique; its sum is.

V is the block the step weighs: the area of the elements of its region, its density and
its cone (:func:`~pfem_skfem.pfem.assemble.element_regions`: the last declared region among
an element's vertices, since the region declared first keeps the interface's particles).
Declared first, the block is weighed as drawn, V = b h_b; declared after the water it loses
the triangles spanning its convex corners, |V - b h_b| <= 4 h^2 / 2. (Until the regions
followed the drawn polygons, an element took the region of most of its vertices:
V = b h_b + (2 h_b + b) h / 2, a buoyant weight 20, 10 and 5 % too large at h = h_b/5,
/10, /20; ``V_majority`` records that block.)

Checks: at each spacing, the effective force under the block against (rho_s - rho_w) g V
(the weighed V) to 1e-6, and against the drawn block, (rho_s - rho_w) g b h_b, within
2 h^2 / (b h_b) (the corner triangles: second order in h); the effective reaction under the
water zero to 1e-6 of p_f h; the floor under the block carrying more than its weight
(total stresses); the walls rho_w g H^2 / 2 each to 1e-6; the block and water at rest
(largest speed after the step 1e-3 of g dt).

Usage::

    python verification/hydrostatics.py --quick --json results/hydrostatics.json   # 4 seconds
    python verification/hydrostatics.py --n 5 10 20 40
"""
import sys

import numpy as np

from pfem_skfem.harness.declare import option_values, own_options
from pfem_skfem.harness.figures import figure_dir, labelled, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, material_options, opt, positive_int,
                                        time_options)
from pfem_skfem.harness.report import Report, observed_order, script_main

QUICK = dict(n=[5, 10])


def tank_scene(L, H, b, h_b, n, *, rho_w, rho_s, c, g, dt, block_first=True,
               solver="clarabel"):
    """The tank (L wide, water to H) with the block (b x h_b, centred on the floor), particles
    on a square lattice of spacing h_b / n, smooth floor and walls: scene and initial state."""
    from pfem_skfem.discretisation import ThetaMethod
    from pfem_skfem.materials import CohesiveTresca, NewtonianFluid
    from pfem_skfem.problems.contact import CoulombCones, RigidSegment
    from pfem_skfem.scene import Body, Region, Scene
    from pfem_skfem.scene.config import PFEMConfig

    h = h_b / n
    x0, x1 = (L - b) / 2, (L + b) / 2
    block = Region(((x0, 0.0), (x1, 0.0), (x1, h_b), (x0, h_b)), CohesiveTresca(c), rho_s, h,
                   name="block")
    water = Region(((0.0, 0.0), (x0, 0.0), (x0, h_b), (x1, h_b), (x1, 0.0), (L, 0.0), (L, H),
                    (0.0, H)), NewtonianFluid(0.0), rho_w, h, name="water")
    far = 50 * L
    bodies = (Body("floor", RigidSegment((-far, 0.0), (far, 0.0), 0.0)),       # water above
              Body("left", RigidSegment((0.0, far), (0.0, -h), 0.0)),          # water right
              Body("right", RigidSegment((L, -h), (L, far), 0.0)))             # water left
    config = PFEMConfig(theta=ThetaMethod(dt, 1.0, 1.0), contact=CoulombCones(), passes=1,
                        solver=solver)
    scene = Scene(regions=(block, water) if block_first else (water, block), bodies=bodies,
                  gravity=(0.0, -g), alpha=1.6, length=H, config=config)
    return scene.initial_state(), scene


def floor_shares(disc):
    """t: each dof's share of a unit pressure on the floor y = 0 (P2 consistent load, at the
    y dofs: h/6 per edge at a vertex, 2h/3 at a midside)."""
    p = disc.mesh.p
    facets = disc.mesh.boundary_facets()
    ends = disc.mesh.facets[:, facets]
    on = np.all(np.abs(p[1, ends]) <= 1e-12 * np.ptp(p[0]), axis=0)
    ends, facets = ends[:, on], facets[on]
    length = np.abs(p[0, ends[1]] - p[0, ends[0]])
    t = np.zeros(disc.n_u)
    y = disc.basis_u.nodal_dofs[1]
    np.add.at(t, y[ends[0]], length / 6)
    np.add.at(t, y[ends[1]], length / 6)
    np.add.at(t, disc.basis_u.facet_dofs[1][facets], 2 * length / 3)
    return t


def buoyancy(L, H, b, h_b, n, *, rho_w, rho_s, c, g, dt, block_first=True, solver="clarabel"):
    """One step of the tank from rest: the floor's reactions and the block the step sees.

    Returns a dict: ``effective`` the floor's effective force under the block (its nodes'
    reactions less p_f t_i) / ((rho_s - rho_w) g V) - 1 (nan for a neutral block: then
    ``effective_force`` [N/m], to compare with 0), ``water_effective`` the largest
    |R_i - p_f t_i| under the water alone / (p_f h), ``under_over_weight`` the floor's
    total force under the block / rho_s g V, ``V`` the area the step weighs with rho_s,
    ``V_drawn`` b h_b, ``walls`` (left, right) / (rho_w g H^2 / 2), ``still`` the largest speed /
    (g dt), and the floor nodes' x, effective reactions R_i - p_f t_i and whether under the
    block; ``V_majority`` the area of the elements with most of their vertices in the
    block (the block the step weighed before the regions followed the drawn polygons).
    """
    from pfem_skfem.drivers.resumable import ResumableRun
    from pfem_skfem.pfem.alpha_shape import triangle_areas
    from pfem_skfem.pfem.assemble import element_regions

    state0, scene = tank_scene(L, H, b, h_b, n, rho_w=rho_w, rho_s=rho_s, c=c, g=g, dt=dt,
                               block_first=block_first, solver=solver)
    step = ResumableRun(scene, state0).advance(lambda run: run.state.step >= 1)
    state, result, record = step.state, step.result, step.record
    disc, inc, contacts = result.disc, result.increment, result.contacts
    k = [r.name for r in scene.regions].index("block")
    area = triangle_areas(disc.mesh.p.T, disc.mesh.t.T)
    in_block = element_regions(state0, result.pm) == k           # density and cone
    V = float(area[in_block].sum())
    r = state0.region[result.pm.particle[disc.mesh.t]]
    majority = np.where(r[1] == r[2], r[1], r[0]) == k           # the rule before
    on_floor = contacts.normal[:, 1] > 1 - 1e-12     # the floor's (+y; wall nodes near it too)
    reaction = (contacts.normal * inc.p[:, None]
                + contacts.tangent * inc.q[:, None])[on_floor, 1]  # on the water and block
    ydof = contacts.dofs[on_floor, 1]
    share = floor_shares(disc)[ydof]
    p_f = rho_w * g * H
    effective = reaction - p_f * share
    under = np.isin(ydof, disc.basis_u.element_dofs[:, in_block])
    buoyant = (rho_s - rho_w) * g * V
    wall = rho_w * g * H ** 2 / 2
    line = share > 0                                  # the nodes on the floor (y = 0)
    order = np.argsort(contacts.x[on_floor, 0][line])
    return dict(effective=effective[under].sum() / buoyant - 1 if buoyant else np.nan,
                effective_force=float(effective[under].sum()),
                water_effective=float(np.abs(effective[~under]).max() / (p_f * h_b / n)),
                under_over_weight=float(reaction[under].sum() / (rho_s * g * V)),
                V=V, V_drawn=b * h_b, V_record=record["area_regions"]["block"],
                V_majority=float(area[majority].sum()),
                walls=(-record["forces"]["left"][0] / wall, record["forces"]["right"][0] / wall),
                still=float(np.abs(state.v).max() / (g * dt)), n=n, h=h_b / n,
                x=contacts.x[on_floor, 0][line][order],
                effective_nodes=effective[line][order], under=under[line][order])


def drawn_block_error(runs, unit):
    """Each run's |effective force / unit - 1| against the drawn block, unit = (rho_s -
    rho_w) g b h_b, and their order in h (nan for one run, or an error at round-off, 1e-8)."""
    nominal = np.array([abs(r["effective_force"] / unit - 1) for r in runs])
    fit = len(runs) >= 2 and np.all(nominal > 1e-8)
    return nominal, observed_order([r["h"] for r in runs], nominal) if fit else np.nan


def check(args):
    if not (args.b < args.L and args.h_b < args.H):
        return "--b and --h-b: the block must be narrower than the tank (--L) and below " \
               "the water (--H)"
    for length, name in ((args.b, "--b"), ((args.L - args.b) / 2, "(--L - --b) / 2"),
                         (args.H, "--H")):
        for n, hh in ((n, args.h_b / n) for n in args.n):
            if abs(length / hh - round(length / hh)) > 1e-9 * length / hh:
                return (f"--n {n}: {name} = {length:g} is not a whole number of spacings "
                        f"--h-b / --n = {hh:g} (block and water share one square lattice)")
    return ("--rho-s must exceed --rho-w (a block lighter than the water floats)"
            if args.rho_s <= args.rho_w else None)


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    own_options(p, L=opt(0.6, "tank width [m]"), H=opt(0.2, "water depth [m]"),
                b=opt(0.2, "block width [m]"), h_b=opt(0.1, "block height [m]"),
                rho_w=opt(1000.0, "water density [kg/m3]"),
                rho_s=opt(2000.0, "block density [kg/m3]"))
    material_options(p, units="Pa", g=9.81,
                     c=opt(1.0e4, "the block's undrained strength [Pa] (Tresca)"))
    time_options(p, dt=opt(0.01, "the one step [s]"))
    own_options(p, n=opt([5, 10, 20], "particle spacings across the block's height (h = h_b / n)",
                         type=positive_int, nargs="+"))
    p.add_argument("--block-first", action=__import__("argparse").BooleanOptionalAction,
                   default=True, help="declare the block before the water (its particles "
                                      "keep the interface; after: it loses its corner triangles)")
    return p


def run(args):
    common = option_values(args, "rho_w", "rho_s", "c", "g", "dt", "block_first", "solver")
    runs = [buoyancy(args.L, args.H, args.b, args.h_b, n, **common) for n in args.n]
    report = Report("hydrostatics", args)
    nominal, order = drawn_block_error(runs, (args.rho_s - args.rho_w) * args.g * args.b * args.h_b)
    for r, error in zip(runs, nominal):
        n, h = r["n"], r["h"]
        report.add(f"buoyant_weight_n{n}", r["effective"] + 1, 1.0,
                   "floor under the block less p_f t_i = (rho_s - rho_w) g V, the weighed V",
                   1e-6)
        report.add_interval(f"drawn_block_n{n}", error, 0.0,
                            2 * h ** 2 / (args.b * args.h_b) + 1e-6,
                            "Archimedes with the drawn block, (rho_s - rho_w) g b h_b, "
                            "within 2 h^2 / (b h_b): the corner triangles")
        report.add_interval(f"water_floor_effective_n{n}", r["water_effective"], 0.0, 1e-6,
                            "floor under water alone: R_i = rho_w g H t_i (/ p_f h)")
        report.add_interval(f"under_block_over_weight_n{n}", r["under_over_weight"], 1.0,
                            np.inf, "total stresses: the floor under the block carries "
                            "more than its weight (the water on it)")
        for side, ratio in zip(("left", "right"), r["walls"]):
            report.add(f"{side}_wall_force_n{n}", ratio, 1.0, "rho_w g H^2 / 2", 1e-6)
        report.add_interval(f"at_rest_n{n}", r["still"], 0.0, 1e-3,
                            "largest speed after the step / (g dt)")
    report.add_table("buoyancy", ["n", "h", "V / b h_b", "effective/(rs-rw)gV - 1",
                                  "against b h_b", "under/weight", "majority V / b h_b"],
                     [[r["n"], r["h"], r["V"] / r["V_drawn"], r["effective"], e,
                       r["under_over_weight"], r["V_majority"] / r["V_drawn"]]
                      for r, e in zip(runs, nominal)],
                     formats={"h": ".4f", "V / b h_b": ".4f", "effective/(rs-rw)gV - 1": ".2e",
                              "against b h_b": ".2e", "under/weight": ".4f",
                              "majority V / b h_b": ".4f"},
                     title=f"buoyancy; order in h against b h_b: {order:.2f} (nan: round-off)")
    report.extra = {"runs": [{k: v for k, v in r.items() if k != "under"} for r in runs],
                    "drawn_block_error": nominal, "drawn_block_error_order": order}
    report.data = dict(runs=runs, nominal=nominal, order=order)
    return report


def figures(args, runs, nominal, order):
    """The floor's effective force summed from the left wall, and the error against the drawn
    block against the spacing."""
    fig, ax = pyplot().subplots(1, 2, figsize=(12, 4.2))
    unit = (args.rho_s - args.rho_w) * args.g * args.b * args.h_b
    ax[0].axvspan((args.L - args.b) / 2, (args.L + args.b) / 2, color="0.9", label="drawn block")
    for r in runs:
        ax[0].step(r["x"], np.cumsum(r["effective_nodes"]) / unit, where="post",
                   label=f"h = h_b / {r['n']}: V = {r['V'] / r['V_drawn']:.2f} b h_b")
    ax[0].axhline(1.0, color="0.3", ls="--", label="(rho_s - rho_w) g b h_b")
    labelled(ax[0], "x [m]", "sum of R_i - p_f t_i to x / (rho_s - rho_w) g b h_b",
             "floor's effective force, from the left wall")
    hs = np.array([q["h"] for q in runs])
    ax[1].loglog(hs, np.maximum(nominal, 1e-16), "o-",       # round-off: no order
                 label=f"ours, order {order:.2f}" if np.isfinite(order) else "ours")
    ax[1].loglog(hs, 2 * hs ** 2 / (args.b * args.h_b), ":", color="0.3",
                 label="2 h^2 / (b h_b): the corner triangles")
    ax[1].loglog(hs, (2 * args.h_b + args.b) * hs / (2 * args.b * args.h_b), "--", color="0.5",
                 label="majority of the vertices (before): (2 h_b + b) h / (2 b h_b)")
    labelled(ax[1], "particle spacing h [m]", "|effective / ((rho_s - rho_w) g b h_b) - 1|",
             "against the drawn block")
    save_figure(fig, figure_dir(args, "hydrostatics") / "hydrostatics.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
