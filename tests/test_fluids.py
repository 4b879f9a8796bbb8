"""Water and mud (pfem_skfem.materials.fluids): the exact films on the periodic strip, the
direct Clarabel statement against cvxpy's, density invariance and bad input."""
import numpy as np
import pytest

from pfem_skfem.discretisation import ThetaMethod, dynamic_operators
from pfem_skfem.discretisation.static import body_force_vector, discretise
from pfem_skfem.drivers.strip import strip_flow
from pfem_skfem.materials import (BinghamFluid, BinghamFluidAxisymmetric, NewtonianFluid,
                                  NewtonianFluidAxisymmetric, TrescaField, VonMisesField)
from pfem_skfem.problems.dynamic import dynamic_increment
from pfem_skfem.problems.step_scaling import DynamicScales
from pfem_skfem.problems.step_terms import step_terms
from verification.fluid_films import (P2_KINK, bingham_velocity, film_velocity, kink_bound,
                                      profile_error)

RHO, G, H, THETA = 1000.0, 9.81, 0.02, 10.0
SIN = np.sin(np.radians(THETA))


def _strip(material, rho=RHO, ny=4, steps=40, mu=1.0, **options):
    return strip_flow(THETA, H, material, rho, ny=ny, steps=steps, t_end=10 * H ** 2 * rho / mu,
                      g=G, passes=1, **options)


def test_a_newtonian_film_has_nusselt_s_parabola_to_round_off():
    """P2 velocities hold the parabola: surface and profile to 1e-7 (the time stepping's
    decay after 40 implicit steps of h^2 / (4 nu) is 4e-9)."""
    r = _strip(NewtonianFluid(mu=1.0))
    u_s = RHO * G * SIN * H ** 2 / 2
    assert r["u"][-1] == pytest.approx(u_s, rel=1e-7)
    assert profile_error(r["z"], r["u"], film_velocity(r["z"], H, THETA, RHO, 1.0, G)) < 1e-7


def test_a_bingham_layer_has_its_plug_and_converges_to_the_closed_form():
    """tau_y = (2/3) rho g h sin(theta): the plug's base at h / 3, inside an element on each
    mesh; the profile's L2 error falls at least as (1/ny)^1.5 from ny = 4 to 16, below 1e-3
    at 16, the plug rigid to 1e-3 above z_y + one element."""
    tau_y = 2 / 3 * RHO * G * H * SIN
    errors = []
    for ny in (4, 16):
        r = _strip(BinghamFluid(tau_y=tau_y, mu=1.0), ny=ny)
        errors.append(profile_error(r["z"], r["u"],
                                    bingham_velocity(r["z"], H, THETA, RHO, tau_y, 1.0, G)))
    assert errors[1] < 1e-3
    assert errors[1] < errors[0] * 4.0 ** -1.5
    plug = r["z"] >= H / 3 + H / 16
    assert np.ptp(r["u"][plug]) < 1e-3 * r["u"][-1]


def test_no_flow_at_or_below_the_yield_stress():
    """rho g h sin(theta) < tau_y: the layer stays at rest (1e-6 of the film's speed)."""
    r = _strip(BinghamFluid(tau_y=1.05 * RHO * G * H * SIN, mu=1.0))
    assert np.abs(r["u"]).max() < 1e-6 * RHO * G * SIN * H ** 2 / 2


@pytest.mark.parametrize("make", [lambda k: NewtonianFluid(mu=k * 1.0),
                                  lambda k: BinghamFluid(tau_y=k * 20.0, mu=k * 1.0)],
                         ids=["newtonian", "bingham"])
def test_density_times_two_with_the_stresses_is_the_same_run_bit_for_bit(make):
    a = _strip(make(1), steps=8)
    b = _strip(make(2), rho=2 * RHO, mu=2.0, steps=8)          # the same time, h^2 / nu
    assert np.array_equal(a["u"], b["u"])


def test_the_direct_statement_agrees_with_cvxpy_on_the_strip():
    for material in (NewtonianFluid(mu=1.0), BinghamFluid(tau_y=15.0, mu=1.0)):
        a = _strip(material, steps=5, solver="clarabel")
        b = _strip(material, steps=5, solver="cvxpy")
        assert np.abs(a["u"] - b["u"]).max() < 1e-6 * np.abs(b["u"]).max()


def _column_step(material, axisymmetric, solver):
    """One step of a column of fluid (0.2 x 0.4) released from rest on a no-slip floor
    (its free side and top traction-free): velocities, stresses and multipliers."""
    from skfem import MeshTri

    mesh = MeshTri.init_tensor(np.linspace(0.0, 0.2, 5), np.linspace(0.0, 0.4, 9))
    disc = discretise(mesh, "axisymmetric" if axisymmetric else "plane")
    dt = 0.01
    ops = dynamic_operators(disc, RHO, ThetaMethod(dt, 1.0, 1.0))
    f = body_force_vector(disc, (0.0, -RHO * G))
    xy = disc.basis_u.doflocs
    floor = np.flatnonzero(xy[1] < 1e-12)
    axis = disc.basis_u.nodal_dofs[0][mesh.p[0] < 1e-12] if axisymmetric else []
    fixed = np.union1d(floor, axis).astype(int)
    n = disc.n_points
    viscous = material.viscous(np.zeros(n), RHO * G * 0.4, None, disc.weights)
    cone = material.cone(np.zeros(n), RHO * G * 0.4)
    scales = DynamicScales(RHO * G * 0.4, G * dt ** 2, RHO * G)
    return dynamic_increment(ops, f, f, np.zeros((n, 4)), np.zeros(disc.n_u), cone,
                             fixed=fixed, scaling=scales, terms=step_terms(viscous=viscous),
                             solver=solver)


@pytest.mark.parametrize("material, axisymmetric", [
    (NewtonianFluid(mu=0.0), False), (NewtonianFluid(mu=0.5), False),
    (BinghamFluid(tau_y=200.0, mu=0.5), False), (NewtonianFluidAxisymmetric(mu=0.0), True),
    (NewtonianFluidAxisymmetric(mu=0.5), True), (BinghamFluidAxisymmetric(tau_y=100.0, mu=0.5),
                                                 True)],
    ids=["water", "viscous water", "mud", "water axi", "viscous water axi", "mud axi"])
def test_a_collapsing_column_step_direct_equals_cvxpy_and_is_isochoric(material, axisymmetric):
    """The first step of a released column: the direct Clarabel statement and cvxpy's give
    the same velocities (1e-6) and plastic multipliers; the flow is isochoric (the volume
    strain of the step at each point, of the P2 velocities, 1e-6 of the shear); water's
    stress is a pressure (zero deviator to 1e-8 of the pressure)."""
    a = _column_step(material, axisymmetric, "clarabel")
    b = _column_step(material, axisymmetric, "cvxpy")
    scale = np.abs(b.du).max()
    assert scale > 0
    assert np.abs(a.du - b.du).max() < 1e-6 * scale
    assert np.abs(a.plastic_multiplier - b.plastic_multiplier).max() \
        < 1e-5 * np.abs(b.plastic_multiplier).max()
    from skfem import MeshTri
    mesh = MeshTri.init_tensor(np.linspace(0.0, 0.2, 5), np.linspace(0.0, 0.4, 9))
    disc = discretise(mesh, "axisymmetric" if axisymmetric else "plane")
    ops = dynamic_operators(disc, RHO, ThetaMethod(0.01, 1.0, 1.0))
    strain = (ops.B @ a.du).reshape(-1, 4) / disc.weights[:, None]   # (ex, ey, et, gxy)
    volume = strain[:, 0] + strain[:, 1] + (strain[:, 2] if axisymmetric else 0.0)
    assert np.abs(volume).max() < 1e-6 * np.abs(strain).max()
    if material.mu == 0 and material.tau_y == 0:
        s = a.sigma
        rows = (VonMisesField if axisymmetric else TrescaField).PRESSURE_ROWS
        assert np.abs(s @ rows.T).max() < 1e-8 * np.abs(s[:, :2]).max()


def test_bad_input_is_refused_naming_the_parameter():
    for bad in (-1.0, float("nan"), "1", None):
        with pytest.raises(ValueError, match="mu"):
            NewtonianFluid(mu=bad)
        with pytest.raises(ValueError, match="mu"):
            BinghamFluid(tau_y=10.0, mu=bad)
    for bad in (0.0, -1.0, float("inf")):
        with pytest.raises(ValueError, match="tau_y"):
            BinghamFluid(tau_y=bad, mu=1.0)
    with pytest.raises(ValueError, match="cone radii"):
        TrescaField([1.0, -1e-9])


def test_a_fluid_has_a_toml_form_whose_bad_values_name_the_field():
    from pfem_skfem.scene.files import MATERIAL
    assert {"NewtonianFluid", "BinghamFluid", "NewtonianFluidAxisymmetric",
            "BinghamFluidAxisymmetric"} <= set(MATERIAL.specs)


def test_a_pfem_dam_break_is_density_invariant_bit_for_bit():
    """Three PFEM steps of the released column (inviscid, and water's viscosity with rho):
    rho x 2 (mu x 2) moves the particles the same, bit for bit."""
    from pfem_skfem.drivers import pfem_loop
    from verification.dam_break import DamBreak

    for mu in (0.0, 1e-3):
        x = []
        for k in (1.0, 2.0):
            state, scene = DamBreak(0.05, 2.0, 6, steps=40, T_end=2.0, rho=k * 1000.0,
                                    mu=k * mu, g=9.81).scene()
            state, _ = pfem_loop.run(state, scene, 3)
            x.append(state.x)
        assert np.array_equal(x[0], x[1])


def test_a_fluid_region_without_a_container_is_refused_naming_it():
    from pfem_skfem.scene import Region, Scene
    water = Region(((0, 0), (1, 0), (1, 1), (0, 1)), NewtonianFluid(1e-3), 1000.0, 0.1,
                   name="water")
    with pytest.raises(ValueError, match="'water' is a fluid.*no rigid bodies"):
        Scene(regions=(water,), gravity=(0.0, -9.81))


@pytest.mark.parametrize("material, axisymmetric", [
    (NewtonianFluid(mu=0.0), False), (BinghamFluid(tau_y=200.0, mu=0.5), False),
    (NewtonianFluidAxisymmetric(mu=0.5), True)], ids=["water", "mud", "viscous water axi"])
def test_the_dual_form_states_the_fluid_step_too(material, axisymmetric):
    """The displacement (dual) form of the direct assembly, water's equality rows among its
    zero cones: the same du as the primal form (measured 1e-12 - 1.2e-7)."""
    a = _column_step(material, axisymmetric, "clarabel")
    b = _column_step(material, axisymmetric, "clarabel-dual")
    assert b.info.extra.get("form") == "dual"
    assert np.abs(a.du - b.du).max() < 1e-6 * np.abs(a.du).max()


def _pipe(ny, R=0.01, mu=1.0):
    """Water of viscosity mu falling from rest in a vertical pipe of radius R, periodic along
    the axis (one element tall, ``periodic_tie(axis=1)``), no slip at the wall, ny elements
    across, 30 implicit steps over 7.5 R^2 / nu (the slowest mode decays by 1e-11): the
    largest error of the axial velocity against Hagen-Poiseuille's, relative to its centre
    value, and the largest radial velocity likewise."""
    from skfem import MeshTri
    from pfem_skfem.discretisation.periodic import periodic_operators, periodic_tie
    from pfem_skfem.problems.nonassociated import StepStart, lagged_step
    from pfem_skfem.scene.config import PFEMConfig

    material = NewtonianFluidAxisymmetric(mu=mu)
    mesh = MeshTri.init_tensor(np.linspace(0.0, R, ny + 1), np.linspace(0.0, R / ny, 2))
    disc = discretise(mesh, "axisymmetric")
    steps, t_end = 30, 7.5 * R ** 2 * RHO / mu
    T, kept = periodic_tie(disc, 0.0, R / ny, axis=1)
    ops = periodic_operators(dynamic_operators(disc, RHO, ThetaMethod(t_end / steps, 1.0, 1.0)), T)
    f = T.T @ body_force_vector(disc, (0.0, -RHO * G))
    xy = disc.basis_u.doflocs[:, kept]
    radial = np.zeros(disc.n_u, dtype=bool)
    radial[np.concatenate([disc.basis_u.nodal_dofs[0], disc.basis_u.facet_dofs[0]])] = True
    radial = radial[kept]
    wall = np.flatnonzero(np.abs(xy[0] - R) < 1e-12)
    axis = np.flatnonzero(radial & (xy[0] < 1e-12))
    fixed = np.union1d(wall, axis)
    v = np.zeros(T.shape[1])
    sigma = np.zeros((disc.n_points, 4))
    sigma_m = np.zeros(disc.mesh.p.shape[1])
    scales = DynamicScales(RHO * G * R, G * (t_end / steps) ** 2, RHO * G)
    for _ in range(steps):
        step = lagged_step(ops, f, None, disc, material, StepStart(v, sigma, sigma_m, scales),
                           config=PFEMConfig(passes=1), stress_scale=RHO * G * R, fixed=fixed)
        v, sigma, scales = step.increment.v, step.increment.sigma, step.increment.scales
    centre = RHO * G * R ** 2 / (4 * mu)
    exact = -RHO * G * (R ** 2 - xy[0, ~radial] ** 2) / (4 * mu)
    return np.abs(v[~radial] - exact).max() / centre, np.abs(v[radial]).max() / centre


def test_hagen_poiseuille_in_a_vertical_pipe_axisymmetric():
    """u_z(r) = -rho g (R^2 - r^2) / (4 mu) is quadratic, but the weak form's integrand in
    axisymmetry (stress x strain x r) is cubic, beyond the three-point rule of the stress
    points: the profile converges, at order 2 (measured 1.3e-4 and 3.2e-5 at ny = 4, 8,
    largest on the axis), with no radial velocity (1e-9)."""
    e4, r4 = _pipe(4)
    e8, r8 = _pipe(8)
    assert e4 < 3e-4
    assert np.log2(e4 / e8) > 1.8
    assert max(r4, r8) < 1e-9


def _tank(rho_s, rho_w=RHO, c=1.0e4):
    """One step of verification/hydrostatics.py's tank (0.6 wide, water 0.2 deep) with a
    Tresca block 0.2 x 0.1 on its floor, particles 0.02 apart."""
    from verification.hydrostatics import buoyancy
    return buoyancy(0.6, 0.2, 0.2, 0.1, 5, rho_w=rho_w, rho_s=rho_s, c=c, g=G, dt=0.01)


@pytest.mark.parametrize("rho_s", [3000.0, 2000.0, RHO], ids=["heavy", "clay", "neutral"])
def test_a_block_in_a_water_tank_presses_on_the_floor_with_its_buoyant_weight(rho_s):
    """Archimedes in total stresses: no water gets under the block, so the floor under it
    carries more than its weight (1.36-2.07 times: the water on it); less the water pressure
    rho_w g H on the floor's shares there, it carries (rho_s - rho_w) g b h_b, the drawn
    block's buoyant weight (measured 7e-12 to 2.4e-11 of rho_w g b h_b; a neutral block,
    nothing), and under the water alone nothing beyond rho_w g H (7e-10 of a node's share).
    The step weighs the drawn block: an element takes the last declared region among its
    vertices' (with the majority, 20 % too much at this spacing, h = h_b / 5)."""
    r = _tank(rho_s)
    V = 0.2 * 0.1
    assert r["V"] == pytest.approx(V, rel=1e-12)
    assert abs(r["effective_force"] - (rho_s - RHO) * G * V) < 1e-8 * RHO * G * V
    assert r["water_effective"] < 1e-8
    assert r["under_over_weight"] > 1.2
    assert r["walls"] == pytest.approx((1.0, 1.0), rel=1e-6)
    assert r["still"] < 1e-3


@pytest.mark.parametrize("block_first, n", [(True, 5), (True, 10), (False, 5), (False, 10)])
def test_the_elements_of_a_two_region_step_weigh_the_particles_masses(block_first, n):
    """The tank's elements, each with its region's density, weigh what the particles carry
    (each region's density times its drawn area): exactly with the block declared first (it
    keeps the interface's particles), and with the water first but for the triangles
    spanning the block's four corners, h^2 / 2 each at most (measured h^2 and h^2 / 2). The
    majority of the vertices weighs a half-spacing layer of water with the block's density:
    (rho_s - rho_w) (2 h_b + b) h / 2 wrong, 3 % of the tank's mass at h = h_b / 5."""
    from pfem_skfem.drivers.pfem_loop import detect_domain
    from pfem_skfem.pfem.alpha_shape import triangle_areas
    from pfem_skfem.pfem.assemble import element_regions
    from verification.hydrostatics import tank_scene

    rho_s, h = 2000.0, 0.1 / n
    state, scene = tank_scene(0.6, 0.2, 0.2, 0.1, n, rho_w=RHO, rho_s=rho_s, c=1.0e4, g=G,
                              dt=0.01, block_first=block_first)
    pm = scene.config.remesher(detect_domain(state, scene.alpha))
    area = triangle_areas(pm.mesh.p.T, pm.mesh.t.T)
    rho = np.array([r.rho for r in scene.regions])
    weighed = float(np.sum(rho[element_regions(state, pm)] * area))
    corners = 0.0 if block_first else 4 * (rho_s - RHO) * h ** 2 / 2
    assert abs(weighed - state.total_mass) <= corners + 1e-12 * state.total_mass
    r = state.region[pm.particle[pm.mesh.t]]
    majority = float(np.sum(rho[np.where(r[1] == r[2], r[1], r[0])] * area))
    assert abs(majority - state.total_mass) == pytest.approx(
        (rho_s - RHO) * (2 * 0.1 + 0.2) * h / 2, rel=0.05)


def test_the_tank_with_every_density_and_c_doubled_is_the_same_step_bit_for_bit():
    a, b = _tank(2000.0), _tank(4000.0, rho_w=2 * RHO, c=2.0e4)
    assert np.array_equal(2 * a["effective_nodes"], b["effective_nodes"])


@pytest.mark.parametrize("n2", [1.0, 2.0, 4.0])
def test_the_dam_break_time_unit_follows_n2(n2):
    """Martin & Moyce's T = n t sqrt(g / a): Ritter's front z = a + 2 sqrt(g n^2 a) t runs at
    dZ/dT = 2 for every n^2 (the unit sqrt(a / 2g) of old gave 2 sqrt(n^2 / 2): 1.41 at
    n^2 = 1, which the bound 2 passed)."""
    from verification.dam_break import time_unit
    a, g = 0.05715, 9.81
    t = np.linspace(0.0, 0.1, 5)
    Z = (a + 2 * np.sqrt(g * n2 * a) * t) / a
    T = t / time_unit(a, n2, g)
    assert np.diff(Z) / np.diff(T) == pytest.approx(2.0, rel=1e-12)
    assert time_unit(a, 2.0, g) == pytest.approx(np.sqrt(a / (2 * g)), rel=1e-15)


def test_the_dam_break_of_a_square_column_has_no_table_and_says_so(tmp_path, capsys):
    """n^2 = 1 runs (quick: 8 across, 40 steps to T = 3) and checks Ritter's bound on the
    main body's front (measured 0.93 of 2 sqrt(g n^2 a)); no table is of n^2 = 1, so none is
    compared, a line says so and the JSON's reference is null: no front_time_error or
    height_time_spread is there to read as a pass. The --T-end help holds for any n^2."""
    import json
    from verification import dam_break
    out = tmp_path / "dam.json"
    assert dam_break.main(["--quick", "--no-figures", "--n2", "1", "--json", str(out)]) == 0
    assert "no experimental reference at n^2 = 1" in capsys.readouterr().out
    result = json.loads(out.read_text())
    assert result["extra"]["experimental_reference"] is None
    names = {q["name"]: q for q in result["quantities"]}
    assert not {"front_time_error", "height_time_spread", "front_positions_compared"} & set(names)
    ritter = names["front_speed_over_ritter"]
    assert ritter["pass"] and 0.5 < ritter["value"] <= 1.0
    # 8 across (Z known to h / a = 1 / 7), dT = 0.075: a window holds 15 samples, whose
    # least-squares slope of a step of h at the middle is h sum_1^7 k / (0.075 * 2 sum_1^7 k^2)
    assert ritter["tolerance"] == pytest.approx(28 / (0.075 * 280) / 7 / 2, rel=1e-12)
    assert "sqrt(a / (n^2 g))" in " ".join(dam_break.build_parser().format_help().split())
    # the domain's area changes through its steps' motions and its remeshings alone, and
    # water leaves the mesh at 8 across (a particle of it 1.6 % of the whole)
    base = result["extra"]["runs"]["base"]
    assert base["area_change_final"] == pytest.approx(
        base["area_motion"] + base["area_remeshing"], abs=1e-12)
    assert 0.015 < base["spray_max"] < 1 and base["spray_at_largest_change"] >= 0


def test_the_dam_break_takes_columns_from_square_to_four_high(capsys):
    """--n2 in [1, 4]; below (n^2 = 0.5: the quick column loses 8.7 % of its area) or above,
    a usage error naming the range."""
    from verification import dam_break
    assert dam_break.build_parser().parse_args(["--n2", "1"]).n2 == 1.0
    assert dam_break.build_parser().parse_args(["--n2", "4"]).n2 == 4.0
    for bad in ("0.5", "4.5"):
        with pytest.raises(SystemExit) as exit_:
            dam_break.build_parser().parse_args(["--n2", bad])
        assert exit_.value.code == 2
        assert "[1, 4]" in capsys.readouterr().err


def test_the_bingham_tolerance_is_the_p2_kink_bound_in_elements_across_the_sheared_layer():
    """issue 56: the tolerance of fluid_films follows B(m) = 2 c / m^2, m = z_y ny / h, c the
    worst P2 interpolation error of a jump of u'' inside an element (recomputed here), not a
    number tuned at z_y / h = 1/3: a thinner sheared layer (m = 2.7 at tau_y = 28.375) gets
    its own bound, a quarter of the elements four times the error."""
    x = np.linspace(0.0, 1.0, 4001)
    worst = 0.0
    for a in np.linspace(0.0, 1.0, 401):
        f = np.maximum(x - a, 0.0) ** 2 / 2
        nodes = np.maximum(np.array([0.0, 0.5, 1.0]) - a, 0.0) ** 2 / 2
        p2 = np.polyval(np.polyfit([0.0, 0.5, 1.0], nodes, 2), x)
        worst = max(worst, np.abs(f - p2).max())
    assert worst == pytest.approx(P2_KINK, abs=5e-5)
    assert kink_bound(1.0, 0.25, 8) == pytest.approx(2 * P2_KINK / 4)
    assert kink_bound(1.0, 0.25, 4) == pytest.approx(4 * kink_bound(1.0, 0.25, 8))
