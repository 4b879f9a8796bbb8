"""Command line: ``pfem-skfem verify [CASE ...] [--quick] [--json-dir DIR]``.

Runs the verification scripts (one per thesis benchmark, in ``verification/``),
each in its own process, shows progress, prints one summary table and exits
non-zero if a case misses its tolerance or fails to run.

``pfem-skfem run SCENE.toml [--steps N] [--out DIR] [--resume]`` runs a scene written
as a TOML file (:mod:`pfem_skfem.scene.files`) and writes its VTU/PVD series, the step
records (``history.json``), the scene as run (``scene.toml``) and a checkpoint into an
output folder; ``pfem-skfem run --example column [PATH]`` writes a commented example.
"""
import argparse
from concurrent.futures import ThreadPoolExecutor
import json
import os
from pathlib import Path
import subprocess
import sys
import time

from .report import nonnegative_int, positive_int, workers


def verification_dir():
    """The ``verification/`` folder of the source tree (an editable install or a clone)."""
    for base in (Path(__file__).resolve().parents[1], Path.cwd()):
        d = base / "verification"
        if d.is_dir():
            return d
    raise SystemExit("cannot find the verification/ folder: run from a clone of pfem_skfem")


def available_cases():
    return sorted(p.stem for p in verification_dir().glob("*.py") if not p.stem.startswith("_"))


def run_case(case, *, quick, json_dir, outdir, figures, extra, live=False):
    """Run one verification script; return (case, exit code, seconds, json path, log).

    With ``live`` the script's stderr (its progress bars) goes to the terminal;
    otherwise it runs with ``--quiet`` and its stderr is part of the log.
    """
    script = verification_dir() / f"{case}.py"
    json_path = Path(json_dir) / f"{case}.json"
    cmd = [sys.executable, str(script), "--json", str(json_path), "--outdir", str(outdir)]
    cmd += ["--quick"] if quick else []
    cmd += [] if figures else ["--no-figures"]
    cmd += [] if live else ["--quiet"]
    cmd += list(extra)
    t0 = time.perf_counter()
    env = {**os.environ, "MPLBACKEND": "Agg"}
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=None if live else subprocess.PIPE,
                          text=True, env=env)
    log = proc.stdout + (proc.stderr or "")
    return case, proc.returncode, time.perf_counter() - t0, json_path, log


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

    def report(i, case, code, secs, log):
        results[case] = (code, json_path(case), log)
        status = "ok" if code == 0 else ("FAILED CHECK" if code == 1 else f"ERROR {code}")
        write(f"[{i}/{len(cases)}] {case:22s} {secs:7.1f} s  {status}")
        if code not in (0, 1) or args.verbose:
            write(log[-4000:])

    def json_path(case):
        return Path(args.json_dir) / f"{case}.json"

    if args.jobs == 1:                       # one case at a time: its own progress bars live
        def write(text):
            print(text, flush=True)
        for i, case in enumerate(cases, 1):
            print(f"[{i}/{len(cases)}] {case} ...", flush=True)
            _, code, secs, _, log = run_case(case, quick=args.quick, json_dir=args.json_dir,
                                             outdir=args.outdir, figures=not args.no_figures,
                                             extra=args.extra or [], live=not args.quiet)
            report(i, case, code, secs, log)
    else:                                    # several at once: one bar over the cases
        from tqdm import tqdm
        running = set()

        def job(case):
            running.add(case)
            bar.set_postfix_str("running " + ", ".join(sorted(running)))
            try:
                return run_case(case, quick=args.quick, json_dir=args.json_dir,
                                outdir=args.outdir, figures=not args.no_figures,
                                extra=args.extra or [])
            finally:
                running.discard(case)

        with tqdm(total=len(cases), unit="case", file=sys.stderr, disable=args.quiet,
                  dynamic_ncols=True) as bar, ThreadPoolExecutor(max_workers=args.jobs) as pool:
            def write(text):
                tqdm.write(text, file=sys.stdout)
            for i, (case, code, secs, _, log) in enumerate(pool.map(job, cases), 1):
                report(i, case, code, secs, log)
                bar.update()
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


# -- run: a scene file -----------------------------------------------------------------
class ProgressBar:
    """The progress bar of a run (tqdm on stderr): step, time t, solver iterations, ETA."""

    def __init__(self, first, last, stream=None):
        from tqdm import tqdm
        self.stream = sys.stderr if stream is None else stream
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.bar = tqdm(total=last - first, initial=0, desc=f"steps {first + 1}-{last}",
                        unit="step", file=self.stream, dynamic_ncols=True,
                        mininterval=0.5 if self.tty else 30.0)

    def __call__(self, i, n, record):
        self.bar.set_postfix_str(f"t = {record['time']:.4g}, it = {record['iterations']}",
                                 refresh=False)
        self.bar.update(i - self.bar.n)
        if i == n:
            self.close()

    def close(self):
        self.bar.close()


def steps_until(t_end, dt):
    """Steps of dt to reach t_end: t_end / dt rounded up (to the nearest within 1e-9)."""
    import math
    n = t_end / dt
    near = round(n)
    return max(1, near if abs(n - near) <= 1e-9 * max(1.0, n) else math.ceil(n))


def _write_history(path, records):
    path.write_text(json.dumps(records, indent=1) + "\n")


class RunError(Exception):
    """A run that cannot start: the message says why (exit code 2)."""


def cmd_run(args):
    try:
        return _run(args)
    except RunError as err:
        print(f"pfem-skfem run: error: {err}", file=sys.stderr)
        return 2


def _run(args):
    from dataclasses import replace
    from .scene import Output
    from .scene.files import EXAMPLES, example_text, load_scene

    if args.example:
        if args.example not in EXAMPLES:
            raise RunError(f"no example {args.example!r}; examples: {', '.join(EXAMPLES)}")
        text = example_text(args.example)
        if args.scene == "-":
            sys.stdout.write(text)
            return 0
        path = Path(args.scene or f"{args.example}.toml")
        if path.exists():
            raise RunError(f"{path} exists; not overwritten")
        path.write_text(text)
        print(f"wrote {path}; run it with: pfem-skfem run {path}")
        return 0
    if not args.scene:
        raise RunError("give a scene file (pfem-skfem run SCENE.toml), or --example column")
    path = Path(args.scene)
    if not path.is_file():
        raise RunError(f"no scene file {path}")
    try:
        scene = load_scene(path)
    except ValueError as err:                        # a located SceneFileError
        raise RunError(str(err)) from None
    out = Path(args.out or scene.output.directory)
    every = scene.output.every if args.every is None else args.every
    checkpoint_every = (scene.output.checkpoint_every if args.checkpoint_every is None
                        else args.checkpoint_every)
    if every < 0 or checkpoint_every < 0:
        raise RunError("--every and --checkpoint-every must be >= 0")
    scene = replace(scene, output=Output(str(out), every, checkpoint_every))
    if args.steps is not None:
        if args.steps < 1:
            raise RunError(f"--steps must be >= 1, got {args.steps}")
        last = args.steps
    elif scene.t_end is not None:
        last = steps_until(scene.t_end, scene.config.dt)
    else:
        raise RunError(f"{path}: the scene has no t_end: give --steps N")
    return _advance(scene, out, last, args.resume, args.quiet)


def _advance(scene, out, last, resume, quiet):
    """Run ``scene`` to step ``last`` in folder ``out`` (from its checkpoint if ``resume``)."""
    from dataclasses import replace
    from .drivers.pfem_loop import load_checkpoint, run, save_checkpoint
    from .io import TimeSeries
    from .problems.conic import SolverError
    from .scene.files import load_scene, scene_to_toml

    checkpoint, history, copy = out / "checkpoint.npz", out / "history.json", out / "scene.toml"
    series = TimeSeries(out, "scene") if scene.output.every else None
    if resume:
        if not checkpoint.is_file() or not copy.is_file():
            raise RunError(f"nothing to resume in {out}/ (no checkpoint.npz and scene.toml)")
        ran = load_scene(copy)
        # the numbers of the run must be the same; its length and output may change
        if replace(ran, t_end=None, output=scene.output) != replace(scene, t_end=None):
            raise RunError(f"the scene differs from the one run in {out}/scene.toml: "
                           "resume only the same scene (t_end and [output] may change)")
        state = load_checkpoint(checkpoint)
        records = [r for r in json.loads(history.read_text()) if r["step"] <= state.step] \
            if history.is_file() else []
    else:
        out.mkdir(parents=True, exist_ok=True)
        state, records = scene.initial_state(), []
    if series is not None:           # the steps up to the checkpoint's (none on a new run)
        series.resume(state.time if resume else float("-inf"))
    copy.write_text(scene_to_toml(scene, header="the scene as run by pfem-skfem run"))
    first = state.step
    if first >= last:
        print(f"{out}/ is already at step {first} (>= {last}): nothing to run")
        return 0
    done = [state]

    def on_step(st, record, result):
        records.append(record)
        done[0] = st
        if scene.output.checkpoint_every and st.step % scene.output.checkpoint_every == 0:
            _write_history(history, records)         # with the checkpoint just written

    bar = None if quiet else ProgressBar(first, last)
    try:
        state, _ = run(state, scene, last - first, checkpoint=checkpoint,
                       checkpoint_every=scene.output.checkpoint_every, series=series,
                       save_every=scene.output.every, on_step=on_step, progress=bar)
    except (SolverError, KeyboardInterrupt) as err:
        save_checkpoint(checkpoint, done[0])         # the last step completed, to resume
        _write_history(history, records)
        if bar is not None:
            bar.close()
        what = ("interrupted" if isinstance(err, KeyboardInterrupt) else
                f"solver failed ({err}; status {err.status})")
        n = done[0].step
        kept = f"steps 1-{n} are" if n > 1 else ("step 1 is" if n == 1 else "the initial state is")
        print(f"pfem-skfem run: {what} in step {n + 1}; {kept} in {out}/ (--resume continues "
              f"from step {n})", file=sys.stderr)
        return 3 if isinstance(err, SolverError) else 130
    save_checkpoint(checkpoint, state)
    _write_history(history, records)
    vtus = f"scene.pvd ({len(series.entries)} VTU), " if series is not None else ""
    print(f"steps {first + 1}-{state.step} (t = {state.time:.6g}) written to {out}/: {vtus}"
          "history.json, scene.toml, checkpoint.npz")
    return 0


def main(argv=None):
    parser = argparse.ArgumentParser(prog="pfem-skfem", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    v = sub.add_parser("verify", help="run verification cases and print a summary table")
    v.add_argument("cases", nargs="*", help="cases to run (default: all)")
    v.add_argument("--quick", action="store_true", help="small sizes (seconds to a minute each)")
    v.add_argument("--json-dir", default="results", help="where to write <case>.json")
    v.add_argument("--outdir", default="results", help="where to write figures")
    v.add_argument("--no-figures", action="store_true")
    v.add_argument("--jobs", type=workers, default=1, help="cases run at once")
    v.add_argument("--quiet", action="store_true",
                   help="no progress (the cases' own bars with --jobs 1; one bar otherwise)")
    v.add_argument("--verbose", action="store_true", help="show each script's output")
    v.add_argument("--extra", nargs=argparse.REMAINDER,
                   help="further options passed to every script")
    v.set_defaults(func=cmd_verify)
    ls = sub.add_parser("list", help="list the verification cases")
    ls.set_defaults(func=lambda a: print("\n".join(available_cases())) or 0)
    r = sub.add_parser("run", help="run a scene file (TOML); --example column writes one",
                       description="Run a PFEM scene written as a TOML file: a progress bar "
                       "on stderr; the VTU/PVD series, history.json, scene.toml and "
                       "checkpoint.npz in the output folder.")
    r.add_argument("scene", nargs="?", help="the scene file (with --example: where to write "
                   "it, default NAME.toml; '-' for stdout)")
    r.add_argument("--example", metavar="NAME", help="write the commented example NAME "
                   "(column) instead of running")
    r.add_argument("--steps", type=positive_int, help="run until step N (default: until t_end)")
    r.add_argument("--out", help="output folder (default: the file's output.directory)")
    r.add_argument("--resume", action="store_true",
                   help="continue from the output folder's checkpoint")
    r.add_argument("--every", type=nonnegative_int, help="a VTU every K steps (0: none; default: "
                   "output.every)")
    r.add_argument("--checkpoint-every", type=nonnegative_int, help="a checkpoint every K steps "
                   "(default: output.checkpoint_every; one is always written at the end)")
    r.add_argument("--quiet", "--no-progress", dest="quiet", action="store_true",
                   help="no progress bar")
    r.set_defaults(func=cmd_run)
    args = parser.parse_args(argv)
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())
