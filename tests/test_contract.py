"""The verification contract (:class:`pfem_skfem.report.Report`): a check can fail.

A one-sided interval used to divide the excess by an infinite scale, so any finite value
passed ``[1, inf]``; NaN and inf values (undefined ratios) passed or were compared with
``<=``. Each check here feeds the contract a value it must refuse."""
import json
import math

import numpy as np
import pytest

from pfem_skfem.report import Report


@pytest.mark.parametrize("value, lower, upper", [
    (0.0, 1.0, np.inf), (-5.0, 1.0, np.inf), (5.0, -np.inf, 1e-7), (0.39, 0.4, np.inf),
    (-0.01, 0.0, np.inf), (1e-3, -np.inf, 0.0), (-2.0, -1e-6, np.inf)])
def test_a_value_outside_a_one_sided_interval_fails(value, lower, upper):
    q = Report("c").add_interval("q", value, lower, upper, "bound")
    assert not q.passed and q.rel_error > 0


@pytest.mark.parametrize("value, lower, upper", [
    (1.0, 1.0, np.inf), (7.0, 1.0, np.inf), (-5.0, -np.inf, 1e-7), (0.0, 0.0, np.inf),
    (3.0, -np.inf, np.inf)])
def test_a_value_inside_a_one_sided_interval_passes(value, lower, upper):
    q = Report("c").add_interval("q", value, lower, upper, "bound")
    assert q.passed and q.rel_error == 0


def test_one_sided_tolerance_is_relative_to_the_finite_end_or_absolute_at_zero():
    r = Report("c")
    assert r.add_interval("a", 0.95, 1.0, np.inf, "s", tolerance=0.06).passed
    assert not r.add_interval("b", 0.95, 1.0, np.inf, "s", tolerance=0.04).passed
    assert r.add_interval("c", -0.01, 0.0, np.inf, "s", tolerance=0.02).passed
    assert r.add_interval("d", 2.1e-7, -np.inf, 2e-7, "s", tolerance=0.1).passed
    assert r.quantity("b").rel_error == pytest.approx(0.05)


def test_two_sided_intervals_keep_their_numbers():
    """max(|lower|, |upper|) as the scale, as before: the same rel_error bit for bit."""
    q = Report("c").add_interval("q", 13.0, 6.0, 12.0, "s", tolerance=0.1)
    assert q.rel_error == (13.0 - 12.0) / 12.0 and q.passed
    q = Report("c").add_interval("q", -0.5, 0.0, 0.03, "s")
    assert q.rel_error == 0.5 / 0.03 and not q.passed


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
@pytest.mark.parametrize("lower, upper", [(1.0, np.inf), (-np.inf, 1e-7), (0.0, 1.0),
                                          (-np.inf, np.inf), (1.0, 1.0)])
def test_nan_and_inf_never_pass_an_interval(value, lower, upper):
    assert not Report("c").add_interval("q", value, lower, upper, "s", tolerance=1e9).passed


@pytest.mark.parametrize("value, reference", [(math.nan, 1.0), (math.inf, 1.0),
                                              (math.nan, 0.0), (math.inf, math.inf),
                                              (1.0, math.inf), (1.0, math.nan)])
def test_nan_and_inf_never_pass_a_reference(value, reference):
    assert not Report("c").add("q", value, reference, "s", 1e9).passed


def test_an_undefined_bound_fails():
    assert not Report("c").add_interval("q", 1.0, math.nan, np.inf, "s").passed
    assert not Report("c").add_interval("q", 1.0, 2.0, 1.0, "s").passed   # empty interval


def test_a_failed_degenerate_value_shows_in_the_table_and_the_json(tmp_path):
    r = Report("c")
    r.add_interval("ratio", math.inf, 1.0, np.inf, "energy bound")
    r.add("other", math.nan, 2.0, "s", 0.1)
    assert not r.passed
    assert all(" NO " in line for line in r.table().splitlines()[3:])
    r.write_json(tmp_path / "r.json")
    qs = json.loads((tmp_path / "r.json").read_text())["quantities"]
    assert [q["pass"] for q in qs] == [False, False]
    assert qs[0]["value"] is None and qs[0]["upper"] is None and qs[0]["lower"] == 1.0
