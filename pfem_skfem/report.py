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

    def main(argv=None):
        args = build_parser().parse_args(argv)     # --quick applied, options checked
        return run(args).finish(args, figures)     # figures, table, --json, exit code

so that tests, the book and the benchmarks call ``run`` in-process
(``from verification import strip_footing``; :func:`run_script`) and ``pfem-skfem verify`` runs the
same script in a subprocess. :meth:`Report.finish` prints the table, writes
``--json PATH`` and returns the exit code; :func:`pyplot`, :func:`figure_dir` and
:func:`save_figure` hold the figure boilerplate.

JSON layout::

    {"case": ..., "params": {...},
     "quantities": [{"name", "value", "reference", "source", "rel_error",
                     "tolerance", "pass"}, ...]}

``rel_error`` is |value - reference| / |reference|, or the absolute error when the
reference is zero; ``pass`` is ``rel_error <= tolerance``. A quantity checked
against an interval (a bound, a range of published values) gives ``lower`` and
``upper`` instead; its ``rel_error`` is the relative distance outside the interval.
"""
import argparse
from dataclasses import asdict, dataclass
import json
import math
from pathlib import Path
import sys

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


HARNESS_OPTIONS = ("json", "outdir", "no_figures", "progress", "workers")
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
        q = Quantity(name, value, reference, source, float(tolerance), err,
                     bool(err <= tolerance))
        self.quantities.append(q)
        return q

    def add_interval(self, name, value, lower, upper, source, tolerance=0.0,
                     reference=None):
        """Check that ``value`` lies in [lower, upper] (widened by ``tolerance`` relative)."""
        value = float(value)
        ref = float(reference) if reference is not None else 0.5 * (lower + upper)
        scale = max(abs(lower), abs(upper), 1e-300)
        outside = max(lower - value, value - upper, 0.0) / scale
        q = Quantity(name, value, ref, source, float(tolerance), outside,
                     bool(outside <= tolerance), float(lower), float(upper))
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


class ScriptParser(argparse.ArgumentParser):
    """An argument parser whose ``parse_args`` applies ``--quick`` and the script's checks.

    With ``--quick``, each option named in ``quick`` takes its quick value unless
    the user gave it a value other than its default; then ``check(args)`` may
    return a message, reported as a usage error (exit code 2).
    """

    def __init__(self, description, quick=None, check=None):
        super().__init__(description=description,
                         formatter_class=argparse.ArgumentDefaultsHelpFormatter)
        self.quick = dict(quick or {})
        self.check = check

    def parse_args(self, args=None, namespace=None):
        parsed = super().parse_args(args, namespace)
        if parsed.quick:
            for key, value in self.quick.items():
                if getattr(parsed, key) == self.get_default(key):
                    setattr(parsed, key, value)
        message = self.check(parsed) if self.check else None
        if message:
            self.error(message)
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
    p.add_argument("--progress", action="store_true", help="progress output on stderr")
    return p


def run_script(script, *argv):
    """A verification script in-process: ``script.run`` on its parsed ``argv``.

    Parameters
    ----------
    script : module
        A script of ``verification/`` (``from verification import strip_footing``).
    *argv : str
        Its command-line options, e.g. ``"--quick", "--no-figures"``.

    Returns
    -------
    Report
        With ``report.data`` holding the in-memory results.
    """
    return script.run(script.build_parser().parse_args(list(argv)))


def positive(name):
    """argparse type: a positive float, with an error naming the option."""
    def parse(text):
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be a number, got {text!r}")
        if not math.isfinite(value) or value <= 0:
            raise argparse.ArgumentTypeError(f"{name} must be positive, got {text!r}")
        return value
    return parse


def progress(message):
    """One line of progress on stderr."""
    print(message, file=sys.stderr, flush=True)


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


def save_figure(fig, path, dpi=120):
    """Lay out ``fig``, write it to ``path`` and close it."""
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    pyplot().close(fig)
