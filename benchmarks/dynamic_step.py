"""Time per step of the dynamic SOCP (4.23): r^T D r as quad_form or as per-element cones.

The elastic cantilever of thesis Section 4.6 (undamped, dt = 0.1 s) at two mesh
sizes, and its elastoplastic variant (Tresca) in free vibration; a few steps
each, both forms of the D term. Prints the mean time per step split into cvxpy
compile and Clarabel solve, the iterations, and the largest difference of the
displacement increments between the two forms (relative to their size).

Run: PYTHONPATH=. python benchmarks/dynamic_step.py [--steps 5] [--sizes 50x5 100x10]
"""
import argparse
import time

import numpy as np
from skfem import MeshTri

from pfem_skfem.materials import Elastic, Tresca
from pfem_skfem.discretisation.static import boundary_dofs, boundary_facets, discretise, traction_vector
from pfem_skfem.discretisation import ThetaMethod, dynamic_operators
from pfem_skfem.problems.backends.cvxpy_step import D_FORMS
from pfem_skfem.problems.dynamic import dynamic_increment


def run(nx, ny, criterion, d_form, steps):
    disc = discretise(MeshTri.init_tensor(np.linspace(0, 10, nx + 1), np.linspace(0, 1, ny + 1)))
    clamp = lambda x: x[0] < 1e-9                                  # noqa: E731
    fixed = np.union1d(boundary_dofs(disc, clamp, 0), boundary_dofs(disc, clamp, 1))
    ops = dynamic_operators(disc, 0.01, ThetaMethod(0.1, 0.5, 0.5), Elastic(3e5, 0.3))
    f = traction_vector(disc, boundary_facets(disc, lambda x: x[0] > 10 - 1e-9), (0.0, 10.0))
    sigma, v = np.zeros((disc.n_points, 4)), np.zeros(disc.n_u)
    scaling, dus, compile_t, solve_t, iters, wall = None, [], [], [], [], []
    for i in range(steps):
        t0 = time.perf_counter()
        res = dynamic_increment(ops, f * min(i / 3, 1), f * min((i + 1) / 3, 1), sigma, v,
                                criterion, fixed=fixed, scaling=scaling, d_form=d_form)
        wall.append(time.perf_counter() - t0)
        sigma, v, scaling = res.sigma, res.v, res.scales
        dus.append(res.du)
        compile_t.append(res.info.compile_time)
        solve_t.append(res.info.solve_time)
        iters.append(res.info.iterations)
    return disc.mesh.nelements, np.array(dus), np.mean(wall), np.mean(compile_t), \
        np.mean(solve_t), np.mean(iters)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--steps", type=int, default=5)
    p.add_argument("--sizes", nargs="+", default=["50x5", "100x10"])
    args = p.parse_args(argv)
    print(f"{'case':>14s} {'elements':>8s} {'d_form':>9s} {'s/step':>7s} {'compile':>7s} "
          f"{'solve':>7s} {'iters':>5s} {'|du - du_quad|/|du|':>20s}")
    for size in args.sizes:
        nx, ny = map(int, size.split("x"))
        for label, criterion in (("elastic", None), ("Tresca Su=20", Tresca(20.0))):
            ref = None
            for d_form in D_FORMS:
                n_el, dus, wall, comp, solve, it = run(nx, ny, criterion, d_form, args.steps)
                diff = 0.0 if ref is None else np.abs(dus - ref).max() / np.abs(ref).max()
                ref = dus if ref is None else ref
                print(f"{label:>14s} {n_el:8d} {d_form:>9s} {wall:7.3f} {comp:7.3f} {solve:7.3f} "
                      f"{it:5.1f} {diff:20.2e}")


if __name__ == "__main__":
    main()
