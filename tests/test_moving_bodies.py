"""Moving rigid bodies in the PFEM: critical taper theory and the wedge stability test
(Buiter et al. 2016, Exp 1), the check of thesis 6.4.2's wedge that has an exact answer."""
import numpy as np
import pytest

from verification.accretionary_wedge import (DEFORMS, RIGID, critical_taper, dahlen_F,
                                             mass_balance_length, stability_test, wedge_length)


def test_critical_taper_satisfies_dahlen_s_identity():
    """On the lower branch tan(alpha_c) = F(psi_0, phi) and tan(phi_b) = F(psi_b, phi),
    psi_b = alpha_c + psi_0 (Dahlen 1984, beta = 0), for several phi, phi_b."""
    for phi, phi_b in ((30, 15), (36, 10), (30, 25), (40, 30)):
        low, high = critical_taper(phi, phi_b)
        a, p = np.radians(low), np.radians(phi)
        psi0 = 0.5 * (np.arcsin(np.sin(a) / np.sin(p)) - a)
        assert np.tan(a) == pytest.approx(dahlen_F(psi0, p), abs=1e-12)
        assert np.tan(np.radians(phi_b)) == pytest.approx(dahlen_F(a + psi0, p), abs=1e-12)
        assert 0 < low < high <= phi


def test_critical_taper_limits():
    """A frictionless base needs no taper, a rougher base a steeper one; a stronger wedge a
    gentler one (Dahlen 1984, Fig 3)."""
    assert critical_taper(30, 0)[0] == pytest.approx(0, abs=1e-10)
    lows = [critical_taper(30, b)[0] for b in (5, 10, 15, 20, 25)]
    assert np.all(np.diff(lows) > 0)
    assert critical_taper(40, 15)[0] < critical_taper(30, 15)[0]


def test_mass_balance_length():
    """A triangle of taper alpha and area A: length sqrt(2 A / tan alpha)."""
    L = wedge_length(0.5 * 0.3 * 0.3 * np.tan(np.radians(10)), 10.0)
    assert L == pytest.approx(0.3, rel=1e-12)


@pytest.mark.parametrize("plateau, cut", [(0.0, 0.0), (0.0, 0.005), (0.1, 0.0), (0.1, 0.005)])
def test_mass_balance_length_of_a_plateau_then_a_slope(plateau, cut):
    """A plateau of height H = 2 cm and length p from the wall, then the slope 10 deg, cut
    where it is ``cut`` above the layer: A = H p + (H^2 - cut^2) / (2 tan alpha) gives back
    L = p + (H - cut) / tan alpha; no plateau and no cut is the triangle's wedge_length."""
    H, t = 0.02, np.tan(np.radians(10.0))
    area = H * plateau + (H ** 2 - cut ** 2) / (2 * t)
    L = mass_balance_length(area, H, 10.0, cut)
    assert L == pytest.approx(plateau + (H - cut) / t, rel=1e-12)
    if plateau == cut == 0:
        assert L == pytest.approx(wedge_length(area, 10.0), rel=1e-12)


@pytest.mark.parametrize("moved", [dict(h=0.02), dict(passes=4), dict(contact="coulomb")])
def test_the_quick_layer_s_wedge_holds_its_mass_balance_with_an_option_moved(moved):
    """The option audit's moves (issue 56) of the --quick layer: its slope falls to 5.6-7.8
    deg (10.0 at the quick values) or its spacing grows, and the triangle's
    sqrt(2 A_up / tan alpha) put the wedge's length 30-34 % off (16 % at the quick values):
    the wedge there is a pop-up's plateau and then the slope, its front cut one spacing above
    h0. The wedge of mass_balance_length holds it to 8-12 % (the check's 30 %)."""
    from types import SimpleNamespace
    from verification import accretionary_wedge as aw
    options = dict(h0=0.08, L=0.5, h=0.016, s=0.05, steps=12, dt=0.16) | moved
    r = aw.run_layer(**options)
    L_w = r["geometry"]["length"]
    assert L_w == pytest.approx(aw.layer_mass_balance_length(SimpleNamespace(**options), r),
                                rel=0.15)


def test_the_stable_wedge_on_coulomb_cones_is_rigid_after_six_pushes():
    """Why --contact coulomb asks for 6 pushes of the stability test: the 15 deg wedge yields
    in its first push and with the associated contact that dies out slower than with the
    zero-dilation one; at the 4th push (the --quick count) it is still above RIGID du/H
    (1.4e-2), from the 6th far below (1.8e-5)."""
    from verification.accretionary_wedge import COULOMB_STABILITY_STEPS
    r = stability_test(15.0, phi_b=15.0, steps=COULOMB_STABILITY_STEPS, layers=5,
                       contact="coulomb")
    assert r["plastic_max_history"][3] > RIGID
    assert r["plastic_max"] < 1e-2 * RIGID
    assert r["wall_force_over_mu_b_W"] == pytest.approx(1.0, rel=0.01)


@pytest.mark.parametrize("taper", [15.0, 3.0])
def test_a_wedge_slides_undeformed_only_inside_the_stable_field(taper):
    """Pushed by a smooth wall on a base of friction tan 15 deg (alpha_c = 5.38 deg): the
    15 deg wedge slides as one rigid block (plastic strain below RIGID du/H, the wall's push
    mu_b W to 1 %); the 3 deg wedge deforms at the wall (above DEFORMS du/H) and the push
    stays below what would slide it."""
    low, high = critical_taper(30.0, 15.0)
    r = stability_test(taper, phi_b=15.0, steps=4, layers=5)
    if low < taper < high:
        assert r["plastic_max"] < RIGID
        assert r["wall_force_over_mu_b_W"] == pytest.approx(1.0, rel=0.01)
    else:
        assert r["plastic_max"] > DEFORMS
        assert r["wall_force_over_mu_b_W"] < 1.0


# -- the passes rule: lagged friction with a lagged material -------------------------------
def lagged_scene(material, contact, passes):
    from pfem_skfem.scene.config import PFEMConfig
    from pfem_skfem.problems.contact import RigidSegment
    from pfem_skfem.discretisation import ThetaMethod
    from pfem_skfem.scene import Body, Region, Scene
    block = Region(((0.0, 0.0), (1.0, 0.0), (1.0, 0.5), (0.0, 0.5)), material, rho=2.0, h=0.25,
                   name="sand")
    return Scene(regions=(block,), bodies=(Body("base", RigidSegment((-5, 0), (5, 0), 0.3)),),
                 config=PFEMConfig(theta=ThetaMethod(0.01), contact=contact, passes=passes))


def test_lagged_friction_with_a_lagged_material_needs_three_passes():
    """Pass 1 of the lagged friction is smooth, so with two passes the last cone of a lagged
    material is built on the mean stress of a frictionless solve: the scene refuses it,
    naming passes, before any step; the other combinations keep passes >= 1 / >= 2."""
    from pfem_skfem.materials import CohesiveTresca, ZeroDilationMohrCoulomb
    from pfem_skfem.problems.contact import CoulombCones, LaggedFriction
    sand = ZeroDilationMohrCoulomb(c=0.0, phi=30.0, k_min=0.005)
    with pytest.raises(ValueError, match=r"passes must be >= 3.*'sand'"):
        lagged_scene(sand, LaggedFriction(), 2)
    assert lagged_scene(sand, LaggedFriction(), 3).config.passes == 3
    assert lagged_scene(sand, CoulombCones(), 1).config.passes == 1
    assert lagged_scene(CohesiveTresca(1.0), LaggedFriction(), 2).config.passes == 2


def test_two_passes_would_let_a_stable_wedge_yield(monkeypatch):
    """Why the rule: with the check switched off, the 15 deg wedge (inside the stable field)
    pushed with two passes a step deforms (plastic strain increment far above the imposed
    strain, the push below mu_b W); with three it slides as one block."""
    from pfem_skfem.scene import Scene
    monkeypatch.setattr(Scene, "_check_passes", lambda self: None)
    two = stability_test(15.0, phi_b=15.0, steps=4, layers=5, passes=2)
    three = stability_test(15.0, phi_b=15.0, steps=4, layers=5, passes=3)
    assert two["plastic_max"] > DEFORMS
    assert two["wall_force_over_mu_b_W"] < 0.99
    assert three["plastic_max"] < RIGID


# -- the studies' checks -----------------------------------------------------------------------
def steady_run(F_H, F_V, **options):
    """A cylinder history (0.1 m a step) with constant lateral forces F_H, F_V."""
    n_v, n_h = 8, 20
    step = np.arange(1, n_v + n_h + 1)
    lateral = step > n_v
    return {"n_v": n_v, "u_H": np.maximum(step - n_v, 0) * 0.1,
            "F_H": np.where(lateral, F_H, 0.0), "F_V": np.where(lateral, F_V, 20.0),
            "options": options}


def test_cylinder_studies_compare_each_run_with_the_most_refined():
    """The time-step and mesh checks compare the steady forces of every run with those of
    the smallest dt (finest h) to 15 %: 10 % off passes, 20 % off fails, whatever the order."""
    from pfem_skfem.harness.report import Report
    from verification.cylinder_soil import STUDY_TOLERANCE, convergence_checks
    import argparse
    assert STUDY_TOLERANCE == 0.15
    runs = [steady_run(11.0, 8.0, dt=0.1), steady_run(10.0, 10.0, dt=0.05),
            steady_run(12.0, 9.0, dt=0.2)]
    report = Report("cylinder_soil", argparse.Namespace())
    convergence_checks(report, runs, lambda r: r["options"]["dt"], "dt", "dt")
    q = {x.name: x for x in report.quantities}
    assert set(q) == {f"{f}_steady_dt{d}_vs_dt0.05" for f in ("F_H", "F_V") for d in (0.1, 0.2)}
    assert q["F_H_steady_dt0.1_vs_dt0.05"].passed and q["F_V_steady_dt0.2_vs_dt0.05"].passed
    assert not q["F_V_steady_dt0.1_vs_dt0.05"].passed and not q["F_H_steady_dt0.2_vs_dt0.05"].passed
    assert q["F_H_steady_dt0.2_vs_dt0.05"].value == pytest.approx(12.0)


def test_wedge_does_not_depend_on_the_increment_at_quick_size():
    """The layer of the --quick size (50 cm, shortened 5 cm) in 12 and in 6 steps: the problem
    is rate-independent, so the slope away from the wall agrees within the taper gate's 2 deg,
    the wedge's length and the wall force over the last quarter within 15 %."""
    from verification import accretionary_wedge as aw
    options = dict(h0=0.08, L=0.5, h=0.016, s=0.05, dt=0.16)
    fine, coarse = (aw.run_layer(steps=n, **options) for n in (12, 6))
    assert abs(fine["geometry"]["slope_deg"] - coarse["geometry"]["slope_deg"]) <= aw.INCREMENT_SLOPE
    assert coarse["geometry"]["length"] == pytest.approx(fine["geometry"]["length"],
                                                         rel=aw.INCREMENT_TOLERANCE)
    assert aw.late_wall_force(coarse) == pytest.approx(aw.late_wall_force(fine),
                                                       rel=aw.INCREMENT_TOLERANCE)
    for r in (fine, coarse):
        assert r["popup"]["is_popup"]
        assert np.abs(r["area_change"]).max() < 0.03
