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
