"""Consolidation of a saturated soil: Terzaghi's column, the undrained and drained limits.

Beyond the thesis (issue 54): the consolidation step (C.1) of
:mod:`pfem_skfem.problems.consolidation`, Biot's principle after backward Euler as a cone
program, P2 displacements and continuous P1 pore pressures (Taylor-Hood).

Terzaghi's column (Terzaghi 1923; e.g. Verruijt, *Theory and Problems of Poroelasticity*,
ch. 2): a column of height H (plane strain, one element across, n over the height; rollers on
the sides, fixed base), drained at the top (p = 0), impermeable elsewhere, loaded at t = 0 by
q on its top. With the constrained modulus E_oed = lambda + 2 G, alpha = 1 and the storage
1/M (``--M-inv``), the undrained response is p0 = M q / (E_oed + M) (p0 = q for
incompressible constituents) and the excess pore pressure diffuses with
c_v = (k / gamma_w) / (1/M + 1/E_oed); with T_v = c_v t / H^2 and M_m = pi (2m + 1) / 2:

    U(T_v) = 1 - sum_m 2 / M_m^2 exp(-M_m^2 T_v),
    p(base, t) / p0 = sum_m 2 / M_m sin(M_m) exp(-M_m^2 T_v),

U the degree of consolidation (s - s0) / (s_inf - s0), s0 = q H / (E_oed + M) and
s_inf = q H / E_oed. Time steps dTv up to T_v = 0.1, 5 dTv to T_v = 1.

Checks:

* U(T_v) at T_v = 0.05 / 0.1 / 0.2 / 0.5 / 1 (0.2523 / 0.3568 / 0.5041 / 0.7640 / 0.9313 for
  the series) and p at the impermeable base against the series, each within 0.005;
* the undrained first step (dt = 0): p at the base = p0 (a closed form, to 1e-6), and the
  settlement of the drained top's elements (p = 0 on a face drains its elements at once, an
  O(h) artefact) at most that of their drained compression, s_inf h / H;
* undrained = incompressible elasticity: the first step of a strip load (half-width b) on a
  block equals the single-phase P2/P1 mixed solve of incompressible elasticity (nu_u = 1/2,
  the standard stiffness K and the div constraint, assembled by scikit-fem and solved by
  scipy, independent of the step) on the same mesh, to 1e-5 relative;
* t -> infinity: after T_v = 1 the steps double to T_v = ``--Tv-end``: the settlements equal
  the drained elastic solve K u = f (scipy), to 1e-6 relative, and p vanishes;
* a flexible strip load q of half-width b on a deep wide domain (``--L``), undrained: the
  centreline pore pressure is (sigma_x + sigma_z) / 2 = q alpha / pi (alpha the angle the
  strip subtends; 0.705 / 0.500 / 0.295 q at z = b/2, b, 2b), within 3 % (the finite
  domain); relative surface settlements (centre against x = 2b) undrained over drained
  (1 - nu_u) / (1 - nu') = 1 / (2 (1 - nu')) (Flamant: they scale with (1 - nu) / G),
  within 1 %;
* reported: the errors on meshes of n and 2n elements and at dTv and dTv / 2 (convergence in
  h and dt), and the pore pressures after one step of dt = r h^2 / (6 c_v) (the early-time
  oscillation limit of Vermeer & Verruijt 1981).

Usage::

    python verification/consolidation.py --quick --json results/consolidation.json
"""
import sys

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, material_options, opt, positive_float,
                                        positive_int, saturated_options)
from pfem_skfem.harness.report import Report, script_main

QUICK = dict(n=10, dTv=0.001, L=20.0, h_min=0.1, h_max=4.0)
REPORT_TV = (0.05, 0.1, 0.2, 0.5, 1.0)
#: depths / b of the strip load's centreline pressures
STRIP_Z = (0.5, 1.0, 2.0)
#: dt / (h^2 / 6 c_v) of the single steps that measure the early-time oscillation
OSCILLATION_RATIOS = (0.1, 0.3, 1.0, 2.0, 3.0, 10.0)


def terzaghi(Tv, terms=2000):
    """Terzaghi's series: the degree of consolidation U and p(base) / p0 at T_v."""
    M = np.pi * (2 * np.arange(terms) + 1) / 2
    decay = np.exp(-M ** 2 * Tv)
    return 1 - np.sum(2 / M ** 2 * decay), np.sum(2 / M * np.sin(M) * decay)


def column(n, H):
    """The column: n square elements of side H / n stacked (two triangles each), supports,
    the top's load facets and its drained face."""
    from skfem import MeshTri

    from pfem_skfem.discretisation.pressure import pressure_field
    from pfem_skfem.discretisation.static import (assemble_B, boundary_dofs, boundary_facets,
                                                  discretise)
    h = H / n
    mesh = MeshTri.init_tensor(np.array([0.0, h]), np.linspace(0.0, H, n + 1))
    disc = discretise(mesh)
    eps = 1e-9 * H
    fixed = np.union1d(boundary_dofs(disc, lambda x: x[1] < eps, 1),
                       boundary_dofs(disc, lambda x: (x[0] < eps) | (x[0] > h - eps), 0))
    top = boundary_facets(disc, lambda x: x[1] > H - eps)
    return dict(disc=disc, B=assemble_B(disc), pressure=pressure_field(disc), fixed=fixed,
                top=top, h=h, H=H, base=int(np.argmin(mesh.p[1] + mesh.p[0])),
                top_y=disc.basis_u.nodal_dofs[1][int(np.argmax(mesh.p[1] + mesh.p[0]))])


def schedule(dTv, Tv_end):
    """The T_v of each step after the undrained one: dTv to 0.1, 5 dTv to 1 (every report
    time a step's end), then doubling steps to Tv_end."""
    ends, start = [], 0.0
    for stop, step in zip(REPORT_TV, (dTv, dTv, 5 * dTv, 5 * dTv, 5 * dTv)):
        count = max(1, int(round((stop - start) / step)))
        ends += list(np.linspace(start, stop, count + 1)[1:])
        start = stop
    step = 1.0
    while ends[-1] < Tv_end:
        ends.append(min(ends[-1] + step, Tv_end))
        step *= 2
    return np.array(ends)


def consolidate(model, args, Tv_steps):
    """The undrained step, then backward Euler over the T_v of ``Tv_steps``: settlement and
    base pressure after each step, the profile p(y) at the report times, the last state."""
    from pfem_skfem.discretisation.static import assemble_C, traction_vector
    from pfem_skfem.problems.consolidation import (Hydraulic, PoreState,
                                                   consolidation_increment)
    disc, pressure = model["disc"], model["pressure"]
    elastic, soil = materials(args)
    C = assemble_C(disc, elastic)
    f = traction_vector(disc, model["top"], (0.0, -args.q))
    hydraulic = Hydraulic.drained_faces(pressure, model["top"])
    cv = consolidation_coefficient(args)
    state = PoreState.zero(disc, pressure)
    u = np.zeros(disc.n_u)
    T = [0.0]
    settlement, p_base, profiles = [], [], {}
    for Tv in np.concatenate([[0.0], Tv_steps]):
        dt = (Tv - T[-1]) * model["H"] ** 2 / cv
        state = consolidation_increment(model["B"], C, f, state, soil, pressure, dt,
                                        fixed=model["fixed"], hydraulic=hydraulic,
                                        solver=args.solver)
        u += state.du
        T.append(Tv)
        settlement.append(-u[model["top_y"]])
        p_base.append(state.p[model["base"]])
        if any(abs(Tv - r) < 1e-12 for r in REPORT_TV):
            profiles[float(Tv)] = state.p.copy()
    return dict(Tv=np.array(T[1:]), settlement=np.array(settlement), p_base=np.array(p_base),
                profiles=profiles, u=u, state=state)


def materials(args):
    """The skeleton (elastic: the cone program without a cone) and the water."""
    from pfem_skfem.materials import Elastic
    from pfem_skfem.problems.consolidation import SaturatedSoil
    M = 1 / args.M_inv if args.M_inv > 0 else np.inf
    return Elastic(args.E, args.nu), SaturatedSoil(None, k=args.k, gamma_w=args.gamma_w, M=M)


def undrained_moduli(args):
    """Skempton's B = M / (K + M) and the undrained Poisson's ratio nu_u, K_u = K + M
    (alpha = 1; B = 1 and nu_u = 1/2 for incompressible constituents, 1/M = 0)."""
    K, G = args.E / (3 * (1 - 2 * args.nu)), args.E / (2 * (1 + args.nu))
    B = 1 / (1 + K * args.M_inv)
    if args.M_inv == 0:
        return B, 0.5
    Ku = K + 1 / args.M_inv
    return B, (3 * Ku - 2 * G) / (2 * (3 * Ku + G))


def oedometric(args):
    """E_oed, p0 / q and c_v of the column (alpha = 1)."""
    nu, E = args.nu, args.E
    e_oed = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    p0 = 1 / (1 + e_oed * args.M_inv)                  # M / (E_oed + M)
    cv = args.k / args.gamma_w / (args.M_inv + 1 / e_oed)
    return e_oed, p0, cv


def consolidation_coefficient(args):
    return oedometric(args)[2]


def degree(result, args):
    """U = (s - s0) / (s_inf - s0) with the closed-form s0 and s_inf."""
    e_oed, p0, _ = oedometric(args)
    s_inf = args.q * args.H / e_oed
    s0 = s_inf * (1 - p0)                             # q H / (E_oed + M)
    return (result["settlement"] - s0) / (s_inf - s0)


def report_errors(result, args):
    """max |U - U_series| and max |p_base / p0 - series| over the report times."""
    p0 = oedometric(args)[1]
    U, e_U, e_p = degree(result, args), 0.0, 0.0
    for r in REPORT_TV:
        i = int(np.argmin(abs(result["Tv"] - r)))
        U_ex, p_ex = terzaghi(r)
        e_U = max(e_U, abs(U[i] - U_ex))
        e_p = max(e_p, abs(result["p_base"][i] / (p0 * args.q) - p_ex))
    return e_U, e_p


def undrained_strip(args, n=8):
    """The first (dt = 0) step of a strip load on a block against the P2/P1 mixed solve of
    undrained elasticity (incompressible at 1/M = 0): (max relative du error, max relative
    p error)."""
    from skfem import Basis, BilinearForm, ElementTriP1, MeshTri
    from skfem.helpers import div

    from pfem_skfem.discretisation.pressure import pressure_field
    from pfem_skfem.discretisation.static import (assemble_B, assemble_C, boundary_dofs,
                                                  boundary_facets, discretise, stiffness_matrix,
                                                  traction_vector)
    from pfem_skfem.problems.consolidation import PoreState, consolidation_increment
    L, b = 2.0 * args.H, 0.5 * args.H
    mesh = MeshTri.init_tensor(np.linspace(0, L, n + 1), np.linspace(-L, 0, n + 1))
    disc = discretise(mesh)
    pressure = pressure_field(disc)
    elastic, soil = materials(args)
    eps = 1e-9 * L
    fixed = np.union1d(boundary_dofs(disc, lambda x: x[1] < -L + eps, 1),
                       boundary_dofs(disc, lambda x: (x[0] < eps) | (x[0] > L - eps), 0))
    strip = boundary_facets(disc, lambda x: (x[1] > -eps) & (x[0] < b))
    f = traction_vector(disc, strip, (0.0, -args.q))
    res = consolidation_increment(assemble_B(disc), assemble_C(disc, elastic), f,
                                  PoreState.zero(disc, pressure), soil, pressure, 0.0,
                                  fixed=fixed, solver=args.solver)
    # the reference: [K -Q^T; Q M_p / M] [u; p] = [f; 0], Q = int N_p div N_u, M_p = int
    # N_p N_p (alpha = 1; the undrained storage div u + p / M = 0, incompressible at 1/M = 0)
    basis_u = Basis(mesh, disc.basis_u.elem, intorder=4)
    basis_p = basis_u.with_element(ElementTriP1())
    Q = BilinearForm(lambda u, q, w: div(u) * q).assemble(basis_u, basis_p)
    Mp = BilinearForm(lambda p, q, w: p * q).assemble(basis_p)
    free = np.setdiff1d(np.arange(disc.n_u), fixed)
    K = stiffness_matrix(disc, elastic)[free][:, free]
    Qf = Q[:, free]
    A = sp.bmat([[K, -Qf.T], [Qf, args.M_inv * Mp if args.M_inv else None]], format="csc")
    x = spla.spsolve(A, np.concatenate([f[free], np.zeros(Q.shape[0])]))
    u_ref, p_ref = np.zeros(disc.n_u), x[free.size:]
    u_ref[free] = x[:free.size]
    return (float(np.abs(res.du - u_ref).max() / np.abs(u_ref).max()),
            float(np.abs(res.p - p_ref).max() / np.abs(p_ref).max()))


def drained_settlement(model, args):
    """The drained elastic solve K u = f of the column (scipy, the standard P2 stiffness)."""
    from pfem_skfem.discretisation.static import stiffness_matrix, traction_vector
    disc = model["disc"]
    elastic, _ = materials(args)
    f = traction_vector(disc, model["top"], (0.0, -args.q))
    free = np.setdiff1d(np.arange(disc.n_u), model["fixed"])
    u = np.zeros(disc.n_u)
    u[free] = spla.spsolve(stiffness_matrix(disc, elastic)[free][:, free].tocsc(), f[free])
    return u


def oscillation(model, args):
    """After the undrained step, one step of dt = r h^2 / (6 c_v) for each r: the largest
    p / p0 (above 1: an overshoot) and the smallest (below 0: an undershoot)."""
    rows = []
    for r in OSCILLATION_RATIOS:
        dTv = r * model["h"] ** 2 / (6 * model["H"] ** 2)
        res = consolidate(model, args, np.array([dTv]))
        p = res["state"].p / (oedometric(args)[1] * args.q)
        rows.append([r, float(p.max()), float(p.min())])
    return rows
























def strip_load(args):
    """A flexible strip load q of half-width b on a deep wide half-domain (L x L, graded
    towards the strip's edge), undrained (dt = 0, every face impermeable): p / q on the
    centreline at depths ``STRIP_Z`` b, and the surface settlements of the undrained step and
    of the drained elastic solve (scipy) at the centre and at x = 2 b."""
    from pfem_skfem.discretisation.meshes import graded_rectangle
    from pfem_skfem.discretisation.pressure import pressure_field
    from pfem_skfem.discretisation.static import (assemble_B, assemble_C, boundary_dofs,
                                                  boundary_facets, discretise,
                                                  stiffness_matrix, traction_vector)
    from pfem_skfem.problems.consolidation import PoreState, consolidation_increment
    b, L = args.b, args.L
    mesh = graded_rectangle(L, L, (b, 0.0), h_min=args.h_min, h_max=args.h_max)
    disc = discretise(mesh)
    pressure = pressure_field(disc)
    elastic, soil = materials(args)
    eps = 1e-9 * L
    base = lambda x: x[1] < -L + eps                        # noqa: E731
    fixed = np.union1d(np.union1d(boundary_dofs(disc, base, 0), boundary_dofs(disc, base, 1)),
                       boundary_dofs(disc, lambda x: (x[0] < eps) | (x[0] > L - eps), 0))
    f = traction_vector(disc, boundary_facets(disc, lambda x: (x[1] > -eps) & (x[0] < b)),
                        (0.0, -args.q))
    res = consolidation_increment(assemble_B(disc), assemble_C(disc, elastic), f,
                                  PoreState.zero(disc, pressure), soil, pressure, 0.0,
                                  fixed=fixed, solver=args.solver)
    z = np.asarray(STRIP_Z) * b
    p = pressure.basis.probes(np.vstack([np.zeros_like(z), -z])) @ res.p / args.q
    free = np.setdiff1d(np.arange(disc.n_u), fixed)
    drained = np.zeros(disc.n_u)
    drained[free] = spla.spsolve(stiffness_matrix(disc, elastic)[free][:, free].tocsc(),
                                 f[free])
    surface_y = [disc.basis_u.nodal_dofs[1][int(np.argmin(np.hypot(mesh.p[0] - x, mesh.p[1])))]
                 for x in (0.0, 2 * b)]
    return dict(p=p, z=z, elements=mesh.nelements,
                relative_undrained=res.du[surface_y[0]] - res.du[surface_y[1]],
                relative_drained=drained[surface_y[0]] - drained[surface_y[1]])


def strip_checks(report, args):
    """The strip's undrained pore pressure on the centreline, B (1 + nu_u) (2/3) q alpha / pi
    (Skempton: p = B times the mean total stress, sigma_y = nu_u (sigma_x + sigma_z) in plane
    strain; q alpha / pi for incompressible constituents), within 3 %, and the ratio of
    relative settlements (1 - nu_u) / (1 - nu') (1 / (2 (1 - nu')) then), within 1 %."""
    run = strip_load(args)
    B, nu_u = undrained_moduli(args)
    # the domain's fixed base, L deep, holds a soil of nu_u below 1/2 more: at 2 b deep and
    # L = 20 b, p is 1.8 / 4.7 / 7.4 % below the half-space's at nu_u = 0.5 / 0.38 / 0.2
    # (4.7 -> 2.9 -> 2.1 % as L doubles)
    tol = 0.03 + 0.2 * (0.5 - nu_u)
    rows = []
    for zb, p in zip(STRIP_Z, run["p"]):
        # (sigma_x + sigma_z) / q = 2 alpha / pi on the centreline, alpha = 2 arctan(b / z)
        ref = B * (1 + nu_u) * 2 / 3 * 2 / np.pi * np.arctan(1 / zb)
        report.add(f"strip_p_z{zb:g}b", p, ref, "elastic strip (Flamant integrated over it): "
                   "p = B (1 + nu_u) (sigma_x + sigma_z) / 3, q alpha / pi at nu_u = 1/2, "
                   f"{100 * tol:.3g} %", tol)
        rows.append([zb, p, ref, p / ref - 1])
    ratio = run["relative_undrained"] / run["relative_drained"]
    expected = (1 - nu_u) / (1 - args.nu)
    report.add("strip_settlement_ratio", ratio, expected,
               "Flamant: relative settlements scale with (1 - nu) / G, 1 %", 0.01)
    rows.append(["s_u / s_d", ratio, expected, ratio / expected - 1])
    report.add_table("strip", ["z / b", "p / q", "q alpha / pi", "relative error"], rows,
                     formats={"relative error": ".1e"})
    report.extra["strip"] = {"elements": run["elements"], "p": run["p"], "ratio": ratio}


def check(args):
    if args.b >= args.L:
        return f"--b {args.b:g}: the strip must lie inside the domain's top, below --L {args.L:g}"
    if args.h_min > args.h_max:
        return f"--h-min {args.h_min:g} must not exceed --h-max {args.h_max:g}"
    return None


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    p.add_argument("--H", type=positive_float, default=1.0, help="column height H [m]")
    p.add_argument("--n", type=positive_int, default=20, help="elements over the height")
    p.add_argument("--b", type=positive_float, default=1.0,
                   help="half-width b of the strip load [m]")
    p.add_argument("--L", type=positive_float, default=40.0,
                   help="width and depth L of the strip's half-domain [m]")
    p.add_argument("--h-min", type=positive_float, default=0.05,
                   help="element size at the strip's edge [m]")
    p.add_argument("--h-max", type=positive_float, default=6.0,
                   help="largest element size of the strip's domain [m]")
    saturated_options(p, q=opt(100.0, "load q on the top [kPa]"), k=1e-8, gamma_w=9.81,
                      M_inv=opt(0.0, why="0: incompressible constituents"),
                      dTv=opt(0.0005, "time step in T_v up to T_v = 0.1 (5 dTv after)"),
                      Tv_end=opt(128.0, "the last T_v (doubling steps after T_v = 1): the "
                                        "drained limit"))
    material_options(p, E=opt(1e4, "Young's modulus E of the skeleton [kPa]"),
                     nu=opt(0.2, "Poisson's ratio nu' of the skeleton"))
    return p


def run(args):
    e_oed, p0, cv = oedometric(args)
    model = column(args.n, args.H)
    Tv = schedule(args.dTv, max(args.Tv_end, 1.0))
    result = consolidate(model, args, Tv)
    U = degree(result, args)
    report = Report("consolidation", args)
    rows = []
    for r in REPORT_TV:
        i = int(np.argmin(abs(result["Tv"] - r)))
        U_ex, p_ex = terzaghi(r)
        p_num = result["p_base"][i] / (p0 * args.q)
        report.add_interval(f"U_Tv{r:g}", U[i], U_ex - 0.005, U_ex + 0.005,
                            "Terzaghi's series, +-0.005", reference=U_ex)
        report.add_interval(f"p_base_Tv{r:g}", p_num, p_ex - 0.005, p_ex + 0.005,
                            "Terzaghi's series at the impermeable base, +-0.005",
                            reference=p_ex)
        rows.append([r, U[i], U_ex, U[i] - U_ex, p_num, p_ex, p_num - p_ex])
    report.add_table("terzaghi", ["T_v", "U", "U series", "error", "p_base/p0", "series",
                                  "error "], rows,
                     formats={"error": ".1e", "error ": ".1e"})
    # the undrained step
    s_inf = args.q * args.H / e_oed
    report.add("undrained_p_base", result["p_base"][0] / args.q, p0,
               "closed form M q / (E_oed + M) (q for incompressible constituents)", 1e-6)
    s0 = s_inf * (1 - p0)
    report.add_interval("undrained_artefact", (result["settlement"][0] - s0) / s_inf, 0.0,
                        model["h"] / args.H, "p = 0 on the top drains its elements at once: "
                        "at most their drained compression, h / H of s_inf")
    du_err, p_err = undrained_strip(args)
    report.add_interval("undrained_vs_incompressible_du", du_err, 0.0, 1e-5,
                        "P2/P1 mixed solve of undrained elasticity (scipy; incompressible "
                        "at 1/M = 0)")
    report.add_interval("undrained_vs_incompressible_p", p_err, 0.0, 1e-5,
                        "its pressure, the multiplier of div u = 0")
    # the drained limit
    u_d = drained_settlement(model, args)
    report.add_interval("drained_limit_du", float(np.abs(result["u"] - u_d).max()
                                                  / np.abs(u_d).max()), 0.0, 1e-6,
                        f"drained elastic solve K u = f (scipy), at T_v = {Tv[-1]:g}")
    report.add_interval("drained_limit_p", float(np.abs(result["state"].p).max() / args.q), 0.0,
                        1e-6, "no excess pore pressure left")
    strip_checks(report, args)
    study = convergence(args, result)
    report.add_table("convergence", ["n", "dTv", "max |U error|", "max |p_base error|",
                                     "artefact"], study,
                     formats={"max |U error|": ".2e", "max |p_base error|": ".2e",
                              "artefact": ".2e"})
    osc = oscillation(model, args)
    report.add_table("oscillation", ["dt / (h^2 / 6 c_v)", "max p/p0", "min p/p0"], osc,
                     formats={"max p/p0": ".5f", "min p/p0": ".5f"})
    report.extra.update({"Tv": result["Tv"], "U": U,
                         "p_base": result["p_base"] / (p0 * args.q), "convergence": study,
                         "oscillation": osc, "c_v": cv})
    report.data = dict(result=result, model=model, U=U, p0=p0)
    return report




def convergence(args, result):
    """The errors at (n, dTv), (2n, dTv) and (n, dTv / 2), to T_v = 1, and the first step's
    settlement beyond s0 (the drained face's artefact, an error of h) over s_inf."""
    e_oed, p0, _ = oedometric(args)
    s_inf = args.q * args.H / e_oed

    def artefact(res):
        return (res["settlement"][0] - s_inf * (1 - p0)) / s_inf
    rows = [[args.n, args.dTv, *report_errors(result, args), artefact(result)]]
    for n, dTv in ((2 * args.n, args.dTv), (args.n, args.dTv / 2)):
        res = consolidate(column(n, args.H), args, schedule(dTv, 1.0))
        rows.append([n, dTv, *report_errors(res, args), artefact(res)])
    return rows


def figures(args, result, model, U, p0):
    """U(T_v) and the pore-pressure isochrones against Terzaghi's series."""
    plt = pyplot()
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4))
    T = np.geomspace(1e-3, 1.0, 200)
    ax.semilogx(T, [terzaghi(t)[0] for t in T], "-", color="0.4", label="Terzaghi's series")
    keep = (result["Tv"] > 0) & (result["Tv"] <= 1)
    ax.semilogx(result["Tv"][keep], U[keep], ".", ms=3, label="conic step (C.1)")
    ax.set_xlabel("T_v = c_v t / H^2")
    ax.set_ylabel("degree of consolidation U")
    ax.set_title(f"Terzaghi's column, {args.n} elements")
    ax.legend()
    y = model["pressure"].basis.doflocs[1]
    order = np.argsort(y)
    z = np.linspace(0, 1, 101)
    for Tv, p in result["profiles"].items():
        M = np.pi * (2 * np.arange(2000) + 1) / 2
        series = [np.sum(2 / M * np.sin(M * (1 - zz)) * np.exp(-M ** 2 * Tv)) for zz in z]
        bx.plot(series, z, "-", color="0.6")
        bx.plot(p[order] / (p0 * args.q), y[order] / args.H, "o", ms=3, label=f"T_v = {Tv:g}")
    bx.set_xlabel("p / p0")
    bx.set_ylabel("y / H")
    bx.set_title("isochrones (lines: series)")
    bx.legend(fontsize=8)
    save_figure(fig, figure_dir(args, "consolidation") / "terzaghi.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
