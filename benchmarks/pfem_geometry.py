"""Timing of the PFEM geometry stages of one step (thesis Section 2.2, steps 1a-1c).

A column of particles (the vertices of a Triangle mesh of a 2 x 1 rectangle) carries
a P2 mesh with a stress and a velocity field; the particles are moved by a collapse-
like displacement, and then, timed per stage:

1a  alpha-shape detection (Delaunay + circumradius filter, bodies, loops);
1b  (a) the alpha-filtered mesh, (b) Triangle's quality remesh, P2 bases on it;
1c  stress mapping by UEM and by IDA, velocity mapping by P2 interpolation.

Reference: one static conic solve (3.45) of about 2,000 elements takes about
1.3 s on this machine; the goal is geometry well under a tenth of a solve.

Run: ``python benchmarks/pfem_geometry.py [--sizes 2000 20000] [--repeat 3]``.
"""
import argparse
import time

import numpy as np

from pfem_skfem.discretisation.meshes import triangulate_polygon
from pfem_skfem.discretisation.static import discretise
from pfem_skfem.pfem.alpha_shape import alpha_shape
from pfem_skfem.pfem.mapping import map_nodal, map_stress
from pfem_skfem.pfem.remesh import alpha_mesh, mesh_quality, quality_remesh

SOLVE_SECONDS_2000 = 1.3       # one static conic solve at ~2,000 elements (measured, see docstring)


def column(n_particles):
    """A Triangle mesh of [0, 2] x [0, 1] with about n_particles vertices, and its spacing h."""
    h = np.sqrt(2.0 / n_particles * 1.87)            # Triangle: ~1.87 / h^2 vertices per unit area
    mesh = triangulate_polygon([(0, 0), (2, 0), (2, 1), (0, 1)], h)
    return mesh, h


def collapse(x, t=0.15):
    """A smooth displacement: the column slumps and spreads (a granular-collapse shape)."""
    return np.c_[t * x[:, 0] * x[:, 1] * (1.2 - x[:, 1]), -t * x[:, 1] * (x[:, 0] / 2) ** 2]


def timed(f, repeat):
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = f()
        best = min(best, time.perf_counter() - t0)
    return out, best


def run(n_particles, alpha=1.5, repeat=3):
    mesh0, h = column(n_particles)
    old = discretise(mesh0)
    sigma = np.c_[old.points @ [1.0, -2.0], old.points @ [0.5, 3.0],
                  old.points[:, 0] ** 0, old.points @ [0.2, 0.1]]
    v = np.random.default_rng(0).normal(size=old.n_u)
    x = mesh0.p.T + collapse(mesh0.p.T)
    rows = []
    shape, t = timed(lambda: alpha_shape(x, h, alpha), repeat)
    rows.append(("1a alpha-shape detection", t))
    a, t = timed(lambda: alpha_mesh(shape), repeat)
    rows.append(("1b (a) alpha mesh (MeshTri)", t))
    q, t = timed(lambda: quality_remesh(shape), repeat)
    rows.append(("1b (b) Triangle quality remesh", t))
    new, t = timed(lambda: discretise(q.mesh), repeat)
    rows.append(("1b P2 + stress bases (skfem)", t))
    _, t = timed(lambda: map_stress(old, sigma, new, "uem"), repeat)
    rows.append(("1c stress, UEM", t))
    _, t = timed(lambda: map_stress(old, sigma, new, "ida"), repeat)
    rows.append(("1c stress, IDA (k=6, c=3.5)", t))
    _, t = timed(lambda: map_nodal(old.basis_u, v, new.basis_u), repeat)
    rows.append(("1c velocities, P2 interpolation", t))
    info = {"particles": len(x), "elements_old": old.mesh.nelements,
            "elements_alpha": a.mesh.nelements, "elements_new": new.mesh.nelements,
            "stress_points_new": new.n_points, "added_nodes": int(q.added.sum()),
            "quality": mesh_quality(q.mesh), "bodies": shape.n_bodies, "holes": shape.n_holes}
    return rows, info


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sizes", type=int, nargs="+", default=[2000, 20000])
    p.add_argument("--alpha", type=float, default=1.5)
    p.add_argument("--repeat", type=int, default=3, help="best of this many runs")
    args = p.parse_args(argv)
    for n in args.sizes:
        rows, info = run(n, args.alpha, args.repeat)
        total = sum(t for name, t in rows if "IDA" not in name and "(a)" not in name)
        # a conic solve grows at least linearly with the number of elements
        solve = SOLVE_SECONDS_2000 * info["elements_new"] / 2000
        print(f"\n== {info['particles']} particles: {info['elements_old']} old elements, "
              f"{info['elements_new']} new ({info['added_nodes']} nodes added), "
              f"{info['bodies']} body, {info['holes']} holes ==")
        print(f"{'stage':36s} {'time [s]':>9s} {'/ solve':>8s}")
        for name, t in rows:
            print(f"{name:36s} {t:9.4f} {t / solve:8.4f}")
        print(f"{'step (1a + 1b(b) + bases + UEM + P2)':36s} {total:9.4f} {total / solve:8.4f}")
        qual = info["quality"]
        print(f"quality remesh: min angle {qual['min_angle']:.1f} deg, max aspect "
              f"{qual['max_aspect']:.2f}; conic solve at this size >= {solve:.1f} s "
              f"(1.3 s per 2,000 elements, linear scaling: a lower bound)")


if __name__ == "__main__":
    main()
