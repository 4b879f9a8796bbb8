"""What is measured on a particle cloud (pfem.measure): each measure on a cloud whose answer
is known by hand."""
from types import SimpleNamespace

import numpy as np
import pytest

from pfem_skfem.pfem.measure import (area_budget, deposit_at_wall, failure_extent, front,
                                     front_speed, front_speed_resolution, ground_particles,
                                     height_at, main_body,
                                     mesh_energy, off_mesh_volume, particle_energy,
                                     surface_level, surface_profile, wedge_geometry)


def lattice(nx, ny, h):
    """A cloud of nx x ny particles, h apart, its bottom-left particle at the origin."""
    X, Y = np.meshgrid(np.arange(nx) * h, np.arange(ny) * h)
    x = np.column_stack([X.ravel(), Y.ravel()])
    return SimpleNamespace(x=x, h=np.full(len(x), h), n=len(x))


def test_the_height_at_a_wall_of_a_lattice_is_its_top_row():
    cloud = lattice(4, 3, 0.5)                      # x in 0..1.5, y in 0..1
    assert height_at(cloud, 0.0) == 1.0
    assert height_at(cloud, 0.0, cloud.x[:, 1] < 0.7) == 0.5       # a mask: the lower rows
    assert height_at(cloud, 2.1, within=0.7) == 1.0               # a wider reach: x = 1.5
    assert np.isnan(height_at(cloud, 2.1, default=np.nan))        # none near: the default
    with pytest.raises(ValueError, match="within one spacing of x = 2.1"):
        height_at(cloud, 2.1)                       # 0.6 from the last column: beyond h


def test_the_deposit_at_the_wall_leaves_out_a_splash():
    cloud = lattice(4, 3, 0.5)                      # x in 0..1.5, y in 0..1
    x = np.vstack([cloud.x[cloud.x[:, 0] + cloud.x[:, 1] <= 2.0], [[5.0, 3.0]]])  # a splash
    deposit = SimpleNamespace(x=x, h=np.full(len(x), 0.5), n=len(x), mesh_p=None)
    assert deposit_at_wall(deposit, 1.4) == (1.0, 1.0, 1.5)      # the wall, the top, the toe


def test_the_front_of_the_particles_takes_a_drop_the_mesh_leaves_out():
    mesh_p = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    cloud = SimpleNamespace(x=np.vstack([mesh_p, [[2.5, 0.3]]]), mesh_p=mesh_p)
    assert front(cloud) == 1.0
    assert front(cloud, mesh=False) == 2.5


def test_the_front_of_the_main_body_leaves_out_a_drop_meshed_on_its_own():
    """A unit square (two triangles), a triangle hanging on its vertex (1, 1) (joined: the
    shared vertex moves both) and, ahead, a small triangle (a drop the alpha-shape meshed
    on its own) and a particle off the mesh: the mesh's front is the drop's, the main
    body's that of the hanging triangle."""
    mesh_p = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0],          # the square
                       [3.0, 0.0], [3.2, 0.0], [3.1, 0.1],                       # a drop
                       [1.5, 1.0], [1.5, 1.2]])                # hanging on the vertex (1, 1)
    mesh_t = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [2, 7, 8]])
    cloud = SimpleNamespace(x=np.vstack([mesh_p, [[5.0, 0.3]]]), mesh_p=mesh_p, mesh_t=mesh_t)
    assert main_body(mesh_p, mesh_t).tolist() == [0, 1, 2, 3, 7, 8]
    assert front(cloud, main=True) == 1.5
    assert front(cloud) == 3.2 and front(cloud, mesh=False) == 5.0
    with pytest.raises(ValueError, match="mesh=True"):
        front(cloud, mesh=False, main=True)


def test_the_water_off_the_mesh_is_its_mass_over_its_density():
    """A meshed 3 x 3 lattice of water (rho 1000, 1 kg a particle) with a drop of it off the
    mesh (2 kg), a particle of a denser region off it too (rho 2000, 3 kg) and a massless
    surface particle (a midside node the move added): the volume left out is 2 / 1000 +
    3 / 2000, the massless one adds nothing, a vertex whose particle was dropped (-1) is
    read as no particle; with every particle on the mesh, none; with no mesh, all."""
    cloud = lattice(3, 3, 0.5)
    n = cloud.n + 3
    state = SimpleNamespace(n=n, mass=np.r_[np.ones(cloud.n), 2.0, 3.0, 0.0],
                            region=np.r_[np.zeros(cloud.n + 1, dtype=int), 1, 0],
                            mesh_particle=np.r_[np.arange(cloud.n), -1])
    rho = np.array([1000.0, 2000.0])
    assert off_mesh_volume(state, rho) == pytest.approx(2 / 1000 + 3 / 2000, rel=1e-15)
    state.mesh_particle = np.arange(n)
    assert off_mesh_volume(state, rho) == 0.0
    state.mesh_particle = None
    assert off_mesh_volume(state, rho) == pytest.approx((cloud.n + 2) / 1000 + 3 / 2000,
                                                        rel=1e-15)
    state.region[:] = 0
    assert off_mesh_volume(state, 1000.0) == pytest.approx((cloud.n + 5) / 1000, rel=1e-15)


def test_the_area_budget_splits_a_run_into_its_motion_and_its_remeshings():
    """Three steps of a domain of area 10: the first step's motion loses 0.1, the second
    remeshing drops a triangle of 0.5 and the third takes it back with 0.2 more, while the
    steps' motions lose 0.05 and 0.02; each step's mesh is the sum of what came before."""
    history = {"mesh_area": [10.0, 9.4, 10.05], "moved_area": [9.9, 9.35, 10.03]}
    motion, remeshing = area_budget(history, 10.0)
    assert motion == pytest.approx([-0.01, -0.005, -0.002], abs=1e-15)
    assert remeshing == pytest.approx([0.0, -0.05, 0.07], abs=1e-15)
    mesh = np.array(history["mesh_area"]) / 10.0 - 1
    for k in range(3):
        assert mesh[k] == pytest.approx(motion[:k].sum() + remeshing[:k + 1].sum(), abs=1e-15)


def test_the_front_speed_over_a_window_is_the_slope_not_a_jump_of_one_particle():
    """x = 2 t, each sample off by +-h/2 (a particle leaving the body and joining it again):
    step to step the front runs at 2 + h / dt; over a window of 1 its slope is 2 within
    h / window. A front speeding up from 1 to 3 at t = 2 runs at 3 over the last window."""
    t = np.linspace(0.0, 4.0, 81)
    h = 0.1
    jumpy = 2 * t + np.where(np.arange(t.size) % 2, h / 2, -h / 2)
    assert np.diff(jumpy).max() / (t[1] - t[0]) == pytest.approx(2 + h / (t[1] - t[0]))
    assert abs(front_speed(t, jumpy, 1.0) - 2.0) < h / 1.0
    assert front_speed(t, 2 * t, 1.0) == pytest.approx(2.0, rel=1e-12)
    bent = np.where(t < 2, t, 2 + 3 * (t - 2))
    assert front_speed(t, bent, 1.0) == pytest.approx(3.0, rel=1e-12)
    assert np.isnan(front_speed(t, bent, 5.0))                 # no window of 5 in 0..4


def test_the_front_speed_resolution_is_the_sharp_bound_of_a_front_known_to_h():
    """A front x = 2 t known within a band h (0 <= e_i <= h): no pattern of errors reads a
    speed above 2 + the resolution, the step of h at a window's middle reads it exactly, and
    for many evenly spaced samples it is 1.5 h / window (the least-squares slope of a unit
    step at the middle of [0, L]: cov(t, step) / var(t) = (L / 8) / (L^2 / 12))."""
    t = np.linspace(0.0, 4.0, 81)                   # dt = 0.05: 21 samples a window of 1
    h = 0.1
    resolution = front_speed_resolution(t, 1.0, h)
    d = np.linspace(0.0, 1.0, 21) - 0.5
    assert resolution == pytest.approx(h * d[d > 0].sum() / (d * d).sum(), rel=1e-12)
    assert resolution == pytest.approx(h * 30 / 21, rel=1e-12)       # 1.43 h / window
    rng = np.random.default_rng(0)
    for _ in range(200):                            # bounded errors, any pattern: within
        e = h * rng.integers(0, 2, t.size) * rng.random(t.size) ** 0.1
        assert front_speed(t, 2 * t + e, 1.0) <= 2.0 + resolution * (1 + 1e-12)
    worst = 2 * t + h * (t > 2.5)                   # a step at the middle of [2, 3]
    assert front_speed(t, worst, 1.0) == pytest.approx(2.0 + resolution, rel=1e-12)
    assert front_speed(t, worst, 1.0) > 2.0 + h / 1.0        # h / window is not a bound
    fine = np.linspace(0.0, 1.0, 100001)
    assert front_speed_resolution(fine, 1.0, h) == pytest.approx(1.5 * h, rel=1e-4)
    assert np.isnan(front_speed_resolution(t, 5.0, h))       # no window of 5 in 0..4


def test_the_surface_level_of_a_lattice_is_its_top_row():
    cloud = lattice(11, 6, 0.1)                     # x in 0..1, top row at y = 0.5
    water = ~np.isclose(cloud.x[:, 0], 0.3)         # a gap: that column holds no water
    x = np.vstack([cloud.x, [[0.55, 9.0]]])         # a particle of another region, higher
    water = np.append(water, False)
    assert surface_level(x, water, 0.1, 0.0, 1.0) == pytest.approx(0.5, abs=1e-15)
    assert np.isnan(surface_level(x, water, 0.1, 2.0, 3.0))        # no column holds one


def test_a_failed_bank_runs_out_from_its_toe_and_retrogresses_from_its_crest():
    """A 1 m bank, 11 x 11 particles 0.1 apart, its face at x = 1 (toe and crest): the top
    row is its ground. Three of it drop, by 0.3, 0.2 and 0.05 (below the threshold 0.1):
    the retrogression is 1 - 0.6 = 0.4, of the furthest back that dropped. The run-out is
    the furthest particle beyond the toe: 2.5 of the bank's own, or 3 counting a particle
    added since (originals=False)."""
    x0 = lattice(11, 11, 0.1).x
    ground = ground_particles(x0, 1.0 - 0.025)
    assert np.all(x0[ground, 1] == pytest.approx(1.0)) and len(ground) == 11
    assert list(ground_particles(x0, 0.975, behind=0.5)) == list(ground[:6])   # x <= 0.5
    x = x0.copy()
    top = {round(x0[i, 0], 1): i for i in ground}
    x[top[0.6], 1] -= 0.3
    x[top[0.8], 1] -= 0.2
    x[top[0.3], 1] -= 0.05
    x[0, 0] = 3.5                                     # a particle of the toe run out
    extent = dict(toe=1.0, crest=1.0, drop=0.1)
    assert failure_extent(x, x0, ground, **extent) == (pytest.approx(2.5), pytest.approx(0.4))
    added = np.vstack([x, [[4.0, 0.0]]])
    assert failure_extent(added, x0, ground, **extent)[0] == pytest.approx(2.5)
    assert failure_extent(added, x0, ground, originals=False, **extent)[0] == \
        pytest.approx(3.0)
    # nothing dropped: no retrogression; one dropped ahead of the crest: none either
    assert failure_extent(x0, x0, ground, **extent) == (pytest.approx(0.0), 0.0)
    assert failure_extent(x, x0, ground, toe=1.0, crest=0.5, drop=0.1)[1] == 0.0


def test_the_surface_profile_of_a_lattice_is_its_top_row():
    cloud = lattice(11, 6, 0.1)                     # x in 0..1, top row at y = 0.5
    bins = np.arange(-0.05, 1.3, 0.1)               # one particle column a bin, two beyond
    xc, top = surface_profile(cloud.x, cloud.h, 1.4, bins)
    assert np.allclose(xc, np.arange(0.0, 1.25, 0.1))
    assert np.all(top[:11] == 0.5) and np.isnan(top[11:]).all()


def test_the_geometry_of_a_triangular_wedge():
    """A surface falling at 10 deg from h0 + H at the wall: the slope is 10 deg, the front
    the first bin centre within one spacing of h0, the uplift the area under the line from
    the first bin centre to the front (the trapezoidal rule is exact on a line)."""
    h0, H, spacing, tan_a = 0.1, 0.04, 0.01, np.tan(np.radians(10.0))
    xc = np.arange(0.005, 1.0, 0.01)
    top = h0 + np.clip(H - xc * tan_a, 0.0, None)
    top[-1] = np.nan                                # an empty bin, left out
    geo = wedge_geometry(np.append(-0.005, xc), np.append(h0 + H, top), 0.0, h0, spacing)
    front = xc[np.argmax(H - xc * tan_a <= spacing)]        # 0.175
    assert geo["slope_deg"] == pytest.approx(10.0, rel=1e-9)
    assert (geo["front"], geo["length"]) == (pytest.approx(front), pytest.approx(front))
    assert (geo["crest_x"], geo["crest"]) == (0.005, pytest.approx(h0 + H - 0.005 * tan_a))
    area = H * (front - 0.005) - tan_a * (front ** 2 - 0.005 ** 2) / 2
    assert geo["area_up"] == pytest.approx(area, rel=1e-12)


def test_the_energy_of_two_particles():
    cloud = SimpleNamespace(mass=np.array([2.0, 3.0]), v=np.array([[1.0, 0.0], [0.0, 2.0]]),
                            x=np.array([[5.0, 1.0], [-4.0, 2.0]]))
    kinetic, potential = particle_energy(cloud, (0.0, -10.0))
    assert kinetic == 0.5 * (2 * 1 + 3 * 4)
    assert potential == 2 * 10 * 1 + 3 * 10 * 2


def test_the_energy_of_a_step_on_one_triangle_lifted_by_one():
    p = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    t = np.array([[0, 1, 2]])
    state = SimpleNamespace(region=np.zeros(3, dtype=int), mesh_p=p + [0.0, 1.0], mesh_t=t)
    scene = SimpleNamespace(regions=[SimpleNamespace(rho=1000.0)], gravity=(0.0, -10.0))
    mesh = SimpleNamespace(p=p.T, t=t.T)
    result = SimpleNamespace(pm=SimpleNamespace(particle=np.arange(3), mesh=mesh),
                             disc=SimpleNamespace(mesh=mesh))
    record = {"kinetic_energy": 3.0, "start_kinetic_energy": 2.0}
    weight = 1000.0 * 0.5 * 10.0                     # rho A g, its centroid at y = 1/3
    np.testing.assert_allclose(mesh_energy(state, scene, record, result),
                               [3.0, weight / 3, weight * 4 / 3, 2.0], rtol=1e-15)


def test_largest_gain_is_the_largest_rise_after_a_low():
    from pfem_skfem.pfem.measure import largest_gain

    assert largest_gain([3.0, 1.0, 2.5, 0.0, 1.0]) == 1.5
    assert largest_gain([3.0, 2.0, 1.0]) == 0.0


def test_an_energy_budget_splits_steps_and_remeshings():
    from pfem_skfem.pfem.measure import energy_budget

    energy = [[0.0, 10.0], [1.0, 8.0], [2.0, 7.5]]        # [kinetic, potential] a record
    # [kinetic t_n+1, potential t_n, potential t_n+1, kinetic t_n] a step
    mesh = [[1.0, 10.0, 8.0, 0.0], [2.0, 8.5, 7.0, 1.5]]
    b = energy_budget(energy, mesh)
    assert b["energy_change_end"] == -0.5 and b["energy_largest_rise"] == 0.5
    assert b["energy_largest_gain"] == 0.5 and b["kinetic_peak"] == 2.0
    assert b["mesh_energy_change_end"] == 0.0 and b["mesh_energy_largest_gain"] == 0.0
    assert b["remeshing_potential"] == 0.5 and b["remeshing_kinetic"] == 0.5
    assert b["steps_energy"] == (1 + 8 - 0 - 10) + (2 + 7 - 1.5 - 8.5)
