"""The PFEM loop of Ch 2.2 on the granular column of 6.4.3."""
import numpy as np
import pyvista as pv
import pytest
from skfem import Functional, MeshTri
from skfem.helpers import grad

from pfem_skfem.scene.config import PFEMConfig
from pfem_skfem.drivers.pfem_loop import pfem_step, run, run_to_rest
from pfem_skfem.discretisation.fields import smoothed_mean_stress, vertex_dofs
from pfem_skfem.io import TimeSeries
from pfem_skfem.materials import CohesiveTresca
from pfem_skfem.discretisation.static import discretise
from pfem_skfem.pfem.alpha_shape import triangle_areas
from pfem_skfem.pfem.state import PFEMState, initial_state, load_checkpoint, save_checkpoint
from pfem_skfem.pfem.surface import bulge_correction
from pfem_skfem.pfem.transfer import old_discretisation
from pfem_skfem.problems.contact import LaggedFriction, RigidSegment
from pfem_skfem.discretisation import ThetaMethod
from pfem_skfem.scene import Body, Region, Scene
from verification.granular_column_plane import granular_column

G = 9.8


def test_column_held_by_its_walls_stays_at_rest():
    # both walls and the base hold a rigid-plastic, zero-dilation column: no mechanism
    state, scene = granular_column(1.0, 6, right_wall=True)
    state, _ = run(state, scene, 4)
    v_ref = np.sqrt(G * 1.0)
    assert state.step == 4
    assert np.max(np.abs(state.v)) < 1e-4 * v_ref
    assert np.max(np.abs(state.history["area_change"])) < 1e-6
    x0 = granular_column(1.0, 6)[0].x
    assert np.max(np.abs(state.x - x0)) < 1e-6


def short_collapse(**options):
    state, scene = granular_column(1.0, 8, dt=0.05 * np.sqrt(1.0 / G), **options)
    state, _ = run(state, scene, 20)          # to t/sqrt(h0/g) = 1
    return state


def test_short_collapse_keeps_its_volume():
    # the psi = 0 flow is isochoric; the detected area may change by at most 1 %
    state = short_collapse()
    change = np.abs(state.history["area_change"])
    assert change.max() < 0.01, change.max()
    assert state.x[:, 0].max() > 1.05          # it did collapse: the toe moved out
    assert state.x[:, 1].max() < 1.0            # and the top came down


def test_surface_particles_and_bulge_correction_reduce_the_area_loss():
    # without them the vertex-only motion and the alpha-shape lose area (module docstring)
    plain = short_collapse(bulge=False, refine_surface=0)
    kept = short_collapse()
    assert np.abs(kept.history["area_change"]).max() < \
        0.5 * np.abs(plain.history["area_change"]).max()


def test_resumed_run_reproduces_an_uninterrupted_one(tmp_path):
    state, scene = granular_column(1.0, 6, dt=0.05 * np.sqrt(1.0 / G))
    straight, _ = run(state, scene, 4)
    half, _ = run(granular_column(1.0, 6)[0], scene, 2, checkpoint=tmp_path / "c.npz",
                  checkpoint_every=2)
    resumed, _ = run(load_checkpoint(tmp_path / "c.npz"), scene, 2)
    assert resumed.step == straight.step == 4
    np.testing.assert_array_equal(resumed.x, straight.x)
    np.testing.assert_array_equal(resumed.v, straight.v)
    np.testing.assert_array_equal(resumed.sigma_m, straight.sigma_m)
    assert resumed.history["area_change"] == straight.history["area_change"]


def test_checkpoint_round_trip_is_exact(tmp_path):
    state, scene = granular_column(0.5, 5, dt=0.05 * np.sqrt(0.5 / G))
    state, _ = run(state, scene, 1)
    save_checkpoint(tmp_path / "s.npz", state)
    back = load_checkpoint(tmp_path / "s.npz")
    for name in ("x", "v", "h", "sigma_m", "region", "mass", "mesh_p", "mesh_t", "v_dofs",
                 "sigma"):
        np.testing.assert_array_equal(getattr(back, name), getattr(state, name))
    assert back.scales == state.scales
    assert (back.step, back.time, back.area0) == (state.step, state.time, state.area0)


def test_smoothed_mean_stress_is_exact_for_a_constant_field():
    disc = discretise(MeshTri.init_symmetric().refined(2))
    sigma = np.tile([-3.0, -1.0, 0.0, 0.7], (disc.n_points, 1))
    np.testing.assert_allclose(smoothed_mean_stress(disc, sigma), -2.0, rtol=1e-12)


def test_initial_state_rejects_bad_clouds():
    with pytest.raises(ValueError, match="empty"):
        initial_state(np.empty((0, 2)), 0.1)
    with pytest.raises(ValueError, match="spacing"):
        initial_state([[0.0, 0.0], [1.0, 0.0]], -1.0)
    with pytest.raises(ValueError, match="stress"):
        initial_state([[0.0, 0.0], [1.0, 0.0]], 0.5, stress=np.zeros((3, 4)))


def test_config_rejects_bad_values():
    with pytest.raises(ValueError, match="theta"):
        PFEMConfig(theta=0.01)
    with pytest.raises(ValueError, match="dt"):
        PFEMConfig(theta=ThetaMethod(0.0))
    with pytest.raises(ValueError, match="passes"):
        PFEMConfig(passes=0)
    with pytest.raises(ValueError, match="contact"):
        PFEMConfig(contact="glue")
    with pytest.raises(ValueError, match="solver"):
        PFEMConfig(solver="gurobi")
    with pytest.raises(ValueError, match="velocity"):
        PFEMConfig(velocity="nearest")
    with pytest.raises(ValueError, match="stress_mapping"):
        PFEMConfig(stress_mapping="nearest")
    with pytest.raises(ValueError, match="passes >= 2"):
        PFEMConfig(contact=LaggedFriction(), passes=1)


def test_run_writes_a_vtu_per_saved_step_and_a_pvd(tmp_path):
    state, scene = granular_column(1.0, 5, dt=0.05 * np.sqrt(1.0 / G))
    series = TimeSeries(tmp_path, "column")
    last = []
    state, _ = run(state, scene, 4, series=series, save_every=2,
                   on_step=lambda st, rec, result: last.append(result))
    dt = scene.config.dt
    assert [t for t, _ in series.entries] == pytest.approx([2 * dt, 4 * dt])
    grid = pv.read(series.entries[-1][1])
    pm = last[-1].pm
    assert grid.n_points == len(pm.particle)
    for name in ("velocity", "pressure", "mean_stress"):
        assert name in grid.point_data
    for name in ("stress", "plastic_strain_increment"):
        assert name in grid.cell_data
    # the velocities written are the particles' velocities
    np.testing.assert_allclose(grid.point_data["velocity"][:, :2],
                               state.v[pm.particle])


def test_strong_slab_slides_to_newton_through_the_whole_loop():
    """A slab far stronger than its stresses, launched at v0 on a rough base, is a rigid box:
    through detect - remesh - map - solve - move with the zero-dilation contact,
    v(t) = v0 - mu g t (theta2 = 1: the velocity is exact) and it stays on the base.
    (The associated cones of (5.12) lift it by mu |slip| per step, which raises the
    normal force of that step: first order in dt, so not exact here.)"""
    mu, v0, dt = 0.3, 3.0, 0.02
    slab = Region(((0.0, 0.0), (1.0, 0.0), (1.0, 0.2), (0.0, 0.2)), CohesiveTresca(1e3),
                  rho=2.0, h=0.2)
    scene = Scene(regions=(slab,), bodies=(Body("base", RigidSegment((-10.0, 0.0),
                                                                     (30.0, 0.0), mu)),),
                  config=PFEMConfig(theta=ThetaMethod(dt), contact=LaggedFriction()))
    state = scene.initial_state()
    x = state.x.copy()
    state.v[:, 0] = v0
    for n in range(1, 11):
        state, _, _ = pfem_step(state, scene)
        assert np.allclose(state.v[:, 0], v0 - mu * G * n * dt, rtol=0, atol=1e-6 * v0)
    assert np.abs(state.x[:, 1] - x[:, 1]).max() < 1e-7


def test_elastoplastic_column_held_by_its_walls_stays_geostatic():
    """With E given, (4.23) keeps the C term; a column started in geostatic equilibrium
    (sy = -rho g (h0 - y), sx = K0 sy, inside the cone) between rough walls stays at rest."""
    state, scene = granular_column(1.0, 6, right_wall=True, E=1e4, nu=0.3)
    assert scene.elastic is not None and state.stress0 is not None
    last = []
    state, _ = run(state, scene, 3, on_step=lambda st, rec, result: last.append(result))
    assert np.max(np.abs(state.v)) < 1e-4 * np.sqrt(G * 1.0)
    disc = last[-1].disc
    y = disc.points[:, 1]
    sy = -2.0 * G * (1.0 - y)
    assert np.allclose(state.sigma[:, 1], sy, atol=1e-3 * 2.0 * G)
    assert np.allclose(state.sigma[:, 0], (1 - np.sin(np.radians(31.0))) * sy,
                       atol=1e-3 * 2.0 * G)


def test_elastoplastic_short_collapse_keeps_its_volume():
    state = short_collapse(E=1e4, nu=0.3)
    assert np.abs(state.history["area_change"]).max() < 0.02
    assert state.x[:, 0].max() > 1.05


def test_backends_give_the_same_collapse():
    """The PFEM loop with the direct Clarabel assembly follows the cvxpy statement.

    Each step agrees to the solver tolerance; the fixed-point passes carry the
    (non-unique, rigid-zone) stresses into the next cone radii, so over 5 steps the
    paths drift apart: measured 1.2e-3 of the motion, asserted 1e-2 (a wrong sign or
    scale in either backend is an O(1) difference)."""
    x0 = granular_column(1.0, 6)[0].x
    runs = {}
    for solver in ("cvxpy", "clarabel"):
        state, scene = granular_column(1.0, 6, dt=0.05 * np.sqrt(1.0 / G), solver=solver)
        runs[solver], _ = run(state, scene, 5)
    a, b = runs["cvxpy"], runs["clarabel"]
    assert a.x.shape == b.x.shape
    motion = np.abs(a.x[:len(x0)] - x0).max()
    assert motion > 0.01
    assert np.abs(a.x - b.x).max() < 1e-2 * motion
    assert np.abs(a.v - b.v).max() < 1e-2 * np.abs(a.v).max()


def test_old_discretisation_leaves_out_collapsed_triangles_and_keeps_the_field():
    """A moved mesh with a collapsed triangle: the map source drops it and carries the P2
    field (checked against the function at every dof location) and the other stresses."""
    mesh = MeshTri.init_tensor(np.linspace(0, 1, 4), np.linspace(0, 1, 4))
    p, t = mesh.p.T, mesh.t.T
    # a collapsed triangle on the bottom edge: (a, b, midpoint of ab)
    bottom = [f for f in mesh.facets.T if np.allclose(p[f, 1], 0.0)]
    a, b = bottom[0]
    p = np.vstack([p, 0.5 * (p[a] + p[b])])
    t = np.vstack([t, [a, b, len(p) - 1]])
    full = MeshTri(p.T, t.T, sort_t=False)
    fn = lambda x: np.stack([x[:, 0] ** 2 + x[:, 1], x[:, 0] * x[:, 1]], axis=1)  # noqa: E731
    nv, nf = full.nvertices, full.facets.shape[1]
    v = np.zeros(2 * nv + 2 * nf)               # scikit-fem P2 vector numbering
    v[:2 * nv] = fn(p).ravel()
    v[2 * nv:] = fn(p[full.facets].mean(axis=0)).ravel()
    sigma = np.arange(3 * len(t) * 4, dtype=float).reshape(-1, 4)
    state = PFEMState(step=1, time=0.0, x=p, v=np.zeros_like(p), h=np.ones(nv),
                      sigma_m=np.zeros(nv), mesh_p=p, mesh_t=t, v_dofs=v, sigma=sigma)
    old, v_old, s_old = old_discretisation(state)
    assert old.mesh.nelements == len(t) - 1
    assert np.allclose(s_old, sigma[:-3])
    x = old.basis_u.doflocs.T
    expected = np.where(np.arange(old.n_u) % 2 == 0, x[:, 0] ** 2 + x[:, 1], x[:, 0] * x[:, 1])
    assert np.allclose(v_old, expected)


def test_added_nodes_take_the_mean_stress_of_a_map_source_without_its_collapsed_triangle():
    """A remesher's added node over a moved mesh whose last vertex only a collapsed
    triangle used (the map source drops both): the node takes the linear mean stress
    exactly (P1 interpolation), the velocity of the P2 field. Before, the source's
    vertex count and the particles' differed and the map raised."""
    from pfem_skfem.pfem.remesh import ParticleMesh
    from pfem_skfem.pfem.transfer import adopt_added_nodes
    mesh = MeshTri.init_tensor(np.linspace(0, 1, 4), np.linspace(0, 1, 4))
    p, t = mesh.p.T, mesh.t.T
    a, b = [f for f in mesh.facets.T if np.allclose(p[f, 1], 0.0)][0]
    p = np.vstack([p, 0.5 * (p[a] + p[b])])
    t = np.vstack([t, [a, b, len(p) - 1]])                  # collapsed, on the bottom edge
    full = MeshTri(p.T, t.T, sort_t=False)
    nv, nf = full.nvertices, full.facets.shape[1]
    linear = lambda x: 2.0 * x[:, 0] - 3.0 * x[:, 1] + 0.5     # noqa: E731
    v = np.zeros(2 * nv + 2 * nf)
    v[:2 * nv] = np.stack([linear(p), -linear(p)], axis=1).ravel()
    v[2 * nv:] = np.stack([linear(p[full.facets].mean(axis=0)),
                           -linear(p[full.facets].mean(axis=0))], axis=1).ravel()
    state = PFEMState(step=1, time=0.0, x=p, v=np.zeros_like(p), h=np.ones(nv),
                      sigma_m=linear(p), mesh_p=p, mesh_t=t, mesh_particle=np.arange(nv),
                      v_dofs=v, sigma=np.zeros((3 * len(t), 4)))
    added = np.array([[0.4, 0.55]])
    pm = ParticleMesh(MeshTri(np.vstack([p, added]).T, t[:-1].T, sort_t=False),
                      np.r_[np.arange(nv), -1])
    new, pm = adopt_added_nodes(state, pm, old_discretisation(state))
    assert new.n == nv + 1 and pm.particle[-1] == nv
    assert new.sigma_m[-1] == pytest.approx(linear(added)[0], abs=1e-12)
    np.testing.assert_allclose(new.v[-1], [linear(added)[0], -linear(added)[0]], atol=1e-12)


def test_a_deposit_coming_to_rest_keeps_solving():
    """The step's scales stay at least those of a free-fall step: without that floor the
    displacement scale of this run shrank as the deposit came to rest, the scaled gaps
    g0 / u_ref grew without bound and Clarabel reported 'unbounded' at step 189."""
    a, steps = 0.5, 200
    state, scene = granular_column(a, 10, phi=35.0, dt=4 * np.sqrt(a / G) / steps)
    state, _ = run(state, scene, steps)
    ke = np.asarray(state.history["kinetic_energy"])
    assert ke[-1] < 0.05 * ke.max()                       # and the deposit is at rest


def _trapezoid_with_bulging_slope(s=1e-5):
    """A flat top (y = 1, 0 <= x <= 1) meets a slope down to (1.5, 0) at the crest (1, 1);
    a P2 displacement that bulges the slope only (zero on the top, base and left side)."""
    m = MeshTri.init_tensor(np.linspace(0, 1, 7), np.linspace(0, 1, 7))
    x, y = m.p
    mesh = MeshTri(np.vstack([x * (1 + 0.5 * (1 - y)), y]), m.t)
    disc = discretise(mesh)
    n_slope = np.array([1.0, 0.5]) / np.hypot(1.0, 0.5)
    X, Y = disc.basis_u.doflocs
    du = s * (Y * (1 - Y) * X * n_slope[np.arange(disc.n_u) % 2])
    return disc, du


def _p2_area(disc, du):
    """Exact area of the body displaced by the P2 field: the integral of det(I + grad du)."""
    @Functional
    def jacobian(w):
        g = grad(w["u"])
        return (1 + g[0, 0]) * (1 + g[1, 1]) - g[0, 1] * g[1, 0]
    return jacobian.assemble(disc.basis_u, u=disc.basis_u.interpolate(du))


def test_bulge_correction_restores_the_p2_area_and_keeps_a_crest_on_its_flat_top():
    disc, du = _trapezoid_with_bulging_slope()
    p = disc.mesh.p.T + du[vertex_dofs(disc)]
    shift = bulge_correction(disc, du)
    chord = np.abs(triangle_areas(p, disc.mesh.t.T)).sum()
    corrected = np.abs(triangle_areas(p + shift, disc.mesh.t.T)).sum()
    exact = _p2_area(disc, du)
    assert abs(exact - chord) > 1e-8                     # the chords do lose the bulge
    assert abs(corrected - exact) < 0.02 * abs(exact - chord)
    crest = np.argmin(np.linalg.norm(disc.mesh.p.T - [1.0, 1.0], axis=1))
    # the crest moves along the top (the top has no bulge), not up: the former rule,
    # a sum of shifts along each edge's normal, lifted it by 0.45 |w|
    assert np.linalg.norm(shift[crest]) > 0
    assert abs(shift[crest, 1]) < 0.02 * np.linalg.norm(shift[crest])
    assert np.all(shift[disc.mesh.p[1] > 1 - 1e-12, 1] <= 0.01 * np.abs(shift).max())


def test_state_tags_the_free_surface_and_the_contacts():
    # a column held by its walls: its outline is the free surface, and the particles on
    # the base and the walls (except the free top row) carry the column's weight
    state, scene = granular_column(1.0, 6, right_wall=True)
    state, _ = run(state, scene, 1)
    x, h = state.x, state.h[0]
    on_outline = (x[:, 0] < 1e-9) | (x[:, 0] > 1 - 1e-9) | (x[:, 1] < 1e-9) | (x[:, 1] > 1 - 1e-9)
    np.testing.assert_array_equal(state.free_surface, on_outline)
    on_base = x[:, 1] < 1e-9
    assert state.contact[on_base].all()
    assert not state.contact[(x[:, 1] > 0.5 * h) & (x[:, 0] > 0.5 * h) & (x[:, 0] < 1 - 0.5 * h)].any()


def test_state_rejects_mismatched_fields():
    with pytest.raises(ValueError, match="sigma_m"):
        initial_state(np.zeros((3, 2)), 1.0, sigma_m=np.zeros(2))
    with pytest.raises(ValueError, match="empty"):
        initial_state(np.zeros((0, 2)), 1.0)
    with pytest.raises(ValueError, match="h"):
        initial_state(np.zeros((3, 2)), -1.0)


def test_particles_appended_to_a_state_with_initial_stresses_keep_its_shapes():
    """Surface particles added after the first step of a geostatic body (the move stage's
    ``appended``) once failed the state's check on stress0 (n, 4); they get zero, which
    only the first mesh reads."""
    stress = -np.ones((3, 4))
    state = initial_state(np.eye(3, 2), 1.0, stress=stress)
    more = state.appended(np.full((2, 2), 5.0), np.zeros((2, 2)), np.ones(2), np.zeros(2),
                          np.zeros(2, dtype=int))
    assert more.stress0.shape == (5, 4)
    np.testing.assert_array_equal(more.stress0[:3], stress)
    assert not more.stress0[3:].any()


def test_run_to_rest_stops_at_rest_or_after_max_steps():
    state, scene = granular_column(1.0, 5, dt=0.05 * np.sqrt(1.0 / G))
    still, rest, taken = run_to_rest(state, scene, 1e-3, 5)      # starts at rest
    assert rest and taken == 0 and still.step == 0
    state, _ = run(state, scene, 1)                               # now collapsing
    moving, rest, taken = run_to_rest(state, scene, 1e-3, 2)
    assert not rest and taken == 2 and moving.step == 3
    assert np.abs(moving.v).max() >= 1e-3


def test_spread_mass_leaves_no_particle_of_the_mesh_massless_and_keeps_each_mass():
    """The clay block into the tank (soil_and_water.py, spacing 0.1): the midside nodes of
    stretched surface edges become massless particles and thinning piles masses onto
    others, so without spread_mass water particles on the mesh carry no mass by t = 1.2 s;
    with it none does, and each region keeps its mass to round-off at every step."""
    from verification.soil_and_water import CLAY, tank_scene
    massless = {}
    for spread in (False, True):
        state, scene, _ = tank_scene(beta=30.0, mu_slope=0.2, mu_floor=0.0, d=0.4, L=2.0,
                                     block=(0.4, 0.2), c=2000.0, rho_w=1000.0, rho_c=1800.0,
                                     g=9.81, h=0.1, dt=0.03, spread_mass=spread)
        first = [state.mass[state.region == r].sum() for r in (0, 1)]
        found = []

        def count(state, record, result):
            meshed = np.zeros(state.n, dtype=bool)
            meshed[state.mesh_particle] = True
            found.append(int(np.sum(meshed & (state.mass == 0))))
            for r in (0, 1):
                assert state.mass[state.region == r].sum() == pytest.approx(first[r],
                                                                            rel=1e-12)

        state, _ = run(state, scene, 40, on_step=count)
        massless[spread] = found
        assert np.any(state.region == CLAY)
    assert max(massless[False]) > 0
    assert max(massless[True]) == 0


def test_refine_interior_adds_the_p2_midside_nodes_of_stretched_interior_edges():
    """With refine_interior = 1.05, every interior edge of the step's mesh longer than 1.05 h
    at the moved positions hands its P2 midside node to the cloud: a new particle there
    (the midside dof moved by its P2 displacement) with the P2 velocity of that node, and
    none elsewhere (the column's square lattice: each square's diagonal, sqrt(2) h); with
    the default 0 none is added inside."""
    from dataclasses import replace
    state, scene = granular_column(1.0, 8, dt=0.05 * np.sqrt(1.0 / G), refine_interior=1.05,
                                   refine_surface=0.0)
    new, record, result = pfem_step(state, scene)
    disc, pm, inc = result.disc, result.pm, result.increment
    inner = np.flatnonzero(disc.mesh.f2t[1] >= 0)
    a, b = pm.particle[disc.mesh.facets[:, inner]]
    moved = new.x[:state.n]
    long = inner[np.linalg.norm(moved[a] - moved[b], axis=1)
                 > 1.05 * 0.5 * (state.h[a] + state.h[b])]
    assert long.size == 7 * 7 and new.n - state.n == long.size == record["surface_particles"]
    mid = disc.basis_u.facet_dofs[:, long]
    np.testing.assert_allclose(new.x[state.n:], disc.basis_u.doflocs[:, mid[0]].T
                               + inc.du[mid].T, atol=1e-12)
    np.testing.assert_array_equal(new.v[state.n:], inc.v[mid].T)
    assert np.all(new.mass[state.n:] == 0)                 # mass is only handed on
    plain, _ = run(state, replace(scene, config=replace(scene.config, refine_interior=0.0)), 1)
    assert plain.n == state.n


@pytest.mark.parametrize("value", [-1.0, np.nan, np.inf])
def test_config_refuses_a_bad_refine_interior(value):
    with pytest.raises(ValueError, match="refine_interior"):
        PFEMConfig(refine_interior=value)


def test_a_remeshing_hands_a_rigid_slide_its_kinetic_energy_unchanged():
    """The strong slab sliding on a rough base is a rigid box: each step starts from
    the kinetic energy (start_kinetic_energy, of the velocities mapped onto the new mesh)
    that the previous one ended with (a uniform field maps exactly), the first from
    rho A v0^2 / 2 of the particles' velocity."""
    mu, v0, dt, rho = 0.3, 3.0, 0.02, 2.0
    slab = Region(((0.0, 0.0), (1.0, 0.0), (1.0, 0.2), (0.0, 0.2)), CohesiveTresca(1e3),
                  rho=rho, h=0.2)
    scene = Scene(regions=(slab,), bodies=(Body("base", RigidSegment((-10.0, 0.0),
                                                                     (30.0, 0.0), mu)),),
                  config=PFEMConfig(theta=ThetaMethod(dt), contact=LaggedFriction()))
    state = scene.initial_state()
    state.v[:, 0] = v0
    state, _ = run(state, scene, 5)
    start = np.array(state.history["start_kinetic_energy"])
    end = np.array(state.history["kinetic_energy"])
    assert start[0] == pytest.approx(0.5 * rho * 0.2 * v0 ** 2, rel=1e-12)
    np.testing.assert_allclose(start[1:], end[:-1], rtol=1e-9)
    assert np.all(np.diff(end) < 0)                        # friction takes it away
