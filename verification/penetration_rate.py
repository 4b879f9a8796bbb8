"""A rigid strip footing pushed into saturated soil at V = v B / c_v: drained to undrained.

Beyond the thesis (issue 54, item 5): the backbone curve of the penetrometer literature
(drained below V ~ 0.01-0.1, undrained above V ~ 10-30: Finnie & Randolph 1994; House,
Oliveira & Randolph 2001) for a smooth rigid strip footing of width B (half model, plane
strain) pushed at a constant velocity v into a weightless saturated soil, by the
consolidation step (C.1) of :mod:`pfem_skfem.problems.consolidation` in time (small
deformation, no remeshing: the settlement s grows by v dt a step). The resistance q(V) is
read at the settlement ``--s-end`` B and set against the drained and the undrained limits
of the same soil, both bracketed by the project's limit analysis
(:mod:`pfem_skfem.problems.bounds`, lower and upper bound).

The soil, and why. A Tresca skeleton (c', phi' = 0) would give no contrast: its strength
ignores the mean stress, its flow is isochoric, and drained and undrained collapse loads
are the same (``verification/effective_bounds.py``, case 4). An associated Mohr-Coulomb
skeleton dilates and, undrained, sucks without end: it never collapses (the pitfall of
issue 54). The skeleton here is Mohr-Coulomb (c', phi') with zero dilation, by the scheme
of Krabbenhoft et al. (2012) that the PFEM uses (:class:`~pfem_skfem.materials.
ZeroDilationMohrCoulomb`): each step is associated on a Tresca cone of radius
k = 2 c' cos phi' - 2 sin phi' sigma'_m at the mean effective stress sigma'_m = (sx' + sy')
/ 2 of the step before (tension positive). Its plastic flow is isochoric, so:

* undrained (V -> infinity, incompressible constituents): no volume change anywhere, so no
  elastic volume change; with eps_z = 0 (plane strain) the elastic law gives
  d(sx' + sy' + sz') = 0 and d sz' = nu' d(sx' + sy'), hence d(sx' + sy') = 0: the in-plane
  mean effective stress keeps its initial value p'_0, and the cone is Tresca of
  s_u = c' cos phi' + p'_0 sin phi' = c' cos phi' (a weightless soil at rest: p'_0 = 0).
  The undrained limit is Prandtl's (2 + pi) s_u, bracketed by the bounds of Tresca(s_u);
* drained (V -> 0): the excess pore pressure vanishes, the resistance is the collapse load
  of the non-associated (psi = 0) Mohr-Coulomb soil. Radenkovic's theorems (1961; as
  recalled from Drescher & Detournay 1993, Geotechnique 43(3), not re-read here) bracket it:
  at most the associated soil's (c', phi'), at least that of the associated soil of
  c* = c' cos phi', tan phi* = sin phi' (Davis' reduction for psi = 0). Both are bounded by
  the limit analysis: the drained bracket is [lower bound of (c*, phi*), upper bound of
  (c', phi')]; for phi' = 15 deg Prandtl-Reissner gives 10.36 c' and 10.98 c' for the two.

Water: the surface beside the footing drained (p = 0), the footing, the sides and the base
impermeable; c_v = (k / gamma_w) / (1/M + 1/E_oed). At rest at t = 0 (no stress, no pore
pressure), the footing's vertical displacement prescribed (smooth: its horizontal motion
free), dt = (s_end B / steps) / v.

Checks (tolerances stated before the run):

* q(V) falls as V rises at every V of ``--V`` (monotone, strictly);
* at the smallest V, q / c' inside the drained bracket, and at the largest V inside the
  undrained bracket, each widened by ``--tolerance`` (5 %): the displacement element's own
  error on this mesh (its plateau with dt = 0 lies above the undrained upper bound: +2.1 %
  on the quick mesh, +1.3 % at full size, measured; the thesis' Table 3.1 shows the same
  overshoot on coarse meshes), the drainage the extremes still see (the largest V drains a layer
  sqrt(c_v t) = sqrt(s_end / V) B beside the drained surface: +2 % at V = 100), and the
  drained resistance still rising (by 1.5 % over the last quarter of the quick push);
* the mid-transition V_50, where q crosses the mean of the two brackets' centres
  (interpolated in log V), inside 0.1 - 30, the range the penetrometer literature reports.

Reported: q(V) / c', the degree of drainage (q - q_u) / (q_d - q_u) (q_d, q_u the
brackets' centres), the largest pore pressure, the same mesh's undrained steps (dt = 0,
V = inf: the element's own error against the undrained bracket), V_50 of the same curves
read at half the settlement, the q - s curves.
No contractancy: the plastic flow generates no excess pore pressure (only the elastic
response to the rising mean total stress does), so the transition is a transient one,
governed by the time factor s_end / V at the reading; V_50 scales with ``--s-end``.

``--engine pfem``: the same push through the PFEM loop (:mod:`pfem_skfem.drivers.pfem_loop`),
a saturated scene (``Scene(water=Water(...))``) remeshed every step, the geometry updated: the
particles (spacing --h-pfem B within 1.25 B by 0.75 B of the footing's centre, --h-far B
elsewhere) carry the pore pressure; the footing is a smooth rigid segment with sharp ends
(:class:`~pfem_skfem.problems.contact.RigidPolyline`: without them the surface beside it is a
contact pushed down with it) moving down at v; the free surface (the boundary that touches no
body: beside the footing) is drained; smooth walls at x = 0 and W, a rough base (friction 1).
The skeleton is the PFEM's :class:`~pfem_skfem.materials.ZeroDilationMohrCoulomb` of the same
c', phi', E', nu' and floor, lagged on the particles' smoothed mean stress; no gravity, density
1e-3 t/m^3 (the inertia below 1e-4 of the footing's force). q = 2 F_y / B, F_y the soil's force
on the footing in the step's record. The static engine runs beside it at the same V. Checks on
the PFEM's q, tolerances set after one trial at the quick size (its q - s curve at V = 100 moved
by up to 4 % from one step to the next: the remeshing and the lag) and before the runs reported:

* monotone to that noise: q may rise from one V to the next by --noise (5 %) of q;
* the extremes in the brackets widened by --pfem-tolerance (10 %): the static engine's 5 % (the
  element, the drainage at the extremes) and the PFEM's noise;
* V_50 in 0.1 - 30, as above;
* q within --agree (10 %) of the static engine's at each V, at s_end and s_end / 2: the two
  meshes' element errors (2 % each, quick), the noise, and what the static engine leaves out
  (the geometry's change over the settlement, the remeshing);
* the extremes inside the brackets of the last step's own geometry (the footing sunk, the
  surface heaved: :mod:`pfem_skfem.drivers.step_bounds`, the footing a punch on the facets it
  loaded, the mesh refined --geometry-levels times), widened by --noise: what the flat
  brackets cannot say, whether a q above them is the geometry's.

Usage::

    python verification/penetration_rate.py --quick --json results/penetration_rate.json
    python verification/penetration_rate.py --quick --engine pfem     # about 45 s of CPU
"""
import sys
import warnings

import numpy as np

from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (adaptive_options, base_parser, in_range,
                                        material_options, nonnegative_int, opt, pfem_options,
                                        positive_float, positive_int, saturated_options,
                                        time_options)
from pfem_skfem.harness.progress import progress_bar
from pfem_skfem.harness.report import Report, script_main

QUICK = dict(V=[0.01, 0.1, 1.0, 100.0], h_min=0.04, steps=20, elements=600, h_pfem=0.0625,
             pfem_steps=10, geometry_levels=0)
#: the literature's window for the mid-transition V (Finnie & Randolph 1994; House et al.
#: 2001: drained below 0.01 - 0.1, undrained above 10 - 30)
LITERATURE_V50 = (0.1, 30.0)
EPS = 1e-9                        # relative tolerance of the boundary selections
FLOOR = 0.01                      # least cone radius, a fraction of 2 c'
#: ``--engine pfem``: the fine region about the footing, x < 1.25 B and y > -0.75 B (spacing
#: --h-pfem; --h-far elsewhere), in units of B: whole numbers of 0.25 B
FINE = (1.25, 0.75)
#: ``--engine pfem``: the soil's density [t/m^3]. Weightless (no gravity); its inertia, which
#: the static step has not, is rho v / dt over the fine region: below 1e-4 of the footing's
#: force at V = 100
RHO = 1e-3
#: the options of ``--engine pfem`` alone: not in the static engine's params
PFEM_OPTIONS = ("engine", "h_pfem", "h_far", "pfem_steps", "pfem_tolerance", "noise", "agree",
                "geometry_levels")


def consolidation_coefficient(args):
    """c_v = (k / gamma_w) / (1/M + 1/E_oed), alpha = 1."""
    nu, E = args.nu, args.E
    e_oed = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    return args.k / args.gamma_w / (args.M_inv + 1 / e_oed)


def footing_model(args):
    """The half model: mesh graded towards the footing's edge, its operators, supports
    (smooth sides, rough base), the footing's vertical dofs and the drained surface."""
    from pfem_skfem.discretisation.meshes import graded_rectangle
    from pfem_skfem.discretisation.pressure import pressure_field
    from pfem_skfem.discretisation.static import (assemble_B, assemble_C, boundary_dofs,
                                                  boundary_facets, discretise)
    from pfem_skfem.materials import Elastic
    from pfem_skfem.problems.consolidation import Hydraulic
    B, W, D = args.B, args.W * args.B, args.D * args.B
    e = EPS * W
    mesh = graded_rectangle(W, D, (B / 2, 0.0), h_min=args.h_min * B, h_max=args.h_max * B)
    disc = discretise(mesh)
    pressure = pressure_field(disc)
    base = lambda x: x[1] < -D + e                                    # noqa: E731
    fixed = np.union1d(np.union1d(boundary_dofs(disc, base, 0), boundary_dofs(disc, base, 1)),
                       boundary_dofs(disc, lambda x: (x[0] < e) | (x[0] > W - e), 0))
    footing = boundary_dofs(disc, lambda x: (x[1] > -e) & (x[0] < B / 2 + e), 1)
    surface = boundary_facets(disc, lambda x: (x[1] > -e) & (x[0] > B / 2))
    return dict(disc=disc, pressure=pressure, B=assemble_B(disc),
                C=assemble_C(disc, Elastic(args.E, args.nu)), fixed=np.setdiff1d(fixed, footing),
                footing=footing, hydraulic=Hydraulic.drained_faces(pressure, surface),
                elements=mesh.nelements)


def skeleton(args, sigma):
    """The step's cone: Tresca of the zero-dilation Mohr-Coulomb radius at the mean effective
    stress of ``sigma`` (the lagged sigma'_m)."""
    from pfem_skfem.materials.criteria import TrescaField, mohr_coulomb_radius
    sigma_m = 0.5 * (sigma[:, 0] + sigma[:, 1])
    return TrescaField(mohr_coulomb_radius(args.c, args.phi, sigma_m, FLOOR * 2 * args.c))


def push(model, args, V, k=None):
    """The footing pushed at v = V c_v / B to s_end B in ``steps`` steps: the settlements
    s / B, the resistances q / c' (q the mean total pressure under the footing), the largest
    pore pressure and the mean effective stresses sigma'_m at the end. V = inf: undrained
    steps (dt = 0). ``k``: the soil's permeability, if not the one c_v is computed from
    (a wrong permeability, for the tests)."""
    from pfem_skfem.problems.consolidation import (PoreState, SaturatedSoil,
                                                   consolidation_increment)
    disc, pressure, footing = model["disc"], model["pressure"], model["footing"]
    M = 1 / args.M_inv if args.M_inv > 0 else np.inf
    v = V * consolidation_coefficient(args) / args.B
    ds = args.s_end * args.B / args.steps
    dt = ds / v if np.isfinite(v) else 0.0
    k = args.k if k is None else k
    state = PoreState.zero(disc, pressure)
    f = np.zeros(disc.n_u)
    s, q = [0.0], [0.0]
    for n in range(args.steps):
        lagged = state.sigma
        for _ in range(args.passes):        # fixed-point passes on sigma'_m (1: the lag)
            soil = SaturatedSoil(skeleton(args, lagged), k=k, gamma_w=args.gamma_w, M=M)
            res = consolidation_increment(model["B"], model["C"], f, state, soil, pressure,
                                          dt, fixed=model["fixed"],
                                          prescribed=(footing, np.full(footing.size, -ds)),
                                          hydraulic=model["hydraulic"], solver=args.solver)
            lagged = res.sigma
        state = res
        s.append((n + 1) * ds / args.B)
        q.append(-2 * res.reactions[footing].sum() / (args.B * args.c))
    return dict(s=np.array(s), q=np.array(q), p_max=float(state.p.max()),
                sigma_m=0.5 * (state.sigma[:, 0] + state.sigma[:, 1]))


def pfem_scene(args, V):
    """The push as a saturated PFEM scene, remeshed every step: the soil (the same skeleton,
    zero dilation, weightless) a region of spacing --h-pfem about the footing and one of
    --h-far around it; the footing a smooth rigid segment with sharp ends (beside it the
    surface is no contact) moving down at v; smooth walls at x = 0 (the symmetry) and
    x = W, a rough base; the free surface (the boundary that touches no body: beside the
    footing) drained. (state, scene, ds), ds the settlement of a step."""
    from pfem_skfem.discretisation import ThetaMethod
    from pfem_skfem.materials import Elastic, ZeroDilationMohrCoulomb
    from pfem_skfem.problems.contact import CoulombCones, RigidSegment
    from pfem_skfem.scene import Body, ConstantVelocity, Region, Scene
    from pfem_skfem.scene.config import PFEMConfig
    from pfem_skfem.scene.water import Drained, Water
    B, W, D = args.B, args.W * args.B, args.D * args.B
    fx, fy = FINE[0] * B, FINE[1] * B
    h, h_far = args.h_pfem * B, args.h_far * B
    v = V * consolidation_coefficient(args) / B
    ds = args.s_end * B / args.pfem_steps
    dt = ds / v
    soil = ZeroDilationMohrCoulomb(args.c, args.phi, k_min=2 * FLOOR,   # of c': c is the
                                   elastic=Elastic(args.E, args.nu))    # stress scale
    regions = (Region(((0, -fy), (fx, -fy), (fx, 0), (0, 0)), soil, RHO, h, name="fine"),
               Region(((0, -D), (W, -D), (W, 0), (fx, 0), (fx, -fy), (0, -fy)), soil, RHO,
                      h_far, name="far"))
    far = 50 * (W + D)
    bodies = (Body("footing", RigidSegment((B / 2, 0.0), (-h, 0.0), 0.0, sharp_ends=True),
                   ConstantVelocity((0.0, -v))),                              # soil below
              Body("base", RigidSegment((-far, -D), (far, -D), 1.0)),         # soil above
              Body("left", RigidSegment((0.0, far), (0.0, -D - h_far), 0.0)),  # soil right
              Body("right", RigidSegment((W, -D - h_far), (W, far), 0.0)))     # soil left
    water = Water(k=args.k, gamma_w=args.gamma_w,
                  M=1 / args.M_inv if args.M_inv > 0 else np.inf, drained=(Drained(),))
    config = PFEMConfig(theta=ThetaMethod(dt, 1.0, 1.0), contact=CoulombCones(),
                        passes=args.passes, remesh_interval=1, solver=args.solver)
    scene = Scene(regions=regions, bodies=bodies, gravity=(0.0, 0.0), length=D, config=config,
                  water=water, t_end=args.pfem_steps * dt)
    return scene.initial_state(), scene, ds


def pfem_push(args, V):
    """The footing pushed at v = V c_v / B to s_end B in --pfem-steps steps of the PFEM loop:
    the settlements s / B, the resistances q / c' (q = 2 F_y / B, F_y the soil's force on the
    half footing in the step's record), the largest pore pressure at the end, the particles
    and the last mesh's elements."""
    from pfem_skfem.drivers.pfem_loop import run as pfem_run
    state, scene, ds = pfem_scene(args, V)
    s, q, last = [0.0], [0.0], {}

    def record(state, rec, result):
        s.append(state.step * ds / args.B)
        q.append(2 * rec["forces"]["footing"][1] / (args.B * args.c))
        last.update(rec, result=result)
    state, _ = pfem_run(state, scene, args.pfem_steps, on_step=record)
    return dict(s=np.array(s), q=np.array(q), p_max=float(last["pore_pressure_max"]),
                particles=int(state.n), elements=int(last["elements"]), last=last["result"])


def same_geometry(args, push, drained):
    """q / c' bracketed on the last PFEM step's own mesh (the footing sunk, the surface
    heaved), the footing a smooth punch on the facets it loaded: drained (Radenkovic's pair)
    or undrained (Tresca of c' cos phi'), the mesh refined --geometry-levels times.
    (lower, upper, elements)."""
    from pfem_skfem.drivers.step_bounds import step_bracket
    from pfem_skfem.materials import MohrCoulomb, Tresca
    from pfem_skfem.problems.bounds import Support
    W, D, e = args.W * args.B, args.D * args.B, 0.05 * args.h_pfem * args.B
    walls = (Support(lambda x: (x[0] < e) | (x[0] > W - e), "x"),         # smooth sides
             Support(lambda x: x[1] < -D + e, "xy"))                       # rough base
    c_star = args.c * np.cos(np.radians(args.phi))
    pair = ((MohrCoulomb(c_star, np.degrees(np.arctan(np.sin(np.radians(args.phi))))),
             MohrCoulomb(args.c, args.phi)) if drained else (Tresca(c_star), None))
    from pfem_skfem.problems.conic import AlmostSolvedWarning
    with warnings.catch_warnings():                 # certified ends, as in limits()
        warnings.simplefilter("ignore", AlmostSolvedWarning)
        lo, up, elements = step_bracket(push["last"], 0, *pair, supports=walls,   # 0: footing
                                        levels=args.geometry_levels, solver=args.solver)
    return lo * 2 / (args.c * args.B), up * 2 / (args.c * args.B), elements


def limits(args):
    """q / c' bracketed by the bounds: drained [LB(c*, phi*), UB(c', phi')] (Radenkovic),
    undrained [LB, UB] of Tresca(c' cos phi'); on a graded half mesh of ``--elements``."""
    from pfem_skfem.discretisation.meshes import graded_rectangle_with_elements
    from pfem_skfem.materials import MohrCoulomb, Tresca
    from pfem_skfem.problems.bounds import (LimitProblem, Punch, Support, lower_bound,
                                            upper_bound)
    from pfem_skfem.problems.conic import AlmostSolvedWarning
    B, W, D = args.B, args.W * args.B, args.D * args.B
    e = EPS * W
    mesh = graded_rectangle_with_elements(W, D, (B / 2, 0.0), args.elements, ratio=args.ratio)
    phi = np.radians(args.phi)
    c_star, phi_star = args.c * np.cos(phi), np.degrees(np.arctan(np.sin(phi)))

    def problem(criterion):
        return LimitProblem(mesh, criterion,
                            supports=(Support(lambda x: (x[0] < e) | (x[0] > W - e), "x"),
                                      Support(lambda x: x[1] < -D + e, "xy")),
                            punch=Punch(lambda x: (np.abs(x[1]) < e) & (x[0] < B / 2 + e),
                                        (0.0, -1.0), "y"))
    to_q = 2.0 / (args.c * B)                 # the half model's force -> q / c'
    settings = dict(solver=args.solver)
    # Clarabel's certified 'AlmostSolved' ends (a bound is its own field's value) are
    # counted, not printed
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", AlmostSolvedWarning)
        drained = (lower_bound(problem(MohrCoulomb(c_star, phi_star)), **settings).load,
                   upper_bound(problem(MohrCoulomb(args.c, args.phi)), **settings).load)
        tresca = problem(Tresca(c_star))
        undrained = (lower_bound(tresca, **settings).load, upper_bound(tresca, **settings).load)
    almost = sum(issubclass(w.category, AlmostSolvedWarning) for w in caught)
    return dict(drained=tuple(b * to_q for b in drained),
                undrained=tuple(b * to_q for b in undrained), elements=mesh.nelements,
                c_star=c_star, phi_star=phi_star, almost_solved_accepted=almost)


def prandtl_reissner(c, phi_deg):
    """q / c' of Prandtl-Reissner for (c, phi) on a weightless soil, c' = ``args.c`` = 1."""
    if phi_deg == 0:
        return c * (2 + np.pi)
    t = np.tan(np.radians(phi_deg))
    return c * (np.tan(np.pi / 4 + np.radians(phi_deg) / 2) ** 2 * np.exp(np.pi * t) - 1) / t


def mid_transition(V, q, q_half):
    """The V where q (falling with V) crosses q_half, interpolated in log V; NaN if it does
    not cross inside the V given."""
    for (v0, q0), (v1, q1) in zip(zip(V, q), zip(V[1:], q[1:])):
        if q0 >= q_half >= q1 and q0 > q1:
            w = (q0 - q_half) / (q0 - q1)
            return float(np.exp(np.log(v0) + w * (np.log(v1) - np.log(v0))))
    return float("nan")


def check(args):
    if any(b <= a for a, b in zip(args.V, args.V[1:])):
        return f"--V must increase, got {args.V}"
    if len(args.V) < 2:
        return "--V needs two values or more (the drained and the undrained end)"
    if args.h_min > args.h_max:
        return f"--h-min {args.h_min:g} must not exceed --h-max {args.h_max:g}"
    if args.W <= 0.5:
        return f"--W {args.W:g}: the footing (half-width B / 2) must lie inside the domain"
    if args.engine == "pfem":
        return check_pfem(args)
    return None


def whole(x, h):
    """Whether x is a whole number of h (to 1e-9)."""
    return abs(x / h - round(x / h)) < 1e-9


def check_pfem(args):
    """The PFEM's particles on whole spacings: the fine region's sides (0.25 B apart) of
    --h-pfem and the domain's of --h-far; halves of the pushes on whole steps."""
    if not whole(0.25, args.h_pfem):
        return f"--h-pfem {args.h_pfem:g}: 0.25 (B) must be a whole number of it"
    if not (whole(0.25, args.h_far) and whole(args.W, args.h_far) and whole(args.D, args.h_far)):
        return f"--h-far {args.h_far:g}: 0.25, --W and --D (B) must be whole numbers of it"
    if args.W <= FINE[0] or args.D <= FINE[1]:
        return f"--W, --D: the PFEM's fine region ({FINE[0]:g} B by {FINE[1]:g} B) lies inside"
    if args.steps % 2 or args.pfem_steps % 2:
        return "--steps, --pfem-steps: even (the curves are compared at half the settlement)"
    return None


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    p.add_argument("--V", type=positive_float, nargs="+",
                   default=[0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0],
                   help="normalised velocities V = v B / c_v, increasing")
    p.add_argument("--B", type=positive_float, default=1.0, help="footing width B [m]")
    p.add_argument("--W", type=positive_float, default=4.0,
                   help="half-width of the domain, in units of B")
    p.add_argument("--D", type=positive_float, default=3.0, help="depth of the domain / B")
    p.add_argument("--s-end", type=in_range(0, 1, low_open=True, what="a fraction of B in "
                                                                        "(0, 1]"),
                   default=0.2, help="settlement s / B at which q is read (small "
                                     "deformation: the mesh does not move)")
    p.add_argument("--h-min", type=positive_float, default=0.015,
                   help="element size at the footing's edge / B")
    p.add_argument("--h-max", type=positive_float, default=0.5,
                   help="largest element size / B")
    p.add_argument("--tolerance", type=positive_float, default=0.05,
                   help="relative widening of the drained and undrained brackets for the "
                        "extremes (the element's error on this mesh, module docstring)")
    saturated_options(p, k=1e-7, gamma_w=9.81,
                      M_inv=opt(0.0, why="the undrained reference c' cos phi' holds for 0 "
                                         "(incompressible constituents)"))
    material_options(p, E=opt(1e5, "Young's modulus E' of the skeleton [kPa]"),
                     nu=opt(0.3, "Poisson's ratio nu' of the skeleton"),
                     c=opt(10.0, "effective cohesion c' [kPa]"),
                     phi=opt(15.0, "effective friction angle phi' (zero dilation) [deg]"))
    time_options(p, steps=opt(40, "settlement steps to s_end B (dt = s_end B / (steps v))"))
    pfem_options(p, passes=opt(1, why="1: the mean stress of the step before (the lag)"))
    adaptive_options(p, what="the bounds", elements=3000, ratio=30.0)
    e = p.add_argument_group("--engine pfem: the same push through the PFEM loop")
    e.add_argument("--engine", choices=("static", "pfem"), default="static",
                   help="static: the consolidation step on one mesh (small deformation); "
                        "pfem: the PFEM loop, remeshed every step, its checks on the PFEM "
                        "curve and the static one run beside it")
    e.add_argument("--h-pfem", type=positive_float, default=0.05,
                   help="particle spacing / B about the footing (x < 1.25 B, y > -0.75 B)")
    e.add_argument("--h-far", type=positive_float, default=0.25,
                   help="particle spacing / B elsewhere")
    e.add_argument("--pfem-steps", type=positive_int, default=20,
                   help="PFEM steps to s_end B")
    e.add_argument("--pfem-tolerance", type=positive_float, default=0.10,
                   help="relative widening of the brackets for the PFEM's extremes (module "
                        "docstring)")
    e.add_argument("--noise", type=positive_float, default=0.05,
                   help="the PFEM's q may rise from one V to the next by this fraction (its "
                        "step-to-step noise, module docstring)")
    e.add_argument("--agree", type=positive_float, default=0.10,
                   help="the PFEM's q / the static engine's - 1, at s_end and s_end / 2, "
                        "within this (module docstring)")
    e.add_argument("--geometry-levels", type=nonnegative_int, default=1,
                   help="uniform refinements of the last PFEM step's mesh for the bounds of "
                        "its own geometry (module docstring)")
    return p


def run(args):
    pfem = args.engine == "pfem"
    report = Report("penetration_rate", report_params(args))
    bar = progress_bar(total=(1 + pfem) * len(args.V) + 2, args=args, desc="penetration rate",
                       unit="case")
    ref = limits(args)
    bar.update(1)
    model = footing_model(args)
    runs = []
    for V in args.V:
        runs.append(push(model, args, V))
        bar.update(1)
    fast = push(model, args, np.inf)        # dt = 0: the step's own undrained limit
    bar.update(1)
    pushes = []
    for V in args.V if pfem else ():
        pushes.append(pfem_push(args, V))
        bar.update(1)
    bar.close()
    q = np.array([r["q"][-1] for r in runs])
    (d_lo, d_up), (u_lo, u_up) = ref["drained"], ref["undrained"]
    q_d, q_u = 0.5 * (d_lo + d_up), 0.5 * (u_lo + u_up)
    backbone_checks(report, args, np.array([r["q"][-1] for r in pushes]) if pfem else q, ref)
    V50 = mid_transition(args.V, q, 0.5 * (q_d + q_u))          # the static engine's
    half = args.steps // 2                  # the same curves read at half the settlement
    V50_half = mid_transition(args.V, [r["q"][half] for r in runs], 0.5 * (q_d + q_u))
    last = runs[0]["q"]
    quarter = max(1, args.steps // 4)
    rise = last[-1] / last[-1 - quarter] - 1
    rows = [[V, qi, (qi - q_u) / (q_d - q_u), r["p_max"] / args.c]
            for V, qi, r in zip(args.V, q, runs)]
    rows.append([np.inf, fast["q"][-1], (fast["q"][-1] - q_u) / (q_d - q_u),
                 fast["p_max"] / args.c])
    report.add_table("backbone", ["V", "q / c'", "drainage", "p_max / c'"], rows,
                     formats={"V": "g", "q / c'": ".3f", "drainage": ".3f",
                              "p_max / c'": ".3f"},
                     title=f"q at s = {args.s_end:g} B, phi' = {args.phi:g}, "
                           f"{model['elements']} elements (V = inf: dt = 0)")
    report.add_table("limits", ["limit", "lower bound", "upper bound", "Prandtl-Reissner"],
                     [["drained (Radenkovic)", d_lo, d_up,
                       f"{prandtl_reissner(np.cos(np.radians(args.phi)), ref['phi_star']):.3f}"
                       f" - {prandtl_reissner(1.0, args.phi):.3f}"],
                      ["undrained (Tresca c' cos phi')", u_lo, u_up,
                       f"{prandtl_reissner(np.cos(np.radians(args.phi)), 0.0):.3f}"]],
                     formats={"lower bound": ".3f", "upper bound": ".3f"},
                     title=f"q / c' bracketed on {ref['elements']} elements")
    report.extra = {"V": list(args.V), "q": q.tolist(), "q_d": q_d, "q_u": q_u,
                    "drained": list(ref["drained"]), "undrained": list(ref["undrained"]),
                    "V50": V50, "drained_rise_last_quarter": float(rise),
                    "q_undrained_step": float(fast["q"][-1]),
                    "V50_half_settlement": V50_half, "s_half": float(runs[0]["s"][half]),
                    "elements": model["elements"], "bound_elements": ref["elements"],
                    "almost_solved_accepted": ref["almost_solved_accepted"],
                    "c_v": consolidation_coefficient(args),
                    "curves": [dict(V=V, s=r["s"].tolist(), q=r["q"].tolist())
                               for V, r in zip(args.V, runs)]}
    report.data = dict(runs=runs, ref=ref, q=q, V50=V50, q_fast=float(fast["q"][-1]))
    if pfem:
        pfem_results(report, args, runs, pushes, q_d, q_u)
    return report


def report_params(args):
    """The JSON's params: the static engine's without the PFEM's options (as before them)."""
    return {k: v for k, v in vars(args).items()
            if args.engine == "pfem" or k not in PFEM_OPTIONS}


def backbone_checks(report, args, q, ref):
    """The checks on the backbone q (the static engine's or the PFEM's): monotone, the
    extremes in their brackets, V_50 in the literature's window; returns V_50."""
    pfem = args.engine == "pfem"
    (d_lo, d_up), (u_lo, u_up) = ref["drained"], ref["undrained"]
    q_d, q_u = 0.5 * (d_lo + d_up), 0.5 * (u_lo + u_up)
    tol = args.pfem_tolerance if pfem else args.tolerance
    why = ("the element's error, the drainage at the extremes and the PFEM's step noise"
           if pfem else "the element's error on this mesh")
    for (v0, q0), (v1, q1) in zip(zip(args.V, q), zip(args.V[1:], q[1:])):
        report.add_interval(f"falls_V{v0:g}_to_V{v1:g}", q0 - q1,
                            -args.noise * q1 if pfem else 0.0, np.inf,
                            "q(V) monotone: a faster push drains less"
                            + (f" (to the PFEM's step noise, {args.noise:g} q)" if pfem else ""),
                            reference=0.0)
    report.add_interval("drained_q", q[0], d_lo, d_up,
                        f"at V = {args.V[0]:g}: the drained bracket (Radenkovic: LB of "
                        f"c' cos phi', atan(sin phi'); UB of c', phi'), +-{tol:g} ({why})", tol,
                        reference=q_d)
    report.add_interval("undrained_q", q[-1], u_lo, u_up,
                        f"at V = {args.V[-1]:g}: the undrained bracket (Tresca, s_u = c' cos "
                        f"phi'), +-{tol:g} ({why})", tol, reference=q_u)
    V50 = mid_transition(args.V, q, 0.5 * (q_d + q_u))
    report.add_interval("V50", V50, *LITERATURE_V50,
                        "halfway between the brackets' centres: inside the penetrometer "
                        "literature's 0.1 - 30 (Finnie & Randolph 1994; House et al. 2001)")
    return V50


def pfem_results(report, args, runs, pushes, q_d, q_u):
    """``--engine pfem``: the PFEM's curve against the static engine's at each V, at s_end
    and at s_end / 2 (within --agree); its table, extra and figure data."""
    q = np.array([r["q"][-1] for r in pushes])
    q_half = np.array([r["q"][args.pfem_steps // 2] for r in pushes])
    static, static_half = (np.array([r["q"][i] for r in runs]) for i in (-1, args.steps // 2))
    geometry = {}
    for name, i in (("drained", 0), ("undrained", -1)):
        lo, up, elements = geometry[name] = same_geometry(args, pushes[i], name == "drained")
        report.add_interval(f"pfem_{name}_q_own_geometry", q[i], lo, up,
                            f"at V = {args.V[i]:g}: the {name} bracket on the last step's own "
                            f"mesh ({elements} elements: the footing sunk, the surface "
                            f"heaved), +-{args.noise:g} (the PFEM's step noise)", args.noise,
                            reference=0.5 * (lo + up))
    for V, a, b, a2, b2 in zip(args.V, q, static, q_half, static_half):
        for name, x, y, at in (("", a, b, "s_end"), ("half_", a2, b2, "s_end / 2")):
            report.add_interval(f"agrees_{name}V{V:g}", x / y - 1, -args.agree, args.agree,
                                f"the PFEM's q / the static engine's - 1 at {at}, within "
                                f"+-{args.agree:g} (module docstring)", reference=0.0)
    rows = [[V, a, b, a / b - 1, a2 / b2 - 1, (a - q_u) / (q_d - q_u), r["p_max"] / args.c]
            for V, a, b, a2, b2, r in zip(args.V, q, static, q_half, static_half, pushes)]
    report.add_table("pfem", ["V", "q / c' PFEM", "static", "diff", "diff at s/2", "drainage",
                              "p_max / c'"], rows,
                     formats={"V": "g", "q / c' PFEM": ".3f", "static": ".3f", "diff": "+.3f",
                              "diff at s/2": "+.3f", "drainage": ".3f", "p_max / c'": ".3f"},
                     title=f"the PFEM at s = {args.s_end:g} B: {pushes[0]['particles']} "
                           f"particles, {pushes[0]['elements']} elements, "
                           f"{args.pfem_steps} steps, remeshed every step")
    report.extra["pfem"] = {
        "q": q.tolist(), "q_half": q_half.tolist(), "q_static_half": static_half.tolist(),
        "V50": mid_transition(args.V, q, 0.5 * (q_d + q_u)),
        "particles": pushes[0]["particles"], "elements": [r["elements"] for r in pushes],
        "p_max": [r["p_max"] for r in pushes], "own_geometry": geometry,
        "curves": [dict(V=V, s=r["s"].tolist(), q=r["q"].tolist())
                   for V, r in zip(args.V, pushes)]}
    report.data["pushes"] = pushes


def figures(args, runs, ref, q, V50, q_fast, pushes=()):
    """The backbone q(V) / c' between the two brackets, and the q - s curves (``--engine
    pfem``: the PFEM's beside them, dashed)."""
    plt = pyplot()
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4))
    V = np.asarray(args.V)
    span = [V.min() / 3, V.max() * 3]
    for (lo, up), name, colour in ((ref["drained"], "drained bracket", "C0"),
                                   (ref["undrained"], "undrained bracket", "C3")):
        ax.fill_between(span, lo, up, color=colour, alpha=0.25, label=name)
    ax.semilogx(V, q, "ko-", label=f"consolidation step, s = {args.s_end:g} B")
    if pushes:
        ax.semilogx(V, [r["q"][-1] for r in pushes], "s--", color="C2",
                    label="PFEM, remeshed every step")
    ax.axhline(q_fast, color="C3", ls="--", lw=1, label="the same mesh, dt = 0 (V = inf)")
    ax.axvspan(*LITERATURE_V50, color="0.85", zorder=0, label="literature V_50 window")
    if np.isfinite(V50):
        ax.axvline(V50, color="k", ls=":", lw=1, label=f"V_50 = {V50:.2g}")
    ax.set_xlim(*span)
    ax.set_xlabel("V = v B / c_v")
    ax.set_ylabel("q / c'")
    ax.set_title(f"strip footing, phi' = {args.phi:g} deg (psi = 0): backbone", fontsize=9)
    ax.legend(fontsize=7)
    for i, (V_i, r) in enumerate(zip(args.V, runs)):
        bx.plot(r["s"], r["q"], "-", color=f"C{i}", label=f"V = {V_i:g}")
        if pushes:
            bx.plot(pushes[i]["s"], pushes[i]["q"], "--", color=f"C{i}")
    bx.set_xlabel("settlement s / B")
    bx.set_ylabel("q / c'")
    bx.set_title("resistance against settlement", fontsize=9)
    bx.legend(fontsize=7)
    save_figure(fig, figure_dir(args, "penetration_rate") / "backbone.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
