"""A softening layer in simple shear: the exact post-peak curve, with and without regularisation.

Beyond the thesis (issue 55; the closed form of ``shared/research/saturated-softening-3d.md``
3.4, W1). A layer of height L (shear modulus G) rests on a fixed base and is sheared by its
top (displacement delta, no vertical motion: u_y = 0 everywhere). Its Tresca strength softens
with the plastic shear strain gamma^p by the linear law c = max(c_r, c_p + H gamma^p),
H = -(c_p - c_r) / gamma_r < 0 (:mod:`pfem_skfem.materials.softening`). One row of height h
(mid-height) starts a fraction epsilon of the way down the law (gamma^p_0 = epsilon gamma_r):
its peak is c_w = c_p - epsilon (c_p - c_r), and only it yields. The shear stress tau is the
same at every height, so the elastic rows carry tau L / G of the top's displacement and the
band its plastic slip h (gamma^p - gamma^p_0), tau = c(gamma^p):

    delta(tau) = tau L / G + h (c_w - tau) / abs(H)                 (post-peak, exact)
    delta_r = c_r L / G + h (c_w - c_r) / abs(H)                     (full softening)
    D = h (c_w^2 - c_r^2) / (2 abs(H))                               (dissipated, per unit width)

with no snap-back while h / abs(H) > L / G. The band is one row: without regularisation its
slip, delta_r - c_r L / G, halves when h halves. With the fracture-energy regularisation of
length ell (gamma_r scaled by ell / h: H(h) = H h / ell) h / abs(H(h)) = ell / abs(H), and delta_r
and D do not depend on h. The exponential law c = c_r + (c_p - c_r) exp(-3 gamma^p /
gamma_95) has the same form, h (gamma^p(tau) - gamma^p_0) with gamma^p(tau) its inverse.
The nonlocal average of gamma^p over a length (--ell-nonlocal) has no closed form here: its
band is as wide as the average, and delta_r must converge as h shrinks.

The mesh: one column of P2 triangles (width h, rows of height h: element size sqrt(2 A) = h),
every x-dof of a height tied to one (u = u(y)) and each mid-row dof the mean of its row's ends
(u linear in each row: the uniform band of the closed form; the free P2 row, refused as
--row-kinematics p2, lets tau vary inside the row and the plastic strain gather to one side
of it, which no closed form here describes). Static increments of (3.45) with the
strength of the start of each increment, updated after it
(:func:`pfem_skfem.drivers.softening.softening_control`), an increment re-solved at half its
size while it drops a strength by more than --max-drop (c_p - c_r).

Checks: the elastic slope G / L and the peak c_w (to 1e-6); at the finest cap the computed
points (delta, tau) from the exact curve, within 2 % of delta_r, on every mesh, regularised
or not, and for the exponential law (within 2 % of the displacement at 95 % softening);
delta_r and D within 2 % (these three: or 1.5 x the finest cap where larger, the explicit
update's one-increment lag, :data:`LAG_PER_CAP`); the points past the elastic limit
c_w L / G are the softening branch; the local slip ratio h_min / h_max (2 %); the regularised delta_r
independent of h within 5 %; the nonlocal delta_r within 5 % on the two finest meshes; the
error shrinking with the cap; with fixed-point passes (each increment solved again with the
strength at its trial end until gamma^p stops changing) every point on the exact curve to
1e-5 of delta_r at the coarsest cap.

The viscous layer (--eta > 0; Zhang, Sheng, Sloan & Bleyer, IJNME 112, 2017: the softening
Tresca clay with a Bingham viscosity eta). Every point intact, the top moved at a velocity V by
dynamic steps of dt (theta = 1, initial velocity V y / L: the uniform shear is the exact
motion, no inertia force arises). The step's Bingham term - dt w tau_v^2 / (2 eta) beside the
compliance of the total stress gives, where the layer flows, tau = c(gamma^p) + eta
gamma_dot^p with gamma_dot^p = Delta gamma^p / dt, Delta gamma^p the increment of the measure
gamma^p accumulates (in simple shear the engineering plastic shear strain): so tau_v =
eta x the plastic shear rate, no factor 2. With the elastic shear tau' = G (V / L - gamma_dot^p):

    steady, after full softening:  tau = c_r + eta V / L;  without softening: c_p + eta V / L
    per step (the scheme, exact):   Delta gamma^p = max(0, tau_n + G V dt / L - c(gamma^p_n))
                                                    / (G + eta / dt)
    continuous (linear law):        gamma_dot^p = a (1 - exp(-s / T)), a = G (V / L) / (G - abs(H)),
                                    T = eta / (G - abs(H)), s the time since yield; after
                                    gamma_r, gamma_dot^p relaxes to V / L at the rate G / eta

Checks: every step on the recurrence (1e-5 c_p), the layer uniform (1e-6 c_p), the two steady
stresses (1e-6), the continuous closed form within 2 % of c_p - c_r at the finest dt (the
largest error is at the step of first yield) and the mean error over t falling as dt (order
in [0.8, 1.2]). The steady stresses need a --t-end past the relaxation: a shorter one is
refused, naming the time it takes (:func:`steady_time`, to 1e-7, plus two steps).

Usage::

    python verification/softening_layer.py --quick --json results/softening_layer.json
"""
import sys

import numpy as np
import scipy.sparse as sp
from skfem import MeshTri

from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, in_range, material_options, opt,
                                        pfem_options, positive_float, softening_options,
                                        time_options)
from pfem_skfem.harness.report import Report, script_main

QUICK = dict(rows=[10, 20, 40], max_drop=[0.04, 0.01])
#: the viscous runs must end this close to their steady stress (relative), a tenth of the
#: 1e-6 of the steady-stress checks: --t-end is refused below the time it takes
#: (:func:`steady_time`, plus two steps: the scheme lags the strength one step)
STEADY = 1e-7
#: the closed-form checks' tolerance (the curve, delta_r, D) is 2 %, or this many times the
#: finest cap where that is larger: the explicit update lags one increment, whose strength
#: drop the cap bounds, and delta_r is off by where the last increment lands; measured at
#: the finest cap 0.01 / 0.04 (10, 20, 40 rows): curve 0.83-0.94 % / 3.2-3.75 %, delta_r
#: 0.5-1.25 % / 3.5-5.0 %, D 0.8-1.1 % / 3.3-4.5 %, at most 1.25 x the cap
LAG_PER_CAP = 1.5

#: tau within this fraction of c_r: the band has reached the residual strength
AT_RESIDUAL = 1e-6


def layer_model(rows, L, G, nu, kinematics="linear"):
    """The layer's operators: B T, C of one column of ``rows`` rows of P2 triangles, T tying
    the x-dofs of each height into one (u = u(y); the y-dofs have no column: u_y = 0), each
    mid-row dof the mean of its row's ends where ``kinematics`` is 'linear' (u linear in each
    row), free where it is 'p2'; and the stress points' heights, weights and element sizes.
    Column 0 is the base, the last column the top."""
    from pfem_skfem.discretisation.static import assemble_B, assemble_C, discretise
    from pfem_skfem.drivers.softening import point_sizes
    from pfem_skfem.materials import Elastic

    h = L / rows
    disc = discretise(MeshTri.init_tensor(np.array([0.0, h]), np.linspace(0.0, L, rows + 1)))
    elastic = Elastic(2 * G * (1 + nu), nu)
    x_dofs = np.concatenate([disc.basis_u.nodal_dofs[0], disc.basis_u.facet_dofs[0]])
    level = disc.basis_u.doflocs[1, x_dofs] / h         # k at row ends, k + 1/2 mid-row
    if kinematics == "p2":
        half = np.rint(2 * level).astype(int)           # one column per height
        T = sp.csr_matrix((np.ones(len(x_dofs)), (x_dofs, half)), shape=(disc.n_u, 2 * rows + 1))
    else:
        lower = np.minimum(np.floor(level + 1e-9).astype(int), rows - 1)
        upper_share = level - lower                     # 0 or 1 at an end, 1/2 mid-row
        T = sp.csr_matrix((np.concatenate([1 - upper_share, upper_share]),
                           (np.concatenate([x_dofs, x_dofs]), np.concatenate([lower, lower + 1]))),
                          shape=(disc.n_u, rows + 1))
    weights = disc.weights
    return dict(B=(assemble_B(disc) @ T).tocsr(), C=assemble_C(disc, elastic), h=h,
                elastic=elastic, points=disc.points, y=disc.points[:, 1], weights=weights,
                size=point_sizes(weights), top=T.shape[1] - 1, disc=disc, T=T)


def exact_delta(tau, law, scale, *, L, G, h, c_w):
    """delta(tau) = tau L / G + h (gamma^p(tau) - gamma^p(c_w)) on the post-peak branch."""
    return tau * L / G + h * (law.strain_at(tau, scale) - law.strain_at(c_w, scale))


def closed_form_tolerance(cap):
    """The relative tolerance of the checks against the closed form at the finest ``cap``:
    2 %, or :data:`LAG_PER_CAP` x the cap (the explicit update's one-increment lag)."""
    return max(0.02, LAG_PER_CAP * cap)


def end_strength(law):
    """Full softening: c_r for the linear law, 95 % of c_p - c_r spent for the exponential."""
    from pfem_skfem.materials.softening import ExponentialSoftening
    spent = 0.95 if isinstance(law, ExponentialSoftening) else 1.0
    return law.c_p - spent * (law.c_p - law.c_r)


def exact_dissipation(law, scale, h, c_w, c_end):
    """h int c dgamma^p as c falls from c_w to c_end: h (c_w^2 - c_end^2) / (2 abs(H)) (linear);
    h [c_r dgamma + (c_w - c_end) gamma_95 / 3] (exponential: dc = -3 (c - c_r) dgamma /
    gamma_95)."""
    from pfem_skfem.materials.softening import LinearSoftening
    if isinstance(law, LinearSoftening):
        H = (law.c_p - law.c_r) / (law.gamma_r * scale)
        return h * (c_w ** 2 - c_end ** 2) / (2 * H)
    slip = law.strain_at(c_end, scale) - law.strain_at(c_w, scale)
    return h * (law.c_r * slip + (c_w - c_end) * law.gamma_95 * scale / 3)


def shear(rows, law, ell, max_drop, args, average_length=0.0, passes=1):
    """The layer of ``rows`` rows sheared to --delta-end times its delta_r: (delta, tau) after
    each accepted increment, the dissipation, and the closed form's delta_r, D and c_w.
    ``average_length`` > 0: gamma^p averaged over that length (no closed form: the band's width is
    the average's; the run goes to --delta-end times the delta_r of a band 1.5 x as wide);
    ``passes`` > 1: each increment's fixed point (:class:`StepControl`)."""
    from pfem_skfem.drivers.softening import StepControl, softening_control
    from pfem_skfem.materials.softening import (FractureEnergy, SofteningTresca,
                                                nonlocal_average)

    m = layer_model(rows, args.L, args.G, args.nu, args.row_kinematics)
    material = SofteningTresca(law, m["elastic"], ell and FractureEnergy(ell))
    h, scale = m["h"], float(material.scale(m["h"]))
    c_w = law.c_p - args.epsilon * (law.c_p - law.c_r)
    weak = (m["y"] > (rows // 2) * h) & (m["y"] < (rows // 2 + 1) * h)
    gamma0 = np.where(weak, law.strain_at(c_w, scale), 0.0)
    c_end = end_strength(law)
    closed = dict(L=args.L, G=args.G, h=h, c_w=c_w)
    delta_r = exact_delta(c_end, law, scale, **closed)
    dissipated = exact_dissipation(law, scale, h, c_w, c_end)
    average, end = None, args.delta_end * delta_r
    if average_length:
        average = nonlocal_average(m["points"], m["weights"], average_length)
        wider = dict(closed, h=1.5 * average_length)
        end = args.delta_end * exact_delta(c_end, law, scale, **wider)
        delta_r = dissipated = np.nan
    run = softening_control(m["B"], m["C"], material, fixed=[0], prescribed=([m["top"]],
                            [end]), n_increments=args.increments, size=m["size"],
                            weights=m["weights"], gamma0=gamma0,
                            control=StepControl(max_drop, passes, average), solver=args.solver)
    delta = run.factors * end
    tau = run.reactions[:, m["top"]] / h                       # per unit width of the column
    # the softening branch: past the elastic limit c_w L / G (delta(tau) >= c_w L / G where
    # there is no snap-back), not from the largest tau sampled: the peak may fall inside an
    # increment, leaving the last elastic point the largest (--c-p 25: 24.36 < c_w = 24.8)
    post = delta >= c_w * args.L / args.G * (1 - 1e-9)
    softening = post & (tau > c_end * (1 + AT_RESIDUAL))
    error = np.abs(delta[softening] - exact_delta(tau[softening], law, scale, **closed)).max() \
        / delta_r
    at_r = np.flatnonzero(post & (tau <= c_end * (1 + AT_RESIDUAL)))
    i_r = at_r[0] if at_r.size else len(tau) - 1
    band = m["y"][run.gamma_p >= 0.5 * run.gamma_p.max()]
    width = band.max() - band.min()
    return dict(rows=rows, h=h, ell=ell, max_drop=max_drop, delta=delta, tau=tau, c_w=c_w,
                error=error, delta_r=delta[i_r], delta_r_exact=delta_r,
                dissipation=run.dissipation[i_r] / h, dissipation_exact=dissipated,
                reached=bool(at_r.size), width=width,
                slope=tau[1] / delta[1], solves=run.solves, uncapped=run.uncapped,
                scale=scale, law=law, weak=weak, y=m["y"], weights=m["weights"],
                tau_points=run.sigma[:, 3], gamma_p=run.gamma_p)


def viscous_recurrence(law, eta, G, rate, dt, n_steps):
    """tau after each step of the time-discrete uniform layer (shear rate ``rate``): the trial
    tau* = tau_n + G rate dt, Delta gamma^p = max(0, tau* - c(gamma^p_n)) / (G + eta / dt) (the
    strength lagged one step; tau_p = c and tau_v = eta Delta gamma^p / dt where it flows),
    tau_{n+1} = tau* - G Delta gamma^p."""
    tau, gamma, out = 0.0, 0.0, [0.0]
    for _ in range(n_steps):
        trial = tau + G * rate * dt
        dgamma = max(0.0, trial - float(law.strength(gamma))) / (G + eta / dt)
        tau, gamma = trial - G * dgamma, gamma + dgamma
        out.append(tau)
    return np.array(out)


def viscous_exact(t, law, eta, G, rate):
    """tau(t) of the uniform layer in continuous time (the linear law, G > abs(H)):
    tau = c(gamma^p) + eta gamma_dot^p, d tau / dt = G (rate - gamma_dot^p). Elastic until
    t_y = c_p / (G rate); then, with a = G rate / (G - abs(H)) and T = eta / (G - abs(H)),
    gamma_dot^p = a (1 - exp(-s / T)) (s = t - t_y) until gamma^p = gamma_r at s_r; after,
    c = c_r and gamma_dot^p = rate + (gamma_dot^p(s_r) - rate) exp(-G (s - s_r) / eta):
    tau -> c_r + eta rate."""
    from scipy.optimize import brentq
    H = (law.c_p - law.c_r) / law.gamma_r
    a, T, t_y = G * rate / (G - H), eta / (G - H), law.c_p / (G * rate)
    s = np.asarray(t, dtype=float) - t_y
    slip = lambda x: a * (x - T * (1 - np.exp(-x / T)))          # noqa: E731 (gamma^p(s))
    s_r = brentq(lambda x: slip(x) - law.gamma_r, 0.0, 10 * (law.gamma_r / a + T)) \
        if H > 0 else np.inf
    rate_r = a * (1 - np.exp(-s_r / T)) if H > 0 else 0.0
    softening = np.clip(s, 0.0, s_r)
    tau = law.c_p - H * slip(softening) + eta * a * (1 - np.exp(-softening / T))
    after = s > s_r
    tau[after] = law.c_r + eta * (rate + (rate_r - rate) * np.exp(-G * (s[after] - s_r) / eta))
    return np.where(s < 0, G * rate * np.asarray(t, dtype=float), tau)


def steady_time(law, eta, G, rate, dt, c_max=None):
    """When the uniform layer of :func:`viscous_exact` is steady to :data:`STEADY` of its stress:
    after yield at t_y = c_p / (G rate), full softening at gamma_r (s_r) and the relaxation of
    gamma_dot^p to the rate, tau - tau_ss = eta (rate_r - rate) exp(-r (s - s_r)), r = G /
    eta in continuous time and ln(1 + G dt / eta) / dt in the scheme's steps of ``dt`` (each
    multiplies the excess by 1 / (1 + G dt / eta)): the slower. With ``c_max`` = c_p (the peak
    run, no softening): tau - tau_ss = -eta rate exp(-r s) from yield."""
    from scipy.optimize import brentq
    t_y = law.c_p / (G * rate)
    r = np.log1p(G * dt / eta) / dt
    if c_max is not None:
        return t_y + np.log(eta * rate / (STEADY * (c_max + eta * rate))) / r
    H = (law.c_p - law.c_r) / law.gamma_r
    a, T = G * rate / (G - H), eta / (G - H)
    s_r = brentq(lambda x: a * (x - T * (1 - np.exp(-x / T))) - law.gamma_r, 0.0,
                 10 * (law.gamma_r / a + T))
    excess = eta * abs(a * (1 - np.exp(-s_r / T)) - rate)
    tau = law.c_r + eta * rate
    return t_y + s_r + max(np.log(excess / (STEADY * tau)), 0.0) / r


def viscous_shear(law, eta, dt, args):
    """The layer (--viscous-rows rows, shear modulus --viscous-G), every point intact, sheared
    at the top velocity --velocity V by dynamic steps (4.23) of ``dt`` (density --rho, theta =
    1; the initial velocity V y / L, so that the uniform shear is the exact motion and no
    inertia force arises) with the Bingham viscosity ``eta``: the PFEM step's own stages, the
    material's cone and viscous stress at the carried gamma^p
    (:func:`~pfem_skfem.pfem.softening.step_material`), gamma^p updated after each step
    (:func:`~pfem_skfem.pfem.softening.strain_update`). Returns t, the mean tau and its spread
    over the points after each step, and gamma^p at the end."""
    from dataclasses import replace

    from pfem_skfem.discretisation.dynamic import dynamic_operators
    from pfem_skfem.discretisation.theta import ThetaMethod
    from pfem_skfem.materials.softening import SofteningTresca
    from pfem_skfem.pfem.softening import step_material, strain_update
    from pfem_skfem.problems.dynamic import dynamic_increment
    from pfem_skfem.problems.step_terms import step_terms

    m = layer_model(args.viscous_rows, args.L, args.viscous_G, args.nu)
    material = SofteningTresca(law, m["elastic"], eta=eta)
    disc, T = m["disc"], m["T"]
    ops = dynamic_operators(disc, args.rho, ThetaMethod(dt), m["elastic"])
    ops = replace(ops, B=m["B"], A=(ops.A @ T).tocsr(), M=(T.T @ ops.M @ T).tocsr())
    rate = args.velocity / args.L
    n_steps = int(np.ceil(args.t_end / dt))
    v = rate * np.arange(T.shape[1]) * m["h"]                 # V y / L at each height
    sigma, gamma = np.zeros((disc.n_points, 4)), np.zeros(disc.n_points)
    f, scales, tau, spread = np.zeros(T.shape[1]), None, [0.0], [0.0]
    for _ in range(n_steps):
        step = step_material(material, gamma, disc)
        sigma_m = step.mean_stress(sigma)
        inc = dynamic_increment(ops, f, f, sigma, v, step.cone(sigma_m, law.c_p), fixed=[0],
                                prescribed=([m["top"]], [args.velocity * dt]),
                                terms=step_terms(viscous=step.viscous(sigma_m, law.c_p, None,
                                                                      disc.weights)),
                                scaling=scales, solver=args.solver)
        gamma, _ = strain_update(material, ops, inc, sigma, disc, gamma)
        sigma, v, scales = inc.sigma, inc.v, inc.scales
        tau.append(float(sigma[:, 3].mean()))
        spread.append(float(np.ptp(sigma[:, 3])))
    return dict(t=dt * np.arange(n_steps + 1), tau=np.array(tau), spread=np.array(spread),
                gamma_p=gamma, dt=dt, eta=eta, rate=rate)


def laws(args):
    """The linear law of --H and the exponential law of --gamma-95."""
    from pfem_skfem.materials.softening import ExponentialSoftening, LinearSoftening
    return (LinearSoftening(args.c_p, args.c_r, (args.c_p - args.c_r) / -args.H),
            ExponentialSoftening(args.c_p, args.c_r, args.gamma_95))


def check(args):
    """Snap-back (h / abs(H) <= L / G on the finest mesh, or ell / abs(H) <= L / G) has no
    displacement-controlled answer: refused."""
    if args.c_r >= args.c_p:
        return f"--c-r {args.c_r:g} must be below --c-p {args.c_p:g}"
    if args.row_kinematics != "linear":
        return (f"--row-kinematics {args.row_kinematics}: every check here is against (S4), a "
                "band one row thick under one tau; the free P2 row's equilibrium fixes only "
                "the mean of tau over the row and its first moment, so tau varies inside the "
                "softening row (3.5 to 10.9 kPa about the 5.49 it carries at the end, 10 rows), "
                "the plastic strain gathers to one edge (gamma^p 0.02 to 1.79) and the layer "
                "is not at c_r by the run's end: curves 29-36 % of delta_r off (S4), D 12-33 "
                "% low, the error growing as the cap shrinks. Local softening has no unique band "
                "inside the weak row, and P2's, its tau not uniform, is none of them: no closed "
                "form to check")
    h_min = args.L / max(args.rows)
    if h_min / -args.H <= args.L / args.G:
        return (f"--rows {max(args.rows)}: h / abs(H) = {h_min / -args.H:g} <= L / G = "
                f"{args.L / args.G:g}, the layer snaps back; fewer rows or a smaller --H")
    if args.ell / -args.H <= args.L / args.G:
        return f"--ell {args.ell:g}: ell / abs(H) <= L / G, the regularised layer snaps back"
    h_max = args.L / min(args.rows)
    if h_max * args.gamma_95 / (3 * (args.c_p - args.c_r)) <= args.L / args.G:
        return f"--gamma-95 {args.gamma_95:g}: the exponential layer snaps back"
    if len(args.rows) < 2 or len(set(args.rows)) < len(args.rows):
        return "--rows: two different meshes at least (the h-dependence)"
    if len(set(args.max_drop)) < 2:
        return "--max-drop: two different caps at least (the error's order in the cap)"
    if args.eta > 0 and len(set(args.dt)) < 2:
        return "--dt: two different steps at least (the viscous transient's order in dt)"
    if args.eta > 0 and args.viscous_G <= -args.H:
        return (f"--viscous-G {args.viscous_G:g} must exceed abs(H) = {-args.H:g}: the "
                f"uniformly softening layer would snap back")
    if args.eta > 0:
        linear, _ = laws(args)
        rate, G = args.velocity / args.L, args.viscous_G
        steady = 2 * max(args.dt) + max(steady_time(linear, args.eta, G, rate, args.dt[-1]),
                                        steady_time(linear, args.eta, G, rate, args.dt[0],
                                                    args.c_p))
        if args.t_end < steady:
            return (f"--t-end {args.t_end:g}: the viscous layer is steady (c_r + eta V / L to "
                    f"{STEADY:g}) only after {steady:.3g} s at --L {args.L:g}, --velocity "
                    f"{args.velocity:g}, --eta {args.eta:g} (yield, softening to gamma_r, "
                    f"relaxation over eta / G): a longer --t-end")
    return None


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    p.add_argument("--L", type=positive_float, default=1.0, help="layer height L [m]")
    material_options(p, G=2000.0, nu=0.3)
    softening_options(p, c_p=20.0, c_r=5.0,
                      H=opt(-20.0, "softening modulus H = dc/dgamma^p of the linear law [kPa]"),
                      gamma_95=opt(2.0, "gamma_95 of the exponential law (run on the coarsest "
                                        "mesh)"),
                      ell=opt(0.2, "regularisation length ell [m]: gamma_r holds for a band ell "
                                   "thick", type=positive_float),
                      ell_nonlocal=0.2,
                      epsilon=opt(0.01, "the weak row starts this fraction down the law"),
                      max_drop=opt([0.04, 0.02, 0.01, 0.005], nargs="+",
                                   help="caps on the strength drop of an increment, "
                                        "/ (c_p - c_r); the finest serves every mesh"),
                      increments=10)
    p.add_argument("--rows", type=in_range(2, integer=True), nargs="+", default=[10, 20, 40],
                   help="rows of the meshes (h = L / rows)")
    pfem_options(p, passes=opt(20, "most fixed-point passes of an increment in the "
                                   "fixed-point run (strength at the trial end)"))
    p.add_argument("--delta-end", type=in_range(1, low_open=True), default=1.2,
                   help="the run's end, a multiple of its delta_r")
    p.add_argument("--row-kinematics", choices=("linear", "p2"), default="linear",
                   help="u linear in each row (the closed form's uniform band); p2, the free "
                        "P2 row, is refused: its stress varies inside the row and no closed "
                        "form holds for it (book, softening.md, 'What P2 does inside the row')")
    viscous = p.add_argument_group("the viscous layer (Bingham viscosity, dynamic steps)")
    viscous.add_argument("--eta", type=in_range(0), default=2.0,
                         help="Bingham viscosity eta [kPa s] of the viscous layer (0: no "
                              "viscous runs)")
    viscous.add_argument("--velocity", type=positive_float, default=1.0,
                         help="the top's velocity V [m/s] (shear rate V / L)")
    viscous.add_argument("--viscous-G", type=positive_float, default=200.0,
                         help="the viscous layer's shear modulus [kPa] (above abs(H))")
    viscous.add_argument("--viscous-rows", type=in_range(1, integer=True), default=4,
                         help="rows of the viscous layer")
    material_options(viscous, rho=opt(2.0, why="of the viscous layer (the exact motion has "
                                               "no inertia force)"))
    time_options(viscous, dt=opt([0.009, 0.0045], nargs="+",
                                 why="of the viscous runs (the first also serves the peak run)"),
                 t_end=opt(1.0, why="of the viscous runs"))
    return p


def viscous_checks(report, args, linear):
    """The viscous layer's checks: every step on the scheme's recurrence, the steady stress
    c + eta V / L after full softening and without softening, the transient's first-order
    approach to the continuous closed form. (A dt of which the yield time c_p L / (G V) is a
    multiple puts a step's trial stress on the cone: the solver's tolerance then decides
    whether that step flows, and the recurrence check sees it, 2e-5 c_p at dt = 0.004.)"""
    from pfem_skfem.materials.softening import LinearSoftening
    eta, rate, G = args.eta, args.velocity / args.L, args.viscous_G
    runs = [viscous_shear(linear, eta, dt, args) for dt in args.dt]
    peak = viscous_shear(LinearSoftening(args.c_p, args.c_p, 1.0), eta, args.dt[0], args)
    span = args.c_p - args.c_r
    for r in runs:
        r["recurrence"] = np.abs(r["tau"] - viscous_recurrence(
            linear, eta, G, rate, r["dt"], len(r["t"]) - 1)).max() / args.c_p
        error = np.abs(r["tau"] - viscous_exact(r["t"], linear, eta, G, rate)) / span
        r["transient"], r["transient_mean"] = error.max(), error.mean()
        report.add_interval(f"viscous_dt{r['dt']:g}_recurrence_error", r["recurrence"], 0.0,
                            1e-5, "max |tau - tau_n| / c_p, tau_n the scheme's recurrence: "
                            "Delta gamma^p = (tau_n + G V dt / L - c_n) / (G + eta / dt)")
        report.add_interval(f"viscous_dt{r['dt']:g}_spread", r["spread"].max() / args.c_p, 0.0,
                            1e-6, "max over steps of (max - min of tau over the points) / c_p: "
                            "the layer shears uniformly")
    report.add("viscous_residual_tau", runs[-1]["tau"][-1], args.c_r + eta * rate,
               "steady shear after full softening: c_r + eta V / L", 1e-6)
    report.add("viscous_peak_tau", peak["tau"][-1], args.c_p + eta * rate,
               "steady shear without softening (c_r = c_p): c_p + eta V / L", 1e-6)
    errors = [r["transient_mean"] for r in runs]
    order = (np.polyfit(np.log(args.dt), np.log(errors), 1)[0] if len(runs) > 1 else np.nan)
    report.add_interval("viscous_transient_error", runs[-1]["transient"], 0.0, 0.02,
                        f"max |tau - tau(t)| / (c_p - c_r) at dt = {args.dt[-1]:g}, tau(t) the "
                        f"continuous closed form (the strength lagged one step: O(dt))")
    report.add_interval("viscous_transient_order", order, 0.8, 1.2,
                        "the mean over t of |tau - tau(t)| falls as dt")
    report.add_table("viscous", ["dt", "steps", "recurrence error / c_p",
                                 "closed-form error / (c_p - c_r): max", "mean",
                                 "tau at the end", "c_r + eta V / L"],
                     [[r["dt"], len(r["t"]) - 1, r["recurrence"], r["transient"],
                       r["transient_mean"], r["tau"][-1], args.c_r + eta * rate] for r in runs],
                     formats={"recurrence error / c_p": ".2e",
                              "closed-form error / (c_p - c_r): max": ".2e", "mean": ".2e"})
    return runs, peak


def run(args):
    linear, exponential = laws(args)
    finest, caps = min(args.max_drop), sorted(set(args.max_drop), reverse=True)
    rows = sorted(args.rows)
    report = Report("softening_layer", args)
    local = [shear(n, linear, None, finest, args) for n in rows]
    regular = [shear(n, linear, args.ell, finest, args) for n in rows]
    expo = shear(rows[0], exponential, None, finest, args)
    spread = [shear(n, linear, None, finest, args, average_length=args.ell_nonlocal)
              for n in rows]
    study = [next((r for r in local if r["rows"] == rows[0]), None) if c == finest
             else shear(rows[0], linear, None, c, args) for c in caps]
    fixed_point = shear(rows[0], linear, None, caps[0], args, passes=args.passes)
    first = local[0]
    tol = closed_form_tolerance(finest)
    report.add("elastic_slope", first["slope"], args.G / args.L, "tau / delta = G / L", 1e-6)
    report.add("peak_tau", first["tau"].max(), first["c_w"],
               "the weak row's strength c_w = c_p - epsilon (c_p - c_r)", 1e-6)
    for name, runs, band in (("local", local, "h"), ("regularised", regular, "ell")):
        for r in runs:
            key = f"{name}_rows{r['rows']}"
            report.add_interval(f"{key}_curve_error", r["error"], 0.0, tol,
                                f"max |delta - delta(tau)| / delta_r, delta(tau) = tau L / G + "
                                f"{band} (c_w - tau) / abs(H)")
            report.add(f"{key}_delta_r", r["delta_r"], r["delta_r_exact"],
                       f"c_r L / G + {band} (c_w - c_r) / abs(H)", tol)
            report.add(f"{key}_dissipation", r["dissipation"], r["dissipation_exact"],
                       f"{band} (c_w^2 - c_r^2) / (2 abs(H))", tol)
    report.add_interval("exponential_curve_error", expo["error"], 0.0, tol,
                        "max |delta - delta(tau)| / delta_95, delta(tau) = tau L / G + "
                        "h (gamma^p(tau) - gamma^p(c_w))")
    elastic_part = args.c_r * args.L / args.G
    slip = [r["delta_r"] - elastic_part for r in (local[0], local[-1])]
    report.add("local_slip_ratio", slip[1] / slip[0], rows[0] / rows[-1],
               "the band is one row: its slip scales with h", 0.02)
    report.add_interval("regularised_delta_r_ratio", regular[-1]["delta_r"] /
                        regular[0]["delta_r"], 0.95, 1.05,
                        "fracture energy: delta_r independent of h (exactly 1)")
    change = [r["delta_r"] if r["reached"] else np.nan for r in spread[-2:]]
    report.add_interval("nonlocal_delta_r_change", abs(change[1] / change[0] - 1), 0.0, 0.05,
                        "nonlocal average: delta_r converges with h (its two finest meshes)")
    errors = [r["error"] for r in study]
    order = (np.polyfit(np.log(caps), np.log(errors), 1)[0] if len(caps) > 1 else np.nan)
    report.add_interval("cap_order", order, 0.5, np.inf,
                        "the explicit update's lag: the error falls with the cap")
    report.add_interval("fixed_point_curve_error", fixed_point["error"], 0.0, 1e-5,
                        f"fixed-point passes at the cap {caps[0]:g}: every point on "
                        f"delta(tau) (the linear law's branch is straight)")
    report.add_table("meshes", ["law", "rows", "h", "delta_r", "exact", "curve error / delta_r",
                                "D", "D exact", "solves"],
                     [[name, r["rows"], r["h"], r["delta_r"], r["delta_r_exact"], r["error"],
                       r["dissipation"], r["dissipation_exact"], r["solves"]]
                      for name, runs in (("local", local), ("ell", regular),
                                         ("exponential", [expo])) for r in runs],
                     formats={"curve error / delta_r": ".2e"})
    report.add_table("nonlocal", ["rows", "h", "delta_r", "band width (gamma^p > max / 2)",
                                  "solves"],
                     [[r["rows"], r["h"], r["delta_r"], r["width"], r["solves"]] for r in spread])
    report.add_table("caps", ["max drop", "passes", "curve error / delta_r", "solves"],
                     [[r["max_drop"], 1, r["error"], r["solves"]] for r in study]
                     + [[caps[0], args.passes, fixed_point["error"], fixed_point["solves"]]],
                     formats={"curve error / delta_r": ".2e"})
    report.extra = {"cap_errors": errors, "caps": caps,
                    "curves": {f"{k}_rows{r['rows']}": {"delta": r["delta"], "tau": r["tau"]}
                               for k, runs in (("local", local), ("regularised", regular),
                                               ("nonlocal", spread))
                               for r in runs}}
    report.data = dict(local=local, regular=regular, expo=expo, study=study, spread=spread)
    if args.eta > 0:
        viscous, peak = viscous_checks(report, args, linear)
        curves = {f"dt{r['dt']:g}": r for r in viscous}
        curves["peak"] = peak
        report.extra["viscous"] = {k: {"t": r["t"], "tau": r["tau"]} for k, r in curves.items()}
        report.data["viscous"] = curves
    return report


def figures(args, local, regular, expo, study, spread, viscous=None):
    """tau - delta against the closed form, local and regularised (the nonlocal runs beside);
    the error against the cap; the viscous layer's tau(t) against its closed form."""
    if viscous:
        viscous_figure(args, viscous)
    fig, ax = pyplot().subplots(1, 3, figsize=(15, 4))
    for a, runs, title in ((ax[0], local + [expo], "local softening"),
                           (ax[1], regular, f"regularised: fracture energy, ell = {args.ell:g} m")):
        for k, r in enumerate(runs):
            tau = np.linspace(r["tau"][r["tau"] > 0].min(), r["c_w"], 200)
            peak = r["c_w"] * args.L / args.G
            exact = exact_delta(tau, r["law"], r["scale"], L=args.L, G=args.G, h=r["h"],
                                c_w=r["c_w"])
            label = f"h = {r['h']:g}" + (" (exponential)" if r is expo else "")
            a.plot(np.r_[0, peak, exact[::-1]], np.r_[0, r["c_w"], tau[::-1]], "-",
                   color=f"C{k}", lw=3, alpha=0.4)
            a.plot(r["delta"], r["tau"], ".", color=f"C{k}", ms=3, label=label)
        if a is ax[1]:
            for k, r in enumerate(spread):
                a.plot(r["delta"], r["tau"], "x", color=f"C{k}", ms=3,
                       label=f"nonlocal, ell = {args.ell_nonlocal:g} m, h = {r['h']:g}")
        a.set(xlabel="top displacement delta [m]", ylabel="shear stress tau [kPa]", title=title)
        a.legend(fontsize=8)
    ax[2].loglog([r["max_drop"] for r in study], [r["error"] for r in study], "o-")
    ax[2].set(xlabel="cap on the strength drop / (c_p - c_r)",
              ylabel="max |delta - exact| / delta_r",
              title=f"increment study, h = {study[0]['h']:g}")
    save_figure(fig, figure_dir(args, "softening_layer") / "softening_layer.png")


def viscous_figure(args, curves):
    """tau(t) of the viscous runs against the continuous closed form and c + eta V / L."""
    from pfem_skfem.materials.softening import LinearSoftening
    fig, ax = pyplot().subplots(figsize=(6, 4))
    rate = args.velocity / args.L
    linear = laws(args)[0]
    t = np.linspace(0.0, args.t_end, 400)
    ax.plot(t, viscous_exact(t, linear, args.eta, args.viscous_G, rate), "k-", lw=3, alpha=0.3,
            label="closed form")
    peak = LinearSoftening(args.c_p, args.c_p, 1.0)
    for k, (name, r) in enumerate(curves.items()):
        ax.plot(r["t"], r["tau"], ".", ms=3, color=f"C{k}",
                label=f"dt = {r['dt']:g} s" + (" (no softening)" if name == "peak" else ""))
    for c in (peak.c_p, linear.c_r):
        ax.axhline(c + args.eta * rate, color="0.5", lw=0.8, ls="--")
    ax.set(xlabel="t [s]", ylabel="shear stress tau [kPa]",
           title=f"viscous layer: eta = {args.eta:g} kPa s, V / L = {rate:g} 1/s")
    ax.legend(fontsize=8)
    save_figure(fig, figure_dir(args, "softening_layer") / "softening_layer_viscous.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
