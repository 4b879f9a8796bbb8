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

    {"case": ..., "params": {the inputs},
     "quantities": [{"name", "value", "reference", "source", "rel_error",
                     "tolerance", "pass"}, ...],
     "extra": {"derived": {results derived before the quantities}, ...},
     "tables": {...}}

``rel_error`` is |value - reference| / |reference|, or the absolute error when the
reference is zero; ``pass`` is ``rel_error <= tolerance``. A quantity checked
against an interval (a bound, a range of published values) gives ``lower`` and
``upper`` (null for an infinite end) and a null ``reference`` (unless the script names
one beside the interval); its ``rel_error`` is the distance outside
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
measurements, :func:`~pfem_skfem.drivers.resumable.save_run`) under
:func:`~pfem_skfem.harness.store.checkpoint_path` (the run's label and a digest of its
parameters) and goes on from it when run again
(``verification/silo_discharge.py --checkpoint-dir``, ``landslide_yangbaodi.py``).

``ScriptParser`` gives every script ``--quiet`` (no progress bars) next to the
``--progress`` of old (now the default); :func:`progress_bar` is the bar (tqdm) of a
long loop, :func:`progress` one line. Conditions between options (``--a`` below
``--b``) go in the script's ``check(args)``, whose message must name the options.

Each job has its module in :mod:`pfem_skfem.harness`: :mod:`.options` (the parser, the
validators above, the option groups), :mod:`.progress` (the bars), :mod:`.sweeps`
(:func:`run_cases`), :mod:`.store` (files named by their parameters, JSON values) and
:mod:`.figures` (:func:`pyplot`, :func:`figure_dir`, :func:`save_figure`).
"""
import argparse
from collections.abc import Mapping
from dataclasses import asdict, dataclass
import json
import math
from pathlib import Path
import sys
import warnings

import numpy as np

from .options import OptionError
from .store import DamagedFileError, _plain
from .sweeps import SweepError

__all__ = ["Quantity", "Report", "relative_error", "HARNESS_OPTIONS", "thinned",
           "run_script", "script_main"]


@dataclass
class Quantity:
    name: str
    value: float
    reference: float | None
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



def relative_error(value, reference):
    """|value - reference| / |reference|, the absolute error for a zero reference."""
    if reference == 0:
        return abs(value - reference)
    return abs(value - reference) / abs(reference)


def observed_order(sizes, errors, *, counts=False):
    """The order p of a convergence study, error ~ size^p: the slope of the least-squares
    line through (log size, log of the error's magnitude).

    ``counts``: the sizes are counts (elements, cells across, steps) of a size ~ 1/count:
    p of error ~ count^-p, the slope's opposite (a positive p for an error that falls).
    """
    slope = np.polyfit(np.log(sizes), np.log(np.abs(errors)), 1)[0]
    return float(-slope if counts else slope)


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
        Results the script derived before its quantities (the element count, a time):
        written to the JSON as ``extra["derived"]``, so that ``params`` holds inputs only.

    Attributes
    ----------
    quantities : list of Quantity
        What :meth:`add` and :meth:`add_interval` compared, in order.
    extra : dict
        Further results written to the JSON (histories).
    tables : dict
        The tables of :meth:`add_table` by name, written to the JSON as ``tables``.
    data : dict
        In-memory results for the script's figures and for callers; not written.
    """

    def __init__(self, case, params=(), **more):
        if isinstance(params, argparse.Namespace):
            params = vars(params)
        self.case = case
        self.params = {k: _plain(v) for k, v in dict(params).items()
                       if k not in HARNESS_OPTIONS}
        self.quantities = []
        # results the script derived (an element count, a time): not inputs, so in extra
        self.extra = {"derived": {k: _plain(v) for k, v in more.items()}} if more else {}
        self.tables = {}
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

        The quantity's ``reference`` is None (JSON null) unless one is given: the interval
        is the reference (``lower``, ``upper``), and ``rel_error`` its excess.

        The excess outside the interval is relative to ``max(|lower|, |upper|)`` when both
        ends are finite; to the finite end's magnitude for a one-sided interval (absolute
        where that end is 0): an infinite scale would let any finite value pass. A NaN or
        infinite value fails (its ``rel_error`` NaN or inf).
        """
        value, lower, upper = float(value), float(lower), float(upper)
        ref = float(reference) if reference is not None else None   # an interval has none
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

    def add_bracket(self, name, lower, upper, reference, source):
        """A strict lower and a strict upper bound of a quantity known to be ``reference``:
        ``name_lower`` checked in [-inf, reference] and ``name_upper`` in [reference, inf],
        each citing ``source``, in which ``{bound}`` reads 'a lower bound' or 'an upper
        bound'. Returns the two quantities."""
        return (self.add_interval(f"{name}_lower", lower, -math.inf, reference,
                                  source.replace("{bound}", "a lower bound"),
                                  reference=reference),
                self.add_interval(f"{name}_upper", upper, reference, math.inf,
                                  source.replace("{bound}", "an upper bound"),
                                  reference=reference))

    def add_table(self, name, columns, rows, *, formats=None, title=None, show=True,
                  skip_empty=False):
        """A table of results: printed now (``show``), and written to the JSON
        (``tables[name]``: its ``columns`` and ``rows``).

        ``columns`` : the column names;  ``rows`` : sequences of one value per column;
        ``formats`` : {column: format spec} (default: integers as they are, other numbers
        ``.4g``, the rest as text);  ``title`` : a line above it (default ``name``);
        ``skip_empty`` : without rows (a study not asked for) no table, printed or kept, and
        None returned, rather than a header alone.

        A table of records: ``columns`` a {column: key, tuple of keys, or function of a
        record} mapping, ``rows`` the records (the results of a study's cases, dicts), each
        cell ``record[key]``, the entry down the keys (``("reference", "h")``:
        ``record["reference"]["h"]``) or ``function(record)``::

            front = lambda r: r["x_f"] / r["x_nye"]
            report.add_table("runs", {"run": "label", "mu": "mu",
                                      "x_f/Nye": front}, runs)
        """
        rows = list(rows)
        if skip_empty and not rows:
            return None
        if isinstance(columns, Mapping):
            rows = [[_entry(r, get) for get in columns.values()] for r in rows]
        columns = [str(c) for c in columns]
        rows = [list(row) for row in rows]
        for row in rows:
            if len(row) != len(columns):
                raise ValueError(f"table {name!r}: a row of {len(row)} values for "
                                 f"{len(columns)} columns")
        self.tables[name] = {"columns": columns, "rows": rows}
        if show:
            print(format_table(columns, rows, formats, title or name))
        return self.tables[name]

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
        if self.tables:
            out["tables"] = json.loads(json.dumps(self.tables, default=_plain))
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



def _entry(record, get):
    """A cell of a table of records (:meth:`Report.add_table`): ``get(record)``, or
    ``record[get]``, or for a tuple of keys the entry down them."""
    if callable(get):
        return get(record)
    for key in get if isinstance(get, tuple) else (get,):
        record = record[key]
    return record


def sampled(history, key, at):
    """A history ({name: a sequence, one entry a step}) as the records of a table at the
    entries whose ``history[key]`` (a time, say) is nearest each of ``at``, in that order:
    [{name: its entry there}], the rows a table shows of a long history."""
    values = np.asarray(history[key])
    return [{name: entries[i] for name, entries in history.items()}
            for i in (int(np.argmin(np.abs(values - t))) for t in at)]


def format_table(columns, rows, formats=None, title=None):
    """The text of a table: a title line, the header, a rule and one line a row, each
    column as wide as its widest cell, numbers right-aligned (:meth:`Report.add_table`)."""
    formats = formats or {}

    def cell(column, value):
        if column in formats and value is not None:
            return format(value, formats[column])
        if isinstance(value, (bool, np.bool_)) or value is None:
            return str(value)
        if isinstance(value, (int, np.integer)):
            return str(int(value))
        if isinstance(value, (float, np.floating)):
            return format(float(value), ".4g")
        return str(value)

    cells = [[cell(c, v) for c, v in zip(columns, row)] for row in rows]
    numeric = [all(isinstance(row[i], (int, float, np.number)) and not isinstance(row[i], bool)
                   for row in rows) for i in range(len(columns))]
    width = [max([len(c)] + [len(r[i]) for r in cells]) for i, c in enumerate(columns)]

    def line(values):
        return "  ".join(v.rjust(w) if num else v.ljust(w)
                         for v, w, num in zip(values, width, numeric)).rstrip()
    head = line(columns)
    return "\n".join(([title] if title else []) + [head, "-" * len(head)]
                     + [line(r) for r in cells])


def thinned(case, histories=(), drop=(), entries=100):
    """A case for the JSON: without the keys ``drop``, its ``histories`` (sequences as
    long as the first of them) thinned to about ``entries`` entries; without histories,
    the case less ``drop``, its keys in their order."""
    every = max(1, len(case[histories[0]]) // entries) if histories else 1
    kept = {k: v for k, v in case.items() if k not in tuple(drop) + tuple(histories)}
    return kept | {k: np.asarray(case[k])[::every].tolist() for k in histories}


def thinned_groups(groups, histories=(), drop=()):
    """A study's groups of cases for the JSON: {group: each of its cases :func:`thinned`
    (``histories`` thinned, ``drop`` left out)}, in the order of ``groups``: what a script
    keeps of every group in ``extra`` and beside its figures."""
    return {name: [thinned(case, histories, drop) for case in cases]
            for name, cases in groups.items()}


class counted_warnings:
    """``with counted_warnings(category) as counted:`` the warnings of ``category`` (and its
    subclasses) raised in the block are counted, ``counted.count``, not shown; the others
    are shown as usual when the block ends (e.g. a solver's accepted near-solutions,
    counted into the report)."""

    def __init__(self, category):
        self.category, self.count = category, 0

    def __enter__(self):
        self._catch = warnings.catch_warnings(record=True)
        self._caught = self._catch.__enter__()
        warnings.simplefilter("always", self.category)
        return self

    def __exit__(self, *exc):
        self._catch.__exit__(*exc)
        mine = [issubclass(w.category, self.category) for w in self._caught]
        self.count = sum(mine)
        for w, counted in zip(self._caught, mine):
            if not counted:
                warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
        return False


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


