"""A softening cylinder in uniaxial compression: the exact axisymmetric post-peak curve.

Beyond the thesis (issue 55, axisymmetric softening). A solid cylinder (radius a, height L,
Young's modulus E) between smooth platens is shortened by delta = eps L (the top moved down,
the base held axially, the side free). Its strength is the axisymmetric softening Tresca
(:class:`~pfem_skfem.materials.softening_axisymmetric.SofteningTrescaAxisymmetric`: the three
principal pairs, |s_i - s_j| <= 2 c(gamma^p)). The stress is uniform uniaxial, s_zz = -q,
s_rr = s_tt = s_rz = 0. Elastic until q = 2 c_p (eps_p = 2 c_p / E); then q = 2 c(gamma^p)
on the corner of the pairs (zz, rr) and (zz, tt), whose flow is axial with radial and hoop
equal to minus half of it: Delta eps^p = (e / 2, -e, e / 2) in (rr, zz, tt), so the measure
gamma^p of :func:`~pfem_skfem.materials.softening_axisymmetric.axisymmetric_shear_invariant`
(max(|de_rr - de_zz|, |de_tt|) + |de_tt| = 3e/2 + e/2) grows by 2e, and the axial strain is

    eps(q) = q / E + gamma^p(q / 2) / 2                              (post-peak, exact)
    linear law: q = 2 c_p - (eps - eps_p) 4 abs(H) / (1 - 4 abs(H) / E) until 2 c_r
    D / V = int c dgamma^p  (c Delta gamma^p is the plastic work sigma . Delta eps^p)

with gamma^p(c) the law's inverse (:meth:`~pfem_skfem.materials.LinearSoftening.strain_at`),
and no snap-back while E > 4 abs(H) (4 x the law's steepest rate for the exponential law).
A measure of another factor (the deviator's norm sqrt(2 de':de') gives sqrt(3) e: eps^p =
gamma^p / sqrt(3)) would move the branch; the checks see it.

The mesh: the rectangle a x L in (r, z) of 2 nr nz P2 triangles, axisymmetric operators
(the hoop row eps_tt = u_r / r, the weight 2 pi r). The post-peak runs tie the motion to the
homogeneous one, u_r = alpha r, u_z = beta z (beta = -eps prescribed, alpha free): at the
limit load of an increment's perfectly plastic problem the uniform stress is unique but the
plastic motion is not, and the tie gives the closed form's. The free mesh (u_z = 0 on the
base, u_r = 0 on the axis, u_z = -delta on the top, every other dof free) is run to past the
peak: its stresses are unique there. Static increments of (3.45) with the strength of the start
of each increment, updated after it (:func:`pfem_skfem.drivers.softening.softening_control`),
an increment re-solved at half its size while it drops the strength by more than --max-drop
(c_p - c_r).

Checks: the elastic slope q / eps = E and the peak 2 c_p, tied and free (1e-6), the free
mesh's stress uniaxial at its first plastic increment (1e-4 c_p: the solver's
tolerance at a limit state, 1.5e-5 measured); at the finest cap every
post-peak point (eps, q) on eps(q) within 1 % of eps at full softening (the exponential law's
at 4 x the finest cap, of eps at 95 % softening); the error falling with the cap (order >=
0.5); with fixed-point passes (cap 0.2) every point on eps(q) to 1e-5; the residual stress
2 c_r (1e-6); gamma^p at the end, uniform (1e-6), and its closed form (1 %); the dissipation
D / V = int c dgamma^p (1 %).

Usage::

    python verification/softening_cylinder.py --quick --json results/softening_cylinder.json
"""
import sys

import numpy as np
import scipy.sparse as sp

from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, in_range, material_options, opt,
                                        pfem_options, positive_float, softening_options)
from pfem_skfem.harness.report import Report, script_main

QUICK = dict(max_drop=[0.02, 0.01, 0.005])

#: d eps^p_axial / d gamma^p under uniaxial flow with the axisymmetric Tresca measure
FLOW = 0.5
#: q within this fraction of 2 c_r: the cylinder has reached the residual strength
AT_RESIDUAL = 1e-6
#: the exponential law's run at this multiple of the finest cap (its steepest rate bounds
#: every increment's drop, down to the tail: 3 / (gamma_95 cap) increments per unit gamma^p)
EXPONENTIAL_CAP = 4
#: the cap of the fixed-point run (its points are exact at any increment)
FIXED_POINT_CAP = 0.2


def cylinder(args, tied=True):
    """The cylinder's operators: B (T), C of the axisymmetric mesh, T tying every dof to
    (alpha, beta) (u_r = alpha r, u_z = beta z) where ``tied``; the supports, the
    prescribed dofs and their motion per unit axial strain; the volume, the stress points'
    weights and element sizes."""
    from skfem import MeshTri

    from pfem_skfem.discretisation.static import (assemble_B, assemble_C, axis_dofs,
                                                  boundary_dofs, discretise)
    from pfem_skfem.materials import Elastic

    a, L = args.radius, args.height
    disc = discretise(MeshTri.init_tensor(np.linspace(0.0, a, args.nr + 1),
                                          np.linspace(0.0, L, args.nz + 1)), "axisymmetric")
    elastic = Elastic(args.E, args.nu)
    B = assemble_B(disc)
    if tied:
        x = disc.basis_u.doflocs
        r_dofs = np.concatenate([disc.basis_u.nodal_dofs[0], disc.basis_u.facet_dofs[0]])
        z_dofs = np.concatenate([disc.basis_u.nodal_dofs[1], disc.basis_u.facet_dofs[1]])
        T = sp.csr_matrix((np.concatenate([x[0, r_dofs], x[1, z_dofs]]),
                           (np.concatenate([r_dofs, z_dofs]),
                            np.r_[np.zeros(len(r_dofs), int), np.ones(len(z_dofs), int)])),
                          shape=(disc.n_u, 2))
        B, fixed, loaded, per_strain = (B @ T).tocsr(), [], np.array([1]), np.array([-1.0])
    else:
        tol = 1e-9 * L
        fixed = np.union1d(boundary_dofs(disc, lambda x: x[1] < tol, 1), axis_dofs(disc))
        loaded = boundary_dofs(disc, lambda x: x[1] > L - tol, 1)
        per_strain = np.full(len(loaded), -L)
    material = softening_material(args)
    return dict(disc=disc, B=B, C=assemble_C(disc, elastic), elastic=elastic, fixed=fixed,
                loaded=loaded, per_strain=per_strain, volume=disc.area, weights=disc.weights,
                size=material.sizes(disc.weights, disc.points))


def softening_material(args, law=None):
    """The axisymmetric softening Tresca of ``law`` (default: the linear law of --H)."""
    from pfem_skfem.materials import Elastic, SofteningTrescaAxisymmetric
    return SofteningTrescaAxisymmetric(law or laws(args)[0], Elastic(args.E, args.nu))


def laws(args):
    """The linear law of --H and the exponential law of --gamma-95."""
    from pfem_skfem.materials.softening import ExponentialSoftening, LinearSoftening
    return (LinearSoftening(args.c_p, args.c_r, (args.c_p - args.c_r) / -args.H),
            ExponentialSoftening(args.c_p, args.c_r, args.gamma_95))


def end_strength(law):
    """Full softening: c_r for the linear law, 95 % of c_p - c_r spent for the exponential."""
    from pfem_skfem.materials.softening import ExponentialSoftening
    spent = 0.95 if isinstance(law, ExponentialSoftening) else 1.0
    return law.c_p - spent * (law.c_p - law.c_r)


def exact_strain(q, law, E, flow=FLOW):
    """eps(q) = q / E + flow gamma^p(q / 2) on the post-peak branch (flow = d eps^p / d
    gamma^p: 1/2 for the axisymmetric Tresca measure)."""
    return np.asarray(q, dtype=float) / E + flow * law.strain_at(np.asarray(q) / 2.0)


def exact_dissipation(law, gamma):
    """int c dgamma^p from 0 to ``gamma`` (per unit volume): the linear law's
    c_p g - (c_p - c_r) g^2 / (2 gamma_r) up to gamma_r, then c_r per unit of gamma^p;
    the exponential law's c_r g + (c_p - c_r) gamma_95 (1 - exp(-3 g / gamma_95)) / 3."""
    from pfem_skfem.materials.softening import LinearSoftening
    span = law.c_p - law.c_r
    if isinstance(law, LinearSoftening):
        g = min(gamma, law.gamma_r)
        return law.c_p * g - span * g ** 2 / (2 * law.gamma_r) + law.c_r * (gamma - g)
    return law.c_r * gamma + span * law.gamma_95 * (1 - np.exp(-3 * gamma / law.gamma_95)) / 3


def curve_error(run, law, E, flow=FLOW):
    """max over the post-peak points still above full softening of |eps - eps(q)|, divided
    by eps(q) at full softening."""
    eps, q = run["eps"], run["q"]
    end = 2 * end_strength(law)
    post = (np.arange(len(q)) >= np.argmax(q)) & (q > end * (1 + AT_RESIDUAL))
    return float(np.abs(eps[post] - exact_strain(q[post], law, E, flow)).max()
                 / exact_strain(end, law, E, flow))


def compress(args, law, max_drop, passes=1, tied=True, eps_end=None, increments=None):
    """The cylinder shortened to ``eps_end`` (default: --delta-end times eps at full
    softening) in ``increments`` base increments (default --increments): (eps, q) after each
    accepted increment, gamma^p, the stresses and the dissipation per unit volume at the end,
    the solves."""
    from pfem_skfem.drivers.softening import StepControl, softening_control

    m = cylinder(args, tied)
    material = softening_material(args, law)
    eps_end = args.delta_end * exact_strain(2 * end_strength(law), law, args.E) \
        if eps_end is None else eps_end
    run = softening_control(m["B"], m["C"], material, fixed=m["fixed"],
                            prescribed=(m["loaded"], eps_end * m["per_strain"]),
                            n_increments=increments or args.increments, size=m["size"],
                            weights=m["weights"],
                            control=StepControl(max_drop, passes), solver=args.solver)
    q = run.reactions[:, m["loaded"]] @ m["per_strain"] / m["volume"]     # -F L / (pi a^2 L)
    return dict(eps=run.factors * eps_end, q=q, gamma_p=run.gamma_p, sigma=run.sigma,
                dissipation=run.dissipation[-1] / m["volume"], solves=run.solves,
                max_drop=max_drop, passes=passes, law=law, elements=m["disc"].mesh.nelements)


def check(args):
    """Snap-back (E <= 4 abs(dc/dgamma^p) at its steepest) has no displacement-controlled
    answer: refused."""
    if args.c_r >= args.c_p:
        return f"--c-r {args.c_r:g} must be below --c-p {args.c_p:g}"
    if args.E <= 4 * -args.H:
        return f"--H {args.H:g}: E <= 4 abs(H), the cylinder snaps back; a smaller abs(H)"
    if args.E * args.gamma_95 <= 12 * (args.c_p - args.c_r):
        return f"--gamma-95 {args.gamma_95:g}: the exponential cylinder snaps back"
    return None


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    p.add_argument("--radius", type=positive_float, default=0.5, help="cylinder radius a [m]")
    p.add_argument("--height", type=positive_float, default=1.0, help="cylinder height L [m]")
    p.add_argument("--nr", type=in_range(1, integer=True), default=2,
                   help="cells across the radius (two triangles each)")
    p.add_argument("--nz", type=in_range(1, integer=True), default=3,
                   help="cells along the height (two triangles each)")
    material_options(p, E=5000.0, nu=0.3)
    softening_options(p, c_p=20.0, c_r=5.0,
                      H=opt(-500.0, "softening modulus H = dc/dgamma^p of the linear law [kPa]"),
                      gamma_95=opt(0.06, "gamma_95 of the exponential law"),
                      max_drop=opt([0.04, 0.02, 0.01, 0.005], nargs="+",
                                   help="caps on the strength drop of an increment, "
                                        "/ (c_p - c_r); the finest serves the checks"),
                      increments=10)
    pfem_options(p, passes=opt(20, "most fixed-point passes of an increment in the "
                                   "fixed-point run (strength at the trial end)"))
    p.add_argument("--delta-end", type=in_range(1, low_open=True), default=1.2,
                   help="the run's end, a multiple of its axial strain at full softening")
    return p


def run(args):
    linear, exponential = laws(args)
    caps = sorted(set(args.max_drop), reverse=True)
    finest = caps[-1]
    report = Report("softening_cylinder", args)
    study = [compress(args, linear, cap) for cap in caps]
    best = study[-1]
    expo = compress(args, exponential, EXPONENTIAL_CAP * finest)
    fixed_point = compress(args, linear, FIXED_POINT_CAP, passes=args.passes)
    eps_p = 2 * args.c_p / args.E
    free = compress(args, linear, 1.0, tied=False, eps_end=1.5 * eps_p, increments=2)
    E = args.E
    for name, r in (("tied", best), ("free", free)):
        report.add(f"{name}_elastic_slope", r["q"][1] / r["eps"][1], E,
                   "q / eps = E (uniaxial stress, smooth platens)", 1e-6)
        report.add(f"{name}_peak_q", r["q"].max(), 2 * args.c_p,
                   "the axisymmetric Tresca's uniaxial strength 2 c_p", 1e-6)
    report.add_interval("free_lateral_stress", np.abs(free["sigma"][:, [0, 2, 3]]).max()
                        / args.c_p, 0.0, 1e-4,
                        "max |s_rr|, |s_tt|, |s_rz| / c_p on the free mesh at 1.5 eps_p (its "
                        "first plastic increment): the stress is uniaxial")
    for r in study + [expo, fixed_point]:
        r["error"] = curve_error(r, r["law"], E)
    report.add_interval("linear_curve_error", best["error"], 0.0, 0.01,
                        f"max |eps - eps(q)| / eps_r at the cap {finest:g}, eps(q) = q / E "
                        f"+ gamma^p(q / 2) / 2")
    report.add_interval("exponential_curve_error", expo["error"], 0.0, 0.01,
                        f"max |eps - eps(q)| / eps_95 at the cap {expo['max_drop']:g}")
    order = (np.polyfit(np.log(caps), np.log([r["error"] for r in study]), 1)[0]
             if len(caps) > 1 else np.nan)
    report.add_interval("cap_order", order, 0.5, np.inf,
                        "the explicit update's lag: the error falls with the cap")
    report.add_interval("fixed_point_curve_error", fixed_point["error"], 0.0, 1e-5,
                        f"fixed-point passes at the cap {FIXED_POINT_CAP:g}: every point on "
                        f"eps(q) (the linear law's branch is straight)")
    report.add("residual_q", best["q"][-1], 2 * args.c_r, "full softening: q = 2 c_r", 1e-6)
    eps_end = best["eps"][-1]
    gamma_end = linear.gamma_r + (eps_end - exact_strain(2 * args.c_r, linear, E)) / FLOW
    report.add("gamma_p_end", float(best["gamma_p"].mean()), gamma_end,
               "gamma_r + 2 (eps - eps_r) after full softening", 0.01)
    report.add_interval("gamma_p_spread", np.ptp(best["gamma_p"]) / gamma_end, 0.0, 1e-6,
                        "gamma^p uniform: (max - min) / gamma^p")
    report.add("dissipation", best["dissipation"], exact_dissipation(linear, gamma_end),
               "D / V = int c dgamma^p (the work sum w sigma . Delta eps^p)", 0.01)
    report.add_table("caps", ["law", "max drop", "passes", "curve error / eps_r", "solves"],
                     [[r["law"].__class__.__name__, r["max_drop"], r["passes"], r["error"],
                       r["solves"]] for r in study + [expo, fixed_point]],
                     formats={"curve error / eps_r": ".2e"})
    report.extra = {"caps": caps, "cap_errors": [r["error"] for r in study],
                    "curves": {k: {"eps": r["eps"], "q": r["q"]} for k, r in
                               (("linear", best), ("exponential", expo), ("free", free))}}
    report.data = dict(study=study, expo=expo, free=free)
    return report


def figures(args, study, expo, free):
    """q against eps with the closed forms (linear and exponential); the error against the
    cap."""
    fig, ax = pyplot().subplots(1, 2, figsize=(11, 4))
    for k, r in enumerate([study[-1], expo]):
        law = r["law"]
        q = np.linspace(2 * end_strength(law), 2 * law.c_p, 200)
        ax[0].plot(np.r_[0, 2 * law.c_p / args.E, exact_strain(q, law, args.E)[::-1]],
                   np.r_[0, 2 * law.c_p, q[::-1]], "-", color=f"C{k}", lw=3, alpha=0.4)
        ax[0].plot(r["eps"], r["q"], ".", color=f"C{k}", ms=3,
                   label=f"{law.__class__.__name__}, cap {r['max_drop']:g}")
    ax[0].plot(free["eps"], free["q"], "x", color="C2", label="free mesh (to past the peak)")
    ax[0].set(xlabel="axial strain eps = delta / L", ylabel="axial stress q [kPa]",
              title="softening cylinder, uniaxial (axisymmetric Tresca)")
    ax[0].legend(fontsize=8)
    ax[1].loglog([r["max_drop"] for r in study], [r["error"] for r in study], "o-")
    ax[1].set(xlabel="cap on the strength drop / (c_p - c_r)",
              ylabel="max |eps - eps(q)| / eps_r", title="increment study (linear law)")
    save_figure(fig, figure_dir(args, "softening_cylinder") / "softening_cylinder.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
