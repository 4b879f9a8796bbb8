"""Terzaghi's column through the PFEM engine: the pore pressure carried by the particles.

Beyond the thesis (issue 54, item 5): a saturated scene (``Scene(water=Water(...))``,
:mod:`pfem_skfem.scene.water`) runs the PFEM loop of Section 2.2 with the pore pressure in
each step (:class:`~pfem_skfem.problems.pore_term.PorePressureTerm`) and p a particle
variable, the domain detected and remeshed every step.

The column (H high, W wide, particles on a square lattice of spacing H / n) stands on a
smooth rigid floor between smooth rigid walls, an elastic skeleton (Tresca, c far above its
stresses; E large enough that the column's strain q / E_oed is 1e-3, Terzaghi's small
strains: the PFEM is updated-Lagrangian) of submerged density rho' under gravity, at rest in
its geostatic effective stress (K0 = nu / (1 - nu)); p is the excess pore pressure (no water
table: the water weighs nothing, the skeleton its buoyant weight). At t = 0 the pore
pressure of the drained top rises by q (a reservoir that rises over the layer); the floor
and walls are impermeable. Its effective stress change is p, the column swells as Terzaghi's
column under a load q settles, and the excess p - q is Terzaghi's (Terzaghi 1923; Verruijt,
*Theory and Problems of Poroelasticity*, ch. 2), so with c_v = k E_oed / gamma_w, T_v = c_v
t / H^2 and M_m = pi (2m + 1) / 2:

    U(T_v) = heave / (q H / E_oed) = 1 - sum_m 2 / M_m^2 exp(-M_m^2 T_v),
    (q - p(base, t)) / q = sum_m 2 / M_m sin(M_m) exp(-M_m^2 T_v).

``--loading fill`` places a dry fill 0.2 H thick, of the density that makes its weight q,
on the column at t = 0: a region outside ``Water.regions``, free-draining, so the column
drains through the vertices it shares with the fill (no drained face is given), and the
fill's weight is Terzaghi's load: U and p(base) equal the load's (to 2e-4 not remeshed, 5e-4
remeshed every step) and Terzaghi's to 2e-3 (quick). U from the pore pressures, Terzaghi's
definition (1 - the excess over the column / (q H)), is kept beside the settlement's
(``U_p``).

``--loading load`` is Terzaghi's own problem: the load q on the drained top (p = 0 there), a
surface load (:mod:`pfem_skfem.scene.loads`); the column settles by the same U and p(base)
is the excess itself. (Until the bounded UEM kept the stresses of the elements a remeshing
keeps, the remeshed column lost settlement step by step under the load and gained it under
the fill: the book, "Saturated soil", has the figures.) The rise (a reservoir that rises
over the layer, the same diffusion, the column swells) is the default: a fall of the top's
pressure by q would make the total horizontal stress tensile ((1 - 2 nu) / (1 - nu) q) and
the column would leave its smooth walls; the rise presses them and leaves the floor the
column's weight, which holds it in place (a floating column's position is undetermined by a
step whose inertia is 1e-10 of its stiffness).

Checks: U at T_v = 0.05 / 0.1 / 0.2 / 0.5 / 1 (0.2523 / 0.3568 / 0.5041 / 0.7640 / 0.9313)
within 0.01 (the issue's band), and the base's pressure against the series within 0.01;
``tests/test_consolidation_pfem.py`` shows that a permeability 10 % off fails them.

Usage::

    python verification/consolidation_pfem.py --quick --json results/consolidation_pfem.json
"""
import argparse
from dataclasses import dataclass, field, replace
import sys

import numpy as np

from pfem_skfem.harness.figures import figure_dir, pyplot, save_figure
from pfem_skfem.harness.options import (base_parser, checkpoint_options, material_options, opt,
                                        positive_float, positive_int, saturated_options)
from pfem_skfem.harness.params import UNKEYED, Parameters, keys_of
from pfem_skfem.harness.report import Report, script_main

QUICK = dict(n=10, dTv=0.005)
REPORT_TV = (0.05, 0.1, 0.2, 0.5, 1.0)
#: the band of the issue's done-when, on U and on p(base) / q
BAND = 0.01
#: ``--loading fill``: the dry fill's thickness over H
FILL = 0.2


def terzaghi(Tv, terms=2000):
    """Terzaghi's series: U and p(base) / p0 (the excess left at the impermeable base)."""
    M = np.pi * (2 * np.arange(terms) + 1) / 2
    decay = np.exp(-M ** 2 * Tv)
    return 1 - np.sum(2 / M ** 2 * decay), np.sum(2 / M * np.sin(M) * decay)


def oedometric(args):
    """E_oed and c_v = k E_oed / gamma_w (alpha = 1, incompressible constituents)."""
    nu = args.nu
    e_oed = args.E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    return e_oed, args.k * e_oed / args.gamma_w


@dataclass(frozen=True)
class TerzaghiColumn(Parameters):
    """The column's parameters, which build its scene (time steps of dTv) and name its
    checkpoint (the keys: all but the solver); the options of the same names. ``k_steps``:
    the permeability whose c_v sets the steps (None: k; a wrong k in the scene's water)."""
    axisymmetric: bool
    loading: str
    H: float
    W: float
    n: int
    q: float
    k: float
    gamma_w: float
    E: float
    nu: float
    rho: float
    g: float
    c: float
    dTv: float
    solver: str = field(default="clarabel", metadata=UNKEYED)
    k_steps: float = field(default=None, metadata=UNKEYED)

    def keys(self):
        """:func:`keys_of` the fields, ``k_steps`` among them where it is given."""
        return keys_of(self, **({} if self.k_steps is None else {"k_steps": self.k_steps}))

    def scene(self):
        """The column's initial state and scene."""
        from pfem_skfem.discretisation import ThetaMethod
        from pfem_skfem.materials import (CohesiveTresca, Elastic,
                                          ZeroDilationMohrCoulombAxisymmetric)
        from pfem_skfem.problems.contact import CoulombCones, RigidSegment
        from pfem_skfem.scene import Body, Geostatic, HalfPlane, Region, Scene
        from pfem_skfem.scene.config import PFEMConfig
        from pfem_skfem.scene.loads import SurfaceLoad
        from pfem_skfem.scene.water import Drained, Water

        H, W = self.H, self.W
        h = H / self.n
        dt = self.dTv * H ** 2 / oedometric(replace(self, k=self.k_steps or self.k))[1]
        elastic = Elastic(self.E, self.nu)
        skeleton = (ZeroDilationMohrCoulombAxisymmetric(self.c, 0.0, elastic=elastic)  # Tresca
                    if self.axisymmetric else CohesiveTresca(self.c, elastic=elastic))
        soil = Region(((0.0, 0.0), (W, 0.0), (W, H), (0.0, H)), skeleton, self.rho, h,
                      stress=Geostatic(k0=self.nu / (1 - self.nu)), name="soil")
        far = 50 * H
        bodies = (Body("floor", RigidSegment((-far, 0.0), (far, 0.0), 0.0)),    # soil above
                  Body("left", RigidSegment((0.0, far), (0.0, -h), 0.0)),       # soil right
                  Body("right", RigidSegment((W, -h), (W, far), 0.0)))          # soil left
        if self.axisymmetric:                  # x = r: the axis holds u_r = 0, no left wall
            bodies = bodies[:1] + bodies[2:]
        rise = self.loading == "rise"
        top = Drained(HalfPlane((0.0, H - h / 2), (0.0, 1.0)), p=self.q if rise else 0.0)
        water = Water(k=self.k, gamma_w=self.gamma_w, drained=(top,))
        # Terzaghi's load q on the top's edges (above the sides' top midpoints, H - h / 2)
        loads = () if self.loading != "load" else (
            SurfaceLoad(HalfPlane((0.0, H - h / 4), (0.0, 1.0)), traction=(0.0, -self.q),
                        name="q"),)
        regions = (soil,)
        if self.loading == "fill":           # a dry layer FILL H thick weighing q, placed
            t = FILL * H                     # at t = 0: the column drains into it
            regions += (Region(((0.0, H), (W, H), (W, H + t), (0.0, H + t)), skeleton,
                               self.q / (self.g * t), h,
                               stress=Geostatic(k0=self.nu / (1 - self.nu)), name="fill"),)
            water = Water(k=self.k, gamma_w=self.gamma_w, regions=("soil",))
        config = PFEMConfig(theta=ThetaMethod(dt, 1.0, 1.0), contact=CoulombCones(), passes=1,
                            remesh_interval=1, solver=self.solver)
        scene = Scene(regions=regions, bodies=bodies, gravity=(0.0, -self.g), length=H,
                      config=config, water=water, loads=loads,
                      geometry="axisymmetric" if self.axisymmetric else "plane")
        return scene.initial_state(), scene


def consolidate(args, k=None):
    """The column from rest to T_v = 1 (and T_v-end): T_v, U, p(base) / q and Terzaghi's
    excess after each step (U: the settlement under the load, the heave under the rise; the
    excess: p(base) / q under the load, (q - p(base)) / q under the rise)."""
    from pfem_skfem.drivers.resumable import Checkpoints, ResumableRun

    params = TerzaghiColumn.of(args, **({} if k is None else {"k": k, "k_steps": args.k}))
    state, scene = params.scene()
    top = np.flatnonzero(np.abs(state.x[:, 1] - args.H) < 1e-9 * args.H)
    base = np.flatnonzero(np.abs(state.x[:, 1]) < 1e-9 * args.H)
    e_oed, _ = oedometric(args)
    heave_inf = args.q * args.H / e_oed
    steps = int(round(args.Tv_end / args.dTv))
    sign = 1.0 if args.loading == "rise" else -1.0         # heave / settlement
    kept = {"Tv": [0.0], "U": [0.0], "U_p": [0.0], "p_base": [0.0], "remeshed": 0}
    clay = np.flatnonzero(state.region == 0)
    row = np.rint(state.x[clay, 1] / (args.H / args.n)).astype(int)       # 0 .. n
    y = np.arange(args.n + 1) * args.H / args.n

    def observe(run, snapshots):
        s = run.state
        kept["Tv"].append(s.step * args.dTv)
        kept["U"].append(sign * float(s.x[top, 1].mean() - args.H) / heave_inf)
        kept["p_base"].append(float(s.pore_pressure[base].mean()) / args.q)
        # U as Terzaghi defines it: 1 - the excess over the column / (q H) (trapezoids)
        p = np.bincount(row, s.pore_pressure[clay]) / np.bincount(row) / args.q
        kept["U_p"].append(1 - float(np.trapezoid(1 - p if args.loading == "rise" else p, y))
                           / args.H)
        kept["remeshed"] += run.record.get("t_detect", 0) > 0   # the domain detected anew

    run = ResumableRun.open(scene, state, kept,
                            checkpoints=Checkpoints(args.checkpoint_dir, "consolidation_pfem",
                                                    params.keys(), args.checkpoint_every))
    run.advance(lambda r: r.state.step >= steps, observe)
    kept = run.kept
    p_base = np.array(kept["p_base"])
    return {"Tv": np.array(kept["Tv"]), "U": np.array(kept["U"]), "p_base": p_base,
            "U_p": np.array(kept["U_p"]),
            "excess": 1 - p_base if args.loading == "rise" else p_base,
            "remeshed": int(kept["remeshed"]),
            "steps": steps, "particles": state.n}


def errors(result):
    """max |U - series| and max |p_base excess / q - series| over the report times."""
    e_U = e_p = 0.0
    U = result["U"]
    for r in REPORT_TV:
        i = int(np.argmin(abs(result["Tv"] - r)))
        U_ex, p_ex = terzaghi(r)
        e_U = max(e_U, abs(U[i] - U_ex))
        e_p = max(e_p, abs(result["excess"][i] - p_ex))
    return e_U, e_p


def check(args):
    if abs(args.H / args.n * round(args.W * args.n / args.H) - args.W) > 1e-9 * args.W:
        return f"--W {args.W:g}: a whole number of spacings --H / --n = {args.H / args.n:g}"
    if abs(1 / args.dTv - round(1 / args.dTv)) > 1e-6 / args.dTv:
        return f"--dTv {args.dTv:g}: T_v = 1 must be a whole number of steps"
    if args.Tv_end < 1:
        return f"--Tv-end {args.Tv_end:g}: the report times reach T_v = 1"
    return None


def build_parser():
    p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
    p.add_argument("--H", type=positive_float, default=1.0, help="column height H [m]")
    p.add_argument("--W", type=positive_float, default=0.2, help="column width W [m]")
    p.add_argument("--n", type=positive_int, default=20,
                   help="particle spacings over the height (h = H / n)")
    saturated_options(p, q=opt(100.0, "the load q on the top at t = 0 (--loading rise: the "
                                      "rise of the top's pore pressure) [kPa]"),
                      k=1e-8, gamma_w=9.81, dTv=0.0025, Tv_end=1.0)
    material_options(p, E=opt(1e5, "Young's modulus E of the skeleton [kPa] (q / E_oed small: "
                                   "Terzaghi's small strains)"),
                     nu=opt(0.2, "Poisson's ratio nu' of the skeleton"),
                     rho=opt(1.0, "submerged density rho' of the skeleton [t/m^3]"), g=9.81,
                     c=opt(1e3, "the skeleton's strength [kPa] (Tresca: far above its "
                                "stresses, an elastic skeleton)"))
    p.add_argument("--axisymmetric", action=argparse.BooleanOptionalAction, default=False,
                   help="the column as a cylinder of radius W about x = 0 (a smooth wall at "
                        "r = W; the material the axisymmetric Mohr-Coulomb with phi = 0)")
    p.add_argument("--loading", choices=("rise", "load", "fill"), default="rise",
                   help="load: Terzaghi's load q on the drained top (a surface load); fill: "
                        "a dry, free-draining fill 0.2 H thick weighing q placed on the "
                        "column (the column drains into it); rise: the top's pore pressure "
                        "raised by q, no load (the same diffusion, the column swells)")
    checkpoint_options(p, "column")
    return p


def run(args):
    result = consolidate(args)
    report = Report("consolidation_pfem", args)
    rows = []
    for r in REPORT_TV:
        i = int(np.argmin(abs(result["Tv"] - r)))
        U_ex, p_ex = terzaghi(r)
        U, p = result["U"][i], result["excess"][i]
        report.add_interval(f"U_Tv{r:g}", U, U_ex - BAND, U_ex + BAND,
                            f"Terzaghi's series, +-{BAND:g} (remeshed every step)",
                            reference=U_ex)
        report.add_interval(f"p_base_Tv{r:g}", p, p_ex - BAND, p_ex + BAND,
                            f"Terzaghi's series at the impermeable base, +-{BAND:g}",
                            reference=p_ex)
        rows.append([r, U, U_ex, U - U_ex, p, p_ex, p - p_ex])
    report.add_table("terzaghi", ["T_v", "U", "U series", "error", "excess p_base/q", "series",
                                  "error "], rows,
                     formats={"error": ".1e", "error ": ".1e"})
    report.extra.update({"Tv": result["Tv"], "U": result["U"], "U_p": result["U_p"],
                         "p_base": result["p_base"],
                         "remeshed": result["remeshed"], "steps": result["steps"],
                         "particles": result["particles"], "c_v": oedometric(args)[1]})
    report.data = dict(result=result)
    return report


def figures(args, result):
    """U(T_v) of the PFEM column against Terzaghi's series."""
    fig, ax = pyplot().subplots(figsize=(6, 4))
    T = np.geomspace(1e-3, args.Tv_end, 200)
    ax.semilogx(T, [terzaghi(t)[0] for t in T], "-", color="0.4", label="Terzaghi's series")
    keep = result["Tv"] > 0
    ax.semilogx(result["Tv"][keep], result["U"][keep], ".", ms=4,
                label="PFEM, remeshed every step")
    ax.set_xlabel("T_v = c_v t / H^2")
    ax.set_ylabel("degree of consolidation U")
    ax.set_title(f"Terzaghi's column in the PFEM, h = H / {args.n}")
    ax.legend()
    save_figure(fig, figure_dir(args, "consolidation_pfem") / "terzaghi_pfem.png")


def main(argv=None):
    return script_main(build_parser, run, figures, argv)


if __name__ == "__main__":
    sys.exit(main())
