"""Elastoplastic dynamics: a vibrating cantilever that yields dissipates energy (thesis Ch 4).

The cantilever of Section 4.6 (10 m x 1 m, rho = 0.01 t/m3, E = 3e5 kPa,
nu = 0.3, clamped at x = 0, no load, g = 0) starts from rest in the undeformed
state with the velocity field v_y = V (x / L)^2 and vibrates freely. It is
integrated by the dynamic SOCP (4.23) with theta1 = theta2 = 1/2, once elastic
and once elastoplastic (Tresca, strength Su low enough to yield at the root).

References (facts, not fits):

* energy identity of the theta1 = theta2 = 1/2 scheme (the KKT conditions (4.25)
  times du): K_N + W_N + D_N = K_0 with D_N the plastic dissipation
  sum sigma_{n+1/2}^T (B du - C dsigma); residual below 1e-6 of K_0;
* no energy gain: the energy K + W never increases from one step to the next
  (to 1e-7 K_0), and D_N >= 0 (convex yield set containing the origin);
* the elastic run conserves K + W to 1e-6 (trapezoidal rule, linear system);
* the elastoplastic run yields: D_N is more than 5 % of K_0.

Usage::

    python verification/plastic_vibration.py --quick --json results/plastic_vibration.json   # seconds
    python verification/plastic_vibration.py --help                                # every option

``--quick`` and ``--json PATH`` (and ``--outdir``, ``--no-figures``, ``--quiet``)
come from :func:`pfem_skfem.harness.options.base_parser`.
"""
import sys

import numpy as np
from skfem import MeshTri

from pfem_skfem.drivers.dynamic import integrate
from pfem_skfem.materials import Elastic, Tresca
from pfem_skfem.discretisation.static import boundary_dofs, discretise
from pfem_skfem.discretisation import ThetaMethod, dynamic_operators
from pfem_skfem.problems.backends import cvxpy_solver
from pfem_skfem.problems.backends.cvxpy_step import D_FORM_CONE_REFUSED, D_FORMS
from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, material_options, opt, positive_float,
                                        positive_int, time_options)
from pfem_skfem.harness.report import Report, script_main

QUICK = dict(nx=20, ny=2, steps=30)


def check(args):
    """Options this script refuses (a usage error), or None: the cone form of the inertia
    cannot meet the energy checks at 1e-6 (:data:`D_FORM_CONE_REFUSED`)."""
    if args.d_form == "cone":
        return D_FORM_CONE_REFUSED
    return None


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    p.add_argument("--length", type=positive_float, default=10.0, help="beam length L (m)")
    p.add_argument("--height", type=positive_float, default=1.0, help="beam depth (m)")
    p.add_argument("--nx", type=positive_int, default=40, help="element columns (2 nx ny triangles)")
    p.add_argument("--ny", type=positive_int, default=4, help="element rows")
    material_options(p, rho=0.01, E=3e5, nu=0.3, su=opt(2.0, "Tresca strength Su [kPa]"))
    p.add_argument("--V", type=positive_float, default=1.0, help="initial tip velocity (m/s)")
    time_options(p, dt=0.02, steps=opt(60, "number of time steps"),
                 theta1=opt(0.5, why="1/2: no damping"), theta2=opt(0.5, why="1/2: no damping"))
    p.add_argument("--d-form", choices=D_FORMS, default="quad_form",
                   help="form of the r^T D r term ('cone' is refused: its accuracy is "
                        "sqrt(the solver's gap), short of the 1e-6 energy checks)")
    return p


def run(args):
    """Free vibration, elastic and elastoplastic: the energy balance of each."""
    mesh = MeshTri.init_tensor(np.linspace(0, args.length, args.nx + 1),
                               np.linspace(0, args.height, args.ny + 1))
    disc = discretise(mesh)
    clamp = lambda x: x[0] < 1e-9 * args.length                    # noqa: E731
    fixed = np.union1d(boundary_dofs(disc, clamp, 0), boundary_dofs(disc, clamp, 1))
    theta = ThetaMethod(args.dt, args.theta1, args.theta2)
    ops = dynamic_operators(disc, args.rho, theta, Elastic(args.E, args.nu))
    y_dofs = np.unique(disc.basis_u.get_dofs().all("u^2"))
    v0 = np.zeros(disc.n_u)
    v0[y_dofs] = args.V * (disc.basis_u.doflocs[0, y_dofs] / args.length) ** 2
    no_load = lambda t: np.zeros(disc.n_u)                         # noqa: E731

    report = Report("vibrating cantilever, elastic vs elastoplastic (thesis Ch 4)", args,
                    elements=mesh.nelements)
    runs = {}
    for name, criterion in (("elastic", None), ("elastoplastic", Tresca(args.su))):
        runs[name] = integrate(ops, no_load, args.steps, criterion=criterion, fixed=fixed,
                               initial=dict(v=v0), d_form=args.d_form,
                               progress=args.progress and name,
                               solver=cvxpy_solver(args.solver))
    K0 = runs["elastic"].energy[0]
    el, pl = runs["elastic"], runs["elastoplastic"]
    undamped = args.theta1 == 0.5 and args.theta2 == 0.5
    if undamped:
        report.add_interval("energy_drift_elastic", np.abs(el.energy - K0).max() / K0, 0.0,
                            1e-6, "trapezoidal rule conserves energy")
        balance = np.abs(pl.energy + pl.dissipation - K0).max() / K0
        report.add_interval("energy_balance_residual", balance, 0.0, 1e-6,
                            "K + W + D_p = K_0 (KKT (4.25) x du)")
    report.add_interval("max_energy_increase", np.diff(pl.energy).max() / K0, -np.inf, 1e-7,
                        "no energy gain")
    report.add_interval("min_step_dissipation", np.diff(pl.dissipation).min() / K0, -1e-9,
                        np.inf, "D_p >= 0 in every step (convex yield set)")
    report.add_interval("plastic_dissipation_fraction", pl.dissipation[-1] / K0, 0.05, 1.0,
                        "the material yields and dissipates")
    report.add_interval("final_energy_fraction", pl.energy[-1] / K0, 0.0, 1.0,
                        "energy lost, not gained")
    report.extra = {"t": el.times.tolist(), "energy_elastic": el.energy.tolist(),
                    "energy_elastoplastic": pl.energy.tolist(),
                    "dissipation": pl.dissipation.tolist(),
                    "iterations_mean": float(np.mean(pl.iterations))}
    report.data = dict(el=el, pl=pl)
    return report


def figures(args, el, pl):
    """Energies of both runs and the plastic dissipation against time."""
    K0 = el.energy[0]
    fig, ax = pyplot().subplots(figsize=(6, 3.5))
    ax.plot(el.times, el.energy / K0, "C0", label="elastic: K + W")
    ax.plot(pl.times, pl.energy / K0, "C3", label="elastoplastic: K + W")
    ax.plot(pl.times, pl.dissipation / K0, "C3--", label="plastic dissipation D")
    ax.plot(pl.times, (pl.energy + pl.dissipation) / K0, "k:", label="K + W + D")
    ax.set(xlabel="time (s)", ylabel="energy / initial kinetic energy",
           title="energy balance of the vibrating beam: K + W + D = K0")
    ax.legend(fontsize=8)
    save_figure(fig, figure_dir(args, "plastic_vibration") / "plastic_vibration.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
