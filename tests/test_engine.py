"""The PFEM engine on scenes with closed-form answers: moving bodies, outlets, held phases,
mass bookkeeping, checkpoints, and the density invariance of a cohesionless body."""
import numpy as np
import pytest

from pfem_skfem.scene.config import PFEMConfig
from pfem_skfem.drivers.pfem_loop import pfem_step, run
from pfem_skfem.materials import CohesiveTresca, ZeroDilationMohrCoulomb
from pfem_skfem.problems.contact import LaggedFriction, RigidCircle, RigidSegment
from pfem_skfem.discretisation import ThetaMethod
from pfem_skfem.pfem.state import load_checkpoint
from pfem_skfem.scene import (Body, ConstantVelocity, Geostatic, HalfPlane, Outlet,
                              PiecewiseLinear, Phase, Region, Scene)
from verification.granular_column_plane import granular_column

G = 9.8
RHO = 2.0
STRONG = CohesiveTresca(1e3)          # far stronger than any stress of these blocks: rigid


def block(width=1.0, height=0.5, h=0.1, material=STRONG, x0=0.0, y0=0.0, **options):
    return Region(((x0, y0), (x0 + width, y0), (x0 + width, y0 + height), (x0, y0 + height)),
                  material, RHO, h, **options)


def base(mu, motion=None):
    return Body("base", RigidSegment((-10.0, 0.0), (30.0, 0.0), mu), motion)


def steps(scene, n, state=None):
    state = scene.initial_state() if state is None else state
    records = []
    for _ in range(n):
        state, record, _ = pfem_step(state, scene)
        records.append(record)
    return state, records


def test_a_smooth_wall_pushing_a_block_over_a_rough_base_feels_mu_w():
    """At constant speed the block does not accelerate: the wall's push balances the base
    friction mu W exactly (the lagged friction rule has no dilation, so the normal force
    is the weight W = rho g A); the smooth wall takes no vertical force."""
    mu, speed, dt = 0.4, 0.05, 0.05
    wall = Body("wall", RigidSegment((0.0, 5.0), (0.0, -0.1), 0.0), ConstantVelocity((speed, 0)))
    scene = Scene(regions=(block(),), bodies=(base(mu), wall),
                  config=PFEMConfig(theta=ThetaMethod(dt), contact=LaggedFriction()))
    state, records = steps(scene, 6)
    W = RHO * G * 0.5
    for rec in records[2:]:                       # after the start-up impulse
        assert rec["forces"]["wall"][0] == pytest.approx(-mu * W, rel=1e-6)
        assert abs(rec["forces"]["wall"][1]) < 1e-6 * W
        assert rec["forces"]["base"] == pytest.approx([mu * W, -W], rel=1e-6)
    # the block moves with the wall: travel = speed t
    assert state.x[:, 0].min() == pytest.approx(speed * state.time, rel=1e-6)


@pytest.mark.parametrize("solver", ["clarabel", "cvxpy"])
def test_a_block_on_a_translated_rough_base_moves_with_it_rigidly(solver):
    """The base moves at V from t = 0; its friction (mu W dt > m V) carries the block along
    from the first step: every particle is displaced by the base's (V t, 0). (The slip of
    (5.12) is relative to the moving body in both statements of the step.)"""
    speed, dt = 0.1, 0.05
    scene = Scene(regions=(block(),), bodies=(base(1.0, ConstantVelocity((speed, 0.0))),),
                  config=PFEMConfig(theta=ThetaMethod(dt), solver=solver))
    x0 = scene.initial_state().x
    state, _ = steps(scene, 5)
    np.testing.assert_allclose(state.x - x0, np.tile([speed * state.time, 0.0], (len(x0), 1)),
                               atol=1e-7 * speed * state.time)


def test_a_body_moved_through_empty_space_feels_no_force():
    """A cylinder moving far from the material touches nothing: zero force and moment."""
    pipe = Body("pipe", RigidCircle((3.0, 3.0), 0.3), ConstantVelocity((0.5, 0.0)))
    scene = Scene(regions=(block(),), bodies=(base(0.5), pipe),
                  config=PFEMConfig(theta=ThetaMethod(0.05)))
    _, records = steps(scene, 3)
    for rec in records:
        assert rec["forces"]["pipe"] == [0.0, 0.0] and rec["moments"]["pipe"] == 0.0
        assert rec["forces"]["base"][1] == pytest.approx(-RHO * G * 0.5, rel=1e-6)


def test_an_outlet_removes_exactly_the_particles_that_crossed_it():
    """A rigid block falls freely (theta2 = 1: y_N = y_0 - g dt^2 N (N + 1) / 2, exactly);
    the outlet y < y_cut removes, at each step, the particles whose fall crossed it, and
    the material inside plus the material discharged is the initial mass."""
    dt, h = 0.05, 0.1
    y_cut = -0.1
    outlet = Outlet("floor", HalfPlane((0.0, y_cut), (0.0, -1.0)))
    scene = Scene(regions=(block(h=h),), outlets=(outlet,),
                  config=PFEMConfig(theta=ThetaMethod(dt)))
    state = scene.initial_state()
    y0, m0, n0 = state.x[:, 1].copy(), state.total_mass, state.n
    for n in range(1, 6):                 # three of the six rows cross; three stay a body
        state, rec, _ = pfem_step(state, scene)
        fall = G * dt ** 2 * n * (n + 1) / 2
        crossed = int(np.sum(y0 - fall < y_cut))
        assert state.discharged["floor"][1] == crossed
        assert state.n == n0 - crossed
        assert state.total_mass + state.discharged["floor"][0] == pytest.approx(m0, rel=1e-14)
        np.testing.assert_allclose(np.sort(state.x[:, 1]), np.sort(y0[y0 - fall >= y_cut]) - fall,
                                   atol=1e-9)
    assert 0 < state.discharged["floor"][1] < n0                 # it did cross, partly


def test_a_particle_in_two_overlapping_outlets_leaves_once():
    """discharge with two outlets whose zones overlap (a corner in both): the first outlet
    takes the corner, the second only what the first left, so every particle is
    discharged once and the material inside plus the material discharged is the
    initial mass, particle by particle."""
    from dataclasses import replace
    from pfem_skfem.pfem.bookkeeping import discharge
    from pfem_skfem.scene import PolygonZone
    bottom = Outlet("bottom", HalfPlane((0.0, 0.15), (0.0, -1.0)))           # y < 0.15
    left = Outlet("left", PolygonZone(((-1.0, -1.0), (0.25, -1.0), (0.25, 2.0), (-1.0, 2.0))))
    state = Scene(regions=(block(),), config=PFEMConfig(theta=ThetaMethod(0.05))).initial_state()
    state = replace(state, mass=1.0 + np.arange(state.n) / state.n)       # unequal masses
    x, m0, n0 = state.x, state.total_mass, state.n
    in_bottom, in_left = bottom.zone.contains(x), left.zone.contains(x)
    assert (in_bottom & in_left).sum() > 0                        # the corner is in both
    after, now = discharge(state, (bottom, left))
    assert now["bottom"] == [pytest.approx(state.mass[in_bottom].sum(), rel=1e-15),
                             int(in_bottom.sum())]
    only_left = in_left & ~in_bottom
    assert now["left"] == [pytest.approx(state.mass[only_left].sum(), rel=1e-15),
                           int(only_left.sum())]
    assert after.n == n0 - int((in_bottom | in_left).sum())
    assert now["bottom"][1] + now["left"][1] + after.n == n0
    assert after.total_mass + now["bottom"][0] + now["left"][0] == pytest.approx(m0, rel=1e-14)
    assert after.discharged == now
    np.testing.assert_array_equal(after.x, x[~(in_bottom | in_left)])


def test_a_run_ends_cleanly_when_every_particle_has_left():
    """The falling block of the test above, run on: its last row forms no element and flies
    free (still y_N = y_0 - g dt^2 N (N + 1) / 2), then the last particles leave; the run
    stops at the step the closed form says, with an empty state that keeps the books."""
    dt, h, y_cut = 0.05, 0.1, -0.1
    scene = Scene(regions=(block(h=h),), outlets=(Outlet("floor", HalfPlane((0.0, y_cut),
                                                                             (0.0, -1.0))),),
                  config=PFEMConfig(theta=ThetaMethod(dt)))
    state = scene.initial_state()
    y_top, m0, n0 = state.x[:, 1].max(), state.total_mass, state.n
    last = next(n for n in range(1, 100) if y_top - G * dt ** 2 * n * (n + 1) / 2 < y_cut)
    state, _ = run(state, scene, 100)
    hist = state.history
    assert state.n == 0 and state.step == last
    assert 0 in hist["elements"]                          # a step without element was taken
    assert hist["mass"][-1] == 0.0
    assert state.discharged["floor"] == [pytest.approx(m0, rel=1e-14), n0]
    assert {len(v) for k, v in hist.items() if not k.startswith("t_")} == {last}
    with pytest.raises(ValueError, match="no particle left"):
        pfem_step(state, scene)


@pytest.mark.parametrize("hold", ["boundary", "free_surface"])
def test_a_held_phase_keeps_the_held_particles_still(hold):
    """A cohesionless column whose side walls are gone would collapse at once; while its
    surface is held (Ch 8) the held particles do not move (to round-off), and after the
    phase it does collapse."""
    state, column = granular_column(1.0, 6, dt=0.05 * np.sqrt(1.0 / G))
    scene = Scene(regions=column.regions, bodies=column.bodies, length=column.length,
                  phases=(Phase(until=4.5 * column.config.dt, hold=hold, name="held"),),
                  config=column.config)
    x0 = state.x.copy()
    held = state.x[:, 1] > 1e-9 if hold == "free_surface" else np.ones(len(x0), bool)
    on_outline = ((x0[:, 0] < 1e-9) | (x0[:, 0] > 1 - 1e-9) | (x0[:, 1] < 1e-9)
                  | (x0[:, 1] > 1 - 1e-9))
    state, records = steps(scene, 5, state)
    assert [r["phase"] for r in records] == ["held"] * 5
    assert np.abs(state.x[on_outline & held] - x0[on_outline & held]).max() < 1e-12
    state, records = steps(scene, 3, state)
    assert records[-1]["phase"] is None
    assert state.x[:, 0].max() > 1.0 + 1e-3                       # released: it collapses


def moving_scene():
    """A column pushed by its left wall, a right wall removed, a toe outlet, a held start."""
    state, column = granular_column(1.0, 6, dt=0.05 * np.sqrt(1.0 / G))
    push = Body("pusher", RigidSegment((0.0, 30.0), (0.0, -0.2), 0.2),
                PiecewiseLinear((0.0, 0.03, 0.53), ((0.0, 0.0), (0.0, 0.0), (0.3, 0.0))))
    # held for the first two steps (dt = 0.016), pushed from t = 0.03 (after the phase: a
    # held boundary cannot give way to a wall)
    return Scene(regions=column.regions, bodies=(column.bodies[0], push),
                 outlets=(Outlet("toe", HalfPlane((1.03, 0.0), (1.0, 0.0))),),
                 phases=(Phase(until=0.02, hold="boundary"),), length=1.0, config=column.config)


def test_checkpoint_and_resume_of_a_scene_with_a_moving_body_an_outlet_and_a_phase(tmp_path):
    scene = moving_scene()
    straight, _ = run(scene.initial_state(), scene, 8)
    run(scene.initial_state(), scene, 4, checkpoint=tmp_path / "c.npz", checkpoint_every=4)
    resumed, _ = run(load_checkpoint(tmp_path / "c.npz"), scene, 4)
    assert straight.discharged["toe"][1] > 0                     # the outlet took some
    for name in ("x", "v", "sigma_m", "mass", "region", "mesh_p", "v_dofs", "sigma"):
        np.testing.assert_array_equal(getattr(resumed, name), getattr(straight, name))
    assert resumed.discharged == straight.discharged
    assert resumed.history["forces"] == straight.history["forces"]


def test_mass_inside_plus_discharged_is_the_initial_mass_at_every_step():
    scene = moving_scene()
    state = scene.initial_state()
    m0, n0 = state.total_mass, state.n
    assert m0 == pytest.approx(RHO * 1.0 * 1.0, rel=1e-14)      # rho times the column's area
    state, _ = run(state, scene, 8)
    h = state.history
    for mass, out in zip(h["mass"], h["discharged"]):
        assert mass + out["toe"] == pytest.approx(m0, rel=1e-13)
    # particles: the initial ones, plus those added (remesher, surface), less those thinned
    # and discharged
    assert state.n == n0 + sum(h["added"]) + sum(h["surface_particles"]) - sum(h["thinned"]) \
        - state.discharged["toe"][1]


def column_run(rho, n_steps, nx=6):
    state, scene = granular_column(1.0, nx, rho=rho, dt=0.05 * np.sqrt(1.0 / G))
    return run(state, scene, n_steps)[0]


def test_a_cohesionless_rigid_plastic_run_does_not_depend_on_the_density():
    """For c = 0 every force scales with rho: the trajectories are independent of it. A
    factor of two scales every floating-point number exactly (bit-identical runs); any
    factor gives the same first steps to the solver's tolerance."""
    a, b, c = column_run(2.0, 8), column_run(4.0, 8), column_run(3.0, 3)
    assert np.abs(a.x - b.x).max() <= 1e-12
    np.testing.assert_array_equal(a.v, b.v)
    three = column_run(2.0, 3)
    motion = np.abs(three.x - column_run(2.0, 0).x).max()
    assert motion > 1e-3
    assert np.abs(c.x - three.x).max() < 1e-4 * motion


# -- bad scenes: clear errors before any step ---------------------------------------------------
def test_bad_scenes_are_refused_before_any_step():
    soil = ZeroDilationMohrCoulomb(0.0, 30.0)
    square = ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0))
    with pytest.raises(ValueError, match="empty"):
        Region(((0, 0), (1, 0), (2, 0)), soil, 2.0, 0.1)
    with pytest.raises(ValueError, match="intersects itself"):
        Region(((0, 0), (3, 0), (3, 2), (1, -1), (0, 1)), soil, 2.0, 0.1)
    with pytest.raises(ValueError, match="h must be positive"):
        Region(square, soil, 2.0, 0.0)
    with pytest.raises(ValueError, match="inside it"):
        Scene(regions=(Region(square, soil, 2.0, 0.1),),
              bodies=(Body("pipe", RigidCircle((0.5, 0.5), 0.2)),))
    with pytest.raises(ValueError, match="function of time"):
        Body("wall", RigidSegment((0, 0), (1, 0)), motion=(1.0, 0.0))
    with pytest.raises(ValueError, match=r"motion\(t\) must return"):
        Body("wall", RigidSegment((0, 0), (1, 0)), motion=lambda t: 3.0)
    with pytest.raises(ValueError, match="every particle"):
        Scene(regions=(Region(square, soil, 2.0, 0.1),),
              outlets=(Outlet("all", HalfPlane((0.0, 2.0), (0.0, -1.0))),))
    with pytest.raises(ValueError, match="at least one"):
        Scene(regions=())


def test_regions_of_a_scene_keep_their_mass_and_tags():
    """Two regions of different density: each particle knows its region, each region's
    mass is its density times its area, and a region's mass is only passed on."""
    soft = ZeroDilationMohrCoulomb(0.0, 30.0)
    lower = block(material=soft, height=0.3, name="lower", stress=Geostatic())
    upper = Region(((0.0, 0.4), (1.0, 0.4), (1.0, 0.6), (0.0, 0.6)), soft, 2 * RHO, 0.1,
                   name="upper")
    scene = Scene(regions=(lower, upper), bodies=(base(0.5),),
                  config=PFEMConfig(theta=ThetaMethod(0.02)))
    state = scene.initial_state()
    assert state.mass[state.region == 0].sum() == pytest.approx(RHO * 0.3)
    assert state.mass[state.region == 1].sum() == pytest.approx(2 * RHO * 0.2)
    state, records = steps(scene, 2, state)
    assert records[-1]["mass_regions"] == pytest.approx({"lower": RHO * 0.3,
                                                         "upper": 2 * RHO * 0.2})


def test_a_step_does_not_change_its_input():
    """pfem_step returns a new state; the one it was given keeps every array and number."""
    import copy
    scene = moving_scene()
    state, _ = run(scene.initial_state(), scene, 3)
    before = copy.deepcopy(state)
    pfem_step(state, scene)
    for name in ("x", "v", "h", "sigma_m", "mass", "region", "mesh_p", "mesh_t",
                 "mesh_particle", "v_dofs", "sigma", "free_surface", "contact"):
        np.testing.assert_array_equal(getattr(state, name), getattr(before, name))
    assert (state.step, state.time, state.area0, state.alpha, state.scales, state.discharged,
            state.history) == (before.step, before.time, before.area0, before.alpha,
                               before.scales, before.discharged, before.history)


def test_the_record_measures_the_largest_move_in_spacings():
    """A freely falling block moves g dt^2 (theta2 = 1) in its first step: the record's
    largest displacement over h says so (a collapse within a step shows as a large value)."""
    dt, h = 0.05, 0.1
    scene = Scene(regions=(block(h=h),), config=PFEMConfig(theta=ThetaMethod(dt)))
    _, rec, _ = pfem_step(scene.initial_state(), scene)
    assert rec["max_displacement_over_h"] == pytest.approx(G * dt ** 2 / h, rel=1e-9)
