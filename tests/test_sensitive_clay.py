"""The sensitive-clay bank's regularisation and mesh study (issue 55 item 4,
verification/sensitive_clay.py): the options reach the material and its steps, and the
study's checks can fail.

The bank: H = 1 m, W = 2 m, 3 particles across H (spacing 1/3 m), S_t = 10, N = 6: it fails
from its first step. The first step starts from gamma^p = 0 everywhere, so its cone, and
hence its solve, is the same with any regularisation: what the regularisation changes in
that step is known exactly."""
import numpy as np
import pytest

from pfem_skfem.drivers.pfem_loop import pfem_step
from pfem_skfem.harness.report import Report
from pfem_skfem.harness.store import checkpoint_path
from pfem_skfem.materials import FractureEnergy, NonlocalAverage
from pfem_skfem.materials.softening import nonlocal_average, point_sizes
from verification import sensitive_clay

ELL = 0.5            # 1.5 spacings


def bank(*argv):
    args = sensitive_clay.build_parser().parse_args(
        ["--n", "3", "--width", "2", "--sensitivities", "1", "10", *argv])
    return args, sensitive_clay.Bank.of(args, S_t=10.0)


def first_step(*argv):
    args, params = bank(*argv)
    state, scene = params.scene()
    new, record, result = pfem_step(state, scene)
    return scene.regions[0].material, new, record, result


def test_the_options_give_the_banks_material_its_regularisation():
    for argv, expected in (((), None),
                           (("--regularisation", "fracture-energy", "--ell", "0.5"),
                            FractureEnergy(ELL)),
                           (("--regularisation", "nonlocal", "--ell", "0.5"),
                            NonlocalAverage(ELL))):
        _, params = bank(*argv)
        assert params.scene()[1].regions[0].material.regularisation == expected


def test_a_fracture_energy_stretches_the_first_steps_strength_drop_by_ell_over_h():
    """Same first solve, same Delta gamma^p; the law's strain scale is gamma_r ell / h, so the
    step's strength drop (a fraction of c_p - c_r) is the local one's times h / ell point by
    point: 1 / 1.5 here (element size h = the spacing). Ignoring the option gives ratio 1."""
    local_material, local, local_record, result = first_step()
    material, energy, record, _ = first_step("--regularisation", "fracture-energy", "--ell",
                                             "0.5")
    np.testing.assert_array_equal(energy.gamma_p, local.gamma_p)
    size = point_sizes(result.disc.weights)
    np.testing.assert_allclose(size, 1 / 3, rtol=1e-9)          # the spacing, every element
    drop = record["softening_drop"]
    assert drop == pytest.approx(local_record["softening_drop"] * (1 / 3) / ELL, rel=1e-9)
    assert local_record["softening_drop"] > 0.01    # it did soften (measured 0.036): not 0 = 0
    strength = material.strength(energy.gamma_p, size)
    c_p, c_r = material.law.c_p, material.law.c_r
    np.testing.assert_allclose(c_p - strength, np.minimum(
        (c_p - local_material.strength(local.gamma_p, size)) * (1 / 3) / ELL, c_p - c_r),
        rtol=1e-12, atol=1e-12 * c_p)


def test_a_nonlocal_average_spreads_the_first_steps_increment_over_ell():
    """The first step's gamma^p is the local one averaged over ell by (S3a) on the step's
    points: its peak lower (the band spread), and the average exactly that operator's."""
    _, local, _, result = first_step()
    _, spread, _, _ = first_step("--regularisation", "nonlocal", "--ell", "0.5")
    A = nonlocal_average(result.disc.points, result.disc.weights, ELL)
    np.testing.assert_allclose(spread.gamma_p, A @ local.gamma_p, rtol=1e-10,
                               atol=1e-12 * local.gamma_p.max())
    assert spread.gamma_p.max() < 0.8 * local.gamma_p.max()


def test_each_regularisation_has_its_own_checkpoint_and_the_local_one_keeps_its_name(tmp_path):
    names = set()
    for argv in ((), ("--regularisation", "fracture-energy", "--ell", "0.5"),
                 ("--regularisation", "nonlocal", "--ell", "0.5"),
                 ("--regularisation", "nonlocal", "--ell", "0.6")):
        _, params = bank(*argv)
        names.add(checkpoint_path(tmp_path, "sensitive_clay_St10", params.keys()))
        if not argv:
            assert "regularisation" not in params.keys() and "ell" not in params.keys()
    assert len(names) == 4


def test_the_remoulded_fraction_reads_the_materials_own_strength():
    """gamma^p = gamma_r at every point: all the area at c_r locally, none of it with a
    fracture energy of ell = 1.5 h (its strain scale 1.5 gamma_r); 0 of an intact bank; half
    the triangles at gamma_r: the fraction of their area."""
    from dataclasses import replace
    _, local = bank()
    _, energy = bank("--regularisation", "fracture-energy", "--ell", "0.5")
    state, scene = local.scene()
    state, _, _ = pfem_step(state, scene)                  # a mesh and gamma^p to replace
    material = scene.regions[0].material
    spent = replace(state, gamma_p=np.full_like(state.gamma_p, 0.2))
    assert sensitive_clay.remoulded_fraction(spent, material) == pytest.approx(1.0)
    assert sensitive_clay.remoulded_fraction(
        spent, energy.scene()[1].regions[0].material) == 0.0
    assert sensitive_clay.remoulded_fraction(
        replace(state, gamma_p=np.zeros_like(state.gamma_p)), material) == 0.0
    half = np.zeros((len(state.mesh_t), 3))
    half[::2] = 0.2
    v = state.mesh_p[state.mesh_t]
    a, b = v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]
    area = 0.5 * np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    assert sensitive_clay.remoulded_fraction(replace(state, gamma_p=half.ravel()), material) \
        == pytest.approx(area[::2].sum() / area.sum(), rel=1e-12)


def study(retrogressions, monkeypatch, tolerance="0.1"):
    """The mesh study's checks on banks whose retrogression at (regularisation, n) is given,
    no bank run."""
    def failure(S_t, args, n, regularisation, ell):
        return dict(n=n, regularisation=regularisation, retrogression=retrogressions[
            regularisation, n], runout=1.0, mobilised=0.1, remoulded=0.1, steps=100,
            largest_drop=0.5, cpu_seconds=1.0)
    monkeypatch.setattr(sensitive_clay, "failure", failure)
    args = sensitive_clay.build_parser().parse_args(
        ["--mesh-study", "6", "12", "24", "--ell", "0.25", "--convergence", tolerance])
    report = Report("sensitive_clay", args)
    sensitive_clay.mesh_study(args, report)
    return {q.name: q for q in report.quantities}


def test_the_study_checks_the_two_finest_counts_and_can_fail(monkeypatch):
    converged = {("none", 6): 1.0, ("none", 12): 1.5, ("none", 24): 2.0,
                 ("fracture-energy", 6): 1.0, ("fracture-energy", 12): 1.9,
                 ("fracture-energy", 24): 2.0, ("nonlocal", 6): 1.2, ("nonlocal", 12): 1.25,
                 ("nonlocal", 24): 1.3}
    q = study(converged, monkeypatch)
    assert q["St10_fracture-energy_retrogression_change"].value == pytest.approx(0.05)
    assert q["St10_nonlocal_retrogression_change"].value == pytest.approx(0.05 / 1.3)
    assert q["St10_nonlocal_over_none_change"].value == pytest.approx(0.05 / 1.3 / 0.25)
    assert all(x.passed for x in q.values())
    # the regularised bank 12 % apart: over 10 %, and more than the local one's 8.3 %
    q = study(converged | {("nonlocal", 12): 1.144, ("none", 12): 2.2, ("none", 24): 2.4},
              monkeypatch)
    assert not q["St10_nonlocal_retrogression_change"].passed
    assert not q["St10_nonlocal_over_none_change"].passed
    assert q["St10_fracture-energy_retrogression_change"].passed
    # the same change with and without: not "more"
    q = study(converged | {("none", 12): 1.9}, monkeypatch)
    assert not q["St10_fracture-energy_over_none_change"].passed
    # no change with the regularisation, some without: less (ratio 0)
    q = study(converged | {("nonlocal", 12): 1.3}, monkeypatch)
    assert q["St10_nonlocal_over_none_change"].passed
    # a bank that did not retrogress at the finest count: no measure, failed
    q = study(converged | {("nonlocal", 24): 0.0}, monkeypatch)
    assert not q["St10_nonlocal_retrogression_change"].passed
