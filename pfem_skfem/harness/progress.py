"""Progress on stderr: one line (:func:`progress`), a bar (:func:`progress_bar`: tqdm, plain
lines in a log) and the callback that counts a driver's rounds on it (:func:`bar_callback`), the bar of a sweep's case forwarded from its Dask worker and drawn by the
client (:class:`_CaseBars`), and the bar of a PFEM run's steps (:class:`StepBar`).
"""
import functools
import io
import sys
import threading


def progress(message, file=None):
    """One line of progress on stderr (or ``file``), above any progress bar."""
    from tqdm import tqdm
    file = sys.stderr if file is None else file
    tqdm.write(str(message), file=file)
    file.flush()


def progress_bar(iterable=None, *, args=None, total=None, desc=None, unit="case",
                 stream=None, **options):
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
    stream : file, optional
        Where the bar is drawn (stderr by default): live on a terminal, plain lines on
        anything else (a log).

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
    stream = sys.stderr if stream is None else stream
    terminal = hasattr(stream, "isatty") and stream.isatty()
    options.setdefault("mininterval", _redraw_seconds(stream))
    return tqdm(iterable, total=total, desc=desc, unit=unit,
                file=stream if terminal else _PlainLines(stream),
                disable=disable, dynamic_ncols=terminal, **options)


def bar_callback(bar, postfix=None):
    """A ``progress`` callback for a driver that reports each of its rounds (``adapt``,
    ``bracket_safety``), or for a loop's results: each call ``callback(item)`` counts one
    on ``bar`` and shows ``postfix(item)`` after it (the latest result), e.g.
    ``adapt(problem, progress=bar_callback(bar, lambda r: f"{r.elements} el"))``."""
    def callback(item):
        bar.update(1)
        if postfix is not None:
            bar.set_postfix_str(postfix(item))
    return callback


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


def _redraw_seconds(stream=None):
    """Seconds between two draws of a bar: often on a terminal, a line in 20 s in a log."""
    stream = sys.stderr if stream is None else stream
    return 0.5 if hasattr(stream, "isatty") and stream.isatty() else 20.0


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
            from .store import _plain         # numpy: imported when a bar is forwarded
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


class StepBar:
    """The bar of a PFEM run's steps ``first + 1``-``last`` (:func:`progress_bar`): by
    default the simulated time t and the solver iterations of the latest step.

    Called as the ``progress`` of :func:`pfem_skfem.drivers.pfem_loop.run`:
    ``bar(i, n, record)`` after each step; closed once at ``last``.

    Parameters
    ----------
    first, last : the steps before and at the end of the run.
    stream : where it is drawn (stderr).
    desc : its title ("steps 1-100").
    postfix : callable ``postfix(record)``, the text after the bar.
    disable : no bar (``--quiet``).
    """

    def __init__(self, first, last, stream=None, *, desc=None, postfix=None, disable=False):
        self.bar = progress_bar(total=last - first, initial=0, unit="step", stream=stream,
                                desc=desc or f"steps {first + 1}-{last}", disable=disable)
        self.postfix = postfix or (lambda record: f"t = {record['time']:.4g}, "
                                                  f"it = {record['iterations']}")

    def __call__(self, i, n, record):
        self.bar.set_postfix_str(self.postfix(record), refresh=False)
        self.bar.update(1)
        if self.bar.n >= self.bar.total:
            self.close()

    def close(self):
        self.bar.close()
