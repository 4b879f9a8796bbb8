"""A rigidly rotated bar: the spurious strain of small-deformation increments (thesis 6.2).

A bar of length L0, initially horizontal, is rotated anticlockwise about its first
node by theta in N equal increments. Each increment is a small-deformation
analysis (the truss problem (B.12), elastic) on the configuration left by the
previous one: the second node is moved to its exact position on the circle, the
first is pinned. A rigid rotation should create no strain, but the small-strain
operator (B.9) sees the projection of each rotation step on the bar,

    delta eps = cos(theta / N) - 1                                   (6.1)

so that after N increments (thesis (6.2)-(6.3))

    eps_N = N (cos(theta / N) - 1) = -theta^2 / (2 N) + theta^4 / (24 N^3) - ...

References
----------
* Leading order: eps = -theta^2 / (2N) (6.3): the error falls as 1/N.
* The exact value of the scheme, N (cos(theta/N) - 1), which the SOCP must
  reproduce to solver precision (the stress is E eps).

Quantities: ``strain_N<max>`` against -theta^2/(2N) (relative tolerance
theta^2/(12 N^2), the next term of the series, plus 1e-6); ``strain_scheme_N<max>``
against N (cos(theta/N) - 1) to 1e-6; ``order`` the slope of log|eps| against
log N fitted over all N >= 4, against 1.

Usage::

    python verification/rotating_bar.py --quick --json results/rotating_bar.json   # seconds
    python verification/rotating_bar.py --help                                # every option

``--quick`` and ``--json PATH`` (and ``--outdir``, ``--no-figures``, ``--quiet``)
come from :func:`pfem_skfem.harness.options.base_parser`.
"""
import sys

import numpy as np

from pfem_skfem.problems.bar import truss_displacement_control
from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, material_options, opt, positive_float,
                                        time_options)
from pfem_skfem.harness.progress import progress
from pfem_skfem.harness.report import Report, script_main

QUICK = dict(steps=[4, 8, 16, 32])


def rotated_strain(n_increments, theta, L0=1.0, E=210e3, A=1.0, solver="clarabel"):
    """Strain of the bar after a rigid rotation theta (radians) in N increments (B.12).

    Returns (strain, x) with x the (N+1, 2, 2) node positions.
    """
    x0 = np.array([[0.0, 0.0], [L0, 0.0]])

    def path(k):  # total displacement of node 2 on the circle after increment k
        a = theta * k / n_increments
        return np.array([L0 * np.cos(a) - L0, L0 * np.sin(a)])

    hist = truss_displacement_control(x0, [[0, 1]], A, E, fixed=[0, 1],
                                      prescribed=([2, 3], path), n_increments=n_increments,
                                      solver=solver)
    return hist.sigma[-1, 0] / E, hist.x


def fit_order(n, err):
    """Slope p of log|err| = -p log N + c (least squares)."""
    return -np.polyfit(np.log(n), np.log(np.abs(err)), 1)[0]


def check(args):
    """Options that cannot go together (a usage error), or None."""
    if any(n < 1 for n in args.steps):
        return "--steps must be positive integers"
    if not 0 < abs(np.radians(args.theta)) <= np.pi:
        return "--theta must lie in (0, 180] degrees"
    if len({n for n in args.steps if n >= 4}) < 2:
        return "--steps needs at least two values >= 4 to fit the order"
    return None


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    p.add_argument("--theta", type=float, default=90.0,
                   help="total rotation theta (degrees)")
    p.add_argument("--L0", type=positive_float, default=1.0, help="bar length")
    material_options(p, units=None, E=opt(210e3, why="only scales the stress"))
    p.add_argument("--A", type=positive_float, default=1.0, help="cross-sectional area")
    time_options(p, steps=opt([1, 2, 4, 8, 16, 32, 64, 128], "numbers of increments N",
                              nargs="+"))
    return p


def run(args):
    """The strain after each number of increments against (6.1)-(6.3), and its order."""
    theta = np.radians(args.theta)
    steps = np.array(sorted(set(args.steps)))
    report = Report("rotating_bar", args)
    strains, rows = [], []
    for n in steps:
        eps, _ = rotated_strain(int(n), theta, args.L0, args.E, args.A, args.solver)
        strains.append(eps)
        scheme, leading = n * (np.cos(theta / n) - 1), -theta ** 2 / (2 * n)
        rows.append([int(n), eps, scheme, leading, n * eps])
        if args.progress:
            progress(f"N = {n}: strain {eps:.6e}")
    report.add_table("strain", ["N", "eps (SOCP)", "N(cos(t/N)-1)", "-t^2/(2N)", "N*eps"], rows,
                     formats={"eps (SOCP)": ".6e", "N(cos(t/N)-1)": ".6e", "-t^2/(2N)": ".6e",
                              "N*eps": ".5f"})
    strains = np.array(strains)
    n_max = int(steps[-1])
    leading = -theta ** 2 / (2 * n_max)
    report.add(f"strain_N{n_max}", strains[-1], leading, "(6.3) -theta^2/(2N)",
               theta ** 2 / (12 * n_max ** 2) + 1e-6)
    report.add(f"strain_scheme_N{n_max}", strains[-1], n_max * (np.cos(theta / n_max) - 1),
               "(6.1)-(6.3) N (cos(theta/N) - 1)", 1e-6)
    fit = steps >= 4
    report.add("order", fit_order(steps[fit], strains[fit]), 1.0, "(6.3) strain ~ 1/N", 0.02)
    report.extra = {"N": steps.tolist(), "strain": strains.tolist(),
                    "leading_order": (-theta ** 2 / (2 * steps)).tolist()}
    report.data = dict(theta=theta, steps=steps, strains=strains)
    return report


def figures(args, theta, steps, strains):
    """The spurious strain against N (log-log) and the bar's path for the coarsest N."""
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4.2))
    nn = np.geomspace(steps[0], steps[-1], 100)
    a1.loglog(steps, -strains, "o", label="SOCP (B.12), updated geometry")
    a1.loglog(nn, theta ** 2 / (2 * nn), "-", label=r"$\theta^2/(2N)$ (6.3)")
    a1.set_xlabel("increments N")
    a1.set_ylabel(r"spurious strain $-\varepsilon$")
    a1.set_title(f"spurious strain of a rigid rotation by {np.degrees(theta):g} deg")
    a1.legend()
    a1.grid(True, which="both", alpha=0.3)
    n0 = int(min(n for n in steps if n >= 4))
    _, x = rotated_strain(n0, theta, args.L0, args.E, args.A, args.solver)
    t = np.linspace(0, theta, 100)
    a2.plot(args.L0 * np.cos(t), args.L0 * np.sin(t), "k:", lw=0.8, label="exact path")
    for k in range(x.shape[0]):
        a2.plot(x[k, :, 0], x[k, :, 1], "-o", ms=3, color=plt.cm.viridis(k / (x.shape[0] - 1)))
    a2.set_aspect("equal")
    a2.set_xlabel("x (units of L0)")
    a2.set_ylabel("y (units of L0)")
    a2.set_title(f"the bar's positions, N = {n0} increments (Fig 6.1)")
    a2.legend()
    save_figure(fig, figure_dir(args, "rotating_bar") / "rotating_bar.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
