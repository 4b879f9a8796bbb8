"""Command line: ``pfem-skfem list | verify | run`` (plain-text help: :data:`DESCRIPTION`).

``pfem-skfem list`` names the verification cases with one line each;
``pfem-skfem verify [CASE ...] [--quick] [--json-dir DIR]`` runs the verification
scripts (one per thesis benchmark, in ``verification/``), each in its own process, shows
progress, prints one summary table and exits non-zero if a case misses its tolerance or
fails to run.

``pfem-skfem run SCENE.toml [--steps N] [--out DIR] [--resume | --overwrite]`` runs a
scene written as a TOML file (:mod:`pfem_skfem.scene.files`) and writes its VTU/PVD
series, the step records (``history.json``), the scene as run (``scene.toml``) and a
checkpoint into an output folder kept safe by :mod:`pfem_skfem.runfolder`;
``pfem-skfem run --example NAME [PATH]`` writes a commented example.
"""
import argparse
import json
import os
from pathlib import Path
import subprocess
import sys
import time

# light imports only: `pfem-skfem --help` and `list` import no science (numpy, scipy, cvxpy,
# scene); `verify` and `run` import what they use when they run (tests/test_cli.py)
from .harness.options import (nonnegative_int, positive_int, SOLVER_NAMES, STEP_SOLVER_NAMES,
                              workers)
from .drivers.stopping import DEFAULT_CHECKPOINT_EVERY, RunFolderError
from .harness.progress import StepBar, progress, progress_bar


def verification_dir():
    """The ``verification/`` folder of the source tree (an editable install or a clone)."""
    for base in (Path(__file__).resolve().parents[1], Path.cwd()):
        d = base / "verification"
        if d.is_dir():
            return d
    raise SystemExit("cannot find the verification/ folder: run from a clone of pfem_skfem")


def default_jobs():
    """The cores this process may use (its CPU affinity, else ``os.cpu_count()``): the
    default ``--jobs`` of ``pfem-skfem verify``."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):        # no affinity on this platform (macOS, Windows)
        return os.cpu_count() or 1


def available_cases():
    return sorted(p.stem for p in verification_dir().glob("*.py") if not p.stem.startswith("_"))


def json_name(case, quick):
    """``<case>.quick.json`` for a --quick run, ``<case>.json`` at full size: the quick
    run never replaces a full-size result."""
    return f"{case}.quick.json" if quick else f"{case}.json"


# the scripts that solve no conic problem and so take no --solver
NO_SOLVER = frozenset({"alpha_shape"})


def run_case(case, *, quick, json_dir, outdir, figures, extra, live=False, solver=None):
    """Run one verification script; return (case, exit code, seconds, json path, log).

    With ``live`` the script's stderr (its progress bars) goes to the terminal;
    otherwise it runs with ``--quiet`` and its stderr is part of the log.
    """
    script = verification_dir() / f"{case}.py"
    json_path = Path(json_dir) / json_name(case, quick)
    cmd = [sys.executable, str(script), "--json", str(json_path), "--outdir", str(outdir)]
    cmd += ["--quick"] if quick else []
    cmd += [] if figures else ["--no-figures"]
    cmd += [] if live else ["--quiet"]
    cmd += ["--solver", solver] if solver and case not in NO_SOLVER else []
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


def unknown_cases(cases):
    """A usage message for the names in ``cases`` that are no verification case (each with
    its nearest case, difflib), or None when all are cases."""
    import difflib
    known = available_cases()
    unknown = [c for c in cases if c not in known]
    if not unknown:
        return None
    parts = []
    for case in unknown:
        near = difflib.get_close_matches(case, known, n=1)
        parts.append(f"unknown case {case!r}" + (f"; did you mean {near[0]!r}?" if near else ""))
    return "; ".join(parts) + " ('pfem-skfem list' names the cases)"


def cmd_verify(args):
    from concurrent.futures import ThreadPoolExecutor
    cases = args.cases or available_cases()
    message = unknown_cases(cases)
    if message:                              # a usage error (2), not a failed check (1)
        print(f"pfem-skfem verify: error: {message}", file=sys.stderr)
        return 2
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
        return Path(args.json_dir) / json_name(case, args.quick)

    if args.jobs == 1:                       # one case at a time: its own progress bars live
        def write(text):
            print(text, flush=True)
        for i, case in enumerate(cases, 1):
            print(f"[{i}/{len(cases)}] {case} ...", flush=True)
            _, code, secs, _, log = run_case(case, quick=args.quick, json_dir=args.json_dir,
                                             outdir=args.outdir, figures=not args.no_figures,
                                             extra=args.extra or [], live=not args.quiet,
                                             solver=args.solver)
            report(i, case, code, secs, log)
    else:                                    # several at once: one bar over the cases
        running = set()

        def job(case):
            running.add(case)
            bar.set_postfix_str("running " + ", ".join(sorted(running)))
            try:
                return run_case(case, quick=args.quick, json_dir=args.json_dir,
                                outdir=args.outdir, figures=not args.no_figures,
                                extra=args.extra or [], solver=args.solver)
            finally:
                running.discard(case)

        with progress_bar(total=len(cases), unit="case", disable=args.quiet) as bar, \
                ThreadPoolExecutor(max_workers=args.jobs) as pool:
            def write(text):
                progress(text, file=sys.stdout)
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
    figures = Path(args.outdir) / "quick" if args.quick else Path(args.outdir)
    print(f"\n{len(cases) - len(failed)}/{len(cases)} case(s) passed in "
          f"{time.perf_counter() - t0:.0f} s; JSON in {args.json_dir}/, figures in {figures}/")
    if failed:
        print("failed: " + ", ".join(failed))
    return 1 if failed else 0


# -- run: a scene file -----------------------------------------------------------------
def steps_until(t_end, dt):
    """Steps of dt to reach t_end: t_end / dt rounded up (to the nearest within 1e-9).

    Raises
    ------
    ValueError when t_end / dt is not a finite number (t_end = inf).
    """
    import math
    n = t_end / dt
    if not math.isfinite(n):
        raise ValueError(f"t_end = {t_end!r} with dt = {dt!r} is no number of steps: give a "
                         "finite t_end, or --steps N")
    near = round(n)
    return max(1, near if abs(n - near) <= 1e-9 * max(1.0, n) else math.ceil(n))


def _me():
    """How the user can call this program again: ``pfem-skfem`` when that is on the PATH
    (an activated venv), else the path they typed (``.venv/bin/pfem-skfem``)."""
    import shutil
    argv0 = sys.argv[0] if sys.argv and sys.argv[0] else ""
    if Path(argv0).name == "pfem-skfem":
        found = shutil.which("pfem-skfem")
        if found and Path(found).resolve() == Path(argv0).resolve():
            return "pfem-skfem"
        return argv0
    on_path = shutil.which("pfem-skfem")
    if on_path and Path(on_path).parent == Path(sys.executable).parent:
        return "pfem-skfem"
    return str(Path(sys.executable).parent / "pfem-skfem")


class RunError(Exception):
    """A run that cannot start: the message says why (exit code 2)."""


def cmd_run(args):
    try:
        return _run(args)
    except (RunError, RunFolderError) as err:
        print(f"pfem-skfem run: error: {err}", file=sys.stderr)
        return 2


def _output_dir(args, scene, path):
    """--out as given (from the current folder), else the scene's output.directory read
    beside the scene file (a relative one)."""
    if args.out:
        return Path(args.out)
    d = Path(scene.output.directory)
    return d if d.is_absolute() else path.parent / d


def _check_not_a_run_file(path, out):
    """Refuse a scene file that is one of the files the run writes into ``out`` (a
    ``scene.toml`` run into its own folder): the run's copy of the scene, or --overwrite,
    would replace the user's file."""
    from .runfolder import RUN_FILES
    for name in RUN_FILES:
        target = Path(out) / name
        if target.exists() and target.resolve() == path.resolve():
            raise RunError(
                f"{path} is the file where the run writes its copy of the scene ({target}): "
                "running it into this folder would replace it (with --overwrite too). "
                f"Rename the scene file (e.g. mv {path} my_scene.toml) or write elsewhere "
                "with --out DIR; nothing written")


def _run(args):
    from dataclasses import replace
    from .runfolder import check_output_dir
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
        try:
            path.write_text(text)
        except OSError as err:
            raise RunError(f"cannot write {path} ({err.strerror or err})") from None
        print(f"wrote {path}; run it with: {_me()} run {path}")
        return 0
    if not args.scene:
        raise RunError(f"give a scene file ({_me()} run SCENE.toml), or --example NAME "
                       f"({', '.join(EXAMPLES)})")
    if args.resume and args.overwrite:
        raise RunError("--resume and --overwrite exclude each other")
    path = Path(args.scene)
    if not path.is_file():
        raise RunError(f"no scene file {path}")
    try:
        scene = load_scene(path)
    except ValueError as err:                        # a located SceneFileError
        raise RunError(str(err)) from None
    out = _output_dir(args, scene, path)
    check_output_dir(out)                            # a file, below a file, read-only
    _check_not_a_run_file(path, out)
    every = scene.output.every if args.every is None else args.every
    checkpoint_every = (scene.output.checkpoint_every if args.checkpoint_every is None
                        else args.checkpoint_every)
    if every < 0 or checkpoint_every < 0:
        raise RunError("--every and --checkpoint-every must be >= 0")
    scene = replace(scene, output=Output(str(out), every, checkpoint_every))
    if args.solver is not None:                     # the scene's config.solver, overridden
        scene = replace(scene, config=replace(scene.config, solver=args.solver))
    dt = scene.config.dt
    if scene.t_end is not None and dt > scene.t_end * (1 + 1e-9):
        raise RunError(f"{path}: the time step dt = {dt:g} s is longer than the run, t_end = "
                       f"{scene.t_end:g} s: one step would go to t = {dt:g} s. Make dt a "
                       "fraction of t_end (or t_end a multiple of dt); nothing run")
    if args.steps is not None:
        if args.steps < 1:
            raise RunError(f"--steps must be >= 1, got {args.steps}")
        last = args.steps
    elif scene.t_end is not None:
        try:
            last = steps_until(scene.t_end, scene.config.dt)
        except ValueError as err:
            raise RunError(f"{path}: {err}") from None
    else:
        raise RunError(f"{path}: the scene has no t_end: give --steps N")
    return _advance(scene, out, last, args.resume, args.quiet, overwrite=args.overwrite,
                    force=args.force)


def _advance(scene, out, last, resume, quiet, overwrite=False, force=False):
    """Run ``scene`` to step ``last`` in folder ``out`` (see :func:`runfolder.run_in_folder`)."""
    from .runfolder import run_in_folder
    return run_in_folder(scene, out, last, resume=resume, overwrite=overwrite,
                         progress=None if quiet else StepBar, force=force)


DESCRIPTION = """\
The command line of pfem_skfem. Commands:

  list     the verification cases, one line each
  verify   run verification cases (one per thesis benchmark), print a summary table,
           exit non-zero if a case misses its tolerance: pfem-skfem verify [CASE ...] --quick
  run      run a PFEM scene file (TOML), or write an example:
           pfem-skfem run --example column; pfem-skfem run column.toml

'pfem-skfem COMMAND --help' tells more. Without an activated virtual environment, call
it by its path, e.g. .venv/bin/pfem-skfem.
"""


#: each case's --quick run in CPU seconds (user + system), measured one case at a time with
#: ``/usr/bin/time python verification/CASE.py --quick --quiet`` (figures on, as
#: ``scripts/verify.sh`` runs them) on the 2-core development machine in December 2026;
#: ``pfem-skfem list`` shows them, and the README's total of ``scripts/verify.sh`` is their
#: sum over the cores. A new case adds its own (tests/test_cli.py requires one per case).
QUICK_SECONDS = {
    "bingham_slump": 50, "granular_column_mu_i": 38, "landslide_yangbaodi": 49,
    "silo_discharge": 22, "limit_bounds": 24, "soil_and_water": 28,
    "granular_column_axisymmetric": 15, "granular_column_plane": 22, "cylinder_soil": 15,
    "accretionary_wedge": 11, "dam_break": 5, "hydrostatics": 3, "inclined_plane_flow": 7,
    "inclined_rod": 3, "block_on_incline": 2, "alpha_shape": 2, "buried_pipe": 3,
    "cantilever": 6, "circular_footing": 10, "fluid_films": 3, "plastic_vibration": 3,
    "rotating_bar": 2, "sliding_box": 2, "strip_footing": 10, "thick_cylinder": 3,
    "trussed_frame": 8, "consolidation": 11, "mandel_cryer": 5, "softening_layer": 30,
    "biaxial_band": 56, "consolidation_pfem": 8, "effective_bounds": 19, "sensitive_clay": 28,
    "penetration_rate": 13, "softening_cylinder": 19, "retrogressive_slope": 13,
}


def case_summary(case):
    """One line on a verification case: the first line of its script's docstring and the
    CPU time of its --quick run (:data:`QUICK_SECONDS`)."""
    import ast
    doc = ast.get_docstring(ast.parse((verification_dir() / f"{case}.py").read_text())) or ""
    lines = doc.strip().splitlines()
    seconds = QUICK_SECONDS.get(case)
    return (lines[0] if lines else "") + (f" (--quick: {seconds} s CPU)" if seconds else "")


def cmd_list(args):
    """``pfem-skfem list``: each case with its one-line summary and its --quick time."""
    cases = available_cases()
    width = max(map(len, cases))
    for case in cases:
        print(f"{case:{width}s}  {case_summary(case)}")
    total = sum(QUICK_SECONDS.get(c, 0) for c in cases)
    jobs = default_jobs()
    print(f"\nall at --quick: {total} s CPU (as measured on a 2-core machine), about "
          f"{total / jobs / 60:.0f} min over the {jobs} process(es) of "
          f"'pfem-skfem verify --quick' (its default --jobs here)")
    return 0


def _examples_help():
    from .scene.files import EXAMPLES, example_text
    lines = []
    for name in EXAMPLES:               # the first line of each example's header
        first = example_text(name).splitlines()[0].lstrip("# ").rstrip(".")
        lines.append(f"{name} ({first})")
    return "; ".join(lines)


RUN_DESCRIPTION = ("Run a PFEM scene written as a TOML file: a progress bar on stderr; the "
                   "VTU/PVD series, history.json, scene.toml and checkpoint.npz in the output "
                   "folder (beside the scene file unless --out is given). A folder holding "
                   "another run is never replaced silently: --resume continues it, "
                   "--overwrite replaces it. It says what the run is before its first step, "
                   "what it will cost after it, and why it stopped at the end. Exit codes: 0 "
                   "done; 2 it could not start; 3 a solver failure or a full disk (the last "
                   "step checkpointed); 4 done, but a step moved particles more than 2 "
                   "spacings or changed the area by more than 5 % (dt too long; --force: 0); "
                   "130, 143 Ctrl-C, SIGTERM.")


class _RunParser(argparse.ArgumentParser):
    """The parser of ``run``: its help names the examples, read from
    :mod:`pfem_skfem.scene.files` (which imports the science) only when the help is shown,
    so that ``pfem-skfem --help`` and ``list`` stay light."""

    def format_help(self):
        from .scene.files import EXAMPLES
        if self.description == RUN_DESCRIPTION:
            self.description += " Examples: " + _examples_help() + "."
        for action in self._actions:
            if action.dest == "example" and "(" not in action.help:
                action.help = action.help.replace(
                    "NAME ", f"NAME ({', '.join(EXAMPLES)}) ", 1)
        return super().format_help()


def build_parser():
    """The parser of ``pfem-skfem`` and its subcommands (their options follow the scripts'
    spelling, CONTRIBUTING.md; tests/test_options.py walks them)."""
    parser = argparse.ArgumentParser(prog="pfem-skfem", description=DESCRIPTION,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True, metavar="{list,verify,run}")
    ls = sub.add_parser("list", help="list the verification cases, one line each")
    ls.set_defaults(func=cmd_list)
    v = sub.add_parser("verify", help="run verification cases and print a summary table")
    v.add_argument("cases", nargs="*", help="cases to run (default: all)")
    v.add_argument("--quick", action="store_true", help="small sizes (seconds to a minute "
                   "each: 'pfem-skfem list' gives each one's time); the JSON is then "
                   "<case>.quick.json and the figures go to <outdir>/quick/<case>/, so that "
                   "they never replace a full-size run's")
    v.add_argument("--json-dir", default="results", help="where to write <case>.json")
    v.add_argument("--outdir", default="results", help="where to write figures and VTU: "
                   "<outdir>/<case>/, a --quick run's in <outdir>/quick/<case>/")
    v.add_argument("--no-figures", action="store_true")
    v.add_argument("--jobs", type=workers, default=default_jobs(),
                   help="cases run at once (default: the cores, %(default)s here; 1 shows "
                   "each case's own progress bars)")
    v.add_argument("--quiet", action="store_true",
                   help="no progress (the cases' own bars with --jobs 1; one bar otherwise)")
    v.add_argument("--verbose", action="store_true", help="show each script's output")
    v.add_argument("--solver", choices=SOLVER_NAMES, help="the conic solver of every case "
                   "that solves one (all but " + ", ".join(sorted(NO_SOLVER)) + "; default: "
                   "each script's, clarabel)")
    v.add_argument("--extra", nargs=argparse.REMAINDER,
                   help="further options passed to every script")
    v.set_defaults(func=cmd_verify)
    sub._parser_class = _RunParser           # its help names the examples when shown
    r = sub.add_parser("run", help="run a scene file (TOML); --example NAME writes one",
                       description=RUN_DESCRIPTION)
    sub._parser_class = argparse.ArgumentParser
    r.add_argument("scene", nargs="?", help="the scene file (with --example: where to write "
                   "it, default NAME.toml; '-' for stdout)")
    r.add_argument("--example", metavar="NAME", help="write the commented example NAME "
                   "instead of running")
    r.add_argument("--steps", type=positive_int, help="run until step N (default: until t_end)")
    r.add_argument("--out", "--outdir", dest="out", help="output folder (default: the file's "
                   "output.directory, read from the scene file's folder)")
    r.add_argument("--resume", action="store_true",
                   help="continue from the output folder's checkpoint")
    r.add_argument("--overwrite", action="store_true",
                   help="replace the results of another run in the output folder")
    r.add_argument("--every", type=nonnegative_int, help="a VTU every K steps (0: none; default: "
                   "output.every)")
    r.add_argument("--checkpoint-every", type=nonnegative_int, help="a checkpoint every K steps "
                   "(default: output.checkpoint_every, or "
                   f"{DEFAULT_CHECKPOINT_EVERY} when that is 0; one is always "
                   "written at the end, on Ctrl-C and on SIGTERM)")
    r.add_argument("--quiet", "--no-progress", dest="quiet", action="store_true",
                   help="no progress bar")
    r.add_argument("--force", action="store_true", help="exit 0 after the warning on steps "
                   "too long for the method (a particle moving more than 2 spacings in a "
                   "step, the area changing by more than 5 %%; pfem_skfem/runreport.py "
                   "says why), not 4")
    r.add_argument("--solver", choices=STEP_SOLVER_NAMES, help="who states and solves every "
                   "step (default: the scene's config.solver, clarabel unless it says; "
                   "'clarabel-dual': the displacement form; 'cvxpy': the reference statement)")
    r.set_defaults(func=cmd_run)
    return parser


def main(argv=None):
    args = build_parser().parse_args(argv)
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())
