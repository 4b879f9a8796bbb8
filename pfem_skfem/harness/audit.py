"""The option audit (issue 56): every option of a verification script moved once off its
default, inside its range, and the script's ``--quick`` run with it, every check required.

The moved value (:func:`moved_argv`) is found from the option's own parser, relative to the
value a ``--quick`` run uses (its quick value where ``--quick`` sets one, else its
default):

* a number x: 1.25 x (x + 1 for x = 0); where the validator or the script's cross-option
  check (the parser's ``check``) refuses it, 0.8 x, then the midpoints of x and the ends of
  the validator's range;
  (then 1.05 x and 0.95 x, where the check holds it between other options);
* an integer: x + 1, else x - 1 (at an upper bound), else the nearest integer the check
  accepts (x + 5 where it asks a whole number of spacings);
* a choice: the next choice that the parser accepts;
* a boolean flag: flipped (``--flag`` or ``--no-flag``);
* a list: its first element alone, else the list and one more element (its last moved as
  above); a list of a fixed count: its first element moved;
* an option whose default is None (the script derives its value, or a mode is off), or
  whose moved value the check refuses alone: the command line of :data:`GIVEN` (the value
  the script uses in its place, moved; or a companion option the check asks for).

Each candidate must parse (the option's validator and the script's check, with ``--quick``)
to a value other than the base: the first that does is the moved value. Options that say
where or how a run goes, not what it computes, are left out (:data:`LEFT_OUT`, each with its
reason). :func:`run_moved` runs a script's ``--quick`` with one option moved and returns the
exit code, the checks that failed (by name) and the CPU seconds.

Offline, over every script (not a test: the slow scripts take minutes each)::

    python scripts/audit_options.py --all --json /tmp/audit.json
    python scripts/audit_options.py sliding_box dam_break        # some scripts
    python scripts/audit_options.py --list --all                 # the moved values only

The harness imports no science: the scripts are imported by name when they are run.
"""
import argparse
import contextlib
import importlib
import io
import json
import math
import signal
from pathlib import Path
import tempfile
import time
import traceback

from .options import SOLVER_NAMES, STEP_SOLVER_NAMES

__all__ = ["LEFT_OUT", "GIVEN", "REFUSED", "option_moves", "moved_argv", "run_moved",
           "audit_script"]

#: options (dest) not moved, and why: where the run reads or writes, how it shows itself,
#: who solves it and where; none of them changes what a check measures; and an option whose
#: one other value every script offering it refuses (a usage error, tested in CHECKS)
LEFT_OUT = {
    "help": "prints the help", "quick": "the size the audit runs at",
    "json": "a path: where the results are written",
    "outdir": "a path: where the figures and VTU go",
    "results_dir": "a path: kept results of a sweep (tests/test_sweeps.py)",
    "checkpoint_dir": "a path: the checkpoints (tests/test_resumable.py)",
    "profile": "a path: the terrain file read (its CHECKS row tests a missing one)",
    "no_figures": "figures: drawn after the checks (tests/test_figures.py draws them)",
    "quiet": "verbosity: the progress bars", "progress": "verbosity: the progress bars",
    "solver": "a solver: every solver on every problem is tests/test_solver_option.py's",
    "workers": "workers: where the cases run, not what they compute (tests/test_sweeps.py)",
    "scheduler": "workers: a Dask cluster's address (none on a test machine)",
    "save_every": "outputs: VTU files every so many steps (tests/test_io_viz.py)",
    "checkpoint_every": "outputs: checkpoint files (tests/test_resumable.py resumes bit "
                        "for bit)",
    "d_form": "the inertia's form: its one other value, 'cone', is refused by the scripts "
              "that offer it (accurate only to sqrt(the solver's gap); tests/test_options.py "
              "CHECKS)",
}

#: (script, dest) -> (the command line that moves it, why it is given here rather than
#: found by the rule): a default of None, a flag that ``--quick`` sets and the command line
#: cannot unset, or a moved value the check refuses alone
GIVEN = {
    ("buried_pipe", "dt"): (["--dt", "0.125"], "None: the quasi-static step; 0.125 s a "
                                               "dynamic one, 1.25 x the shortest"),
    ("cantilever", "steps"): (["--steps", "101"], "None: t_end / dt = 100 at --quick; +1"),
    ("circular_footing", "tol"): (["--tol", "0.0375"], "None: 3 % at --quick; x 1.25"),
    ("inclined_rod", "tol"): (["--tol", "0.05"], "None: 1.1 E_1(N) = 3.86 % at --quick; "
                                                   "about x 1.3"),
    ("strip_footing", "tol_tresca"): (["--tol-tresca", "0.0625"],
                                      "None: 5 % at --quick; x 1.25"),
    ("strip_footing", "mc_elements"): (["--mc-elements", "401"],
                                       "None: the finest, 400 at --quick; +1"),
    ("trussed_frame", "tol"): (["--tol", "0.05"], "None: 4 % at --quick; x 1.25"),
    ("sliding_box", "time"): (["--time", "1.25"], "None: v0 / (mu g) = 1 s; x 1.25"),
    ("silo_discharge", "h_study"): (["--h-study", "0.01"], "None: the narrowest outlet / 4 "
                                                          "(an outlet study; off at --quick)"),
    ("granular_column_axisymmetric", "phi_s"): (["--phi-s", "25"], "None: phi_g; a smoother "
                                                                   "base"),
    ("granular_column_axisymmetric", "courant"): (["--courant", "0.5"],
                                                  "None: --steps only; a Courant bound on"),
    ("granular_column_mu_i", "d0_over_d"): (["--d0-over-d", "50"],
                                            "None: --h0-over-d sets the size"),
    ("granular_column_mu_i", "rho_s"): (["--rho-s", "1.25"], "None: --rho; x 1.25"),
    ("granular_column_mu_i", "density_factor"): (["--density-factor", "4"],
                                                 "a power of 2 (the bit-exact invariance): x 2"),
    ("granular_column_plane", "E"): (["--E", "10000"], "None: rigid-plastic; elastoplastic"),
    ("granular_column_plane", "nu"): (["--nu", "0.375", "--E", "10000"],
                                      "None (0.3 with --E); x 1.25, with the --E it needs"),
    ("granular_column_plane", "mu"): (["--mu", "0.7"], "None: tan phi; x 1.25"),
    ("granular_column_plane", "h0"): (["--h0", "0.1"], "None: d0 sets the size"),
    ("granular_column_plane", "passes"): (["--passes", "3"], "None: 2; +1"),
    ("sliding_box", "contact"): (["--contact", "zero-dilation", "--body", "fe"],
                                 "the other choice, with the --body fe it needs"),
    ("accretionary_wedge", "contact"): (["--contact", "coulomb", "--stability-steps", "6"],
                                        "the other choice, with the 6 push steps the "
                                        "stability test needs with it"),
    ("softening_layer", "L"): (["--L", "1.25", "--t-end", "1.25"],
                               "x 1.25, with the t_end its slower shear needs to be steady "
                               "(1.15 s; --t-end 1 refused)"),
    ("softening_layer", "c_p"): (["--c-p", "25", "--t-end", "1.25"],
                                 "x 1.25, with the t_end its longer softening needs to be "
                                 "steady (1.21 s; --t-end 1 refused)"),
    ("sensitive_clay", "regularisation"): (["--regularisation", "fracture-energy", "--ell",
                                            "0.25"], "another choice, with the length it needs "
                                                     "(1.25 x the quick spacing H / 5)"),
    ("retrogressive_slope", "regularisation"): (["--regularisation", "nonlocal", "--ell",
                                                 "1.25"], "the other choice offered, with the "
                                                          "length it needs (1.25 x the spacing)"),
    ("retrogressive_slope", "ell"): (["--ell", "1.25", "--regularisation", "nonlocal"],
                                     "None: no regularisation; 1.25 x the spacing, with the "
                                     "regularisation that reads it"),
    ("sensitive_clay", "ell"): (["--ell", "0.25", "--regularisation", "nonlocal"],
                                "None: no regularisation; 1.25 x the quick spacing, with the "
                                "regularisation that reads it"),
    # studies off by default ([]): one run of the study
    ("sensitive_clay", "mesh_study"): (["--mesh-study", "4", "5", "--ell", "0.25"],
                                       "[]: a study of 4 and 5 across H, with the length its "
                                       "regularised banks need"),
    ("sensitive_clay", "study_sensitivities"): (["--study-sensitivities", "3", "--mesh-study",
                                                 "4", "5", "--ell", "0.25"],
                                                "the study's only: 3, with a study"),
    ("sensitive_clay", "study_regularisations"): (["--study-regularisations", "none",
                                                   "nonlocal", "--mesh-study", "4", "5",
                                                   "--ell", "0.25"],
                                                  "the study's only: one left out, with a study"),
    ("sensitive_clay", "convergence"): (["--convergence", "0.125", "--mesh-study", "4", "5",
                                         "--ell", "0.25"], "the study's only: x 1.25, with a "
                                                           "study"),
    ("accretionary_wedge", "increment_study"): (["--increment-study", "16"],
                                                "[]: one run of 16 increments"),
    ("cylinder_soil", "dt_study"): (["--dt-study", "0.1"], "[]: one run at dt / 2"),
    ("cylinder_soil", "mesh_study"): (["--mesh-study", "0.3125"], "[]: one run at 1.25 h"),
    ("granular_column_axisymmetric", "compare_mc"): (["--compare-mc", "0.5"],
                                                     "[]: the quick a with the other material"),
    ("granular_column_axisymmetric", "density"): (["--density", "2.5"],
                                                  "[]: one density, 1.25 rho"),
    ("granular_column_axisymmetric", "friction_study"): (["--friction-study", "25"],
                                                         "[]: one phi_g"),
    ("granular_column_axisymmetric", "base_study"): (["--base-study", "20"], "[]: one phi_s"),
    ("granular_column_axisymmetric", "mesh_study"): (["--mesh-study", "7"],
                                                     "[]: one mesh, nr + 1"),
    ("granular_column_plane", "time_steps"): (["--time-steps", "125"],
                                              "[]: one run of 1.25 x the steps"),
    ("granular_column_plane", "mesh_study"): (["--mesh-study", "12"], "[]: one mesh"),
}

#: (script, dest) -> why: an option kept to refuse, with its reason, every value but its
#: default (each a usage error of the script's check, named by the option): nothing to move
#: it to. Kept rather than removed, so that the value's refusal says why (a test requires
#: that no value moves it)
REFUSED = {
    ("softening_layer", "row_kinematics"): "p2 refused: the free P2 row's tau varies inside "
                                           "the row; no closed form of the script holds",
}


def _quiet_parse(parser, argv):
    """The namespace of ``argv`` (with ``--quick``), or None where it is a usage error."""
    with contextlib.redirect_stderr(io.StringIO()):
        try:
            return parser.parse_args(["--quick", *argv])
        except SystemExit:
            return None


def _scalars(action, x):
    """Candidate moved values of one number ``x`` of ``action``'s type, in order."""
    kind = action.type
    integer = getattr(kind, "integer", False) or kind is int
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        return []
    if integer:                 # x + 1, x - 1, then the nearest the check accepts
        return [int(x) + s * k for k in range(1, max(int(abs(x)), 1) + 1) for s in (1, -1)]
    low, high = getattr(kind, "low", -math.inf), getattr(kind, "high", math.inf)
    out = [1.25 * x, 0.8 * x] if x != 0 else [1.0]
    for end in (high, low):
        if math.isfinite(end):
            out.append((x + end) / 2)
    if math.isfinite(low) and math.isfinite(high):
        out.append((low + high) / 2)
    return out + ([1.05 * x, 0.95 * x] if x != 0 else [])   # where the check bounds it


def _text(value):
    return f"{value:.6g}" if isinstance(value, float) else str(value)


def _candidates(action, base):
    """Command lines that move ``action`` off ``base``, in the order of the rule."""
    flag = action.option_strings[0]
    if action.nargs == 0:                           # a flag
        if isinstance(action, argparse.BooleanOptionalAction):
            return [[action.option_strings[1 if base else 0]]]
        return [[flag]] if base == action.default else []
    if isinstance(base, (list, tuple)):
        base = list(base)
        if isinstance(action.nargs, int):           # a fixed count: its first moved
            return [[flag, _text(v), *map(_text, base[1:])] for v in _scalars(action, base[0])]
        lists = []
        if len(base) > 1:
            lists.append(base[:1])
        pool = base or list(action.default or [])
        if action.choices is not None:
            lists += [base + [c] for c in action.choices if c not in base]
            lists += [[c] for c in action.choices if [c] != base]
        elif pool:
            lists += [base + [v] for v in _scalars(action, pool[-1])]
        return [[flag, *map(_text, v)] for v in lists]
    if action.choices is not None:
        return [[flag, str(c)] for c in action.choices if c != base]
    return [[flag, _text(v)] for v in _scalars(action, base)]


def _why_left_out(action):
    """Why ``action`` is not moved (:data:`LEFT_OUT` and the kinds it names), or None."""
    if action.dest in LEFT_OUT:
        return LEFT_OUT[action.dest]
    if action.choices is not None and set(action.choices) <= set(STEP_SOLVER_NAMES) | set(
            SOLVER_NAMES):
        return LEFT_OUT["solver"]
    if action.nargs != 0 and action.choices is None and action.type in (None, str):
        return "free text: a path or a name"
    return None


def option_moves(name, parser=None):
    """Each option of script ``name``: ``(dest, argv or None, why)``.

    ``argv`` is the command line that moves it (with ``--quick`` it parses, the value other
    than the quick run's); None for an option left out or one no candidate moves, ``why``
    then saying so. ``why`` is the rule's word otherwise (``"x 1.25"``, ``"given: ..."``).
    """
    parser = parser or importlib.import_module(f"verification.{name}").build_parser()
    base_args = _quiet_parse(parser, [])
    moves = []
    for action in parser._actions:
        if not action.option_strings:
            continue
        why = _why_left_out(action)
        if why is not None:
            moves.append((action.dest, None, why))
            continue
        base = getattr(base_args, action.dest)
        given = GIVEN.get((name, action.dest))
        candidates = ([given[0]] if given else []) + _candidates(action, base)
        found = None
        for argv in candidates:
            args = _quiet_parse(parser, argv)
            if args is not None and getattr(args, action.dest) != base:
                found = argv
                break
        if found is None and action.nargs == 0 and base != action.default:
            moves.append((action.dest, None, "--quick sets this flag and a flag cannot be "
                                             "unset: its other value is the full size's"))
        elif found is None and (name, action.dest) in REFUSED:
            moves.append((action.dest, None, "refused: " + REFUSED[name, action.dest]))
        elif found is None:
            moves.append((action.dest, None, f"no value moves it from {base!r} that the "
                                              "parser accepts"))
        else:
            moves.append((action.dest, found, ("given: " + given[1]) if given
                          and found is given[0] else "the rule"))
    return moves


def moved_argv(name, dest):
    """The command line that moves option ``dest`` of script ``name`` (KeyError if none)."""
    for key, argv, why in option_moves(name):
        if key == dest:
            if argv is None:
                raise KeyError(f"{name}: --{dest} is not moved: {why}")
            return argv
    raise KeyError(f"{name} has no option {dest}")


class RunTooLong(Exception):
    """A moved run stopped at its wall-clock limit (:func:`run_moved`'s ``limit``)."""


def _alarm(signum, frame):
    raise RunTooLong("stopped at the audit's limit")


def run_moved(name, argv, outdir=None, limit=None):
    """Run script ``name`` at ``--quick`` with ``argv`` (one option moved), in-process;
    ``limit``: wall-clock seconds before it is stopped (SIGALRM; the main thread only).

    Returns
    -------
    (int, list of str, float)
        The exit code (1 for an exception, 2 a usage error), the names of the checks that
        failed (``"exception: ..."`` for an exception) and the CPU seconds of the process
        (its threads included) the run took.
    """
    script = importlib.import_module(f"verification.{name}")
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(outdir or tmp)
        report = out / f"{name}.audit.json"
        full = ["--quick", *argv, "--quiet", "--no-figures", "--outdir", str(out),
                "--json", str(report)]
        failed = []
        t0 = time.process_time()
        old = signal.signal(signal.SIGALRM, _alarm) if limit else None
        if limit:
            signal.alarm(int(limit))
        with contextlib.redirect_stdout(io.StringIO()), \
                contextlib.redirect_stderr(io.StringIO()) as err:
            try:
                code = script.main(full)
            except SystemExit as stop:
                code = stop.code if isinstance(stop.code, int) else 1
            except Exception as error:                      # noqa: BLE001 (reported)
                code = 1
                where = traceback.extract_tb(error.__traceback__)[-1]
                failed.append(f"exception: {type(error).__name__}: {error} "
                              f"({Path(where.filename).name}:{where.lineno})")
        if limit:
            signal.alarm(0)
            signal.signal(signal.SIGALRM, old)
        seconds = time.process_time() - t0
        if report.is_file():
            quantities = json.loads(report.read_text())["quantities"]
            failed += [q["name"] for q in quantities if not q["pass"]]
        if code == 2 and not failed:
            failed.append("usage error: " + err.getvalue().strip().splitlines()[-1])
    return int(code or 0), failed, seconds


def audit_script(name, dests=None, log=None, limit=None):
    """Every moved option of ``name`` (or those of ``dests``) run once: a list of rows
    ``{script, option, argv, why, code, failed, cpu_s}``, a left-out option with no run."""
    rows = []
    for dest, argv, why in option_moves(name):
        if dests is not None and dest not in dests:
            continue
        row = dict(script=name, option=dest, argv=argv, why=why)
        if argv is not None:
            code, failed, seconds = run_moved(name, argv, limit=limit)
            row.update(code=code, failed=failed, cpu_s=round(seconds, 2))
        rows.append(row)
        if log is not None:
            print(_line(row), file=log, flush=True)
    return rows


def _line(row):
    if row["argv"] is None:
        return f"{row['script']:28s} --{row['option']:20s} left out: {row['why']}"
    verdict = "ok" if row["code"] == 0 else f"exit {row['code']}: {', '.join(row['failed'])}"
    return (f"{row['script']:28s} {' '.join(row['argv']):34s} {row['cpu_s']:7.1f} s  "
            f"{verdict}")
