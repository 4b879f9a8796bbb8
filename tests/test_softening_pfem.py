"""Strain softening in the PFEM loop (issue 55): gamma^p carried at the stress points, the
strength of each step read from it, and its update, checkpoints, VTU output and step control.

The scene: a Tresca column (h0 = d0 = 1, rho g = 19.6, E = 1e4, nu = 0.45, 6 particles
across) on a frictionless base released by its right wall; its peak strength c_p = 4 is
below the strength of a vertical cut, about rho g h0 / 3.8, so it collapses."""
import numpy as np
import pyvista as pv
import pytest

from pfem_skfem.discretisation.fields import element_mean
from pfem_skfem.drivers.pfem_loop import pfem_step, run
from pfem_skfem.drivers.time_step import SofteningTimeStep
from pfem_skfem.io import TimeSeries
from pfem_skfem.materials import (CohesiveTresca, Elastic, LinearSoftening, NonlocalAverage,
                                  RegionCones,
                                  SofteningMohrCoulomb, SofteningStep, SofteningTresca,
                                  ZeroDilationMohrCoulomb)
from pfem_skfem.scene import Region, Scene
from pfem_skfem.materials.softening import point_sizes
from pfem_skfem.pfem.softening import carried_strain
from pfem_skfem.pfem.state import PFEMState, load_checkpoint
from pfem_skfem.pfem.transfer import old_discretisation
from verification.granular_column_plane import granular_column

G = 9.8
ELASTIC = Elastic(1e4, 0.45)
C_P, C_R, GAMMA_R = 4.0, 1.0, 0.05


def column(soil, **options):
    return granular_column(1.0, 6, phi=0.0, soil=soil, E=ELASTIC.E, nu=ELASTIC.nu,
                           dt=0.05 * np.sqrt(1.0 / G), **options)


def softening(c_r=C_R, gamma_r=GAMMA_R):
    return SofteningTresca(LinearSoftening(C_P, c_r, gamma_r), ELASTIC)


def test_a_run_without_softening_carries_no_plastic_shear_strain():
    state, _ = run(*column(CohesiveTresca(C_P, ELASTIC)), 2)
    assert state.gamma_p is None
    assert "softening_drop" not in state.history


def test_an_elastic_column_accumulates_no_plastic_shear_strain():
    """Held by both walls and far from yield (c_p = 100), every step is elastic: Delta eps^p
    = eps(du) - C^-1 dsigma vanishes to the solver's tolerance (measured 2e-12), against
    elastic strains of order rho g h0 / E = 2e-3."""
    state, _ = run(*column(softening().__class__(LinearSoftening(100.0, 10.0, GAMMA_R),
                                                 ELASTIC), right_wall=True), 3)
    assert state.gamma_p.shape == (3 * state.mesh_t.shape[0],)
    assert state.gamma_p.max() < 1e-6 * 2 * G / ELASTIC.E


def test_softening_without_end_is_the_perfectly_plastic_run_bit_for_bit():
    """gamma_r = 1e300: c(gamma^p) = c_p in floating point, and the run is the
    CohesiveTresca(c_p) run bit for bit (the cone of radii 2 c_p at every point is Tresca's)."""
    plastic, _ = run(*column(CohesiveTresca(C_P, ELASTIC)), 6)
    endless, _ = run(*column(softening(gamma_r=1e300)), 6)
    x0 = column(CohesiveTresca(C_P, ELASTIC))[0].x
    assert np.abs(plastic.x[:len(x0)] - x0).max() > 0.02          # it collapsed
    np.testing.assert_array_equal(endless.x, plastic.x)
    np.testing.assert_array_equal(endless.sigma, plastic.sigma)
    assert endless.gamma_p.max() > 0.01                            # it flowed plastically


def test_a_softening_mohr_coulomb_without_end_is_the_zero_dilation_run_bit_for_bit():
    """The same for the lagged material: SofteningMohrCoulomb (c_p = 1, phi = 30) with
    gamma_r = 1e300 against ZeroDilationMohrCoulomb(c = 1, phi = 30), both [80]'s psi = 0
    cone at the lagged mean stress, over 6 steps of a collapsing column."""
    elastic = Elastic(1e4, 0.3)
    runs = [run(*granular_column(1.0, 6, phi=30.0, soil=soil, E=1e4, nu=0.3,
                                 dt=0.05 * np.sqrt(1.0 / G)), 6)[0]
            for soil in (ZeroDilationMohrCoulomb(c=1.0, phi=30.0, k_min=0.005, elastic=elastic),
                         SofteningMohrCoulomb(LinearSoftening(1.0, 0.2, 1e300), elastic,
                                              phi=30.0, k_min=0.005))]
    x0 = granular_column(1.0, 6, phi=30.0)[0].x
    assert np.abs(runs[0].x[:len(x0)] - x0).max() > 0.01
    np.testing.assert_array_equal(runs[1].x, runs[0].x)
    np.testing.assert_array_equal(runs[1].sigma_m, runs[0].sigma_m)


def test_the_softening_collapse_lies_between_the_peak_and_the_residual_ones():
    """The strength lies between c_r and c_p at every point: the toe after 10 steps lies
    between the c_p column's and the c_r column's, strictly (the strength did fall)."""
    toes = {}
    for name, soil in (("peak", CohesiveTresca(C_P, ELASTIC)), ("soft", softening()),
                       ("residual", CohesiveTresca(C_R, ELASTIC))):
        state, _ = run(*column(soil), 10)
        toes[name] = state.x[:, 0].max()
    assert toes["peak"] < toes["soft"] < toes["residual"], toes


def test_each_step_reads_the_law_at_the_carried_strain_and_flows_on_that_cone():
    """After each remeshing the step's strength is c(gamma^p) of the gamma^p mapped from the
    last mesh by the stresses' scheme (exactly), the mapped gamma^p within [0, the old
    largest] (the bounded UEM's maximum principle), the step's stresses inside
    sqrt((sx - sy)^2 + 4 sxy^2) / 2 <= c(gamma^p) and on it where the point flows (to 1e-5:
    the solver's tolerance), and the strength below c_p there (the softening is read)."""
    state, scene = column(softening())
    material = scene.regions[0].material
    state, _, _ = pfem_step(state, scene)
    softened = 0
    for _ in range(6):
        new, record, result = pfem_step(state, scene)
        carried = carried_strain(state, result.disc, old_discretisation(state),
                                 scene.config.stress_mapping)
        assert 0 <= carried.min() and carried.max() <= state.gamma_p.max()
        np.testing.assert_array_equal(
            result.strength, material.strength(carried, point_sizes(result.disc.weights)))
        sigma = result.increment.sigma
        q = 0.5 * np.hypot(sigma[:, 0] - sigma[:, 1], 2 * sigma[:, 3]) / result.strength
        flowing = new.gamma_p - carried > 1e-3 * (new.gamma_p - carried).max()
        assert q.max() < 1 + 1e-5
        assert q[flowing].min() > 1 - 1e-5
        softened += int(np.sum(result.strength[flowing] < C_P - 0.1 * (C_P - C_R)))
        assert record["gamma_p_max"] == new.gamma_p.max()
        state = new
    assert softened > 50


def test_a_nonlocal_average_longer_than_the_body_spreads_the_increment_evenly():
    """NonlocalAverage(ell): each step's Delta gamma^p averaged over the points within ell.
    The first step does not depend on gamma^p (zero everywhere), so with ell = 1000 (the bell
    weights 1 - O(r^2 / ell^2) = 1 - 5e-6 over the column) the nonlocal gamma^p after it is
    the weighted mean of the local one at every point, to 1e-5."""
    local, scene = column(softening())
    local, _, result = pfem_step(local, scene)
    spread, _, _ = pfem_step(*column(SofteningTresca(LinearSoftening(C_P, C_R, GAMMA_R),
                                                     ELASTIC, NonlocalAverage(1000.0))))
    w = result.disc.weights
    mean = np.sum(w * local.gamma_p) / np.sum(w)
    assert local.gamma_p.max() > 2 * mean                      # the local field is uneven
    np.testing.assert_allclose(spread.gamma_p, mean, rtol=1e-5)


def test_the_static_driver_refuses_a_nonlocal_material():
    from pfem_skfem.drivers.softening import softening_control
    material = SofteningTresca(LinearSoftening(C_P, C_R, GAMMA_R), ELASTIC, NonlocalAverage(0.1))
    with pytest.raises(ValueError, match="StepControl"):
        softening_control(None, None, material, fixed=[], prescribed=([], []), n_increments=1,
                          size=np.ones(1), weights=np.ones(1))


def test_gamma_p_never_decreases_at_a_point_between_remeshings():
    state, scene = column(softening(), remesh_interval=3)
    kept = 0
    for _ in range(6):
        new, _, _ = pfem_step(state, scene)
        if state.mesh_t is not None and np.array_equal(new.mesh_t, state.mesh_t):
            kept += 1
            assert np.all(new.gamma_p >= state.gamma_p)
            assert np.any(new.gamma_p > state.gamma_p)
        state = new
    assert kept >= 3


def test_a_resumed_softening_run_restores_gamma_p_bit_for_bit(tmp_path):
    straight, _ = run(*column(softening()), 4)
    first, scene = column(softening())
    run(first, scene, 2, checkpoint=tmp_path / "c.npz", checkpoint_every=2)
    back = load_checkpoint(tmp_path / "c.npz")
    assert back.gamma_p is not None and back.gamma_p.max() > 0
    resumed, _ = run(back, scene, 2)
    np.testing.assert_array_equal(resumed.gamma_p, straight.gamma_p)
    np.testing.assert_array_equal(resumed.x, straight.x)
    assert resumed.history["softening_drop"] == straight.history["softening_drop"]


def test_the_vtu_holds_the_plastic_shear_strain_and_the_strength(tmp_path):
    state, scene = column(softening())
    series = TimeSeries(tmp_path, "soft")
    results = []
    state, _ = run(state, scene, 2, series=series, on_step=lambda s, r, res: results.append(res))
    grid = pv.read(sorted(tmp_path.glob("soft_*.vtu"))[-1])
    disc = results[-1].disc
    np.testing.assert_allclose(grid.cell_data["plastic_shear_strain"],
                               element_mean(disc, state.gamma_p), rtol=1e-12)
    np.testing.assert_allclose(grid.cell_data["strength"],
                               element_mean(disc, results[-1].strength), rtol=1e-12)


def test_the_softening_time_step_halves_dt_after_a_step_over_the_cap():
    """The step control: after a step whose strength drop exceeds the cap the next dt is
    half the last (until the floor), after one below a quarter of it twice the last, the
    same between (measured here: drops 0.08-0.19 of c_p - c_r, dt down to dt0 / 8)."""
    state, scene = column(softening())
    policy = SofteningTimeStep(scene.config.dt, max_drop=0.1, halvings=3)
    dts = []
    for _ in range(8):
        step_scene, state = policy.before(scene, state)
        dts.append(step_scene.config.dt)
        state, _ = run(state, step_scene, 1)
        policy.after(step_scene, state)
    drops = state.history["softening_drop"]
    assert max(drops) > 0.1                                     # the cap was reached
    for k in range(len(drops) - 1):
        if drops[k] > 0.1:
            assert dts[k + 1] == max(dts[k] / 2, scene.config.dt / 8)
        elif drops[k] < 0.025:
            assert dts[k + 1] == min(dts[k] * 2, scene.config.dt)
        else:
            assert dts[k + 1] == dts[k]
    back = SofteningTimeStep(scene.config.dt, max_drop=0.1, halvings=3)
    back.restore(policy.saved())
    assert back.rung == policy.rung


@pytest.mark.parametrize("bad, words", [
    (dict(max_drop=0.0), "max_drop"), (dict(max_drop=1.5), "max_drop"),
    (dict(halvings=0), "halvings"), (dict(halvings=1.5), "halvings")])
def test_the_softening_time_step_refuses_bad_data(bad, words):
    with pytest.raises(ValueError, match=words):
        SofteningTimeStep(0.01, **bad)


def test_softening_is_refused_where_it_cannot_run():
    """Before any work: beside another region's material, in axisymmetry (naming the
    axisymmetric material), and a state whose gamma^p does not match its stresses."""
    clay = Region(((0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)), softening(), 2.0, 0.25)
    other = Region(((1.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0)),
                   CohesiveTresca(C_P, ELASTIC), 2.0, 0.25, name="other")
    with pytest.raises(ValueError, match="softening material"):
        Scene(regions=(clay, other))
    with pytest.raises(ValueError, match="use SofteningTrescaAxisymmetric"):
        Scene(regions=(clay,), geometry="axisymmetric")
    state, scene = column(softening())
    state, _ = run(state, scene, 1)
    with pytest.raises(ValueError, match="one value per stress point"):
        PFEMState(step=1, time=0.0, x=state.x, h=state.h, sigma_m=state.sigma_m,
                  sigma=state.sigma, gamma_p=state.gamma_p[:-3])
    with pytest.raises(ValueError, match="softening material"):
        RegionCones.check([softening(), CohesiveTresca(C_P, ELASTIC)])
    with pytest.raises(ValueError, match="gamma_p and size"):
        SofteningStep(softening(), np.zeros(3), np.ones(4))
    with pytest.raises(ValueError, match="SofteningTresca"):
        SofteningStep(CohesiveTresca(C_P, ELASTIC), np.zeros(3), np.ones(3))


def test_the_step_control_s_own_check_that_it_halved_after_each_step_over_its_cap():
    """halved_after_cap: each step over the cap is followed by half its dt (or the floor
    dt0 / 2^halvings); a step over the cap whose successor kept its dt is a failure."""
    from pfem_skfem.drivers.time_step import SofteningTimeStep

    policy = SofteningTimeStep(1.0, max_drop=0.1, halvings=2)
    assert policy.halved_after_cap([0.05, 0.2, 0.3, 0.3, 0.01], [1.0, 1.0, 0.5, 0.25, 0.25])
    assert not policy.halved_after_cap([0.05, 0.2, 0.01], [1.0, 1.0, 1.0])
    assert policy.halved_after_cap([0.01, 0.02], [1.0, 1.0])          # never over the cap
