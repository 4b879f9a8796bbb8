"""The verification contract (:class:`pfem_skfem.harness.report.Report`): a check can fail.

A one-sided interval used to divide the excess by an infinite scale, so any finite value
passed ``[1, inf]``; NaN and inf values (undefined ratios) passed or were compared with
``<=``. Each check here feeds the contract a value it must refuse."""
import json
import math

import numpy as np
import pytest

from pfem_skfem.harness.report import Report


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


# The one-sided checks of the --quick suite (issue 36: 16 of its quantities), each with its
# interval and its quick value (the values of the checked-in code, 2026-12-04): each passes
# at its value and fails at a value beyond its finite end, at NaN and at inf.
ONE_SIDED = [
    ("accretionary_wedge", "taper3_plastic_max", 10.476, 1.0, np.inf),
    ("alpha_shape", "holes at alpha=0.5 (voids)", 15.0, 1.0, np.inf),
    ("alpha_shape", "bodies at alpha=0.4", 75.0, 3.0, np.inf),
    ("buried_pipe", "min_contact_pressure", 1.44e-9, -1e-6, np.inf),
    ("cylinder_soil", "F_H_jump_at_switch", 7.801, 2.674, np.inf),
    ("cylinder_soil", "F_V_drop_at_switch", 8.307, 0.0, np.inf),
    ("cylinder_soil", "F_V_min_lateral", 2.995, 0.0, np.inf),
    ("granular_column_plane", "a1_phi31_runout_over_d0", 2.364, 0.0, np.inf),
    ("inclined_plane_flow", "fast_acceleration_over_bound", 1.281, 0.97, np.inf),
    ("landslide_yangbaodi", "mu14_energy_ratio", 1.217, 1.0, np.inf),
    ("landslide_yangbaodi", "mu18_energy_ratio", 1.195, 1.0, np.inf),
    ("landslide_yangbaodi", "runout_decrease_with_mu", -62.76, -np.inf, -3.671e-7),
    ("plastic_vibration", "max_energy_increase", -1.215e-6, -np.inf, 1e-7),
    ("plastic_vibration", "min_step_dissipation", 1.215e-6, -1e-9, np.inf),
    ("silo_discharge", "Q_smooth_over_rough", 3.274, 1.0, np.inf),
    ("sliding_box", "dilation_order", 0.5802, 0.03, np.inf),
]


@pytest.mark.parametrize("case, name, value, lower, upper", ONE_SIDED,
                         ids=[f"{c}:{n}" for c, n, *_ in ONE_SIDED])
def test_each_one_sided_check_of_the_quick_suite_can_fail(case, name, value, lower, upper):
    r = Report(case)
    assert r.add_interval(name, value, lower, upper, "s").passed
    end = lower if np.isfinite(lower) else upper
    beyond = end - (abs(end) or 1.0) if np.isfinite(lower) else end + (abs(end) or 1.0)
    for bad in (beyond, math.nan, math.inf, -math.inf):
        assert not r.add_interval(name, bad, lower, upper, "s").passed, bad
