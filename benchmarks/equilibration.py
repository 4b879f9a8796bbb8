"""Clarabel's equilibration off against on: every benchmark's quantities, checks and time.

Issue 40, item 3. On the conic data of the a = 1 column, Clarabel's default Ruiz
equilibration left the displacement increment (the equilibrium dual) 100-1,800x less
accurate than the same solve with ``equilibrate_enable=False``, at about the same cost.
This script asks whether that shows in the benchmarks' own figures: each verification
case given runs in-process at ``--quick`` size (``run(build_parser().parse_args([...]))``),
twice, round-robin: once with Clarabel's settings as they are (equilibration on, the
default) and once with ``equilibrate_enable=False`` added to them, for every Clarabel
solve (the cvxpy statements through ``conic.CLARABEL_DEFAULTS`` /
``ClarabelBackend.defaults`` and the direct PFEM / dynamic assembly through
``problems.backends.direct.SETTINGS``; restored after). Each solve is recorded (iterations,
status, and whether it really ran with equilibration off). The table gives, per case, the
Report quantities compared, the largest relative difference between the two runs (which
quantity), the checks each run passes, the solves, mean iterations, 'AlmostSolved' ends,
the bound problems' retries and the wall time ratio off / on (with ``--repeats N`` the
order alternates and the least time of each setting is kept).

Quantities whose value is at round-off level (|value| <= 1e-6 in both runs: residuals,
drifts) are compared by their check only, not by a relative difference.

The bound problems (``pfem_skfem/problems/bounds.py``) retry with equilibration off
(``BOUND_RETRIES``) when Clarabel stops with a NumericalError or an uncertified
'AlmostSolved'; the 'retries' column counts the bound solves that needed it
(``info.extra['bound']['settings']`` not empty).

``--density CASE`` adds the issue's density-rerun spread for a PFEM case (default the
plane granular column, c = 0): its run at the script's density rho, at 2 rho (c = 0: the
same run bit for bit by design: checked with equilibration off as on) and at
``--density-factors`` x rho (3 and 5: only round-off depends on them); the spread of each
quantity is its largest relative change from the rho run, per setting.

Run: python benchmarks/equilibration.py [--cases strip_footing cantilever ...]
     [--repeats 1] [--density granular_column_plane] [--detail]
(the default cases take about 3 minutes on 2 loaded cores; the density study of the
column, 8 runs, about 3.5 minutes more)
"""
import argparse
from contextlib import contextmanager, redirect_stdout
import importlib
import io
import os
from pathlib import Path
import sys
import tempfile
import time
import warnings

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))       # the verification scripts
import clarabel                                                     # noqa: E402

from pfem_skfem.harness.report import relative_error  # noqa: E402

CASES = ("strip_footing", "thick_cylinder", "circular_footing", "cantilever",
         "plastic_vibration", "sliding_box", "buried_pipe", "limit_bounds")
EXTRA_ARGV = {"granular_column_plane": ["--workers", "1"]}
NEAR_ZERO = 1e-6                 # a residual or drift: judged by its check, not a ratio
SETTING = dict(equilibrate_enable=False)


@contextmanager
def equilibration(enabled, record):
    """Every Clarabel solve inside runs with equilibration as ``enabled`` (True: the
    settings as they are); ``record`` gets (iterations, status, equilibrate_enable) per
    solve and ('bound', settings) per bound problem solved."""
    from pfem_skfem.problems import bounds, conic
    from pfem_skfem.problems.backends import direct
    saved = (conic.CLARABEL_DEFAULTS, conic.ClarabelBackend.defaults,
             direct.SETTINGS, clarabel.DefaultSolver, bounds._solve_bound)
    solver_class, solve_bound = clarabel.DefaultSolver, bounds._solve_bound
    if not enabled:
        conic.CLARABEL_DEFAULTS = {**conic.CLARABEL_DEFAULTS, **SETTING}
        conic.ClarabelBackend.defaults = {**conic.ClarabelBackend.defaults, **SETTING}
        direct.SETTINGS = {**direct.SETTINGS, **SETTING}

    class Solver:                       # records every solve, cvxpy's and the direct ones
        def __init__(self, P, q, A, b, cones, opts):
            self._equilibrate = bool(opts.equilibrate_enable)
            self._solver = solver_class(P, q, A, b, cones, opts)

        def solve(self):
            sol = self._solver.solve()
            record.append((int(sol.iterations), str(sol.status), self._equilibrate))
            return sol

        def __getattr__(self, name):
            return getattr(self._solver, name)

    def recorded_bound(*a, **k):
        info = solve_bound(*a, **k)
        record.append(("bound", dict(info.extra.get("bound", {}).get("settings") or {})))
        return info

    clarabel.DefaultSolver, bounds._solve_bound = Solver, recorded_bound
    try:
        yield
    finally:
        (conic.CLARABEL_DEFAULTS, conic.ClarabelBackend.defaults, direct.SETTINGS,
         clarabel.DefaultSolver, bounds._solve_bound) = saved


def run_case(name, enabled, outdir, more=()):
    """One run of verification case ``name`` at --quick: ({quantity: (value, passed)},
    record, seconds)."""
    script = importlib.import_module(f"verification.{name}")
    argv = ["--quick", "--no-figures", "--quiet", "--outdir", str(outdir),
            *EXTRA_ARGV.get(name, []), *more]
    args = script.build_parser().parse_args(argv)
    record = []
    t0 = time.perf_counter()
    try:
        with equilibration(enabled, record), redirect_stdout(io.StringIO()), \
                warnings.catch_warnings():
            warnings.simplefilter("ignore")
            report = script.run(args)
    except Exception as err:        # a solver failure is a result: say which solve, how
        seconds = time.perf_counter() - t0
        last = next((r[1] for r in reversed(record) if r[0] != "bound"), "?")
        what = str(err).split(":")[0]
        return None, record, seconds, f"failed: {last} in {what}"
    seconds = time.perf_counter() - t0
    values = {q.name: (q.value, bool(q.passed)) for q in report.quantities}
    return values, record, seconds, report


def differences(values, reference):
    """{quantity: relative difference} of the quantities both runs have (NaN: at round-off
    level in both, or not finite)."""
    out = {}
    for k, (ref, _) in reference.items():
        if k not in values:
            continue
        val = values[k][0]
        try:
            val, ref_f = float(val), float(ref)
        except (TypeError, ValueError):
            out[k] = 0.0 if val == ref else np.inf
            continue
        if not (np.isfinite(val) and np.isfinite(ref_f)):
            out[k] = 0.0 if (val == ref_f or (np.isnan(val) and np.isnan(ref_f))) else np.inf
        elif max(abs(val), abs(ref_f)) <= NEAR_ZERO:
            out[k] = np.nan
        else:
            out[k] = relative_error(val, ref_f)
    return out


def solves(record):
    rows = [r for r in record if r[0] != "bound"]
    iters = np.array([r[0] for r in rows]) if rows else np.zeros(1)
    almost = sum(r[1] == "AlmostSolved" for r in rows)
    off = sum(not r[2] for r in rows)
    bounds_ = [r[1] for r in record if r[0] == "bound"]
    retries = sum(bool(s) for s in bounds_)
    return dict(n=len(rows), iters=float(iters.mean()), almost=almost, eq_off=off,
                bounds=len(bounds_), retries=retries)


def checks(values):
    return f"{sum(p for _, p in values.values())}/{len(values)}"


def largest(diff):
    finite = {k: v for k, v in diff.items() if not np.isnan(v)}
    if not finite:
        return np.nan, "-"
    k = max(finite, key=finite.get)
    return finite[k], k


def _checks_or_failure(run):
    values, _, _, report = run
    return checks(values) if values is not None else report


def compare_cases(cases, repeats, outdir, detail):
    rows = []
    for name in cases:
        runs = {True: [], False: []}
        for rep in range(repeats):                 # round-robin: on, off; then off, on ...
            order = (True, False) if rep % 2 == 0 else (False, True)
            for enabled in order:
                runs[enabled].append(run_case(name, enabled, outdir))
        on, off = runs[True][0], runs[False][0]
        t_on = min(r[2] for r in runs[True])
        t_off = min(r[2] for r in runs[False])
        ok = on[0] is not None and off[0] is not None
        diff = differences(off[0], on[0]) if ok else {}
        worst, which = largest(diff) if ok else (np.nan, "-")
        s_on, s_off = solves(on[1]), solves(off[1])
        if s_off["eq_off"] != s_off["n"]:
            raise RuntimeError(f"{name}: {s_off['n'] - s_off['eq_off']} solves ran with "
                               "equilibration on in the 'off' run: the patch missed them")
        rows.append((name, len(diff), sum(np.isnan(v) for v in diff.values()), worst, which,
                     _checks_or_failure(on), _checks_or_failure(off), s_on, s_off, t_on,
                     t_off, ok))
        print(f"  {name}: on {t_on:.1f} s ({_checks_or_failure(on)}), off {t_off:.1f} s "
              f"({_checks_or_failure(off)}), largest difference {worst:.1e} ({which})",
              flush=True)
        if detail and ok:
            for k, d in diff.items():
                v_on, p_on = on[0][k]
                v_off, p_off = off[0][k]
                print(f"      {k:40s} on {_fmt(v_on):>12s} {'ok' if p_on else 'FAIL'}  "
                      f"off {_fmt(v_off):>12s} {'ok' if p_off else 'FAIL'}  diff {d:.1e}")
    print("\n| case | quantities (round-off level) | largest rel. difference off vs on "
          "(quantity) | checks on | checks off | solves on / off | iterations per solve "
          "on / off | AlmostSolved on / off | bound retries on / off | time off / on |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for (name, n, nz, worst, which, c_on, c_off, s_on, s_off, t_on, t_off, ok) in rows:
        retries = (f"{s_on['retries']}/{s_on['bounds']} / {s_off['retries']}/{s_off['bounds']}"
                   if s_on["bounds"] or s_off["bounds"] else "-")
        ratio = f"{t_off / t_on:.2f}" if ok else "- (a run failed)"
        print(f"| {name} | {n} ({nz}) | {worst:.1e} ({which}) | {c_on} | {c_off} | "
              f"{s_on['n']} / {s_off['n']} | {s_on['iters']:.1f} / {s_off['iters']:.1f} | "
              f"{s_on['almost']} / {s_off['almost']} | {retries} | {ratio} |")
    return rows


def _fmt(v):
    try:
        return f"{float(v):.6g}"
    except (TypeError, ValueError):
        return str(v)


def density_spread(name, factors, outdir, detail):
    """The spread of ``name``'s quantities over density reruns, equilibration on and off."""
    script = importlib.import_module(f"verification.{name}")
    rho = script.build_parser().parse_args(["--quick"]).rho
    print(f"\n== density reruns of {name} --quick (rho = {rho:g}; x 2: bit for bit when "
          f"c = 0; x {', '.join(f'{f:g}' for f in factors)}: round-off) ==", flush=True)
    results = {}
    for factor in (1.0, 2.0, *factors):            # round-robin: on, off at each density
        for enabled in (True, False):
            more = [] if factor == 1.0 else ["--rho", f"{rho * factor:.17g}"]
            t0 = time.perf_counter()
            results[enabled, factor] = run_case(name, enabled, outdir, more)
            print(f"  rho x {factor:g}, equilibration {'on' if enabled else 'off'}: "
                  f"{time.perf_counter() - t0:.1f} s", flush=True)
    print("\n| equilibration | quantities | x 2 identical (values) | spread x "
          f"{', '.join(f'{f:g}' for f in factors)} (largest, quantity) | checks |")
    print("|---|---|---|---|---|")
    spreads = {}
    failed = {k: r[3] for k, r in results.items() if r[0] is None}
    for (enabled, factor), why in failed.items():
        print(f"| {'on' if enabled else 'off'} | rho x {factor:g} {why} | | | |")
    if failed:
        return results
    for enabled in (True, False):
        base = results[enabled, 1.0][0]
        same2 = all(results[enabled, 2.0][0][k][0] == v or
                    (isinstance(v, float) and np.isnan(v) and np.isnan(results[enabled, 2.0][0][k][0]))
                    for k, (v, _) in base.items())
        spread = {}
        for f in factors:
            for k, d in differences(results[enabled, f][0], base).items():
                spread[k] = np.nanmax([spread.get(k, np.nan), d])
        spreads[enabled] = spread
        worst, which = largest(spread)
        all_checks = ", ".join(checks(results[enabled, f][0]) for f in (1.0, 2.0, *factors))
        print(f"| {'on' if enabled else 'off'} | {len(base)} | {'yes' if same2 else 'NO'} | "
              f"{worst:.1e} ({which}) | {all_checks} |")
    off_vs_on = differences(results[False, 1.0][0], results[True, 1.0][0])
    worst, which = largest(off_vs_on)
    print(f"\noff vs on at rho: largest relative difference {worst:.1e} ({which})")
    if detail:
        print(f"\n{'quantity':40s} {'spread on':>10s} {'spread off':>10s} {'off vs on':>10s}")
        for k in spreads[True]:
            print(f"{k:40s} {spreads[True][k]:10.1e} {spreads[False].get(k, np.nan):10.1e} "
                  f"{off_vs_on.get(k, np.nan):10.1e}")
    return results


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--cases", nargs="*", default=list(CASES),
                   help="verification scripts run at --quick (default: the cheap static "
                        "and dynamic ones; PFEM ones such as granular_column_plane work too)")
    p.add_argument("--repeats", type=int, default=1,
                   help="runs of each setting (the order alternates; least time kept)")
    p.add_argument("--density", metavar="CASE", default=None,
                   help="also the density-rerun spread of this PFEM case, e.g. "
                        "granular_column_plane")
    p.add_argument("--density-factors", type=float, nargs="+", default=[3.0, 5.0],
                   help="the round-off reruns' density factors (x 2 is always run)")
    p.add_argument("--detail", action="store_true", help="every quantity, on and off")
    p.add_argument("--off-extra", metavar="NAME=VALUE", nargs="*", default=[],
                   help="more Clarabel settings for the 'off' run, e.g. "
                        "static_regularization_constant=1e-7 (bounds.BOUND_RETRIES' pair)")
    args = p.parse_args(argv)
    for item in args.off_extra:
        key, value = item.split("=", 1)
        SETTING[key] = (value == "True") if value in ("True", "False") else float(value)
    load = os.getloadavg()
    print(f"load average {load[0]:.2f} / {load[1]:.2f} / {load[2]:.2f} on {os.cpu_count()} "
          f"cores; Clarabel {clarabel.__version__}; off = the settings as they are plus "
          f"{', '.join(f'{k}={v}' for k, v in SETTING.items())}", flush=True)
    with tempfile.TemporaryDirectory() as outdir:
        if args.cases:
            compare_cases(args.cases, args.repeats, outdir, args.detail)
        if args.density:
            density_spread(args.density, args.density_factors, outdir, args.detail)


if __name__ == "__main__":
    main()
