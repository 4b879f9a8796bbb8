"""del Castillo et al.'s 5 m sensitive-clay slope (verification/retrogressive_slope.py): the
scene's geometry and initial stress, the conversions of the paper's parameters (closed
forms), and the script's quick run."""
import math

import numpy as np
import pytest

from verification import retrogressive_slope as rs


def slope(*argv):
    args = rs.build_parser().parse_args(list(argv))
    return args, rs.Slope.of(args)


def test_the_scene_is_the_papers_slope():
    """5 m high at 45 deg, 25 m along the base and 20 m along the top (p. 14): 112.5 m2 of
    clay, its mass rho x that on the lattice, a smooth wall at x = 0 and a rough base."""
    _, params = slope()
    poly = np.asarray(params.polygon())
    x, y = poly[:, 0], poly[:, 1]
    assert 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))) == pytest.approx(112.5)
    assert math.degrees(math.atan2(params.height, params.base - params.top)) == pytest.approx(45)
    state, scene = params.scene()
    assert state.mass.sum() == pytest.approx(2.15 * 112.5, rel=0.03)
    bodies = {b.name: b for b in scene.bodies}
    assert bodies["wall"].shape.mu == 0.0 and bodies["base"].shape.mu == 2.0
    assert state.x[:, 0].max() <= params.base + 1e-9 and state.x[:, 1].max() <= 5 + 1e-9


def test_the_initial_stress_is_the_total_stress_of_an_effective_k0():
    """K0 = 0.5 on the effective stress, water at the surface: sigma_h / sigma_v in total
    stress (0.5 x 1.15 + 1) / 2.15 = 0.7326; sigma_v = rho g (H - y) at every particle."""
    assert rs.total_k0(0.5, 2.15, 1.0) == pytest.approx((0.5 * 1.15 + 1.0) / 2.15, rel=1e-15)
    assert rs.total_k0(0.5, 2.15, 1.0) == pytest.approx(0.7326, abs=1e-4)
    state, _ = slope()[1].scene()
    s0, y = state.stress0, state.x[:, 1]
    np.testing.assert_allclose(s0[:, 1], -2.15 * 9.81 * (5.0 - y), rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(s0[:, 0], rs.total_k0(0.5, 2.15, 1.0) * s0[:, 1], rtol=1e-12,
                               atol=1e-9)


def test_the_exponential_law_is_the_papers_in_closed_form():
    """exp(-eta eps) = exp(-3 gamma^p / gamma_95) at gamma^p = k eps exactly when
    gamma_95 = 3 k / eta: 3 sqrt(3) / 5 = 1.0392 by default; the library's c_p and c_r are the
    paper's times tau_over_c / F = (2 / sqrt(3)) / 1.65."""
    _, params = slope()
    law = params.law()
    assert law.gamma_95 == pytest.approx(3 * math.sqrt(3) / 5, rel=1e-15)
    s = 2 / math.sqrt(3) / 1.65
    assert (law.c_p, law.c_r) == (pytest.approx(15.1 * s, rel=1e-15),
                                  pytest.approx(1.5 * s, rel=1e-15))
    eps = np.array([0.0, 0.05, 0.2, math.log(20) / 5, 1.0, 3.0])
    np.testing.assert_allclose(law.strength(math.sqrt(3) * eps),
                               s * (1.5 + 13.6 * np.exp(-5 * eps)), rtol=1e-14)
    assert rs.conversion_error(params) < 1e-14
    # ln(20) k / eta (95 % exactly) in place of 3 k / eta is another law: its c - c_r is
    # exp(5 (1 - 3 / ln 20)) - 1 = -0.72 % off at eps = 1
    other = type(law)(law.c_p, law.c_r, math.log(20) * math.sqrt(3) / 5)
    off = (other.strength(math.sqrt(3)) - law.c_r) / (law.strength(math.sqrt(3)) - law.c_r) - 1
    assert off == pytest.approx(math.exp(5 * (1 - 3 / math.log(20))) - 1, rel=1e-9)
    assert off < -0.007


@pytest.mark.parametrize("argv, k, fit", [(["--gamma-per-eps", "1"], 1.0, 2 / math.sqrt(3)),
                                          (["--tau-over-c", "1"], math.sqrt(3), 1.0)])
def test_the_conversions_follow_their_options(argv, k, fit):
    _, params = slope(*argv)
    assert params.law().gamma_95 == pytest.approx(3 * k / 5, rel=1e-15)
    assert params.law().c_p == pytest.approx(fit * 15.1 / 1.65, rel=1e-15)
    assert rs.conversion_error(params) < 1e-14


def test_the_measures_count_from_the_toe_and_the_crest():
    """Run-out from the toe (x = 25 m) to the furthest particle; retrogression from the crest
    (x = 20 m) back to the furthest surface particle that dropped by more than --drop."""
    from pfem_skfem.pfem.measure import failure_extent, ground_particles
    _, params = slope()
    x0 = np.array([[2.0, 5.0], [8.0, 5.0], [19.0, 5.0], [24.0, 1.0], [20.5, 5.0]])
    x = x0 + np.array([[0.0, -0.4], [0.5, -0.6], [3.0, -2.0], [20.0, -0.9], [0.0, -1.0]])
    ground = ground_particles(x0, params.height - 0.25 * params.h, behind=params.top)
    assert list(ground) == [0, 1, 2]                # the top behind the crest, not the face

    def measures(x):
        return failure_extent(x, x0, ground, toe=params.base, crest=params.top, drop=0.5)
    assert measures(x) == (pytest.approx(19.0), pytest.approx(12.0))
    assert measures(x0) == (pytest.approx(-1.0), 0.0)


def test_the_viscosity_and_the_nonlocal_average_reach_the_clay_and_key_their_runs():
    """--viscosity is the clay's Bingham eta [kPa s], --regularisation nonlocal --ell its
    NonlocalAverage; each keys its own checkpoint, and a run without them keeps the keys of
    before they were options (its checkpoints are found again)."""
    keys = {}
    for argv, eta, reg in (((), 0.0, None), (("--viscosity", "0.3"), 0.3, None),
                           (("--regularisation", "nonlocal", "--ell", "2"), 0.0,
                            2.0)):
        _, params = slope(*argv)
        material = params.scene()[1].regions[0].material
        assert material.eta == eta
        if reg is None:
            assert material.regularisation is None
        else:
            assert material.regularisation.length == 2.0
        keys[argv] = params.keys()
    assert not {"viscosity", "regularisation", "ell"} & set(keys[()])
    assert keys[("--viscosity", "0.3")]["viscosity"] == 0.3
    assert keys[("--regularisation", "nonlocal", "--ell", "2")]["ell"] == 2.0


@pytest.mark.parametrize("argv, word", [(["--ell", "2"], "--ell"),
                                        (["--regularisation", "nonlocal"], "--ell"),
                                        (["--regularisation", "nonlocal", "--ell", "0.5"],
                                         "--ell"),
                                        (["--regularisation", "fracture-energy", "--ell", "2"],
                                         "fracture-energy")])
def test_a_regularisation_without_a_length_above_the_spacing_is_a_usage_error(argv, word,
                                                                               capsys):
    with pytest.raises(SystemExit) as exit_:
        rs.build_parser().parse_args(argv)
    assert exit_.value.code == 2 and word in capsys.readouterr().err


def test_a_face_leaning_over_its_toe_is_a_usage_error(capsys):
    with pytest.raises(SystemExit) as exit_:
        rs.build_parser().parse_args(["--top", "26"])
    assert exit_.value.code == 2 and "--top" in capsys.readouterr().err


def test_the_quick_run_fails_the_slope_and_states_no_paper_check(quick_run):
    """h = 1 m to 2 s (13 s of CPU): the conversion, the failure and the step control are
    checked; the paper's run-out and retrogression only from its 20 s on."""
    report, _ = quick_run("retrogressive_slope")
    names = {q.name for q in report.quantities}
    assert names == {"conversion_error", "runout_over_h", "halved_after_cap"}
    assert report.passed
    assert report.extra["runout"] > 2.0 and report.extra["retrogression"] > 0.0
    assert 0.0 <= report.extra["remoulded"] <= 1.0
    assert report.extra["remoulded_heap_runout"] == pytest.approx(40.89, abs=0.01)


def test_a_wholly_remoulded_heap_rests_no_shorter_than_nyes_profile():
    """The slope's 112.5 m2 at c_r = 1.5 x (2 / sqrt(3)) / 1.65 = 1.0497 kPa, resting against
    the smooth wall on the rough base, spreads at least L = (1.5 A / sqrt(2 c / (rho g)))^(2/3)
    = 65.9 m from the wall: 40.9 m beyond the toe, twice the paper's 21.6 m. The profile
    y = sqrt(2 c s / (rho g)) holds the area; its basal shear rho g y dy/ds is c everywhere."""
    _, params = slope()
    c, rg = params.law().c_r, 2.15 * 9.81
    runout = rs.remoulded_heap_runout(112.5, c, 2.15, 9.81, 25.0)
    assert runout == pytest.approx(40.89, abs=0.01)
    length = runout + 25.0
    s = np.linspace(0.0, length, 200001)
    y = np.sqrt(2 * c * s / rg)
    assert np.trapezoid(y, s) == pytest.approx(112.5, rel=1e-5)
    mid = slice(1000, -1)
    np.testing.assert_allclose((rg * y * np.gradient(y, s))[mid], c, rtol=1e-3)
    # a stronger residual shortens it as c^(-1/3): the paper's c_r undivided by F, 30.8 m
    assert rs.remoulded_heap_runout(112.5, 1.65 * c, 2.15, 9.81, 25.0) == pytest.approx(
        length * 1.65 ** (-1 / 3) - 25.0, rel=1e-12)
