"""The sweep runner (report.run_cases) on Dask: the serial results, bit for bit, on a local
cluster and on an existing one given its address; a failing case reported with its
parameters while the others finish; ``--scheduler`` checked when parsed."""
import argparse

import numpy as np
import pytest

from pfem_skfem.drivers.resumable import sitting
from pfem_skfem.harness.options import base_parser, scheduler_address, sweep_options
from pfem_skfem.harness.report import relative_error
from pfem_skfem.harness.sweeps import SweepError, run_cases, run_groups
from verification.granular_column_plane import run_case as column

# two short columns (a few steps each, about 0.5 s): solves, remeshing, contact, histories
COLUMNS = [dict(a=a, nx=6, steps=4, phi=30.0, mu=0.5, settle=0.5) for a in (1.0, 2.0)]
TIMINGS = {"seconds", "seconds_per_step"}           # wall-clock times differ run to run


def identical(a, b):
    """True when ``a`` and ``b`` are equal bit for bit (arrays, nested dicts and lists)."""
    if isinstance(a, dict):
        return (isinstance(b, dict) and a.keys() == b.keys()
                and all(identical(a[k], b[k]) for k in a if k not in TIMINGS))
    if isinstance(a, (list, tuple)):
        return (type(a) is type(b) and len(a) == len(b)
                and all(identical(x, y) for x, y in zip(a, b)))
    if isinstance(a, (np.ndarray, float, np.floating)):
        a, b = np.asarray(a), np.asarray(b)
        return a.shape == b.shape and a.dtype == b.dtype and \
            a.tobytes() == b.tobytes()                   # NaN == NaN, -0.0 != 0.0
    return type(a) is type(b) and a == b


def test_a_sweep_on_a_local_cluster_gives_the_serial_results_bit_for_bit():
    serial = run_cases(column, COLUMNS, workers=1)
    parallel = run_cases(column, COLUMNS, workers=2)
    assert [r["a"] for r in parallel] == [1.0, 2.0]           # in the order of the cases
    assert identical(serial, parallel)
    assert not identical(serial[0], serial[1])               # the comparison can fail


def test_a_sweep_on_an_existing_cluster_given_its_address():
    from distributed import LocalCluster
    cases = [dict(value=v, reference=r) for v, r in ((2.0, 1.0), (3.0, 2.0), (1.0, 4.0))]
    with LocalCluster(n_workers=1, threads_per_worker=1, dashboard_address=None) as cluster:
        address = scheduler_address(cluster.scheduler_address)
        assert run_cases(relative_error, cases, workers=1, scheduler=address) == \
            [1.0, 0.5, 0.75]


@pytest.mark.parametrize("workers", [1, 2])
def test_a_failing_case_is_reported_with_its_parameters_while_the_others_finish(
        workers, capsys):
    cases = [dict(value=2.0, reference=1.0), dict(value="x", reference=2.0),
             dict(value=1.0, reference=4.0)]
    with pytest.raises(SweepError) as error:
        run_cases(relative_error, cases, workers=workers, desc="checks")
    assert [(i, case) for i, case, _ in error.value.failures] == [(1, cases[1])]
    assert error.value.results == [1.0, None, 0.75]          # the others finished
    assert isinstance(error.value.__cause__, TypeError)      # the case's own error
    message = str(error.value)
    assert "1 of 3 checks failed" in message and "value='x', reference=2.0" in message
    assert "value='x', reference=2.0" in capsys.readouterr().err   # reported when it failed


@pytest.mark.parametrize("text, address", [("tcp://127.0.0.1:8786", "tcp://127.0.0.1:8786"),
                                           ("scheduler.local:8786", "tcp://scheduler.local:8786"),
                                           ("tls://10.0.0.2:443", "tls://10.0.0.2:443")])
def test_scheduler_addresses_are_accepted(text, address):
    assert scheduler_address(text) == address


@pytest.mark.parametrize("text", ["nonsense", "tcp://host", "http://host:80", "host:0",
                                  "host:99999", "tcp://:8786"])
def test_bad_scheduler_addresses_are_usage_errors_naming_the_option(text, capsys):
    with pytest.raises(argparse.ArgumentTypeError, match=f"got '{text}'"):
        scheduler_address(text)
    parser = sweep_options(base_parser("sweep"))
    with pytest.raises(SystemExit) as exit_:
        parser.parse_args(["--scheduler", text])
    assert exit_.value.code == 2 and "--scheduler" in capsys.readouterr().err


def test_a_case_may_have_keywords_that_dask_submit_also_takes():
    """The keywords travel as one dict: 'key', 'priority', 'workers' reach the function."""
    cases = [dict(key="k", priority=2), dict(workers=3, pure=True)]
    assert run_cases(dict, cases, workers=2) == cases


CALLS = []


def counted_error(value, reference, verbose=False):
    """relative_error, counting its calls (serial runs only: the calls of this process)."""
    CALLS.append((value, reference, verbose))
    return relative_error(value, reference)


def test_kept_results_are_taken_instead_of_run_again(tmp_path):
    cases = [dict(value=2.0, reference=1.0, verbose=True), dict(value=3.0, reference=2.0)]
    CALLS.clear()
    first = run_cases(counted_error, cases, workers=1, desc="checks", results_dir=tmp_path)
    assert first == [1.0, 0.5] and len(CALLS) == 2 and CALLS[0][2] is True
    assert len(list(tmp_path.glob("checks-*.result.pkl"))) == 2
    # the same cases again: taken from the directory, verbose or not; a new one is run
    again = [dict(cases[0], verbose=False), cases[1], dict(value=1.0, reference=4.0)]
    assert run_cases(counted_error, again, workers=1, desc="checks",
                     results_dir=tmp_path) == [1.0, 0.5, 0.75]
    assert len(CALLS) == 3 and CALLS[-1][:2] == (1.0, 4.0)
    assert run_cases(counted_error, cases, workers=1, desc="checks") == first
    assert len(CALLS) == 5                                      # no directory: both run


def test_the_sitting_a_kept_result_records_names_this_host_processor_and_boot():
    import platform
    here = sitting()
    assert here.startswith(platform.node()) and platform.machine() in here
    assert "boot " in here and sitting() == here          # one sitting, one name


def test_kept_results_from_workers_and_failures_named_by_their_own_case(tmp_path):
    cases = [dict(value=2.0, reference=1.0), dict(value="x", reference=2.0),
             dict(value=1.0, reference=4.0)]
    with pytest.raises(SweepError) as error:
        run_cases(relative_error, cases, workers=2, desc="checks", results_dir=tmp_path)
    assert [(i, case) for i, case, _ in error.value.failures] == [(1, cases[1])]
    assert error.value.results == [1.0, None, 0.75]
    assert isinstance(error.value.__cause__, TypeError)
    assert len(list(tmp_path.glob("*.result.pkl"))) == 2          # the two that finished
    with pytest.raises(SweepError) as error:                     # only the failed one runs
        run_cases(relative_error, cases, workers=1, desc="checks", results_dir=tmp_path)
    assert error.value.results == [1.0, None, 0.75]
    assert [i for i, _, _ in error.value.failures] == [1]


def test_each_running_case_s_progress_is_drawn_by_the_client(capsys):
    """A case's bar on a worker draws nothing there (its process' stderr is not this
    one's) and sends its counts: the client draws a bar per running case."""
    def steps(name, n, verbose=False):             # pickled by value for the workers
        import time
        import numpy as np
        from pfem_skfem.harness.progress import progress_bar
        bar = progress_bar(total=np.int64(n), desc=f"case {name}", unit="step",
                           disable=not verbose)          # numpy counts go as Python ones
        for k in range(n):
            time.sleep(0.5)                        # the first count reaches the client
            bar.set_postfix_str(f"k = {k}")
            bar.update(np.int64(1))
        bar.close()
        return name

    cases = [dict(name=name, n=3, verbose=True) for name in ("first", "second")]
    assert run_cases(steps, cases, workers=2, desc="steps") == ["first", "second"]
    err = capsys.readouterr().err
    assert "steps on 2 workers" in err                        # the bar over the cases
    assert "case first" in err and "case second" in err       # each case's own bar
    assert run_cases(steps, [dict(c, verbose=False) for c in cases], workers=2,
                     desc="steps") == ["first", "second"]
    assert capsys.readouterr().err == ""                      # no progress: no bars


def test_a_case_s_next_bar_starts_its_count_and_rate_again(capsys):
    from pfem_skfem.harness.progress import _CaseBars
    bars = _CaseBars()
    count = dict(case=0, total=10, desc="case", unit="step", postfix="")
    bars((0.0, dict(count, n=5)))
    bars((0.0, dict(count, n=7)))
    assert bars.bars[0].n == 7 and bars.bars[0].initial == 5    # the rate counts from 5
    bars((0.0, dict(count, n=2, total=4, desc="settle")))      # the case's next bar
    bar = bars.bars[0]
    assert (bar.n, bar.initial, bar.total, bar.desc) == (2, 2, 4, "settle")
    bars.end(0)
    bars((0.0, dict(count, n=3)))                              # late: the case ended
    assert not bars.bars


def _power(x, p=1):
    return x ** p


def test_named_groups_run_as_one_sweep_and_come_back_under_their_names(tmp_path):
    groups = {"main": dict(x=3), "squares": [dict(x=x, p=2) for x in (1, 2, 4)], "none": []}
    assert run_groups(_power, groups) == {"main": 3, "squares": [1, 4, 16], "none": []}
    # kept results too: the same answer, taken from --results-dir the second time
    assert run_groups(_power, groups, results_dir=tmp_path) == run_groups(
        _power, groups, results_dir=tmp_path) == {"main": 3, "squares": [1, 4, 16], "none": []}
    with pytest.raises(SweepError, match="1 of 2 powers failed"):
        run_groups(_power, {"a": dict(x=2), "b": [dict(x=0, p=-1)]}, desc="powers")


def test_a_study_runs_its_groups_with_the_sweep_options_and_says_where(tmp_path, capsys):
    from pfem_skfem.harness.sweeps import run_study

    parser = sweep_options(argparse.ArgumentParser())
    parser.add_argument("--progress", action="store_true")
    args = parser.parse_args(["--workers", "1", "--results-dir", str(tmp_path), "--progress"])
    groups = {"main": dict(x=3), "squares": [dict(x=x, p=2) for x in (1, 2)]}
    assert run_study(_power, groups, args, desc="powers") == {"main": 3, "squares": [1, 4]}
    assert "3 case(s) on 1 worker(s)" in capsys.readouterr().err
    assert len(list(tmp_path.glob("powers-*.result.pkl"))) == 3      # --results-dir kept them
    args.progress = False
    assert run_study(_power, groups, args, desc="powers") == {"main": 3, "squares": [1, 4]}
    assert "case(s) on" not in capsys.readouterr().err


def test_a_study_s_results_by_group_in_increasing_order():
    from pfem_skfem.harness.sweeps import grouped

    rows = [dict(a=4.0, phi=30), dict(a=0.5, phi=35), dict(a=4.0, phi=25), dict(a=0.5, phi=20)]
    by_a = grouped(rows, "a", "phi")
    assert list(by_a) == [0.5, 4.0]
    assert [r["phi"] for r in by_a[0.5]] == [20, 35] and [r["phi"] for r in by_a[4.0]] == [25, 30]
    assert [r["phi"] for r in grouped(rows, "a")[4.0]] == [30, 25]      # no order: as given
    assert grouped([], "a") == {}


def test_a_pair_from_two_sittings_is_said_to_be(capsys):
    from pfem_skfem.harness.sweeps import one_sitting

    assert one_sitting("density pair", {"sitting": "m 1"}, {"sitting": "m 1"})
    assert capsys.readouterr().out == ""
    assert not one_sitting("density pair", {"sitting": "m 1"}, {"sitting": "m 2"})
    assert "density pair may come from two sittings (m 1; m 2)" in capsys.readouterr().out
    assert not one_sitting("pair", {"sitting": None}, {"sitting": None})     # unknown: said
    assert "(None; None)" in capsys.readouterr().out


def test_a_case_listed_in_two_groups_runs_once(capsys):
    from pfem_skfem.harness.options import sweep_options
    from pfem_skfem.harness.sweeps import run_study

    calls = []
    sweep = [dict(x=x, calls=calls) for x in (1, 2)]
    groups = {"sweep": sweep, "study": [dict(x=3, calls=calls), sweep[1]], "one": sweep[0]}
    args = sweep_options(argparse.ArgumentParser()).parse_args(["--workers", "1"])
    args.progress = True
    assert run_study(_counted, groups, args) == {"sweep": [1, 4], "study": [9, 4], "one": 1}
    assert sorted(calls) == [1, 2, 3]                          # each object once
    assert "3 case(s) on 1 worker(s)" in capsys.readouterr().err


def _counted(x, calls):
    calls.append(x)
    return x * x


def test_a_study_s_case_that_is_a_sweep_case_s_run_is_the_sweep_s_listed_last():
    from pfem_skfem.harness.sweeps import shared_cases

    sweep = [dict(a=a, phi=30.0, phi_s=None) for a in (0.5, 4.0)]
    run_of = lambda c: (c["a"], c["phi"], c["phi"] if c["phi_s"] is None else c["phi_s"])  # noqa
    study = [dict(a=a, phi=30.0, phi_s=p) for a in (0.5, 8.0) for p in (20.0, 30.0)]
    cases = shared_cases(study, sweep, run_of)
    assert cases[:3] == [study[0], study[2], study[3]]          # their own, as they were
    assert cases[3] is sweep[0] and len(cases) == 4          # the sweep's case object, last
    assert shared_cases(study, [], run_of) == study and shared_cases([], sweep, run_of) == []


def test_each_group_s_first_and_last_row_where_it_has_two():
    from pfem_skfem.harness.sweeps import grouped, spans

    rows = [dict(a=4.0, phi=30), dict(a=0.5, phi=35), dict(a=4.0, phi=25), dict(a=8.0, phi=20)]
    assert spans(grouped(rows, "a", "phi")) == [(4.0, rows[2], rows[0])]      # a = 0.5, 8: one
    assert spans({}) == []


def test_a_kept_result_without_what_a_measurement_needs_is_said_to_be(capsys):
    from pfem_skfem.harness.sweeps import kept_with

    assert kept_with("mass", {"mass": 1}, {"mass": 2, "x": 0})
    assert capsys.readouterr().out == ""
    assert not kept_with("mass", {"mass": 1}, {"x": 0}, what="masses at rest",
                         why="measure the mass moved")
    assert capsys.readouterr().out == (
        "  a kept result has no masses at rest (made by an older version): delete it from "
        "--results-dir and run again to measure the mass moved\n")
