"""The PFEM engine in axisymmetry (thesis 7.4): closed forms on a column of revolution.

A column r0 in radius and h0 high (x = r, y = z) in a smooth container keeps still and
presses on its base with its weight rho g pi r0^2 h0; its particles weigh their shares of
the volume of revolution, summing to rho V; the particles on the axis stay on it; the
volume the records report is the integral of 2 pi r dA; c = 0 makes the deposit
independent of the density; the zero-dilation cones have the strength of their
criterion at a fixed point.
"""
from dataclasses import replace

import numpy as np
import pytest
from pytest import approx

from pfem_skfem.drivers.pfem_loop import run
from pfem_skfem.materials import (ZeroDilationDruckerPrager, ZeroDilationMohrCoulombAxisymmetric,
                                  drucker_prager_match)
from pfem_skfem.materials.axisymmetric import mean_stress
from pfem_skfem.scene import Region, Scene
from pfem_skfem.scene.columns import granular_column_axisymmetric

# every test of this file on one xdist worker: its module fixture is computed once
pytestmark = pytest.mark.xdist_group("test_axisymmetric_pfem")

G, RHO, R0 = 9.8, 2.0, 1.0
COLLAPSE_STEPS = 50          # to t = 1.0 sqrt(h0/g) at dt = 0.02 sqrt(h0/g)


def test_column_in_a_smooth_container_keeps_still_on_its_weight():
    a = 1.0
    state, scene = granular_column_axisymmetric(a, 6, container=True, rho=RHO, g=G)
    x0 = state.x.copy()
    state, _ = run(state, scene, 4)
    hist = state.history
    assert np.abs(state.x - x0).max() < 1e-10 * R0
    weight = RHO * G * np.pi * R0 ** 2 * a * R0                 # rho g pi r0^2 h0
    assert hist["forces"][-1]["base"][1] == approx(-weight, rel=1e-8)
    assert hist["area"][0] == approx(np.pi * R0 ** 2 * a * R0, rel=1e-12)   # 2 pi int r dA
    assert max(abs(c) for c in hist["area_change"]) < 1e-12


def test_particle_masses_are_volume_shares_summing_to_rho_V():
    state, scene = granular_column_axisymmetric(2.0, 7, rho=RHO)
    V = np.pi * R0 ** 2 * 2.0 * R0
    assert scene.regions[0].volume == approx(V, rel=1e-14)
    assert state.mass.sum() == approx(RHO * V, rel=1e-14)
    # interior particles: mass h^2 2 pi r (lumped P1 weights), proportional to r
    h = R0 / 6
    inner = (state.x[:, 0] > 0.5 * h) & (state.x[:, 0] < R0 - 0.5 * h) & \
        (state.x[:, 1] > 0.5 * h) & (state.x[:, 1] < 2.0 * R0 - 0.5 * h)
    assert state.mass[inner] == approx(RHO * 2 * np.pi * state.x[inner, 0] * h ** 2, rel=1e-12)
    assert np.all(state.mass[state.x[:, 0] == 0] > 0)        # the axis particles weigh too


def test_axis_particles_stay_on_the_axis_and_are_not_free_surface():
    state, scene = granular_column_axisymmetric(1.0, 5, dt=0.02 * np.sqrt(1.0 / G))
    axis = np.flatnonzero(state.x[:, 0] == 0.0)
    n0 = state.n
    state, _ = run(state, scene, 20)
    assert state.x.shape[0] >= n0
    assert np.all(state.x[axis, 0] == 0.0)                  # exactly, every step
    assert np.all(state.x[:, 0] >= 0.0)
    moved = np.abs(state.x[axis, 1] - np.sort(state.x[axis, 1])).max()
    assert moved == 0.0                                       # their order is kept
    top, foot = axis[np.argmax(state.x[axis, 1])], axis[np.argmin(state.x[axis, 1])]
    between = np.setdiff1d(axis, [top, foot])
    assert between.size >= 2
    assert not state.free_surface[between].any()              # the axis is no free surface
    assert state.free_surface[top] and state.free_surface[foot]   # its ends are boundary
    mass = np.asarray(state.history["mass"])
    assert mass == approx(RHO * np.pi * R0 ** 2 * 1.0, rel=1e-13)


def test_density_invariance_of_a_cohesionless_collapse():
    """c = 0: every force scales with rho, so the particles move alike (coarse, 15 steps)."""
    out = []
    for rho in (1.0, 2.0):
        state, scene = granular_column_axisymmetric(1.0, 5, rho=rho, dt=0.03 * np.sqrt(1.0 / G))
        state, _ = run(state, scene, 15)
        out.append(state.x)
    assert out[0].shape == out[1].shape
    assert np.abs(out[0] - out[1]).max() < 1e-4 * R0
    assert np.abs(out[0] - granular_column_axisymmetric(1.0, 5)[0].x[:len(out[0])]).max() > 0.05


@pytest.mark.parametrize("phi", [20.0, 30.0, 40.0])
def test_zero_dilation_drucker_prager_has_the_strength_of_7_10_at_a_fixed_point(phi):
    rng = np.random.default_rng(int(phi))
    sigma = rng.normal(size=(50, 4)) - 3.0                    # compressive states
    material = ZeroDilationDruckerPrager(c=0.5, phi=phi, k_min=1e-9)
    criterion = drucker_prager_match(0.5, phi, "compression-meridian")
    cone = material.cone(mean_stress(sigma))
    np.testing.assert_allclose(cone.F(sigma), criterion.F(sigma), atol=1e-12)


def test_zero_dilation_mohr_coulomb_radius_is_mohr_coulombs_at_the_mean_stress():
    material = ZeroDilationMohrCoulombAxisymmetric(c=1.0, phi=30.0, k_min=1e-9)
    k = material.cone(np.array([-2.0])).k
    assert k[:, 0] == approx([2 * np.cos(np.pi / 6) + 4 * 0.5] * 3)


def test_scene_geometry_is_checked_and_plane_by_default():
    _, scene = granular_column_axisymmetric(1.0, 4)
    assert scene.axisymmetric and scene.geometry == "axisymmetric"
    plane = replace(scene, geometry="plane")
    assert not plane.axisymmetric
    shifted = Region(((-0.5, 0.0), (1.0, 0.0), (1.0, 1.0), (-0.5, 1.0)),
                     scene.regions[0].material, 2.0, 0.25)
    with pytest.raises(ValueError, match="x >= 0"):
        Scene(regions=(shifted,), geometry="axisymmetric")
    with pytest.raises(ValueError, match="geometry"):
        Scene(regions=(shifted,), geometry="spherical")
    assert Scene(regions=(shifted,)).geometry == "plane"


# -- where the volume of a collapsing column goes -------------------------------------------
@pytest.fixture(scope="module")
def collapse_steps():
    """Per step of a collapsing column (a = 2, 6 across, dt/sqrt(h0/g) = 0.02, to t = 1.0
    sqrt(h0/g), before its toe thins): the volume of the P2 body moved by du (quadrature of
    2 pi (r + u_r) det F), its first-order part, that of the straight-sided mesh through the
    moved vertices, the same with the bulge correction, and the radial displacement's size."""
    from skfem import Basis, Functional
    from pfem_skfem.discretisation.fields import vertex_dofs
    from pfem_skfem.pfem.alpha_shape import measure
    from pfem_skfem.pfem.surface import axis_vertices, bulge_correction

    @Functional
    def exact(w):
        G = w["du"].grad
        det_f = (1 + G[0, 0]) * (1 + G[1, 1]) - G[0, 1] * G[1, 0]
        return 2 * np.pi * (w.x[0] + w["du"][0]) * det_f

    @Functional
    def first_order(w):
        G, u_r = w["du"].grad, w["du"][0]
        return 2 * np.pi * (w.x[0] * (G[0, 0] + G[1, 1]) + u_r)     # r tr(eps), hoop included

    @Functional
    def radial(w):
        return 2 * np.pi * np.abs(w["du"][0])

    rows = []

    def on_step(st, rec, res):
        disc, du = res.disc, res.increment.du
        basis = Basis(disc.mesh, disc.basis_u.elem, intorder=8)
        field = basis.interpolate(du)
        moved = disc.mesh.p.T + du[vertex_dofs(disc)]
        axis = axis_vertices(disc)
        shift = bulge_correction(disc, du, axis=axis)
        volume = lambda p: float(measure(p, disc.mesh.t.T, True).sum())   # noqa: E731
        rows.append(dict(before=volume(disc.mesh.p.T), p2=exact.assemble(basis, du=field),
                         first=first_order.assemble(basis, du=field),
                         radial=radial.assemble(basis, du=field),
                         chords=volume(moved), corrected=volume(moved + shift)))

    state, scene = granular_column_axisymmetric(2.0, 6, dt=0.02 * np.sqrt(2.0 * R0 / G))
    run(state, scene, COLLAPSE_STEPS, on_step=on_step)
    return rows


def test_zero_dilation_flow_is_isochoric_to_first_order_with_the_hoop_strain(collapse_steps):
    """int 2 pi (r (eps_rr + eps_zz) + u_r) dA = 0: the constraint holds the hoop strain u_r/r
    (without it the residual would be int 2 pi u_r dA, of the size of ``radial``)."""
    for row in collapse_steps[5:]:
        assert abs(row["first"]) <= 1e-7 * row["radial"]
        assert row["radial"] > 1e-5 * row["before"]              # the column does move


def test_bulge_correction_puts_back_the_volume_the_chords_drop(collapse_steps):
    """The straight-sided moved mesh with the bulge correction holds the volume of the curved
    P2 body (the bulges between its moved edges and their chords), to 3 % of the bulges."""
    dropped = np.array([r["p2"] - r["chords"] for r in collapse_steps[5:]])
    missed = np.array([r["p2"] - r["corrected"] for r in collapse_steps[5:]])
    assert np.abs(dropped).sum() > 1e-4 * collapse_steps[0]["before"]   # there is a bulge
    assert np.abs(missed).sum() <= 0.03 * np.abs(dropped).sum()


@pytest.mark.parametrize("a, nr, courant", [(0.5, 6, 0.5), (2.0, 8, 0.3), (8.0, 10, 1.0)])
def test_courant_steps_hold_the_free_fall_courant_number(a, nr, courant):
    from pfem_skfem.scene.columns import courant_steps
    steps = courant_steps(a, nr, courant)
    for r0, g in ((1.0, 9.8), (0.039, 9.81)):                # whatever r0 and g
        h0, h = a * r0, r0 / (nr - 1)
        number = lambda n: np.sqrt(2 * g * h0) * 4 * np.sqrt(h0 / g) / n / h   # noqa: E731
        assert number(steps) <= courant * (1 + 1e-12) < number(steps - 1)


@pytest.mark.parametrize("a", [0.25, 0.5, 0.7, 1.0, 2.0, 8.0])
@pytest.mark.parametrize("nr", [6, 10])
def test_a_short_column_gets_nr_particles_over_its_height(a, nr):
    """The fewest particles across r0 whose spacing puts nr - 1 spacings over the smaller
    of r0 and h0 = a r0 (nr across the radius when a >= 1)."""
    from pfem_skfem.scene.columns import particles_across_radius
    n = particles_across_radius(a, nr)
    spacings = lambda n: min(1.0, a) * (n - 1)             # over min(r0, h0), r0 = 1  # noqa: E731
    assert spacings(n) >= (nr - 1) * (1 - 1e-12) and spacings(n - 1) < nr - 1
    assert n == nr if a >= 1 else n > nr
    state, _ = granular_column_axisymmetric(a, n)
    assert state.x[:, 1].max() == approx(a)                  # the top row at h0
    assert len(np.unique(state.x[:, 1])) >= nr                # nr rows at least


def test_a_column_stopped_and_resumed_from_its_checkpoint_is_the_same_column(tmp_path,
                                                                           monkeypatch):
    """--checkpoint-dir: a column stopped in its settling phase (after t_stop, so the
    deposit at t_stop and the history are in the saved measurements) and run again goes
    on from its checkpoint and gives the uninterrupted column bit for bit."""
    from verification import granular_column_axisymmetric as column
    from pfem_skfem.drivers import pfem_loop          # the steps of its ResumableRun
    case = dict(nr=4, steps=24, phi=30.0, settle=2.0, t_stop=1.5, history=True,
                volume_correction=True, alpha_advected=3.0)
    whole = column.run_case(2.0, **case)
    assert whole["track"]["t_bar"][-1] > 1.5          # it settles after t_stop
    real, calls = pfem_loop.run, []

    def stopping(*args, **kwargs):                    # a stop after 12 of the steps
        calls.append(1)
        if len(calls) > 12:
            raise KeyboardInterrupt
        return real(*args, **kwargs)
    monkeypatch.setattr(pfem_loop, "run", stopping)
    with pytest.raises(KeyboardInterrupt):
        column.run_case(2.0, **case, checkpoint_dir=tmp_path, checkpoint_every=4)
    monkeypatch.setattr(pfem_loop, "run", real)
    resumed = column.run_case(2.0, **case, checkpoint_dir=tmp_path, checkpoint_every=4)
    for key in ("runout_over_r0", "h_inf_over_r0", "runout_t4_over_r0", "h_t4_over_r0",
                "kinetic_energy_t4_over_peak", "t_rest", "area_change", "track"):
        assert resumed[key] == whole[key], key
    assert resumed["snapshots"].keys() == whole["snapshots"].keys()
    for t, snap in whole["snapshots"].items():
        assert np.array_equal(resumed["snapshots"][t]["points"], snap["points"]), t


def test_mass_moved_is_the_share_of_the_mass_on_the_other_side_of_a_radius():
    """The base-friction effect at a = 0.5 (Fig 7.11) is measured as the largest share of
    the mass two deposits put on opposite sides of one radius: zero for one deposit
    (whatever the order of its particles or the unit of mass), the tail's own share when
    only the tail slides further, however far, and one for deposits apart."""
    from pfem_skfem.pfem.measure import mass_moved
    rng = np.random.default_rng(3)
    r, m = rng.uniform(0, 2, 50), rng.uniform(0.5, 1.5, 50)
    order = rng.permutation(50)
    assert mass_moved(r, m, r[order], 2.5 * m[order]) == approx(0.0, abs=1e-14)
    tail = np.argmax(r)
    for reach in (2.5, 40.0):                           # the tail alone slides on
        slid = r.copy()
        slid[tail] = reach
        assert mass_moved(r, m, slid, m) == approx(m[tail] / m.sum(), rel=1e-12)
    assert mass_moved(r, m, r + 3.0, m) == approx(1.0, rel=1e-12)


def test_a_runs_checkpoint_keys_are_its_scenes_parameters_and_todays_for_quick(
        quick_case_keys):
    """Issue 52, item 4: one ColumnRun builds the scene and the checkpoint keys, so a field
    that changes the scene changes the keys; --quick's first case keys its checkpoint as
    before (the same dict, hence the same file name)."""
    from verification import granular_column_axisymmetric as column
    _, keys = quick_case_keys(column, "run_study",
                              lambda run_case, groups, args, desc: groups["sweep"][0])
    assert keys == dict(         # written out from the keys before issue 52
        a=0.5, nr=6, steps=100, phi=30.0, phi_s=None, rho=2.0, g=9.8, r0=1.0, material="dp",
        passes=2, alpha=1.6, floor=0.005, settle=4.0, t_stop=4.0, courant=None,
        volume_correction=True, adaptive_alpha=False, alpha_advected=3.0)
    params = column.ColumnRun(a=0.5, nr=6, steps=100, phi=30.0, courant=0.1)
    assert params.keys()["steps"] == params.sizes()[1] > 100      # the steps run, keyed
    rougher = replace(params, phi_s=40.0)
    assert rougher.keys() == params.keys() | {"phi_s": 40.0}
    bases = [p.scene()[1].bodies[0].shape.mu for p in (params, rougher)]
    assert bases == approx([np.tan(np.radians(30.0)), np.tan(np.radians(40.0))])
    soil = ZeroDilationDruckerPrager(c=0.0, phi=35.0, k_min=0.005)
    assert replace(params, soil=soil).keys()["material"] == repr(soil)
