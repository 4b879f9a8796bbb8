"""Report.add_table: a table printed as the scripts printed theirs, and in the JSON."""
import json

import numpy as np
import pytest

from pfem_skfem.harness.report import Report, format_table


def test_a_table_is_printed_aligned_and_written_to_the_json(capsys, tmp_path):
    report = Report("case")
    rows = [[512, 21.5, 0.123456, "ok"], [np.int64(2048), np.float64(27.0), 1.5, "AlmostSolved"]]
    report.add_table("sizes", ["elements", "iterations", "seconds", "status"], rows,
                     formats={"seconds": ".2f"})
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "sizes"
    assert lines[1].split() == ["elements", "iterations", "seconds", "status"]
    assert set(lines[2]) == {"-"} and len(lines[2]) == len(lines[1])
    assert lines[3].split() == ["512", "21.5", "0.12", "ok"]
    # numbers right-aligned under their header, text left-aligned
    assert lines[4].index("2048") + 4 == lines[1].index("elements") + len("elements")
    assert lines[4].endswith("AlmostSolved") and lines[3].rstrip().endswith("ok")
    report.write_json(tmp_path / "r.json")
    table = json.loads((tmp_path / "r.json").read_text())["tables"]["sizes"]
    assert table["columns"] == ["elements", "iterations", "seconds", "status"]
    assert table["rows"][1] == [2048, 27.0, 1.5, "AlmostSolved"]       # the values, unrounded


def test_a_row_of_the_wrong_length_is_refused():
    with pytest.raises(ValueError, match="3 values for 2 columns"):
        Report("case").add_table("t", ["a", "b"], [[1, 2, 3]], show=False)


def test_a_report_without_tables_writes_none():
    assert "tables" not in Report("case").as_json()
    assert format_table(["a"], [], title=None).splitlines() == ["a", "-"]


def test_a_table_of_records_takes_each_cell_by_key_or_function(capsys):
    report = Report("case")
    runs = [dict(label="a", x=1.0, y=2.0), dict(label="b", x=3.0, y=4.0)]
    table = report.add_table("runs", {"run": "label", "x": "x", "x/y": lambda r: r["x"] / r["y"]},
                             runs, formats={"x/y": ".2f"})
    assert table == {"columns": ["run", "x", "x/y"], "rows": [["a", 1.0, 0.5], ["b", 3.0, 0.75]]}
    assert capsys.readouterr().out.splitlines()[3].split() == ["a", "1", "0.50"]


def test_the_observed_order_is_the_slope_of_the_log_log_line():
    from pfem_skfem.harness.report import observed_order
    h = np.array([0.1, 0.05, 0.025])
    assert observed_order(h, 3 * h ** 2) == pytest.approx(2.0)
    assert observed_order(h, -3 * h ** 2) == pytest.approx(2.0)         # |error|
    n = np.array([8, 16, 32])
    assert observed_order(n, 5.0 / n, counts=True) == pytest.approx(1.0)
    # bit for bit the scripts' own fit: -polyfit(log n, log e)
    e = np.array([0.3, 0.11, 0.04])
    assert observed_order(n, e, counts=True) == float(-np.polyfit(np.log(n), np.log(e), 1)[0])


def test_a_case_thinned_for_the_json():
    from pfem_skfem.harness.report import thinned
    case = dict(label="a", t=np.arange(250.0), ke=np.arange(250.0) ** 2, x=1.5, points=None)
    kept = thinned(case, ("t", "ke"), drop=("points",))
    assert list(kept) == ["label", "x", "t", "ke"] and kept["t"] == list(np.arange(0.0, 250, 2))
    # without histories: the case less the dropped keys, in its order
    assert list(thinned(case, drop=("label", "points"))) == ["t", "ke", "x"]


def test_a_study_s_groups_thinned_for_the_json():
    from pfem_skfem.harness.report import thinned, thinned_groups
    case = dict(label="a", t=np.arange(250.0), points=None)
    groups = {"sweep": [case, case], "mesh": []}
    kept = thinned_groups(groups, ("t",), drop=("points",))
    assert list(kept) == ["sweep", "mesh"] and kept["mesh"] == []
    assert kept["sweep"] == [thinned(case, ("t",), ("points",))] * 2


def test_a_table_of_records_reads_nested_entries_and_a_history_at_chosen_times():
    from pfem_skfem.harness.report import sampled
    report = Report("case")
    rows = [{"a": 1, "fit": {"h": 0.5}}, {"a": 2, "fit": {"h": 0.25}}]
    table = report.add_table("fits", {"a": "a", "h": ("fit", "h"), "2h": lambda r: 2 * r["a"]},
                             rows, show=False)
    assert table["rows"] == [[1, 0.5, 2], [2, 0.25, 4]]
    history = {"t": [0.0, 0.4, 1.1, 2.0], "h": [1.0, 0.9, 0.7, 0.6]}
    assert sampled(history, "t", (1.0, 0.0, 1.9)) == [
        {"t": 1.1, "h": 0.7}, {"t": 0.0, "h": 1.0}, {"t": 2.0, "h": 0.6}]     # nearest, in order


def test_a_table_of_no_rows_is_left_out_where_asked():
    report = Report("case")
    assert report.add_table("empty", ["a"], [], skip_empty=True) is None
    assert "empty" not in report.tables
    assert report.add_table("header", ["a"], (r for r in ())) == {"columns": ["a"], "rows": []}
    assert report.add_table("one", {"a": "a"}, iter([{"a": 1}]), skip_empty=True)["rows"] == [[1]]


def test_a_bracket_is_a_lower_and_an_upper_bound_on_either_side_of_the_reference():
    report = Report("case")
    lower, upper = report.add_bracket("Nc", 5.0, 5.2, 2 + np.pi, "Prandtl; {bound} (9 el)")
    assert (lower.name, lower.lower, lower.upper, lower.reference) == \
        ("Nc_lower", -np.inf, 2 + np.pi, 2 + np.pi)
    assert (upper.name, upper.lower, upper.upper) == ("Nc_upper", 2 + np.pi, np.inf)
    assert (lower.source, upper.source) == ("Prandtl; a lower bound (9 el)",
                                            "Prandtl; an upper bound (9 el)")
    assert report.passed
    report.add_bracket("wrong", 5.2, 5.0, 2 + np.pi, "{bound}")   # on the wrong sides
    assert [q.passed for q in report.quantities[2:]] == [False, False]
