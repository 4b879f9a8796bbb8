"""Independent cases on Dask (:func:`run_cases`): a local cluster or one at ``--scheduler``,
the cases' bars forwarded, failures reported with their case (:class:`SweepError`), and
the result cache of ``--results-dir`` (:func:`result_path`); a study's named groups of
cases (its sweep, its variants) run as one sweep by :func:`run_groups` (a study's case
that is a sweep's run taken as the sweep's: :func:`shared_cases`), their results by group
(:func:`grouped`; each group's first and last: :func:`spans`), whether kept results were
made in one sitting (:func:`one_sitting`) and hold what a measurement needs
(:func:`kept_with`).
"""
from pathlib import Path

import numpy as np

from .options import OptionError
from .progress import _SWEEP_CASE, _CaseBars, _redraw_seconds, progress, progress_bar
from .store import DamagedFileError, _dump_pickle, _named_by

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


def run_groups(function, groups, workers=1, *, desc="cases", scheduler=None,
               results_dir=None):
    """A study's named groups of cases as one sweep: :func:`run_cases` of every case in
    turn, the results given back under their group's name.

    ``groups``: {name: a case (a dict of ``function``'s keywords) or a list of cases}, e.g.
    ``{"main": dict(base, mu=0.2), "friction": [dict(base, mu=m) for m in mus]}``; the
    answer is {name: the case's result, or the list of its cases' results, in order}. All
    the cases share the workers (a group of one case does not wait for another group), and
    a failure is reported as :func:`run_cases` reports it (:class:`SweepError`). A case
    listed in several groups (the same dict: a sweep's case that a study takes as one of
    its own) runs once, its result given to each.
    """
    single = {name: isinstance(cases, dict) for name, cases in groups.items()}
    listed = {name: [cases] if single[name] else list(cases) for name, cases in groups.items()}
    cases = _distinct(listed)
    results = dict(zip(map(id, cases), run_cases(function, cases, workers, desc=desc,
                                                 scheduler=scheduler, results_dir=results_dir)))
    out = {name: [results[id(c)] for c in cases] for name, cases in listed.items()}
    return {name: rs[0] if single[name] else rs for name, rs in out.items()}


def _distinct(groups):
    """The cases of ``groups`` ({name: a case or a list of cases}), each object once, in the
    order first listed."""
    listed = ([cases] if isinstance(cases, dict) else cases for cases in groups.values())
    return list({id(c): c for cases in listed for c in cases}.values())


def run_study(function, groups, args, *, desc="cases"):
    """:func:`run_groups` of ``groups`` with the options of :func:`~.options.sweep_options`
    in ``args`` (``--workers``, ``--scheduler``, ``--results-dir``), saying first, with
    ``--progress``, how many cases run where."""
    if getattr(args, "progress", False):
        progress(f"{len(_distinct(groups))} case(s) on "
                 f"{args.scheduler or str(args.workers) + ' worker(s)'}")
    return run_groups(function, groups, args.workers, desc=desc, scheduler=args.scheduler,
                      results_dir=args.results_dir)


def grouped(rows, by, order=None):
    """A study's results by group: {value of ``by``, increasing: the rows (dicts) that have
    it, in increasing ``order`` (a key of the rows; None: as given)}, e.g. the cases of a
    friction study at each aspect ratio, from the least angle to the largest."""
    groups = {}
    for row in rows:
        groups.setdefault(row[by], []).append(row)
    return {value: rows if order is None else sorted(rows, key=lambda row: row[order])
            for value, rows in sorted(groups.items())}


def spans(groups):
    """(value, first row, last row) of each group of ``groups`` ({value: rows}, as
    :func:`grouped` gives them, each in increasing order) that has more than one row: a
    study's change from its least parameter to its largest, group by group."""
    return [(value, rows[0], rows[-1]) for value, rows in groups.items() if len(rows) > 1]


def shared_cases(cases, kept, run_of):
    """A study's ``cases`` with each that is the same run as a case of ``kept`` (a sweep's
    cases: equal ``run_of(case)``, the run's identity, its parameters with their defaults
    filled in) replaced by that case object and listed after the others, in order:
    :func:`run_groups` then runs it once for both groups, and the cases keep the
    keywords, and so the kept-result names (:func:`result_path`), they had."""
    runs = {run_of(case): case for case in kept}
    return ([case for case in cases if run_of(case) not in runs]
            + [runs[run_of(case)] for case in cases if run_of(case) in runs])


def one_sitting(what, *results):
    """Whether ``results`` (of :func:`run_cases`, each with its ``sitting``, None if
    unknown) were made in one sitting; if not, says so: a pair compared to round-off taken
    from --results-dir may come from two machines or versions, and would measure them."""
    sittings = [r.get("sitting") for r in results]
    same = None not in sittings and len(set(sittings)) == 1
    if not same:
        print(f"\nthe {what} may come from two sittings ({'; '.join(map(str, sittings))}): "
              "if it differs, run both again in one sitting")
    return same


def kept_with(key, *results, what=None, why="measure it"):
    """Whether each of ``results`` (cases' results, perhaps kept by an older version in
    ``--results-dir``) holds ``key``; if not, says so (its ``what``, default ``key``) and
    how to make it (delete it there and run again, to ``why``): a quantity added to the
    results since finds nothing in them, and is then not measured rather than failing."""
    if all(key in r for r in results):
        return True
    print(f"  a kept result has no {what or key} (made by an older version): delete it "
          f"from --results-dir and run again to {why}")
    return False


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
