"""Time one elastoplastic increment of (3.45) and one limit analysis at several sizes.

Splits each into assembly (scikit-fem: bases, B, C), cvxpy compilation and the
Clarabel solve, on the strip-footing mesh of ``verification/strip_footing.py``.

    python benchmarks/static_step.py [--elements 500 2000 8000] [--repeat 1]

Reference measured on the project machine (2 cores) before this script existed:
compile 0.03 / 0.11 / 0.41 s, solve 0.18 / 1.31 / 10.3 s at 500 / 2,000 / 8,000 elements.
"""
import argparse
from pathlib import Path
import sys
import time

import numpy as np

from pfem_skfem.materials import Elastic, Tresca
from pfem_skfem.discretisation.static import assemble_B, assemble_C
from pfem_skfem.problems.static import static_increment

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))   # run as a file: the root
from verification import strip_footing  # noqa: E402


def time_case(n_elements):
    t0 = time.perf_counter()
    model = strip_footing.footing_model(n_elements)
    C = assemble_C(model["disc"], Elastic(1e5, 0.49))
    B = assemble_B(model["disc"])  # timed again: footing_model built it once already
    t_assembly = time.perf_counter() - t0
    disc, fp = model["disc"], model["footing"]
    zero = np.zeros((disc.n_points, 4))
    ep = static_increment(B, C, np.zeros(disc.n_u), zero, Tresca(100.0), fixed=model["fixed"],
                          prescribed=(fp, -0.02 * np.ones(fp.size)))
    la = static_increment(B, None, np.zeros(disc.n_u), zero, Tresca(100.0),
                          fixed=model["fixed"], prescribed=(fp, -np.ones(fp.size)))
    return model["n_elements"], t_assembly, ep.info, la.info


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--elements", type=int, nargs="+", default=[500, 2000, 8000])
    args = p.parse_args()
    print(f"{'elements':>8s} {'problem':>16s} {'mesh+asm s':>11s} {'compile s':>10s} "
          f"{'solve s':>8s} {'iters':>6s}")
    for n in args.elements:
        n_el, t_asm, ep, la = time_case(n)
        for name, info in (("elastoplastic", ep), ("limit analysis", la)):
            print(f"{n_el:8d} {name:>16s} {t_asm:11.3f} {info.compile_time:10.3f} "
                  f"{info.solve_time:8.3f} {info.iterations:6d}", flush=True)


if __name__ == "__main__":
    main()
