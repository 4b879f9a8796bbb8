"""Water at rest in a box: the spurious current of the PFEM step, and what sets it.

The dam break's column held by its gate (``verification/dam_break.py``: a = 2.25 in,
n^2 = 2, water of 1e-3 Pa s, smooth floor, wall and gate, free top) is stepped from rest
with the PFEM loop (:func:`~pfem_skfem.drivers.pfem_loop.pfem_step`: alpha-shape, remesh,
map, solve, move, every step). Exact rest is a solution of every step; the table gives the
largest particle speed after step 1 and after ``--steps`` steps, in units of g dt, over
the particle spacing (``--nx`` across) and the time step (``--dts``), then over Clarabel's
tolerance (``--tolerances``: tol_gap_abs = tol_gap_rel = tol_feas, the step's direct
assembly only), and with the two corners where the free surface meets the walls held
(``--held``: each wall's topmost contact node gets its normal velocity fixed to zero, a
bilateral support, instead of the unilateral contact (5.12)).

What it shows (book/water_and_mud.md, "Water at rest"): the residual is the interior-point
solver's. At each top corner the contact is degenerate, its force and its gap both zero at
the solution (the hydrostatic pressure vanishes at the free surface and the P2 consistent
load of a linear pressure on the top edge is zero at its end vertex); an interior-point
iterate stopped at complementarity mu has s z = mu there with s ~ z ~ sqrt(mu), so the
corner leaves the wall by ~ sqrt(tol) (a speed ~ sqrt(tol) g dt), where every loaded
contact is off by mu / z ~ tol. Holding the corners takes the residual to ~ tol.

Run: python benchmarks/water_at_rest.py [--nx 8 12 16] [--dts 0.005 0.0025 0.00125]
     [--steps 10] [--tolerances 1e-8 1e-10 1e-12] [--long-steps 300] [--held]
     [--json PATH]
"""
import argparse
from contextlib import contextmanager
import json
import os
from pathlib import Path
import sys
import time

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))       # the verification scripts

#: the held column of verification/dam_break.py (SI units)
A, N2, RHO, MU, G = 0.05715, 2.0, 1000.0, 1.0e-3, 9.81


@contextmanager
def step_tolerance(tol):
    """Every PFEM step's Clarabel solve (the direct assembly, ``backends.direct.SETTINGS``)
    with tol_gap_abs = tol_gap_rel = tol_feas = ``tol`` (None: the package's, Clarabel's
    default 1e-8)."""
    from pfem_skfem.problems.backends import direct
    saved = direct.SETTINGS
    if tol is not None:
        direct.SETTINGS = {**saved, "tol_gap_abs": tol, "tol_gap_rel": tol, "tol_feas": tol}
    try:
        yield
    finally:
        direct.SETTINGS = saved


def top_corners(contacts):
    """The x dofs of each wall's topmost node on it (a wall: a body whose contacts have a
    horizontal normal; on it: a gap below 1e-6 of the wetted height; the surface's nodes
    within the search distance are not), the corners where the free surface meets the
    walls."""
    wall = np.abs(contacts.normal[:, 0]) > 0.5
    wall &= contacts.gap <= 1e-6 * np.ptp(contacts.x[wall, 1])
    dofs = []
    for body in np.unique(contacts.body[wall]):
        mine = np.flatnonzero(wall & (contacts.body == body))
        dofs.append(contacts.dofs[mine[np.argmax(contacts.x[mine, 1])], 0])
    return np.array(dofs, dtype=int)


@contextmanager
def corners_held():
    """The PFEM step with the top corners' normal velocity held (:func:`top_corners`; their
    contacts dropped: a held node is a support): the diagnostic of the residual's cause."""
    from pfem_skfem.drivers import pfem_loop
    plain = pfem_loop.held_dofs

    def held(disc, phase, contacts):
        fixed = plain(disc, phase, contacts)
        return fixed if contacts is None else np.union1d(fixed, top_corners(contacts))

    pfem_loop.held_dofs = held
    try:
        yield
    finally:
        pfem_loop.held_dofs = plain


def at_rest(nx, dt, steps, *, tol=None, held=False):
    """The held column (nx particles across) stepped ``steps`` times from rest: a dict of the
    largest particle speed / (g dt) after each step (``speed``), the largest displacement /
    h, the iterations per step, the seconds."""
    from pfem_skfem.drivers.pfem_loop import pfem_step
    from verification.dam_break import DamBreak, time_unit

    # one step of dt in the dam break's time unit: its scene, held by its gate
    state, scene = DamBreak(A, N2, nx, steps=1, T_end=dt / time_unit(A, N2, G), rho=RHO,
                            mu=MU, g=G).scene(gate=True)
    x0, h = state.x.copy(), A / (nx - 1)
    speed, iterations = [], []
    t0 = time.process_time()
    with step_tolerance(tol), (corners_held() if held else _nothing()):
        for _ in range(steps):
            state, record, _ = pfem_step(state, scene)
            speed.append(float(np.abs(state.v).max() / (G * dt)))
            iterations.append(record["iterations"])
    return dict(nx=nx, dt=dt, tol=tol, held=held, speed=speed,
                displacement=float(np.abs(state.x - x0).max() / h),
                iterations=float(np.mean(iterations)), seconds=time.process_time() - t0)


@contextmanager
def _nothing():
    yield


def row(r, last):
    """A row of the first table: speeds after step 1 and after ``last`` steps / (g dt), and
    those / sqrt(tol)."""
    tol = 1e-8 if r["tol"] is None else r["tol"]
    s1, sn = r["speed"][0], r["speed"][last - 1]
    return (f"{r['nx']:4d} {r['dt']:8.5f} {s1:11.2e} {sn:11.2e} {s1 / np.sqrt(tol):10.2f} "
            f"{sn / np.sqrt(tol):10.2f} {r['iterations']:6.1f} {r['seconds']:6.1f}")


def marks(steps):
    """The steps the second table reports: 1, 10, 100, ... and the last."""
    return sorted({10 ** k for k in range(int(np.log10(steps)) + 1)} | {steps})


def long_row(r):
    """A row of the second table: the speed / (g dt) after each of :func:`marks`."""
    tol = 1e-8 if r["tol"] is None else r["tol"]
    return (f"{tol:7.0e} {'yes' if r['held'] else 'no':>5s} "
            + " ".join(f"{r['speed'][k - 1]:10.2e}" for k in marks(len(r["speed"])))
            + f" {r['displacement']:10.2e} {r['iterations']:6.1f} {r['seconds']:6.1f}")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--nx", type=int, nargs="+", default=[8, 12, 16],
                   help="particles across the column (h = a / (nx - 1))")
    p.add_argument("--dts", type=float, nargs="+", default=[0.005, 0.0025, 0.00125],
                   help="time steps [s]")
    p.add_argument("--steps", type=int, default=10, help="steps of the first table's runs")
    p.add_argument("--tolerances", type=float, nargs="*", default=[1e-8, 1e-10, 1e-12],
                   help="Clarabel tolerances of the second table (first --nx and --dts)")
    p.add_argument("--long-steps", type=int, default=300, help="steps of the second table's runs")
    p.add_argument("--held", action="store_true",
                   help="the second table again with the top corners held")
    p.add_argument("--json", type=Path, default=None, help="write every run here")
    args = p.parse_args(argv)
    if min(args.nx) < 3 or min(args.dts) <= 0 or min(args.steps, args.long_steps) < 1:
        p.error("--nx >= 3, --dts > 0, --steps and --long-steps >= 1")
    load = os.getloadavg()
    print(f"load average {load[0]:.2f} on {os.cpu_count()} cores; largest speed / (g dt)")
    head = (f"{'nx':>4s} {'dt':>8s} {'step 1':>11s} {'step ' + str(args.steps):>11s} "
            f"{'1/sqrt tol':>10s} {'N/sqrt tol':>10s} {'its':>6s} {'cpu s':>6s}")
    runs = []
    print(head)
    for nx in args.nx:
        for dt in args.dts:
            runs.append(at_rest(nx, dt, args.steps))
            print(row(runs[-1], args.steps), flush=True)
    print(f"\nnx = {args.nx[0]}, dt = {args.dts[0]:g}; speed / (g dt) after step N; the largest "
          "displacement / h")
    print(f"{'tol':>7s} {'held':>5s} " + " ".join(f"{'N = ' + str(k):>10s}"
                                                  for k in marks(args.long_steps))
          + f" {'disp / h':>10s} {'its':>6s} {'cpu s':>6s}")
    for held in (False, True) if args.held else (False,):
        for tol in args.tolerances:
            runs.append(at_rest(args.nx[0], args.dts[0], args.long_steps, tol=tol, held=held))
            print(long_row(runs[-1]), flush=True)
    if args.json is not None:
        args.json.write_text(json.dumps(runs, indent=1))


if __name__ == "__main__":
    main()
