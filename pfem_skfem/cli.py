"""Command line: ``pfem-skfem verify [CASE ...] [--quick] [--json-dir DIR]``.

Runs the verification scripts (one per thesis benchmark, in ``verification/``),
each in its own process, shows progress, prints one summary table and exits
non-zero if a case misses its tolerance or fails to run.
"""
import argparse
from concurrent.futures import ThreadPoolExecutor
import json
import os
from pathlib import Path
import subprocess
import sys
import time


def verification_dir():
    """The ``verification/`` folder of the source tree (an editable install or a clone)."""
    for base in (Path(__file__).resolve().parents[1], Path.cwd()):
        d = base / "verification"
        if d.is_dir():
            return d
    raise SystemExit("cannot find the verification/ folder: run from a clone of pfem_skfem")


def available_cases():
    return sorted(p.stem for p in verification_dir().glob("*.py") if not p.stem.startswith("_"))


def run_case(case, *, quick, json_dir, outdir, figures, extra):
    """Run one verification script; return (case, exit code, seconds, json path, log)."""
    script = verification_dir() / f"{case}.py"
    json_path = Path(json_dir) / f"{case}.json"
    cmd = [sys.executable, str(script), "--json", str(json_path), "--outdir", str(outdir)]
    cmd += ["--quick"] if quick else []
    cmd += [] if figures else ["--no-figures"]
    cmd += list(extra)
    t0 = time.perf_counter()
    env = {**os.environ, "MPLBACKEND": "Agg"}
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
    return case, proc.returncode, time.perf_counter() - t0, json_path, proc.stdout + proc.stderr


def summary_table(rows):
    head = (f"{'case':22s} {'quantity':28s} {'ours':>12s} {'reference':>14s} "
            f"{'error':>9s} {'tol':>8s}  pass")
    lines = [head, "-" * len(head)]
    for case, q in rows:
        if q is None:
            lines.append(f"{case:22s} {'(did not run)':28s}")
            continue
        if "lower" in q:                     # an interval; JSON writes infinite ends as null
            lo = "-inf" if q["lower"] is None else f"{q['lower']:.4g}"
            hi = "inf" if q["upper"] is None else f"{q['upper']:.4g}"
            ref = f"[{lo},{hi}]"
        else:
            ref = "-" if q["reference"] is None else f"{q['reference']:.6g}"
        val = "nan" if q["value"] is None else f"{q['value']:.6g}"
        err = "-" if q["rel_error"] is None else f"{q['rel_error']:.2e}"
        lines.append(f"{case:22s} {q['name']:28s} {val:>12s} {ref:>14s} {err:>9s} "
                     f"{q['tolerance']:8.1e}  {'yes' if q['pass'] else 'NO'}")
    return "\n".join(lines)


def cmd_verify(args):
    cases = args.cases or available_cases()
    unknown = sorted(set(cases) - set(available_cases()))
    if unknown:
        raise SystemExit(f"unknown case(s): {', '.join(unknown)}; "
                         f"available: {', '.join(available_cases())}")
    Path(args.json_dir).mkdir(parents=True, exist_ok=True)
    print(f"running {len(cases)} verification case(s){' (quick)' if args.quick else ''} "
          f"on {args.jobs} process(es)", flush=True)
    t0 = time.perf_counter()
    results = {}

    def job(case):
        return run_case(case, quick=args.quick, json_dir=args.json_dir, outdir=args.outdir,
                        figures=not args.no_figures, extra=args.extra or [])

    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for i, (case, code, secs, path, log) in enumerate(pool.map(job, cases), 1):
            results[case] = (code, path, log)
            status = "ok" if code == 0 else ("FAILED CHECK" if code == 1 else f"ERROR {code}")
            print(f"[{i}/{len(cases)}] {case:22s} {secs:7.1f} s  {status}", flush=True)
            if code not in (0, 1) or args.verbose:
                print(log[-4000:], flush=True)
    rows, failed = [], []
    for case in cases:
        code, path, _ = results[case]
        if path.exists() and code in (0, 1):
            data = json.loads(path.read_text())
            rows += [(case, q) for q in data["quantities"]]
        else:
            rows.append((case, None))
        if code != 0:
            failed.append(case)
    print()
    print(summary_table(rows))
    print(f"\n{len(cases) - len(failed)}/{len(cases)} case(s) passed in "
          f"{time.perf_counter() - t0:.0f} s; JSON in {args.json_dir}/, figures in {args.outdir}/")
    if failed:
        print("failed: " + ", ".join(failed))
    return 1 if failed else 0


def main(argv=None):
    parser = argparse.ArgumentParser(prog="pfem-skfem", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    v = sub.add_parser("verify", help="run verification cases and print a summary table")
    v.add_argument("cases", nargs="*", help="cases to run (default: all)")
    v.add_argument("--quick", action="store_true", help="small sizes (seconds to a minute each)")
    v.add_argument("--json-dir", default="results", help="where to write <case>.json")
    v.add_argument("--outdir", default="results", help="where to write figures")
    v.add_argument("--no-figures", action="store_true")
    v.add_argument("--jobs", type=int, default=1, help="cases run at once")
    v.add_argument("--verbose", action="store_true", help="show each script's output")
    v.add_argument("--extra", nargs=argparse.REMAINDER,
                   help="further options passed to every script")
    v.set_defaults(func=cmd_verify)
    ls = sub.add_parser("list", help="list the verification cases")
    ls.set_defaults(func=lambda a: print("\n".join(available_cases())) or 0)
    args = parser.parse_args(argv)
    if getattr(args, "jobs", 1) < 1:
        parser.error("--jobs must be at least 1")
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())
