"""Where a dam break's domain gains and loses area, step by step: each remeshing's mesh
against the mesh the step before moved (book/water_and_mud.md, "The square column's
area"). A study beside verification/dam_break.py, whose scene it runs (its base run).

Every remeshing changes the domain by the triangles it drops and the ones it adds, at the
same particles (the step's detection is made on the moved particles; a triangle the move
inverted and the detection keeps counts twice its area), so its change is exactly the new
mesh's area less the moved one's; each mesh is cut into places: at the wall (x < a), at
the tip (within a of the main body's front) and along the layer between (the triangles
clipped at those lines: a retriangulation moves no area between places). The sum of the
places is checked against the records' (printed beside). The triangles dropped at
a particle that leaves the mesh (with mass: a particle the move added carries none) are
what its water took out of the domain; its volume m / rho is beside them. The largest
single drop is shown with its triangles (circumradius over the mean h of their three
particles: the alpha test drops one above alpha).

Run: python scripts/dam_break_area.py --n2 1            (16 across, 80 steps to T = 4)
     python scripts/dam_break_area.py --n2 1 --alpha-advected 3 --json /tmp/area.json
"""
import argparse
from dataclasses import replace
import json
from pathlib import Path
import sys

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from pfem_skfem.drivers import pfem_loop                                    # noqa: E402
from pfem_skfem.pfem.alpha_shape import circumradius, triangle_areas        # noqa: E402
from pfem_skfem.pfem.measure import main_body                               # noqa: E402
from verification.dam_break import DamBreak, time_unit                      # noqa: E402

PLACES = ("wall", "layer", "tip")


def triangles_of(state):
    """The state's mesh as particle triples, {sorted triple: the triple as meshed}."""
    t = state.mesh_particle[state.mesh_t]
    return dict(zip(map(tuple, np.sort(t, axis=1)), t))


def area_left_of(triangle, c):
    """The signed area of the part of a triangle ((3, 2) vertices) left of x = c (the
    polygon clipped by the half-plane, Sutherland-Hodgman; its orientation kept)."""
    clipped = []
    for p, q in zip(triangle, np.roll(triangle, -1, axis=0)):
        if p[0] <= c:
            clipped.append(p)
        if (p[0] - c) * (q[0] - c) < 0:                   # the edge crosses x = c
            clipped.append(p + (c - p[0]) / (q[0] - p[0]) * (q - p))
    if len(clipped) < 3:
        return 0.0
    x, y = np.array(clipped).T
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def remeshing(before, after, a):
    """What the remeshing at the start of the step from ``before`` (the state it starts
    from: its mesh moved to t_n) to ``after`` changed: the area by place (wall, layer,
    tip), the triangles it dropped (particle triples) and their areas at ``before.x``, and
    the particles with mass that left the mesh."""
    old, new = triangles_of(before), triangles_of(after)
    dropped = np.array([old[k] for k in sorted(old.keys() - new.keys())],
                       dtype=int).reshape(-1, 3)
    front = before.mesh_p[main_body(before.mesh_p, before.mesh_t), 0].max()
    cuts = (a, max(front - a, a))

    def by_place(t):
        """The mesh t's (signed) area at the wall, along the layer and at the tip."""
        left = [sum(area_left_of(before.x[tri], c) for tri in t) for c in cuts]
        return np.array([left[0], left[1] - left[0],
                         triangle_areas(before.x, t).sum() - left[1]])

    meshed_after = np.zeros(before.n, dtype=bool)
    meshed_after[after.mesh_particle[after.mesh_particle >= 0]] = True
    was = before.mesh_particle[before.mesh_particle >= 0]
    left = was[~meshed_after[was] & (before.mass[was] > 0)]
    old_t, new_t = np.array(list(old.values())), np.array(list(new.values()))
    # by place, each mesh's whole area (the triangles both hold cancel, but for one the
    # moved mesh held inverted), signed as meshed
    change = by_place(new_t) - by_place(old_t)
    return dict(dropped=dropped, change=change, left=left,
                dropped_area=triangle_areas(before.x, dropped))


def study(params, alpha_advected):
    state, scene = params.scene()
    scene = replace(scene, config=replace(scene.config, alpha_advected=alpha_advected))
    a, rho, t_unit = params.a, params.rho, time_unit(params.a, params.n2, params.g)
    alpha = scene.alpha                              # the alpha test drops R > alpha h
    states = [state]
    pfem_loop.run(state, scene, params.steps, on_step=lambda s, r, res: states.append(s))
    area0 = states[-1].area0
    net = np.zeros(3)
    took = volume = 0.0
    drops = []
    for k in range(1, len(states) - 1):     # the remeshing at the start of step k + 1
        before, after = states[k], states[k + 1]
        r = remeshing(before, after, a)
        net += r["change"] / area0
        at_left = np.isin(r["dropped"], r["left"]).any(axis=1)
        took += r["dropped_area"][at_left].sum() / area0
        volume += before.mass[r["left"]].sum() / rho / area0
        change = r["change"].sum() / area0
        t = r["dropped"]
        ratio = circumradius(before.x, t) / before.h[t].mean(axis=1) if len(t) else []
        cut = np.flatnonzero(np.asarray(ratio) > alpha)          # the alpha test's
        big = cut[np.argsort(-np.abs(r["dropped_area"][cut]))[:2]]
        drops.append(dict(T=before.time / t_unit, change=change, triangles=[
            dict(area=float(abs(r["dropped_area"][i]) / area0), radius_over_h=float(ratio[i]),
                 x_over_a=float(before.x[t[i], 0].mean() / a),
                 y_over_a=float(before.x[t[i], 1].mean() / a)) for i in big]))
    history = states[-1].history
    motion = (np.asarray(history["moved_area"]) - history["mesh_area"])[:-1].sum() / area0
    recorded = (np.asarray(history["mesh_area"][1:]) - history["moved_area"][:-1]).sum() / area0
    worst = min(drops, key=lambda d: d["change"])
    return dict(n2=params.n2, nx=params.nx, steps=params.steps, alpha_advected=alpha_advected,
                area_change_final=float(history["area_change"][-1]),
                area_change_largest=float(np.abs(history["area_change"]).max()),
                motion=float(motion), remeshing=dict(zip(PLACES, net.tolist())),
                remeshing_recorded=float(recorded),
                spray_took=float(took), spray_volume=float(volume), largest_drop=worst)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n2", type=float, default=1.0)
    p.add_argument("--nx", type=int, default=16)
    p.add_argument("--steps", type=int, default=80)
    p.add_argument("--T-end", type=float, default=4.0)
    p.add_argument("--alpha-advected", type=float, default=0.0)
    p.add_argument("--json", type=Path, default=None)
    args = p.parse_args(argv)
    params = DamBreak(a=0.05715, n2=args.n2, nx=args.nx, steps=args.steps, T_end=args.T_end,
                      rho=1000.0, mu=1.0e-3, g=9.81)
    out = study(params, args.alpha_advected)
    r, w = out["remeshing"], out["largest_drop"]
    print(f"n^2 = {args.n2:g}, {args.nx} across, {args.steps} steps (fractions of the first "
          f"area): the domain's change {out['area_change_final']:+.4f} at the last step, "
          f"largest {out['area_change_largest']:.4f}")
    print(f"  the steps' motions {out['motion']:+.4f}; the remeshings " + ", ".join(
        f"{k} {v:+.4f}" for k, v in r.items()) + f" (sum {sum(r.values()):+.4f}; the records' {out['remeshing_recorded']:+.4f})")
    print(f"  particles with mass leaving the mesh: their triangles {out['spray_took']:.4f}, "
          f"their m / rho {out['spray_volume']:.4f}")
    print(f"  the largest drop of one remeshing, {w['change']:+.4f} at T = {w['T']:.2f}; "
          "the largest triangles it dropped above alpha: " + ("; ".join(
              f"{t['area']:.4f} (R / h {t['radius_over_h']:.3f}) at x/a {t['x_over_a']:.2f}, "
              f"y/a {t['y_over_a']:.2f}" for t in w["triangles"]) or "none"))
    if args.json is not None:
        args.json.write_text(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
