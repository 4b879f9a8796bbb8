"""The verification-script contract: options, quantities against references, JSON.

Every script under ``verification/`` builds its parser with :func:`base_parser`,
collects its results in a :class:`Report` and ends with :meth:`Report.finish`,
which prints the table, writes ``--json PATH`` and returns the exit code.

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


class Report:
    """Quantities of one verification case, compared with their references."""

    def __init__(self, case, params):
        self.case = case
        self.params = {k: _plain(v) for k, v in dict(params).items()}
        self.quantities = []
        self.extra = {}

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
        return all(q.passed for q in self.quantities)

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

    def finish(self, args):
        """Print the table, write the JSON named by ``--json``; return the exit code."""
        print(self.table())
        if getattr(args, "json", None):
            self.write_json(args.json)
            print(f"results written to {args.json}")
        return 0 if self.passed else 1


def base_parser(description):
    """An argument parser with the options every verification script shares."""
    p = argparse.ArgumentParser(description=description,
                                formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    p.add_argument("--quick", action="store_true",
                   help="a small size that runs in seconds to a minute (tests, CI)")
    p.add_argument("--json", metavar="PATH", help="write the results as JSON to PATH")
    p.add_argument("--outdir", default="results",
                   help="directory for figures and VTU files")
    p.add_argument("--no-figures", action="store_true", help="skip figures")
    p.add_argument("--progress", action="store_true", help="progress output on stderr")
    return p


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
