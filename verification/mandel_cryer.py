"""The Mandel-Cryer effect: Mandel's slab (plane strain) and Cryer's sphere (axisymmetry).

Beyond the thesis (issue 54): the consolidation step (C.1) of
:mod:`pfem_skfem.problems.consolidation` (P2 displacements, continuous P1 pore pressures)
where the pore pressure at the centre first rises above its undrained value, the drained
surface consolidating first and taking load from the centre. Incompressible constituents
(1/M = 0, alpha = 1: Skempton's B = 1, nu_u = 1/2), c = k E_oed / gamma_w.

Checks:

* Mandel's slab (Mandel 1953; the series of Cheng & Detournay 1988 as the GEOS validation
  example writes it): a quarter of a slab 2a wide between rigid frictionless impermeable
  plates pressed by the force q a (``--q`` the mean stress), drained at its sides x = +-a.
  The plate is a rigid constraint (its vertical dofs tied to one, the force on it), not a
  prescribed displacement, so that the Mandel-Cryer overshoot can appear: p(0, t) / p0 at
  c t / a^2 = 0.01 / 0.05 / 0.1 / 0.2 / 0.5 (1.0438 / 1.0989 / 1.0954 / 0.9681 / 0.5928 at
  nu' = 0.2, incompressible constituents) and its peak (1.1069 at 0.072) within 0.005 of the
  series; the undrained start p0 = B (1 + nu_u) q / 3 (q / 2 for incompressible
  constituents) within h / a (the drained side's O(h) artefact);
* Cryer's sphere (Cryer 1963; the series in Verruijt's form, research file 2.3) in
  axisymmetry: a hemisphere of radius a (the quarter of a straight-sided disc mesh, x = r)
  under the surface pressure q, drained at its surface: p(0, t) / q at c t / a^2 = 0.01 /
  0.05 / 0.1 / 0.2 (1.1758 / 1.3637 / 1.1941 / 0.6817 at nu' = 0.2) and its peak (1.3643 at
  0.052) within 0.01 (a coarser mesh than the slab's, with a polygonal surface); its steps
  are uniform (``--dT-cryer``), kept above the early-time oscillation limit (about
  2 h^2 / (6 c): below it the first pressures overshoot).

Usage::

    python verification/mandel_cryer.py --quick --json results/mandel_cryer.json
"""
import sys

import numpy as np
import scipy.sparse as sp

from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, material_options, opt, positive_float,
                                        positive_int, saturated_options)
from pfem_skfem.harness.report import Report, script_main

QUICK = dict(n=10, dT=0.001, nrefs=3, dT_cryer=0.0025)
#: Mandel's report times, T = c t / a^2
MANDEL_T = (0.01, 0.05, 0.1, 0.2, 0.5)
#: Cryer's report times, T = c t / a^2
CRYER_T = (0.01, 0.05, 0.1, 0.2)


def materials(args):
    """The elastic skeleton (no cone) and the water, incompressible constituents."""
    from pfem_skfem.materials import Elastic
    from pfem_skfem.problems.consolidation import SaturatedSoil
    return Elastic(args.E, args.nu), SaturatedSoil(None, k=args.k, gamma_w=args.gamma_w)


def mandel_constants(args, M_inv=0.0):
    """Mandel's slab (alpha = 1): Skempton's B, the undrained nu_u, p0 / sigma and c
    (Cheng & Detournay 1988, as the GEOS validation example writes them)."""
    nu, E = args.nu, args.E
    G, K = E / (2 * (1 + nu)), E / (3 * (1 - 2 * nu))
    B = 1 / (1 + K * M_inv)                                # M / (K + M)
    inv_Ku = M_inv / (1 + K * M_inv)                       # 1 / (K + M)
    nu_u = (3 - 2 * G * inv_Ku) / (2 * (3 + G * inv_Ku))
    kappa = args.k / args.gamma_w
    c = 2 * kappa * B ** 2 * G * (1 - nu) * (1 + nu_u) ** 2 / (9 * (1 - nu_u) * (nu_u - nu))
    return B, nu_u, B * (1 + nu_u) / 3, c


def mandel_roots(nu, nu_u, terms=200):
    """The roots of tan(x) = (1 - nu) / (nu_u - nu) x, one in each (i pi, i pi + pi/2)."""
    from scipy.optimize import brentq
    slope = (1 - nu) / (nu_u - nu)
    roots = []
    for i in range(terms):
        lo, hi = i * np.pi + 1e-12, i * np.pi + np.pi / 2 - 1e-12
        if (np.tan(lo) - slope * lo) * (np.tan(hi) - slope * hi) < 0:
            roots.append(brentq(lambda x: np.tan(x) - slope * x, lo, hi))
    return np.array(roots)


def mandel_centre(T, roots):
    """p(0, t) / p0 of Mandel's series at T = c t / a^2."""
    a = roots
    weight = np.sin(a) / (a - np.sin(a) * np.cos(a)) * (1 - np.cos(a))
    return 2 * np.sum(weight * np.exp(-a ** 2 * T))


def slab(n, a):
    """A quarter of Mandel's slab: n elements across the half-width a, two up; the top's
    vertical dofs tied to one (the rigid plate), the rollers on the symmetry lines (in the
    tied numbering), the drained side x = a and the centre vertex."""
    from skfem import MeshTri

    from pfem_skfem.discretisation.pressure import pressure_field
    from pfem_skfem.discretisation.static import (assemble_B, boundary_dofs, boundary_facets,
                                                  discretise)
    h = a / n
    mesh = MeshTri.init_tensor(np.linspace(0.0, a, n + 1), np.linspace(0.0, 2 * h, 3))
    disc = discretise(mesh)
    eps = 1e-9 * a
    plate = boundary_dofs(disc, lambda x: x[1] > 2 * h - eps, 1)
    T, column = rigid_tie(disc.n_u, plate)
    fixed = column[np.union1d(boundary_dofs(disc, lambda x: x[1] < eps, 1),
                              boundary_dofs(disc, lambda x: x[0] < eps, 0))]
    return dict(disc=disc, B=(assemble_B(disc) @ T).tocsr(), T=T, plate=column[plate[0]],
                fixed=fixed, pressure=pressure_field(disc), h=h, a=a,
                side=boundary_facets(disc, lambda x: x[0] > a - eps),
                centre=int(np.argmin(np.hypot(mesh.p[0], mesh.p[1] - 2 * h))))


def rigid_tie(n_u, dofs):
    """u = T u_r with every dof of ``dofs`` moving as the first (a rigid frictionless plate):
    T (n_u, n_r), and each dof's column (its tied dof's)."""
    target = np.arange(n_u)
    target[dofs] = dofs[0]
    kept = np.setdiff1d(np.arange(n_u), dofs[1:])
    column = np.full(n_u, -1)
    column[kept] = np.arange(kept.size)
    T = sp.csr_matrix((np.ones(n_u), (np.arange(n_u), column[target])), shape=(n_u, kept.size))
    return T, column[target]


def mandel(args, n, dT):
    """The slab under a rigid plate pressed by the force q a (mean stress q): the undrained
    step, then steps dT in T = c t / a^2 to 0.1 and 5 dT to 0.5; p at the centre / p0."""
    from pfem_skfem.discretisation.static import assemble_C
    from pfem_skfem.problems.consolidation import (Hydraulic, PoreState,
                                                   consolidation_increment)
    model = slab(n, 1.0)
    disc, pressure = model["disc"], model["pressure"]
    elastic, soil = materials(args)
    C = assemble_C(disc, elastic)
    f = np.zeros(model["B"].shape[1])
    f[model["plate"]] = -args.q * model["a"]                # the plate's force
    hydraulic = Hydraulic.drained_faces(pressure, model["side"])
    p0 = mandel_constants(args)[2] * args.q
    c = mandel_constants(args)[3]
    times = np.concatenate([[0.0], np.linspace(0, 0.1, int(round(0.1 / dT)) + 1)[1:],
                            np.linspace(0.1, 0.5, int(round(0.4 / (5 * dT))) + 1)[1:]])
    state, t, centre = PoreState.zero(disc, pressure), 0.0, []
    for T in times:
        state = consolidation_increment(model["B"], C, f, state, soil, pressure,
                                        (T - t) * model["a"] ** 2 / c, fixed=model["fixed"],
                                        hydraulic=hydraulic, solver=args.solver)
        t = T
        centre.append(state.p[model["centre"]] / p0)
    return dict(T=times, p_centre=np.array(centre), h=model["h"])


def cryer_roots(eta, terms=300):
    """The roots of (1 - eta x^2 / 2) tan(x) = x (as sin and cos, no poles), the first
    ``terms`` pi's worth."""
    from scipy.optimize import brentq

    def g(x):
        return (1 - eta * x ** 2 / 2) * np.sin(x) - x * np.cos(x)
    xs = np.linspace(1e-6, terms * np.pi, terms * 200)
    v = g(xs)
    return np.array([brentq(g, xs[i], xs[i + 1]) for i in np.flatnonzero(v[:-1] * v[1:] < 0)])


def cryer_centre(T, nu, roots):
    """p(0, t) / p0 of Cryer's sphere at T = c t / a^2, incompressible constituents
    (Verruijt's form, research file 2.3; eta = (1 - nu) / (1 - 2 nu))."""
    eta, x = (1 - nu) / (1 - 2 * nu), roots
    return np.sum(eta * (np.sin(x) - x) / ((eta - 1) * np.sin(x) + eta * x * np.cos(x) / 2)
                  * np.exp(-x ** 2 * T))


def sphere(nrefs):
    """A quarter of the unit disc (x = r >= 0, y = z >= 0; scikit-fem's disc refined
    ``nrefs`` times, straight-sided) in axisymmetry: a hemisphere on its plane of symmetry."""
    from skfem import MeshTri

    from pfem_skfem.discretisation.pressure import pressure_field
    from pfem_skfem.discretisation.static import (assemble_B, axis_dofs, boundary_dofs,
                                                  boundary_facets, discretise)
    disc_mesh = MeshTri.init_circle(nrefs)
    centroid = disc_mesh.p[:, disc_mesh.t].mean(axis=1)
    mesh = MeshTri(disc_mesh.p, disc_mesh.t[:, (centroid[0] > 0) & (centroid[1] > 0)])
    mesh = mesh.remove_unused_nodes()
    disc = discretise(mesh, "axisymmetric")
    eps = 1e-9
    fixed = np.union1d(boundary_dofs(disc, lambda x: x[1] < eps, 1), axis_dofs(disc))
    surface = boundary_facets(disc, lambda x: (x[0] > eps) & (x[1] > eps))
    return dict(disc=disc, B=assemble_B(disc), fixed=fixed, surface=surface,
                pressure=pressure_field(disc), centre=int(np.argmin(np.hypot(*mesh.p))))


def cryer(args, nrefs, dT):
    """The sphere under the surface pressure q (drained surface): the undrained step, then
    steps dT in T = c t / a^2 to 0.3; p at the centre / q."""
    from pfem_skfem.discretisation.static import assemble_C, traction_vector
    from pfem_skfem.problems.consolidation import (Hydraulic, PoreState,
                                                   consolidation_increment)
    model = sphere(nrefs)
    disc, pressure = model["disc"], model["pressure"]
    elastic, soil = materials(args)
    C = assemble_C(disc, elastic)
    f = traction_vector(disc, model["surface"], lambda x: -args.q * x / np.hypot(x[0], x[1]))
    hydraulic = Hydraulic.drained_faces(pressure, model["surface"])
    c = soil.consolidation_coefficient(elastic)
    times = np.concatenate([[0.0], np.linspace(0, 0.3, int(round(0.3 / dT)) + 1)[1:]])
    state, t, centre = PoreState.zero(disc, pressure), 0.0, []
    for T in times:
        state = consolidation_increment(model["B"], C, f, state, soil, pressure, (T - t) / c,
                                        fixed=model["fixed"], hydraulic=hydraulic,
                                        solver=args.solver)
        t = T
        centre.append(state.p[model["centre"]] / args.q)
    return dict(T=times, p_centre=np.array(centre), elements=disc.mesh.nelements)


def cryer_checks(report, args):
    """Cryer's sphere against the series: p(0, t) / p0 and its peak, within 0.01."""
    roots = cryer_roots((1 - args.nu) / (1 - 2 * args.nu))
    run = cryer(args, args.nrefs, args.dT_cryer)
    rows = []
    for T in CRYER_T:
        i = int(np.argmin(abs(run["T"] - T)))
        ref = cryer_centre(T, args.nu, roots)
        report.add_interval(f"cryer_p_centre_T{T:g}", run["p_centre"][i], ref - 0.01,
                            ref + 0.01, "Cryer's series (Verruijt), +-0.01", reference=ref)
        rows.append([T, run["p_centre"][i], ref, run["p_centre"][i] - ref])
    grid = np.linspace(1e-3, 0.3, 2991)
    series = np.array([cryer_centre(T, args.nu, roots) for T in grid])
    i, j = int(np.argmax(series)), int(np.argmax(run["p_centre"]))
    report.add_interval("cryer_peak", run["p_centre"][j], series[i] - 0.01, series[i] + 0.01,
                        "the Mandel-Cryer overshoot in axisymmetry: the series' peak +-0.01",
                        reference=series[i])
    rows.append(["peak", run["p_centre"][j], series[i], run["p_centre"][j] - series[i]])
    report.add_table("cryer", ["c t / a^2", "p(0)/q", "series", "error"], rows,
                     formats={"error": ".1e"})
    report.extra["cryer"] = {"T": run["T"], "p_centre": run["p_centre"],
                             "elements": run["elements"], "peak_T": float(run["T"][j]),
                             "series_peak_T": float(grid[i])}
    report.data["sphere"] = dict(run, series=series, grid=grid)


def mandel_checks(report, args):
    """Mandel's slab against the series: p(0, t) / p0, its peak, the undrained start."""
    roots = mandel_roots(args.nu, mandel_constants(args)[1])
    run = mandel(args, args.n, args.dT)
    rows = []
    for T in MANDEL_T:
        i = int(np.argmin(abs(run["T"] - T)))
        ref = mandel_centre(T, roots)
        report.add_interval(f"mandel_p_centre_T{T:g}", run["p_centre"][i], ref - 0.005,
                            ref + 0.005, "Mandel's series (Cheng & Detournay 1988), +-0.005",
                            reference=ref)
        rows.append([T, run["p_centre"][i], ref, run["p_centre"][i] - ref])
    grid = np.linspace(1e-3, 0.5, 4991)
    series = np.array([mandel_centre(T, roots) for T in grid])
    i, j = int(np.argmax(series)), int(np.argmax(run["p_centre"]))
    report.add_interval("mandel_peak", run["p_centre"][j], series[i] - 0.005,
                        series[i] + 0.005, "the Mandel-Cryer overshoot: the series' peak "
                        "+-0.005", reference=series[i])
    rows.append(["peak", run["p_centre"][j], series[i], run["p_centre"][j] - series[i]])
    report.add_interval("mandel_undrained", abs(run["p_centre"][0] - 1), 0.0, run["h"],
                        "undrained p0 = B (1 + nu_u) q / 3; O(h) from the drained side: "
                        "at most h / a")
    report.add_table("mandel", ["c t / a^2", "p(0)/p0", "series", "error"], rows,
                     formats={"error": ".1e"})
    report.extra["mandel"] = {"T": run["T"], "p_centre": run["p_centre"],
                              "peak_T": float(run["T"][j]), "series_peak_T": float(grid[i])}
    report.data["slab"] = dict(run, series=series, grid=grid)



def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK)
    p.add_argument("--n", type=positive_int, default=20,
                   help="elements across the slab's half-width a")
    p.add_argument("--dT", type=positive_float, default=0.0005,
                   help="the slab's time step in c t / a^2 to 0.1 (5 dT after, to 0.5)")
    p.add_argument("--nrefs", type=positive_int, default=4,
                   help="refinements of the disc whose quarter is Cryer's (hemi)sphere")
    p.add_argument("--dT-cryer", type=positive_float, default=0.001,
                   help="the sphere's time step in c t / a^2 (to 0.3)")
    saturated_options(p, q=opt(100.0, "the plate's mean stress, the sphere's surface pressure "
                                      "q [kPa]"), k=1e-8, gamma_w=9.81)
    material_options(p, E=opt(1e4, "Young's modulus E of the skeleton [kPa]"),
                     nu=opt(0.2, "Poisson's ratio nu' of the skeleton"))
    return p


def run(args):
    report = Report("mandel_cryer", args)
    mandel_checks(report, args)
    cryer_checks(report, args)
    report.data = dict(slab=report.data["slab"], sphere=report.data["sphere"])
    return report


def figures(args, slab, sphere):
    """p(0, t) / p0 of the slab and of the sphere against their series."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, run, name, what in ((axes[0], slab, "Mandel's slab (plane strain)",
                                 f"{args.n} elements across a"),
                                (axes[1], sphere, "Cryer's sphere (axisymmetry)",
                                 f"{sphere['elements']} elements")):
        ax.plot(run["grid"], run["series"], "-", color="0.4", label="series")
        ax.plot(run["T"][1:], run["p_centre"][1:], ".", ms=3, label="conic step (C.1)")
        ax.axhline(1.0, color="0.7", ls=":")
        ax.set_xlabel("c t / a^2")
        ax.set_ylabel("p(0, t) / p0")
        ax.set_title(f"{name}, {what}", fontsize=10)
        ax.legend()
    save_figure(fig, figure_dir(args, "mandel_cryer") / "mandel_cryer.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
