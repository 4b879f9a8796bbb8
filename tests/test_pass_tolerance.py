"""The pass tolerance of the fixed-point passes (PFEMConfig.pass_tolerance, lagged_step)."""
from dataclasses import replace

import numpy as np
import pytest

from pfem_skfem.scene.config import PFEMConfig
from pfem_skfem.drivers.pfem_loop import pfem_step, run
from pfem_skfem.materials import MuIRheology
from pfem_skfem.problems.contact import CoulombCones, LaggedFriction
from pfem_skfem.problems.nonassociated import least_passes
from pfem_skfem.scene import Region, Scene
from verification.granular_column_plane import granular_column

G = 9.8
DT = 0.05 * np.sqrt(1.0 / G)


def column(steps, **kw):
    state, scene = granular_column(1.0, 8, dt=DT, **kw)
    return run(state, scene, steps)[0]


def test_two_passes_are_one_pass_started_from_the_first_pass_mean_stress():
    # the fixed point's definition: pass 2 is pass 1 of the lagged mean stress pass 1 gave
    state, scene = granular_column(1.0, 8, dt=DT, passes=2, pass_tolerance=0.0)
    state = run(state, scene, 3)[0]
    two, rec, _ = pfem_step(state, scene)
    one_scene = replace(scene, config=replace(scene.config, passes=1))
    _, _, first = pfem_step(state, one_scene)
    sm = state.sigma_m.copy()
    sm[first.pm.particle] = first.sigma_m
    again, _, _ = pfem_step(replace(state, sigma_m=sm), one_scene)
    assert rec["passes"] == 2 and len(rec["pass_changes"]) == 2
    for name in ("x", "v", "sigma_m"):
        assert np.array_equal(getattr(two, name), getattr(again, name)), name


def test_tolerance_zero_runs_every_pass():
    state = column(4, passes=3, pass_tolerance=0.0)
    assert state.history["passes"] == [3] * 4
    assert all(len(c) == 3 for c in state.history["pass_changes"])


def test_an_infinite_tolerance_solves_one_pass_as_passes_1_does():
    loose = column(5, passes=3, pass_tolerance=np.inf)
    single = column(5, passes=1)
    assert loose.history["passes"] == [1] * 5
    for name in ("x", "v", "sigma_m"):
        assert np.array_equal(getattr(loose, name), getattr(single, name)), name


def test_passes_stop_exactly_where_a_pass_changed_the_mean_stress_less_than_the_tolerance():
    tol, most = 0.15, 3
    hist = column(10, passes=most, pass_tolerance=tol).history
    assert len(set(hist["passes"])) > 1                # the rule decided both ways
    for passes, changes in zip(hist["passes"], hist["pass_changes"]):
        assert len(changes) == passes
        assert all(c >= tol for c in changes[:-1])     # went on only while above it
        assert passes == most or changes[-1] < tol     # stopped early only below it


def test_a_lagged_contact_with_a_lagged_material_keeps_its_three_passes():
    hist = column(3, contact="zero-dilation", passes=4, pass_tolerance=np.inf).history
    assert hist["passes"] == [3] * 3
    hist = column(3, contact="zero-dilation", material="davis", passes=3,
                  pass_tolerance=np.inf).history           # Davis is not lagged
    assert hist["passes"] == [2] * 3


def test_least_passes():
    assert least_passes(True, CoulombCones()) == 1
    assert least_passes(False, LaggedFriction()) == 2
    assert least_passes(True, LaggedFriction()) == 3


def test_a_c0_run_with_a_tolerance_does_not_depend_on_density():
    runs = [column(8, rho=rho, passes=2, pass_tolerance=0.15) for rho in (2.0, 4.0)]
    assert runs[0].history["passes"] == runs[1].history["passes"]
    assert len(set(runs[0].history["passes"])) > 1
    assert np.array_equal(runs[0].x, runs[1].x)
    assert np.array_equal(runs[0].v, runs[1].v)
    assert np.array_equal(2.0 * runs[0].sigma_m, runs[1].sigma_m)


@pytest.mark.parametrize("bad", [-1e-3, np.nan, "0.1", True])
def test_a_bad_tolerance_is_refused_naming_it(bad):
    with pytest.raises(ValueError, match="pass_tolerance"):
        PFEMConfig(pass_tolerance=bad)


def test_a_tolerance_with_a_rate_dependent_material_is_refused():
    layer = Region(((0, 0), (1, 0), (1, 0.2), (0, 0.2)), MuIRheology(), 2.0, 0.1)
    with pytest.raises(ValueError, match="pass_tolerance"):
        Scene(regions=(layer,), gravity=(0.0, -G), length=0.2,
              config=PFEMConfig(pass_tolerance=1e-2))


@pytest.mark.parametrize("tol", [0.05, np.inf])
def test_a_scene_file_keeps_the_pass_tolerance(tol):
    from pfem_skfem.materials import ZeroDilationMohrCoulomb
    from pfem_skfem.scene.files import scene_from_toml, scene_to_toml
    block = Region(((0, 0), (1, 0), (1, 1), (0, 1)), ZeroDilationMohrCoulomb(c=0.0, phi=30.0),
                   2.0, 0.25)
    scene = Scene(regions=(block,), gravity=(0.0, -G), length=1.0,
                  config=PFEMConfig(pass_tolerance=tol))
    back = scene_from_toml(scene_to_toml(scene))
    assert back.config.pass_tolerance == tol and back == scene
