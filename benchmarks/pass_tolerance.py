"""Fewer fixed-point passes per PFEM step: ``PFEMConfig.pass_tolerance`` against the figures.

Each step of a lagged material (the zero-dilation Mohr-Coulomb of [80]) solves (4.23) +
(5.12) once per fixed-point pass on the smoothed mean stress (two by default). With a
pass tolerance the passes stop once a pass changes the mean stress by less than it, in
units of the scene's stress scale rho g L
(:func:`pfem_skfem.problems.nonassociated.lagged_change`). Here the verification
scripts run (``--quick``, in this process) with every step's passes at each tolerance
(0: every pass, today's; inf: one pass always), and with the mean stress a first pass
starts from

* 'lagged': the previous step's (carried by the particles; today's), or
* 'extrapolated': the previous two steps' extrapolated in time, particle by particle,
  2 sm^n - sm^(n-1) (a prototype made here, not an engine option; after a step that
  removed particles, the lagged guess);

the table gives passes and iterations per step, the steps that stopped before the last
pass, the solve time, and each benchmark quantity's change from the run at tolerance 0
(lagged), against the spread that round-off alone gives (the tolerance-0 run with the
density scaled by ``--density-factors``: with c = 0 only round-off depends on it). A
second table: the change of the mean stress the first pass makes (the one deciding
whether pass 2 runs), its quantiles over the steps, and the fraction of steps below
each tolerance.

Cases: the plane column a = 1 and a = 3 (``verification/granular_column_plane.py
--quick``: 10 particles across, 100 steps to t = 4 sqrt(h0/g), then on to rest) and
the silo (``verification/silo_discharge.py --quick``: smooth and rough walls).

Run: python benchmarks/pass_tolerance.py [--cases column_a1 column_a3 silo]
     [--tolerances 0 1e-2 5e-2 inf] [--extrapolated 0 inf] [--density-factors 3]
     [--json PATH]
"""
import argparse
from contextlib import contextmanager, redirect_stdout
from dataclasses import replace
import importlib
import io
import json
import os
from pathlib import Path
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))       # the verification scripts
from pfem_skfem.drivers import pfem_loop                            # noqa: E402
from pfem_skfem.harness.report import relative_error, run_script  # noqa: E402

# case: (script, its arguments, its default density)
CASES = {
    "column_a1": ("granular_column_plane", ["--quick", "--a", "1", "--workers", "1"], 2.0),
    "column_a3": ("granular_column_plane", ["--quick", "--a", "3", "--workers", "1"], 2.0),
    "silo": ("silo_discharge", ["--quick", "--workers", "1"], 1.5),
}
GUESSES = ("lagged", "extrapolated")
NEAR_ZERO = 1e-6      # a residual or drift (round-off level): judged by its check


def column_extra(data):
    """The column's deposit at t = 4 sqrt(h0/g) and its final area change (besides its
    Report's quantities; less chaotic than the deposit at rest)."""
    return {f"a{r['a']:g}_{key}": r[key] for r in data["sweep"]
            for key in ("h_t4_over_d0", "runout_t4_over_d0", "volume_change_final")}


EXTRA = {"granular_column_plane": column_extra}


@contextmanager
def pass_settings(tolerance, guess, steps):
    """Inside, every PFEM step's passes stop at ``tolerance`` and its first pass starts from
    the ``guess`` of the mean stress; ``steps`` gets (passes, changes, iterations) per
    meshed step."""
    lagged_step, pfem_step = pfem_loop.lagged_step, pfem_loop.pfem_step

    def stepping(*args, **kw):
        kw["config"] = replace(kw["config"], pass_tolerance=tolerance)
        solved = lagged_step(*args, **kw)
        steps.append((solved.passes, solved.changes, solved.iterations))
        return solved

    previous = {}                      # scene id -> the mean stress of the step before

    def extrapolating(state, scene):
        before = previous.pop(id(scene), None)
        sm_n = state.sigma_m.copy()
        if before is not None and state.step > 0:
            n = min(len(before), state.n)          # particles keep their index; new ones last
            sm = sm_n.copy()
            sm[:n] = 2.0 * sm_n[:n] - before[:n]
            state = replace(state, sigma_m=sm)
        new, record, result = pfem_step(state, scene)
        # a step that removed particles (an outlet, thinning) shifts the indices after
        # them: its successor starts from the lagged guess
        if not (record["thinned"] or sum(record["discharged_now"].values())):
            previous[id(scene)] = sm_n
        return new, record, result

    pfem_loop.lagged_step = stepping
    if guess == "extrapolated":
        pfem_loop.pfem_step = extrapolating
    try:
        yield
    finally:
        pfem_loop.lagged_step, pfem_loop.pfem_step = lagged_step, pfem_step


def run_variant(script_name, argv, tolerance, guess, outdir):
    """One run: {quantity: value}, the per-step records, the seconds, (passed, checks)."""
    script = importlib.import_module(f"verification.{script_name}")
    steps = []
    t0 = time.perf_counter()
    with pass_settings(tolerance, guess, steps), redirect_stdout(io.StringIO()):
        report = run_script(script, *argv, "--no-figures", "--outdir", str(outdir))
    seconds = time.perf_counter() - t0
    values = {q.name: q.value for q in report.quantities}
    if script_name in EXTRA:
        values.update(EXTRA[script_name](report.data))
    checks = (sum(q.passed for q in report.quantities), len(report.quantities))
    return dict(values=values, steps=steps, seconds=seconds, checks=checks)


def step_summary(run, most):
    """passes / step, the share of steps below ``most`` passes, iterations / step."""
    passes = np.array([s[0] for s in run["steps"]])
    iters = np.array([s[2] for s in run["steps"]])
    return dict(steps=len(passes), passes=float(passes.mean()),
                short=float(np.mean(passes < most)), iterations=float(iters.mean()))


def changes(values, reference):
    return {k: (relative_error(values[k], reference[k]) if np.isfinite(reference[k])
                and k in values else np.nan) for k in reference}


def label(tolerance, guess):
    return f"tol {tolerance:g}, {guess}"


def first_change_table(run, tolerances):
    """Quantiles of the first pass's change and the fraction of steps below each tolerance."""
    first = np.array([s[1][0] for s in run["steps"] if s[1]])
    q = np.quantile(first, [0.1, 0.5, 0.9])
    below = {t: float(np.mean(first < t)) for t in tolerances}
    return dict(q10=float(q[0]), median=float(q[1]), q90=float(q[2]), below=below)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--cases", nargs="+", choices=tuple(CASES), default=list(CASES))
    p.add_argument("--tolerances", type=float, nargs="+", default=[0.0, 1e-2, 5e-2, np.inf],
                   help="pass tolerances of the runs from the lagged guess (0 always run)")
    p.add_argument("--extrapolated", type=float, nargs="*", default=[0.0, np.inf],
                   help="pass tolerances of the runs from the extrapolated guess")
    p.add_argument("--density-factors", type=float, nargs="*", default=[3.0],
                   help="the round-off reruns at tolerance 0: density scaled by these")
    p.add_argument("--json", type=Path, default=None, help="write every measurement here")
    args = p.parse_args(argv)
    if any(not t >= 0 for t in args.tolerances + args.extrapolated):
        p.error(f"--tolerances and --extrapolated must be >= 0, got {args.tolerances} and "
                f"{args.extrapolated}")
    variants = [(t, "lagged") for t in sorted(set(args.tolerances) | {0.0})] + \
        [(t, "extrapolated") for t in sorted(set(args.extrapolated))]
    tols = sorted({t for t, _ in variants})
    load = os.getloadavg()
    print(f"load average {load[0]:.2f} / {load[1]:.2f} / {load[2]:.2f} on {os.cpu_count()} "
          "cores; changes relative to the run at tolerance 0 (every pass), lagged guess")
    out = {}
    with tempfile.TemporaryDirectory() as outdir:
        for case in args.cases:
            script_name, script_argv, rho = CASES[case]
            runs = {}
            for tol, guess in variants:
                runs[label(tol, guess)] = run_variant(script_name, script_argv, tol, guess,
                                                      outdir)
                print(f"  {case}: {label(tol, guess)} done, "
                      f"{runs[label(tol, guess)]['seconds']:.0f} s", flush=True)
            ref_key = label(0.0, "lagged")
            reference = runs[ref_key]["values"]
            reruns = {f: run_variant(script_name, script_argv + ["--rho", f"{rho * f:g}"], 0.0,
                                     "lagged", outdir) for f in args.density_factors}
            spread = {k: max([changes(r["values"], reference)[k] for r in reruns.values()],
                             default=np.nan) for k in reference}
            most = max(s[0] for s in runs[ref_key]["steps"])
            print(f"\n== {case}: {script_name} {' '.join(script_argv)} ==")
            print(f"  {'variant':28s} {'steps':>5s} {'passes':>6s} {'short':>6s} "
                  f"{'iters':>6s} {'seconds':>8s} {'checks':>6s}")
            for key, r in runs.items():
                s = step_summary(r, most)
                r["summary"] = s
                print(f"  {key:28s} {s['steps']:5d} {s['passes']:6.2f} {s['short']:6.1%} "
                      f"{s['iterations']:6.1f} {r['seconds']:8.1f} "
                      f"{r['checks'][0]:>3d}/{r['checks'][1]:<2d}")
            for f, r in reruns.items():
                print(f"  {'rho x ' + format(f, 'g'):28s} {len(r['steps']):5d} "
                      f"{'':6s} {'':6s} {'':6s} {r['seconds']:8.1f} "
                      f"{r['checks'][0]:>3d}/{r['checks'][1]:<2d}")
            others = [k for k in runs if k != ref_key]
            head = f"  {'quantity':34s} {'tol 0':>11s} " + " ".join(
                f"{k.replace('tol ', '').replace(', ', ' ')[:14]:>14s}" for k in others) \
                + f" {'round-off':>9s}"
            print(head)
            print("  " + "-" * (len(head) - 2))
            for name, value in reference.items():
                ch = [changes(runs[k]["values"], reference)[name] for k in others]
                star = " *" if abs(value) < NEAR_ZERO else ""
                print(f"  {name + star:34s} {value:11.5g} "
                      + " ".join(f"{c:14.1e}" for c in ch) + f" {spread[name]:9.1e}")
            print(f"  * near zero (|value| < {NEAR_ZERO:g}): judged by its check")
            print("  the first pass's change of the mean stress (/ rho g L) over the steps:")
            firsts = {}
            for guess in GUESSES:
                key = label(0.0, guess)
                if key in runs:
                    firsts[guess] = first_change_table(runs[key], [t for t in tols if t > 0])
                    ft = firsts[guess]
                    print(f"    {guess:12s} 10 % {ft['q10']:.2e}  median {ft['median']:.2e}  "
                          f"90 % {ft['q90']:.2e};  below: " + ", ".join(
                              f"{t:g}: {v:.0%}" for t, v in ft["below"].items()), flush=True)
            out[case] = dict(script=script_name, argv=script_argv,
                             runs={k: dict(values=r["values"], summary=r["summary"],
                                           seconds=r["seconds"], checks=r["checks"])
                                   for k, r in runs.items()},
                             spread=spread, first_change=firsts,
                             density_reruns={f"{f:g}": dict(values=r["values"],
                                                           seconds=r["seconds"])
                                             for f, r in reruns.items()})
            if args.json is not None:
                args.json.write_text(json.dumps(out, indent=1, default=float))


if __name__ == "__main__":
    main()
