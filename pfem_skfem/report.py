"""The verification-script contract: options, quantities against references, JSON.

Every script under ``verification/`` has the same shape::

    QUICK = dict(steps=[10, 20])           # the --quick sizes

    def build_parser():                    # base_parser + the script's own options
        p = base_parser(__doc__.splitlines()[0], quick=QUICK, check=check)
        ...

    def run(args):                         # the work; returns a Report
        report = Report("case", args)
        report.add(...)                    # quantities against references
        report.data = dict(...)            # in-memory results for figures(...)
        return report

    def figures(args, **data):             # from report.data; skipped by --no-figures
        ...

    def main(argv=None):                   # --quick applied, options and output paths
        return script_main(build_parser, run, figures, argv)   # checked; then run(args),
                                           # figures, table, --json, exit code; ^C one line

so that tests, the book and the benchmarks call ``run`` in-process
(``from verification import strip_footing``; :func:`run_script`) and ``pfem-skfem verify`` runs the
same script in a subprocess. :func:`script_main` parses, runs and finishes (Ctrl-C,
an unreachable ``--scheduler`` and a damaged kept file are one line, not a traceback);
:meth:`Report.finish` prints the table, writes
``--json PATH`` and returns the exit code; :func:`pyplot`, :func:`figure_dir` and
:func:`save_figure` hold the figure boilerplate.

JSON layout::

    {"case": ..., "params": {...},
     "quantities": [{"name", "value", "reference", "source", "rel_error",
                     "tolerance", "pass"}, ...]}

``rel_error`` is |value - reference| / |reference|, or the absolute error when the
reference is zero; ``pass`` is ``rel_error <= tolerance``. A quantity checked
against an interval (a bound, a range of published values) gives ``lower`` and
``upper`` instead (null for an infinite end); its ``rel_error`` is the distance outside
the interval relative to the larger end, or to the finite end of a one-sided interval
(absolute where it is 0). A NaN or infinite value (an undefined ratio) never passes;
the JSON writes it as null.

Options are checked when they are parsed, before any work, with the shared argparse
types below: a bad value is a usage error (exit code 2) whose message names the
option, its allowed range and the value given, e.g. ``argument --phi: must be an
angle in [0, 90) degrees, got '95'``. Use them as ``type=`` of ``add_argument``::

    p.add_argument("--elements", type=positive_int, nargs="+", default=[100, 400])
    p.add_argument("--phi", type=friction_angle, default=30.0)
    p.add_argument("--nu", type=poisson_ratio, default=0.3)

=========================  ===================================================
``positive_float``         a finite number > 0 (lengths, moduli, densities, dt)
``nonnegative_float``      a finite number >= 0 (friction coefficients, tolerances)
``positive_int``           an integer >= 1 (element, step, increment counts)
``nonnegative_int``        an integer >= 0 (``--save-every``: 0 for none)
``workers``                an integer >= 1 (parallel processes)
``scheduler_address``      a Dask scheduler address ``[tcp://]host:port``
``friction_angle``         an angle in [0, 90) degrees (as a TOML scene)
``positive_angle(why)``    an angle in (0, 90) where phi = 0 has no meaning, saying why
``poisson_ratio``          a number in (-1, 0.5)
``fraction``               a number in [0, 1]
``theta_weight``           a theta-method weight in [1/2, 1] (4.4)
``element_count``          an integer >= 4 (the approximate element count of a mesh)
``in_range(low, high)``    any other interval (``low_open``, ``high_open``,
                           ``integer``, ``unit``)
``positive(name)``         the older spelling of ``positive_float``
=========================  ===================================================

A script that runs independent cases adds ``--workers`` and ``--scheduler`` with
:func:`sweep_options` and runs them with :func:`run_cases` (on Dask: a local cluster
of ``--workers`` processes, or the cluster at ``--scheduler``).

A long run that should survive a stop saves its state with
:func:`~pfem_skfem.drivers.pfem_loop.save_checkpoint` (or, with the driver's own
measurements, :func:`save_run`) under :func:`checkpoint_path` (the run's label and a
digest of its parameters) and goes on from it when run again
(``verification/silo_discharge.py --checkpoint-dir``, ``landslide_yangbaodi.py``).

``ScriptParser`` gives every script ``--quiet`` (no progress bars) next to the
``--progress`` of old (now the default); :func:`progress_bar` is the bar (tqdm) of a
long loop, :func:`progress` one line. Conditions between options (``--a`` below
``--b``) go in the script's ``check(args)``, whose message must name the options.
"""
import argparse
from dataclasses import asdict, dataclass
import functools
import io
import json
import math
from pathlib import Path
import sys
import threading

import numpy as np


@dataclass
class Quantity:
    name: str
    value: float
    reference: float
    source: str
    tolerance: float
    rel_error: float
    passed: bool
    lower: float | None = None
    upper: float | None = None

    def as_json(self):
        d = asdict(self)
        d["pass"] = d.pop("passed")
        if self.lower is None:
            d.pop("lower"), d.pop("upper")
        return {k: _plain(v) for k, v in d.items()}


def _plain(v):
    """A JSON value for ``v``: numpy scalars and arrays as Python numbers and lists."""
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, (np.floating, np.integer)):
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    if isinstance(v, np.bool_):
        return bool(v)
    return v


def relative_error(value, reference):
    """|value - reference| / |reference|, the absolute error for a zero reference."""
    if reference == 0:
        return abs(value - reference)
    return abs(value - reference) / abs(reference)


HARNESS_OPTIONS = ("json", "outdir", "no_figures", "progress", "quiet", "workers",
                   "scheduler")
"""Options that say how a script runs, not what it computes: never in ``params``."""


class Report:
    """Quantities of one verification case, compared with their references.

    Parameters
    ----------
    case : str
        Name of the case (the ``case`` of the JSON).
    params : argparse.Namespace or mapping, optional
        The parameters of the run, usually the parsed options; the harness-only
        options (:data:`HARNESS_OPTIONS`) are left out.
    **more
        Further parameters (derived sizes such as the element count), added to or
        replacing those of ``params``.

    Attributes
    ----------
    quantities : list of Quantity
        What :meth:`add` and :meth:`add_interval` compared, in order.
    extra : dict
        Further results written to the JSON (histories, tables).
    data : dict
        In-memory results for the script's figures and for callers; not written.
    """

    def __init__(self, case, params=(), **more):
        if isinstance(params, argparse.Namespace):
            params = vars(params)
        params = {**dict(params), **more}
        self.case = case
        self.params = {k: _plain(v) for k, v in params.items() if k not in HARNESS_OPTIONS}
        self.quantities = []
        self.extra = {}
        self.data = {}

    def add(self, name, value, reference, source, tolerance):
        """Compare ``value`` with ``reference`` to a relative ``tolerance``."""
        value, reference = float(value), float(reference)
        err = relative_error(value, reference)
        # a NaN or infinite value (an undefined ratio) never passes: NaN <= tol is False,
        # but inf - inf in the error is NaN and an infinite reference makes any error finite
        passed = math.isfinite(value) and math.isfinite(reference) and err <= tolerance
        q = Quantity(name, value, reference, source, float(tolerance), err, bool(passed))
        self.quantities.append(q)
        return q

    def add_interval(self, name, value, lower, upper, source, tolerance=0.0,
                     reference=None):
        """Check that ``value`` lies in [lower, upper] (widened by ``tolerance`` relative).

        The excess outside the interval is relative to max(|lower|, |upper|) when both
        ends are finite; to the finite end's magnitude for a one-sided interval (absolute
        where that end is 0): an infinite scale would let any finite value pass. A NaN or
        infinite value fails (its ``rel_error`` NaN or inf).
        """
        value, lower, upper = float(value), float(lower), float(upper)
        ref = float(reference) if reference is not None else 0.5 * (lower + upper)
        finite = [abs(b) for b in (lower, upper) if math.isfinite(b)]
        if len(finite) == 2:
            scale = max(abs(lower), abs(upper), 1e-300)
        else:                                    # one-sided (or unbounded: always inside)
            scale = (finite[0] or 1.0) if finite else 1.0
        if math.isfinite(value) and lower <= upper:    # a NaN end (undefined bound) fails
            outside = max(lower - value, value - upper, 0.0) / scale
        else:
            outside = abs(value) if lower <= upper else math.nan   # fails below
        q = Quantity(name, value, ref, source, float(tolerance), outside,
                     bool(math.isfinite(value) and lower <= upper and outside <= tolerance),
                     lower, upper)
        self.quantities.append(q)
        return q

    @property
    def passed(self):
        """True when every quantity is within its tolerance."""
        return all(q.passed for q in self.quantities)

    def quantity(self, name):
        """The :class:`Quantity` called ``name`` (KeyError naming the ones there are)."""
        for q in self.quantities:
            if q.name == name:
                return q
        raise KeyError(f"no quantity {name!r} in {self.case}; there are "
                       f"{[q.name for q in self.quantities]}")

    def as_json(self):
        out = {"case": self.case, "params": self.params,
               "quantities": [q.as_json() for q in self.quantities]}
        if self.extra:
            out["extra"] = json.loads(json.dumps(self.extra, default=_plain))
        return out

    def table(self):
        head = f"{'quantity':28s} {'ours':>12s} {'reference':>12s} {'error':>9s} {'tol':>8s}  pass  source"
        lines = [f"== {self.case} ==", head, "-" * len(head)]
        for q in self.quantities:
            ref = (f"[{q.lower:.4g},{q.upper:.4g}]" if q.lower is not None
                   else f"{q.reference:.6g}")
            lines.append(f"{q.name:28s} {q.value:12.6g} {ref:>12s} {q.rel_error:9.2e} "
                         f"{q.tolerance:8.1e}  {'yes' if q.passed else 'NO ':4s}  {q.source}")
        return "\n".join(lines)

    def write_json(self, path):
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(self.as_json(), indent=2))

    def finish(self, args, figures=None):
        """Draw the figures, print the table, write ``--json``; return the exit code.

        Parameters
        ----------
        args : argparse.Namespace
            The parsed options (``--no-figures``, ``--json``).
        figures : callable, optional
            ``figures(args, **self.data)``, called unless ``--no-figures``.

        Returns
        -------
        int
            0 when every quantity passes, 1 otherwise.
        """
        if figures is not None and not getattr(args, "no_figures", False):
            figures(args, **self.data)
        print(self.table())
        if getattr(args, "json", None):
            self.write_json(args.json)
            print(f"results written to {args.json}")
        return 0 if self.passed else 1


class _DefaultsOnce(argparse.ArgumentDefaultsHelpFormatter):
    """argparse's "(default: ...)", once: not where the help states its default itself,
    nor for a flag or an option whose default is None (it said "(default: False)")."""

    def _get_help_string(self, action):
        text = action.help or ""
        if "default" in text.lower() or action.default is None or action.default is False:
            return text
        return super()._get_help_string(action)


# options naming files or folders the run writes: checked when parsed (a usage error)
# rather than after the computation, which was lost (dest -> what it names)
OUTPUT_PATHS = {"json": "file", "outdir": "directory", "results_dir": "directory",
                "checkpoint_dir": "directory"}


def output_path_problem(path, kind="file"):
    """Why ``path`` cannot be written as a ``kind`` ("file" or "directory"), or None.

    Nothing is created: the nearest existing folder on the way must be a folder in which a
    file can be made (a probe file, removed); an existing ``path`` must be of its kind (and
    a file writable)."""
    import os
    import tempfile
    target = Path(path).expanduser()
    if target.exists():
        if kind == "file" and target.is_dir():
            return f"{path} is a directory, not a file"
        if kind == "directory" and not target.is_dir():
            return f"{path} exists and is not a directory"
        if kind == "file":
            try:
                with open(target, "r+b"):
                    pass
            except OSError as error:
                return f"cannot write {path} ({error.strerror or error})"
            return None
        folder = target
    else:
        folder = target.parent
        while not folder.exists() and folder != folder.parent:
            folder = folder.parent
        if not folder.is_dir():
            return f"{folder} (on the way to {path}) is a file, not a directory"
    try:
        with tempfile.TemporaryFile(dir=folder, prefix=".write-probe-"):
            pass
    except OSError as error:
        return f"cannot write in {folder} ({error.strerror or error})"
    return None


class ScriptParser(argparse.ArgumentParser):
    """An argument parser whose ``parse_args`` applies ``--quick`` and the script's checks.

    With ``--quick``, each option named in ``quick`` takes its quick value unless
    the user gave it a value other than its default; then ``check(args)`` may
    return a message, reported as a usage error (exit code 2).
    """

    def __init__(self, description, quick=None, check=None):
        super().__init__(description=description,
                         formatter_class=_DefaultsOnce)
        self.quick = dict(quick or {})
        self.check = check

    def parse_args(self, args=None, namespace=None):
        parsed = super().parse_args(args, namespace)
        if hasattr(parsed, "quiet"):             # progress is the default; --quiet turns it off
            parsed.progress = not parsed.quiet
        if parsed.quick:
            for key, value in self.quick.items():
                if getattr(parsed, key) == self.get_default(key):
                    setattr(parsed, key, value)
        message = self.check(parsed) if self.check else None
        if message:
            self.error(message)
        for dest, kind in OUTPUT_PATHS.items():
            value = getattr(parsed, dest, None)
            if value is None or (dest == "outdir" and value == self.get_default(dest)
                                 and getattr(parsed, "no_figures", False)
                                 and not getattr(parsed, "save_every", 0)):
                continue                         # the default outdir, unused
            problem = output_path_problem(value, kind)
            if problem:
                self.error(f"argument --{dest.replace('_', '-')}: {problem}")
        return parsed


def base_parser(description, quick=None, check=None):
    """An argument parser with the options every verification script shares.

    Parameters
    ----------
    description : str
        First line of ``--help``.
    quick : dict, optional
        Option (dest) name -> value for ``--quick``; applied only where the user
        kept the default.
    check : callable, optional
        ``check(args) -> str or None``: a message for options that are
        inconsistent (a usage error), None when they are fine.

    Returns
    -------
    ScriptParser
    """
    p = ScriptParser(description, quick, check)
    sizes = ", ".join(f"{k}={v}" for k, v in p.quick.items())
    p.add_argument("--quick", action="store_true",
                   help="a small size that runs in seconds to a minute (tests, CI)"
                        + (f": {sizes}" if sizes else ""))
    p.add_argument("--json", metavar="PATH", help="write the results as JSON to PATH")
    p.add_argument("--outdir", default="results",
                   help="directory for figures and VTU files")
    p.add_argument("--no-figures", action="store_true", help="skip figures")
    p.add_argument("--quiet", action="store_true",
                   help="no progress bars on stderr (they are on by default)")
    p.add_argument("--progress", action="store_true",
                   help="progress bars on stderr (the default; kept for older command lines)")
    return p


def thinned(case, histories, drop=(), entries=100):
    """A case for the JSON: without the keys ``drop``, its ``histories`` (sequences as
    long as the first of them) thinned to about ``entries`` entries."""
    every = max(1, len(case[histories[0]]) // entries)
    kept = {k: v for k, v in case.items() if k not in tuple(drop) + tuple(histories)}
    return kept | {k: np.asarray(case[k])[::every].tolist() for k in histories}


def run_script(script, *argv):
    """A verification script in-process: ``script.run`` on its parsed ``argv``.

    Parameters
    ----------
    script : module
        A script of ``verification/`` (``from verification import strip_footing``).
    *argv : str
        Its command-line options, e.g. ``"--quick", "--no-figures"``; ``--quiet`` is
        added (no progress bars in tests and the book) unless ``--progress`` is given.

    Returns
    -------
    Report
        With ``report.data`` holding the in-memory results.
    """
    argv = list(argv)
    if "--progress" not in argv:
        argv = ["--quiet", *argv]
    return script.run(script.build_parser().parse_args(argv))


class OptionError(ValueError):
    """An option found wrong only when used (an unreachable ``--scheduler``): a usage
    error of the script (:func:`script_main`), not a traceback."""


class DamagedFileError(RuntimeError):
    """A kept file (a checkpoint, a sweep's result) that cannot be read: its message names
    the file and what to do."""


def script_main(build_parser, run, figures=None, argv=None):
    """A verification script's ``main``: parse, ``run(args)``, :meth:`Report.finish`.

    Ctrl-C is one line (exit 130), not a traceback; an :class:`OptionError` is a usage error
    (exit 2) and a :class:`DamagedFileError` one line (exit 1), also when every failed case
    of a sweep (:class:`SweepError`) failed with one."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return run(args).finish(args, figures)
    except KeyboardInterrupt:
        print(f"{parser.prog}: interrupted", file=sys.stderr)
        return 130
    except OptionError as error:
        parser.error(str(error))
    except (DamagedFileError, SweepError) as error:
        causes = ([e for _, _, e in error.failures] if isinstance(error, SweepError)
                  else [error])
        if isinstance(error, SweepError) and not all(
                isinstance(e, (DamagedFileError, OptionError)) for e in causes):
            raise
        for cause in causes:
            print(f"{parser.prog}: error: {cause}", file=sys.stderr)
        return 2 if all(isinstance(e, OptionError) for e in causes) else 1


def in_range(low=-math.inf, high=math.inf, *, low_open=False, high_open=False,
             integer=False, unit="", what=None):
    """argparse type: a number in an interval, its error naming the range and the value.

    Parameters
    ----------
    low, high : float
        The ends of the interval (infinite: unbounded).
    low_open, high_open : bool
        Whether the ends are excluded.
    integer : bool
        Accept integers only.
    unit : str
        Shown after the interval ("degrees").
    what : str, optional
        The whole description ("a positive integer"); by default built from the rest.

    Returns
    -------
    callable
        ``parse(text) -> float or int``, raising ``argparse.ArgumentTypeError``; argparse
        prefixes its message with the option (``argument --phi: ...``).
    """
    if what is None:
        kind = "an integer" if integer else "a number"
        if math.isinf(low) and math.isinf(high):
            what = kind
        elif math.isinf(high):
            what = f"{kind} {'>' if low_open else '>='} {low:g}"
        elif math.isinf(low):
            what = f"{kind} {'<' if high_open else '<='} {high:g}"
        else:
            what = (f"{kind} in {'(' if low_open else '['}{low:g}, {high:g}"
                    f"{')' if high_open else ']'}")
        what += f" {unit}" if unit else ""

    def parse(text):
        try:
            value = int(text) if integer else float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be {what}, got {text!r}") from None
        inside = (math.isfinite(value)
                  and (value > low if low_open else value >= low)
                  and (value < high if high_open else value <= high))
        if not inside:
            raise argparse.ArgumentTypeError(f"must be {what}, got {text!r}")
        return value
    parse.__name__ = what                       # argparse's name for the type
    parse.what = what
    return parse


positive_float = in_range(0, low_open=True, what="a positive number")
nonnegative_float = in_range(0, what="a number >= 0")
positive_int = in_range(1, integer=True, what="a positive integer")
nonnegative_int = in_range(0, integer=True, what="an integer >= 0")
workers = in_range(1, integer=True, what="a number of workers >= 1")
friction_angle = in_range(0, 90, high_open=True, what="an angle in [0, 90) degrees")


def positive_angle(why):
    """argparse type: an angle in (0, 90) degrees, for a script whose physics or reference
    needs phi > 0; ``why`` is said in the message (``friction_angle`` allows 0, as TOML)."""
    return in_range(0, 90, low_open=True, high_open=True,
                    what=f"an angle in (0, 90) degrees ({why})")
poisson_ratio = in_range(-1, 0.5, low_open=True, high_open=True,
                         what="a Poisson's ratio in (-1, 0.5)")
fraction = in_range(0, 1, what="a fraction in [0, 1]")
theta_weight = in_range(0.5, 1, what="a theta-method weight in [1/2, 1]")
element_count = in_range(4, integer=True, what="a number of elements >= 4")


def positive(name=None):
    """argparse type: a positive float (the older spelling of :data:`positive_float`).

    ``name`` is not needed (argparse names the option) and kept for older scripts.
    """
    return positive_float


def progress(message):
    """One line of progress on stderr (above any progress bar)."""
    from tqdm import tqdm
    tqdm.write(str(message), file=sys.stderr)
    sys.stderr.flush()


def progress_bar(iterable=None, *, args=None, total=None, desc=None, unit="case", **options):
    """A progress bar (tqdm) on stderr: count, elapsed time, rate and the time left.

    Parameters
    ----------
    iterable : iterable, optional
        What the loop runs over (or give ``total`` and call ``update``).
    args : argparse.Namespace, optional
        The parsed options: no bar when ``args.progress`` is false (``--quiet``).
    total, desc, unit : optional
        As in tqdm; ``desc`` names what is computed, ``bar.set_postfix_str(...)``
        shows the latest result.

    Returns
    -------
    tqdm.tqdm
    """
    from tqdm import tqdm
    disable = options.pop("disable", False) or (args is not None
                                                and not getattr(args, "progress", True))
    forward = getattr(_SWEEP_CASE, "forward", None)
    if forward is not None and not disable:    # a case of a sweep, on a Dask worker
        return _forwarded_bar()(iterable, forward, total=total, desc=desc, unit=unit,
                                **options)
    options.setdefault("mininterval", _redraw_seconds())
    terminal = hasattr(sys.stderr, "isatty") and sys.stderr.isatty()
    return tqdm(iterable, total=total, desc=desc, unit=unit,
                file=sys.stderr if terminal else _PlainLines(sys.stderr),
                disable=disable, dynamic_ncols=terminal, **options)


class _PlainLines:
    """A bar's stream for a log (stderr not a terminal): each redraw a line of its own, the
    cursor moves of stacked bars (ESC [A) and carriage returns left out."""

    def __init__(self, stream):
        self.stream, self.last = stream, None

    def write(self, text):
        import re
        for line in re.split(r"[\r\n]", re.sub(r"\x1b\[[0-9;]*[A-Za-z]", "", text)):
            if line.strip() and line != self.last:
                self.stream.write(line.rstrip() + "\n")
                self.last = line
        return len(text)

    def flush(self):
        self.stream.flush()


def _redraw_seconds():
    """Seconds between two draws of a bar: often on a terminal, a line in 20 s in a log."""
    return 0.5 if hasattr(sys.stderr, "isatty") and sys.stderr.isatty() else 20.0


# on a sweep's worker while a case runs: .forward = (topic, case index, seconds between
# updates), where the case's progress bars send their counts (see run_cases)
_SWEEP_CASE = threading.local()


@functools.cache
def _forwarded_bar():
    from tqdm import tqdm

    class ForwardedBar(tqdm):
        """A case's bar on a sweep's worker: it draws nothing there and sends its count,
        total and postfix to the client (a Dask event), which draws it (:class:`_CaseBars`)."""

        monitor_interval = 0           # no refresh from tqdm's thread: counts go as updated

        def __init__(self, iterable, forward, **options):
            from distributed import get_worker
            self._worker = get_worker()
            self._topic, self._case, options["mininterval"] = forward
            options.pop("file", None)
            options.setdefault("miniters", 1)     # no tqdm monitor to lower its own miniters
            super().__init__(iterable, file=io.StringIO(), **options)

        def display(self, msg=None, pos=None):
            try:              # a count must never fail its case; events take no numpy scalars
                self._worker.log_event(self._topic, {
                    "case": self._case, "n": _plain(self.n), "total": _plain(self.total),
                    "desc": str(self.desc), "unit": str(self.unit),
                    "postfix": str(self.postfix or "")})
            except Exception:                     # noqa: BLE001 - progress only
                pass
            return True

    return ForwardedBar


class _CaseBars:
    """The progress bars of a sweep's running cases, drawn here from the counts their
    workers send (the handler of the sweep's Dask topic; it runs on the client's event
    loop, the cases' ends are told by the main thread)."""

    def __init__(self):
        self.bars, self.ended, self.lock = {}, set(), threading.Lock()

    def __call__(self, event):
        _, msg = event
        with self.lock:
            i = msg["case"]
            if i in self.ended:                   # a late count of a case that ended
                return
            bar = self.bars.get(i)
            if bar is None:                       # its first count: drawn as it is made
                self.bars[i] = progress_bar(total=msg["total"], initial=msg["n"],
                                            desc=msg["desc"], unit=msg["unit"],
                                            postfix=msg["postfix"] or None, leave=False)
                return
            if msg["n"] < bar.n:                  # the case's next bar (or a rerun)
                bar.reset(total=msg["total"])
                bar.initial = msg["n"]
            bar.total, bar.n = msg["total"], msg["n"]
            bar.set_description_str(msg["desc"], refresh=False)   # a case may rename its stage
            bar.set_postfix_str(msg["postfix"], refresh=False)
            bar.refresh()

    def end(self, i):
        with self.lock:
            self.ended.add(i)
            bar = self.bars.pop(i, None)
        if bar is not None:
            bar.close()

    def close(self):
        for i in list(self.bars):
            self.end(i)


SCHEDULER_SCHEMES = ("tcp", "tls", "inproc", "ucx", "ws", "wss")


def scheduler_address(text):
    """argparse type: a Dask scheduler's address, ``[tcp://]host:port`` (``--scheduler``).

    Only its form is checked here (no connection is made while options are parsed);
    :func:`run_cases` connects before any case runs, and an unreachable scheduler is an
    error naming ``--scheduler``.
    """
    import re
    match = re.fullmatch(r"(?:(?P<scheme>[a-z]+)://)?(?P<host>[^\s:/]+|\[[0-9a-fA-F:]+\])"
                         r":(?P<port>\d{1,5})", text.strip())
    if match is None or (match["scheme"] or "tcp") not in SCHEDULER_SCHEMES \
            or not 0 < int(match["port"]) < 65536:
        raise argparse.ArgumentTypeError(
            f"must be a Dask scheduler address [SCHEME://]HOST:PORT with SCHEME in "
            f"{', '.join(SCHEDULER_SCHEMES)} (e.g. tcp://127.0.0.1:8786), got {text!r}")
    return text.strip() if match["scheme"] else f"tcp://{text.strip()}"


scheduler_address.__name__ = "a Dask scheduler address"


def sweep_options(parser, default_workers=None, what="the cases of the sweep"):
    """Add ``--workers``, ``--scheduler`` and ``--results-dir``, the options of
    :func:`run_cases`, to ``parser``.

    Parameters
    ----------
    parser : argparse.ArgumentParser
    default_workers : int, optional
        Default of ``--workers``; the number of cores when None.
    what : str
        What runs in parallel (the help text).
    """
    import os
    parser.add_argument("--workers", type=workers, default=default_workers or os.cpu_count() or 1,
                        help=f"local Dask worker processes (one thread each) for {what}; "
                             "1: one after the other in this process")
    parser.add_argument("--scheduler", type=scheduler_address, metavar="ADDRESS",
                        help=f"run {what} on the existing Dask cluster at ADDRESS "
                             "(tcp://host:port; its workers must import pfem_skfem); "
                             "--workers is then ignored")
    parser.add_argument("--results-dir", metavar="DIR", default=None,
                        help=f"keep the result of each of {what} in DIR as it finishes, and "
                             "take those already there instead of running them again (a "
                             "long study stopped and resumed; for the same code)")
    return parser


def volume_correction_option(parser, default="off", why=""):
    """Add ``--volume-correction {on,off}``, ``PFEMConfig.volume_correction`` (the move
    stage's volume projection, :mod:`pfem_skfem.pfem.volume_projection`), to ``parser``;
    the script reads it as ``args.volume_correction == "on"``.

    Parameters
    ----------
    parser : argparse.ArgumentParser
    default : "on" or "off"
    why : str
        Appended to the help text (e.g. what the default is chosen for).
    """
    if default not in ("on", "off"):
        raise ValueError(f"default must be 'on' or 'off', got {default!r}")
    parser.add_argument("--volume-correction", choices=("on", "off"), default=default,
                        help="shift the moved particles so that every vertex patch keeps the "
                             "volume their linearised motion states "
                             "(PFEMConfig.volume_correction)" + (f"; {why}" if why else ""))
    return parser


def checkpoint_path(directory, label, keys):
    """The checkpoint file of one run in ``directory`` (created): ``label`` and a digest of
    ``keys`` (the parameters that define the run, a dict of JSON values), so that a run
    never goes on from another run's state. Returns a Path."""
    if not str(label) or any(c in str(label) for c in "/\\"):
        raise ValueError(f"label must be a file name part, got {label!r}")
    return _named_by(directory, label, keys, ".npz")


def _named_by(directory, label, keys, suffix, default=float):
    """``directory``/``label``-digest``suffix`` (the directory created), the digest that
    of ``keys`` as sorted JSON (``default`` for values JSON has no form for)."""
    import hashlib
    text = json.dumps({k: keys[k] for k in sorted(keys)}, default=default)
    digest = hashlib.sha256(text.encode()).hexdigest()[:12]
    folder = Path(directory)
    folder.mkdir(parents=True, exist_ok=True)
    return folder / f"{label}-{digest}{suffix}"


def save_run(path, state, loop):
    """Write a run's checkpoint at ``path``: the state
    (:func:`~pfem_skfem.drivers.pfem_loop.save_checkpoint`) and the driver's own loop
    variables ``loop`` (a dict; pickled beside it as PATH.loop.pkl with the state's step).
    Each file is written under a temporary name and then renamed, so that a stop while
    writing leaves the previous one whole (:func:`load_run` checks that the two are of
    the same step)."""
    from .pfem.state import save_checkpoint
    path = Path(path)
    save_checkpoint(path, state)
    _dump_pickle({"step": state.step, "loop": loop}, path.with_name(path.stem + ".loop.pkl"))


def _dump_pickle(value, path):
    """Pickle ``value`` at ``path`` under a temporary name and then rename it, so that a
    stop while writing leaves the previous file whole (or none)."""
    import os
    import pickle
    path = Path(path)
    with open(path.with_suffix(".tmp"), "wb") as stream:
        pickle.dump(value, stream)
    os.replace(path.with_suffix(".tmp"), path)


def sitting():
    """The machine and boot a kept result was made in: host, processor (model, family,
    stepping, a digest of its feature flags), architecture and boot id. A PFEM run grows
    its round-off through remeshing, so two runs compared bit for bit (the density
    doubled, c = 0) must carry the same one."""
    import hashlib
    import platform
    info = {}
    try:
        with open("/proc/cpuinfo") as stream:
            for line in stream:
                key, _, value = line.partition(":")
                info.setdefault(key.strip(), value.strip())
    except OSError:
        pass
    try:
        with open("/proc/sys/kernel/random/boot_id") as stream:
            boot = stream.read().strip()[:8]
    except OSError:
        boot = "?"
    flags = hashlib.sha1(info.get("flags", "").encode()).hexdigest()[:8]
    model = info.get("model name", platform.processor())
    return (f"{platform.node()} ({model}, family {info.get('cpu family', '?')} model "
            f"{info.get('model', '?')} stepping {info.get('stepping', '?')}, flags {flags}, "
            f"{platform.machine()}), boot {boot}")


def load_run(path):
    """(state, loop) written by :func:`save_run`, or None when ``path`` has no checkpoint
    or its two files are not of the same step (a stop between the two renames)."""
    import pickle
    from .pfem.state import load_checkpoint
    path = Path(path)
    side = path.with_name(path.stem + ".loop.pkl")
    if not (path.is_file() and side.is_file()):
        return None
    try:
        state = load_checkpoint(path)
        with open(side, "rb") as stream:
            saved = pickle.load(stream)
    except Exception as error:                   # noqa: BLE001 - any damage, named
        raise DamagedFileError(
            f"checkpoint {path} (with {side.name}) cannot be read ({type(error).__name__}: "
            f"{error}); delete both files to start that run again") from None
    return (state, saved["loop"]) if saved["step"] == state.step else None


def checkpoint_options(parser, what="run"):
    """Add ``--checkpoint-dir DIR`` and ``--checkpoint-every K`` to ``parser``: each
    ``what`` saves itself in DIR (every K steps and at the end, :func:`checkpoint_path`)
    and goes on from its own checkpoint when the script is run again."""
    parser.add_argument("--checkpoint-dir", default=None,
                        help=f"save each {what}'s state in this directory (every "
                             f"--checkpoint-every steps and at the end) and go on from a "
                             f"{what}'s checkpoint if there is one: a long study can be "
                             f"stopped and resumed")
    parser.add_argument("--checkpoint-every", type=positive_int, default=20,
                        help=f"steps between a {what}'s checkpoints")
    return parser


def alpha_advected_option(parser, default=0.0, why=""):
    """Add ``--alpha-advected R``, ``PFEMConfig.alpha_advected`` (keep a triangle of the
    previous step's moved mesh up to circumradius R h; 0: the plain alpha-shape)."""
    parser.add_argument("--alpha-advected", type=nonnegative_float, default=default,
                        help="keep a Delaunay triangle inside the previous step's moved mesh "
                             "while its circumradius is at most this many h "
                             "(PFEMConfig.alpha_advected; 0: off, the plain alpha-shape)"
                             + (f"; {why}" if why else ""))
    return parser


class SweepError(RuntimeError):
    """Cases of a sweep failed: ``failures`` holds (index, case, exception) of each,
    ``results`` the results of all cases (None where a case failed)."""

    def __init__(self, desc, failures, results):
        self.failures, self.results = failures, results
        lines = [f"{len(failures)} of {len(results)} {desc} failed:"]
        lines += [f"  case {i}: {_case_text(case)}: {type(e).__name__}: {e}"
                  for i, case, e in failures]
        super().__init__("\n".join(lines))


def _case_text(case, width=300):
    """The keywords of a case on one line (arrays and long values shortened)."""
    parts = []
    for key, value in case.items():
        text = repr(value)
        parts.append(f"{key}={text if len(text) <= 40 else text[:37] + '...'}")
    text = ", ".join(parts)
    return text if len(text) <= width else text[:width - 3] + "..."


def run_cases(function, cases, workers=1, *, desc="cases", scheduler=None, results_dir=None):
    """``function(**case)`` for each case (a dict of its keywords); the results in order.

    With ``workers`` > 1 (and more than one case) the cases run on a Dask
    ``LocalCluster`` of ``workers`` single-threaded worker processes, started here and
    closed on return; with ``scheduler`` (an address, ``--scheduler``) on that existing
    cluster instead, whatever ``workers`` says. ``function`` must be importable there
    (a module-level function). Results are gathered as they finish. With progress (a
    case's ``verbose`` keyword) a bar counts the cases and each running case's own bar
    is drawn below it: the case's bar on its worker draws nothing and sends its counts
    here (Dask events), so that the bars of several processes do not interleave. With
    ``workers`` = 1 the cases run one after the other in this process, without Dask.

    A failing case is reported (one line with its parameters) when it fails and the others
    go on; at the end :class:`SweepError` lists every failure (the first one chained as
    its cause), so a script exits non-zero.

    With ``results_dir`` (``--results-dir``) each case's result is kept there as it
    finishes (:func:`result_path`), and a case whose result is there is not run again:
    a sweep stopped part way goes on where it stopped. The file is named by the case's
    parameters, not by the code: a cache is for the same code.
    """
    cases = [dict(c) for c in cases]
    if results_dir is not None:
        return _run_cached(function, cases, workers, desc, scheduler, results_dir)
    if scheduler is None and (workers <= 1 or len(cases) <= 1):
        return _run_serial(function, cases, desc)
    verbose = any(c.get("verbose") for c in cases)
    results = [None] * len(cases)
    failures = []
    topic, bars = f"{desc}-progress-{_token()}", _CaseBars()
    with _dask_client(min(workers, len(cases)), scheduler) as client:
        where = (f"on the cluster at {scheduler}" if scheduler
                 else f"on {min(workers, len(cases))} workers")
        # the bar over the cases first: the cases' own bars are drawn below it
        with progress_bar(total=len(cases), disable=not verbose, unit="case",
                          desc=f"{desc} {where}") as bar:
            subscribed = False
            try:
                if verbose:
                    client.subscribe_topic(topic, bars)
                    subscribed = True
                interval = _redraw_seconds()
                # the keywords go as one dict: a case's own 'key' or 'priority' is not submit's
                futures = {client.submit(_call, function, c,
                                         (topic, i, interval) if c.get("verbose") else None,
                                         pure=False, key=f"{desc}-{i}-{_token()}"): i
                           for i, c in enumerate(cases)}
                from distributed import as_completed
                for future in as_completed(futures):
                    i = futures[future]
                    bars.end(i)
                    try:
                        results[i] = future.result()
                    except Exception as error:   # noqa: BLE001 - reported with its case
                        failures.append((i, cases[i], error))
                        progress(f"{desc}: case {i} failed ({_case_text(cases[i])}): "
                                 f"{type(error).__name__}: {error}")
                    bar.update(1)
            finally:                             # also on an error or Ctrl-C
                if subscribed:
                    client.unsubscribe_topic(topic)
                bars.close()
    _raise_failures(desc, failures, results)
    return results


def _call(function, keywords, forward=None):
    """``function(**keywords)`` on a sweep's worker; ``forward``: where its progress bars
    send their counts (:func:`progress_bar`), None for no progress."""
    _SWEEP_CASE.forward = forward
    try:
        return function(**keywords)
    finally:
        _SWEEP_CASE.forward = None


def _key_value(value):
    """A case's keyword as JSON for :func:`result_path`: a function by its import name,
    anything else without a JSON form by its repr (an address in it only misses the
    cache)."""
    if callable(value) and hasattr(value, "__qualname__"):
        return f"{value.__module__}.{value.__qualname__}"
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    return str(value) if isinstance(value, Path) else repr(value)


def result_path(directory, desc, case):
    """Where :func:`run_cases` keeps the result of ``case`` (its keywords, but its
    ``verbose``): ``directory``/``desc``-digest.result.pkl, as :func:`checkpoint_path`."""
    keys = {k: v for k, v in case.items() if k != "verbose"}
    label = str(desc).replace(" ", "_").replace("/", "_").replace("\\", "_")
    return _named_by(directory, label, keys, ".result.pkl", default=_key_value)


def _call_kept(function, keywords, path, verbose=None):
    """``function(**keywords)``, its result pickled at ``path`` (written under a temporary
    name and renamed: a stop while writing leaves no half file). ``verbose`` (None: as the
    keywords say) is the case's own."""
    if verbose is not None:
        keywords = dict(keywords, verbose=verbose)
    result = function(**keywords)
    _dump_pickle(result, path)
    return result


def _run_cached(function, cases, workers, desc, scheduler, results_dir):
    import pickle
    paths = [result_path(results_dir, desc, c) for c in cases]
    results = [None] * len(cases)
    todo = []
    for i, path in enumerate(paths):
        if path.is_file():
            try:
                with open(path, "rb") as stream:
                    results[i] = pickle.load(stream)
            except Exception as error:           # noqa: BLE001 - any damage, named
                raise DamagedFileError(
                    f"{path}: a kept result of --results-dir cannot be read "
                    f"({type(error).__name__}: {error}); delete it to run that case "
                    f"again") from None
        else:
            todo.append(i)
    if todo and any(c.get("verbose") for c in cases):
        progress(f"{desc}: {len(cases) - len(todo)} of {len(cases)} case(s) taken from "
                 f"{results_dir}")
    wrapped = [dict(function=function, keywords=cases[i], path=str(paths[i]),
                    **({"verbose": cases[i]["verbose"]} if "verbose" in cases[i] else {}))
               for i in todo]
    try:
        done = run_cases(_call_kept, wrapped, workers, desc=desc, scheduler=scheduler)
    except SweepError as error:                  # name the failures by their own case
        failures = [(todo[i], cases[todo[i]], e) for i, _, e in error.failures]
        for k, i in enumerate(todo):
            results[i] = error.results[k]
        raise SweepError(desc, failures, results) from error.__cause__
    for k, i in enumerate(todo):
        results[i] = done[k]
    return results


def _run_serial(function, cases, desc):
    results, failures = [], []
    for i, case in enumerate(cases):
        try:
            results.append(function(**case))
        except Exception as error:               # noqa: BLE001 - reported with its case
            results.append(None)
            failures.append((i, case, error))
            if len(cases) > 1:
                progress(f"{desc}: case {i} failed ({_case_text(case)}): "
                         f"{type(error).__name__}: {error}")
    _raise_failures(desc, failures, results)
    return results


def _raise_failures(desc, failures, results):
    if failures:
        failures.sort(key=lambda f: f[0])
        raise SweepError(desc, failures, results) from failures[0][2]


def _token():
    import uuid
    return uuid.uuid4().hex[:8]


class _dask_client:
    """A ``distributed.Client``: to the cluster at ``scheduler``, or to a quiet
    ``LocalCluster`` of ``workers`` single-threaded processes that is closed on exit."""

    def __init__(self, workers, scheduler=None):
        self.workers, self.scheduler = workers, scheduler
        self.cluster = self.client = None

    def __enter__(self):
        import logging
        import dask
        from distributed import Client, LocalCluster
        # a long solve holds a worker's GIL for minutes: no timeout may declare it dead
        self._config = dask.config.set({"distributed.scheduler.worker-ttl": None,
                                        "distributed.admin.system-monitor.gil.enabled": False})
        self._config.__enter__()
        quiet = logging.CRITICAL          # failures are reported by run_cases, with their case
        self._levels = {name: logging.getLogger(name).level
                        for name in ("distributed", "tornado", "bokeh")}
        for name in self._levels:
            logging.getLogger(name).setLevel(quiet)
        try:
            if self.scheduler:
                try:
                    self.client = Client(self.scheduler, timeout="10s")
                except (OSError, TimeoutError) as error:
                    raise OptionError(f"--scheduler {self.scheduler}: no Dask scheduler "
                                     f"reachable there ({error})") from None
            else:
                import warnings
                with warnings.catch_warnings():    # its HTTP server takes another port
                    warnings.filterwarnings("ignore", "Port .* is already in use", UserWarning)
                    self.cluster = LocalCluster(n_workers=self.workers, threads_per_worker=1,
                                                processes=True, dashboard_address=None,
                                                memory_limit=0, silence_logs=quiet)
                self.client = Client(self.cluster)
        except BaseException:
            self.__exit__(None, None, None)
            raise
        return self.client

    def __exit__(self, *exc):
        import logging
        try:
            if self.client is not None:
                self.client.close()
            if self.cluster is not None:
                self.cluster.close()
        finally:
            for name, level in self._levels.items():
                logging.getLogger(name).setLevel(level)
            self._config.__exit__(None, None, None)
        return False


def pyplot():
    """matplotlib.pyplot, on the Agg backend unless pyplot is already in use (a notebook)."""
    import matplotlib
    if "matplotlib.pyplot" not in sys.modules:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def figure_dir(args, name):
    """``args.outdir / name``, created."""
    out = Path(args.outdir) / name
    out.mkdir(parents=True, exist_ok=True)
    return out


FIGURE_PIXELS = ((400, 2600), (250, 2000))
"""The (min, max) width and height of a saved figure in pixels."""
SMALLEST_FONT = 7.0
"""Tick labels and axis labels at least this many points (at the saved dpi: readable)."""
LEGIBLE_AXES_PX = (160, 100)
"""The least width and height of a panel with data, in CSS pixels as a page shows it."""
LEGIBLE_TEXT_PX = 8.0
"""The least size of a tick or axis label, in CSS pixels as a page shows it."""
COLOUR_WORDS = r"\bcolou?r(?:ed|s)?\b"
"""A title matching this (case aside) says that colour means something."""


def _is_colorbar(ax):
    return hasattr(ax, "_colorbar") or ax.get_label() == "<colorbar>"


def _has_content(ax):
    return bool(ax.lines or ax.collections or ax.images or ax.patches or ax.texts
                or ax.tables or ax.artists or ax.get_legend())


def _labelled_sibling(ax, axis):
    """A panel sharing ``ax``'s ``axis`` has the label (a grid labels its outer panels)."""
    shared = ax.get_shared_x_axes() if axis == "x" else ax.get_shared_y_axes()
    return any(getattr(other, f"get_{axis}label")().strip()
               for other in shared.get_siblings(ax) if other is not ax)


def _colour_mapped(ax):
    """The artists of ``ax`` whose colour encodes a quantity (a varying array, colormap)."""
    found = []
    for artist in [*ax.collections, *ax.images]:
        data = artist.get_array() if hasattr(artist, "get_array") else None
        if data is None or np.ndim(data) != 1 and not (np.ndim(data) == 2
                                                        and artist in ax.images):
            continue                         # no colour mapping, or an RGB(A) picture
        values = np.ma.compressed(np.ma.masked_invalid(np.asarray(data, dtype=float)))
        if values.size and np.ptp(values) > 0:
            found.append(artist)
    return found


def _colour_explained(fig, ax, artist, colorbars):
    """A colour bar of the same colormap and range, a legend, or contour labels."""
    if ax.get_legend() is not None or getattr(artist, "labelTexts", None):
        return True
    for cb in colorbars:
        m = cb.mappable
        if m is artist or (m.get_cmap().name == artist.get_cmap().name
                           and m.get_clim() == artist.get_clim()):
            return True
    return False


def _page_problems(fig, axes, page_width):
    """Panels and labels too small once ``fig`` is shown at ``page_width`` CSS pixels."""
    fig.canvas.draw()                        # aspect-fixed axes take their final size
    renderer = fig.canvas.get_renderer()
    width = fig.get_tightbbox(renderer).width * fig.dpi    # as shown inline: cropped
    scale = min(1.0, page_width / width)    # a PNG pixel is a CSS pixel, shrunk to fit
    (w_min, h_min), problems = LEGIBLE_AXES_PX, []
    for i, ax in axes:
        name = f"axes {i + 1} ({ax.get_title() or 'untitled'})"
        box = ax.get_window_extent(renderer)
        w, h = box.width * scale, box.height * scale
        if w < w_min or h < h_min:
            problems.append(f"{name}: {w:.0f} x {h:.0f} px at the page's {page_width} px "
                            f"(want at least {w_min} x {h_min}: fewer or larger panels)")
        texts = [ax.xaxis.label, ax.yaxis.label, *ax.get_xticklabels(), *ax.get_yticklabels()]
        sizes = [t.get_fontsize() * fig.dpi / 72 * scale for t in texts
                 if t.get_visible() and t.get_text()]
        if sizes and min(sizes) < LEGIBLE_TEXT_PX:
            problems.append(f"{name}: labels of {min(sizes):.1f} px at the page's "
                            f"{page_width} px (want {LEGIBLE_TEXT_PX:g}: a narrower figure)")
    return problems


def figure_problems(fig, dpi=120, page_width=None, content=True):
    """What makes ``fig`` hard to read, before it is saved; an empty list when nothing.

    Every figure has a title (an axes title or ``suptitle``) and a saved size within
    :data:`FIGURE_PIXELS`, no wider than 4.5 times its height; every visible axes
    has something drawn in it; every axes with data has x and y labels (a colour bar:
    its label; an axis without ticks, a picture's, or sharing a labelled one: none),
    and its tick labels are at least :data:`SMALLEST_FONT` points; colour
    that encodes a quantity (a scatter's ``c``, an image, a ``tripcolor``) has a colour
    bar (or a legend), and a title that speaks of colour has one too. Given
    ``page_width``, the figure is judged as a page shows it (scaled down to that many
    CSS pixels when wider): each panel with data at least :data:`LEGIBLE_AXES_PX`,
    its labels at least :data:`LEGIBLE_TEXT_PX`.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    dpi : float
        The resolution it will be saved at.
    page_width : float, optional
        The width of the page's content column in CSS pixels (the book's).
    content : bool
        Check for empty panels and for colour without a colour bar (default).

    Returns
    -------
    list of str
    """
    import re
    problems = []
    w, h = fig.get_size_inches() * dpi
    (w0, w1), (h0, h1) = FIGURE_PIXELS
    if not (w0 <= w <= w1 and h0 <= h <= h1) or w > 4.5 * h:
        problems.append(f"size {w:.0f} x {h:.0f} px (want {w0}-{w1} x {h0}-{h1}, "
                        "at most 4.5:1)")
    suptitle = fig._suptitle.get_text() if getattr(fig, "_suptitle", None) else ""
    axes = [ax for ax in fig.get_axes() if ax.get_visible()]
    if not suptitle and not any(ax.get_title() or ax.get_title("left") for ax in axes):
        problems.append("no title: say what the figure shows (set_title or suptitle)")
    colorbars = [ax._colorbar for ax in axes if getattr(ax, "_colorbar", None)]
    titles = [suptitle] + [ax.get_title() for ax in axes]
    speaks_of_colour = any(re.search(COLOUR_WORDS, t, re.I) for t in titles)
    legends = any(ax.get_legend() for ax in axes)
    if content and speaks_of_colour and not colorbars and not legends:
        problems.append("a title speaks of colour but there is no colour bar (or legend)")
    with_data = []
    for i, ax in enumerate(axes):
        name = f"axes {i + 1} ({ax.get_title() or 'untitled'})"
        if _is_colorbar(ax):
            if ax.axison and not (ax.get_ylabel() or ax.get_xlabel()):
                problems.append(f"{name}: a colour bar without a label")
            continue
        if not _has_content(ax):
            if content:
                problems.append(f"{name}: empty (nothing drawn: remove it)")
            continue
        for artist in _colour_mapped(ax) if content else ():
            if not _colour_explained(fig, ax, artist, colorbars):
                problems.append(f"{name}: colour encodes a quantity "
                                f"({type(artist).__name__}) without a colour bar")
                break
        with_data.append((i, ax))
        if not ax.axison:
            continue
        for axis, label in (("x", ax.get_xlabel()), ("y", ax.get_ylabel())):
            ticked = len(getattr(ax, f"get_{axis}ticks")()) > 0   # no ticks: a picture
            if ticked and not label.strip() and not _labelled_sibling(ax, axis):
                problems.append(f"{name}: no {axis} label")
        for tick in ax.get_xticklabels() + ax.get_yticklabels():
            if tick.get_visible() and tick.get_fontsize() < SMALLEST_FONT:
                problems.append(f"{name}: tick labels of {tick.get_fontsize():g} pt")
                break
    if page_width is not None and with_data:
        problems += _page_problems(fig, with_data, page_width)
    return problems


def inspect_figures(script, argv, outdir):
    """Draw ``script``'s figures at ``argv`` (a quick run) and report what is hard to read.

    Runs the case in-process, then its ``figures`` with every :func:`save_figure`
    checked by :func:`figure_problems` before it saves; the other pictures it writes
    (pyvista PNGs) are checked for their size.

    Returns
    -------
    (Report, dict)
        The report, and for each file written, the list of its problems.
    """
    import matplotlib.image as mpimg

    args = script.build_parser().parse_args(["--quiet", *argv, "--outdir", str(outdir)])
    report = script.run(args)
    found = {}
    original = getattr(script, "save_figure", None)

    def checked(fig, path, dpi=120):
        # the content checks (empty panels, colour without a bar) are the book's so far:
        # the scripts' figures have not been surveyed for them (issue 36, item 7)
        found[str(path)] = figure_problems(fig, dpi, content=False)
        save_figure(fig, path, dpi)

    script.save_figure = checked
    try:
        script.figures(args, **report.data)
    finally:
        if original is not None:
            script.save_figure = original
    (w0, w1), (h0, h1) = FIGURE_PIXELS
    for png in sorted(Path(outdir).rglob("*.png")):
        if str(png) in found:
            continue
        h, w = mpimg.imread(png).shape[:2]
        found[str(png)] = ([] if w0 <= w <= w1 and h0 <= h <= h1 else
                           [f"picture of {w} x {h} px"])
    return report, found


def save_figure(fig, path, dpi=120):
    """Lay out ``fig`` (unless it has a layout engine), write it to ``path`` and close it."""
    engine = getattr(fig, "get_layout_engine", lambda: None)()
    if engine is None or type(engine).__name__ == "PlaceHolderLayoutEngine":
        fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    pyplot().close(fig)
