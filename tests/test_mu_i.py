"""The mu(I) rheology (pfem_skfem.materials.rate) and the steady inclined-plane flow.

Facts checked: mu(I) is mu_s at I = 0, half-way at I_0 and tends to mu_2; with
mu_2 = mu_s it is the rate-independent zero-dilation Mohr-Coulomb of sin(phi) = mu_s to
solver tolerance (both lags); the viscous stress of the conic step obeys the Bingham
relation R(sigma) = k/2 + eta gamma_dot at flowing points (KKT) and the cvxpy and direct
Clarabel statements agree; the periodic tie pairs the two ends' dofs; a factor of two
on both densities leaves the flow bit-identical; the inclined plane at a small size
meets Bagnold's profile to 6 % (looser than the script's 3 % at its --quick size) and a
layer below atan(mu_s) stops; the layer's u / u_s does not depend on I_0 (the step's error
depends on the slope through J = I / I_0 alone), and the script's --ny rule (resolution)
reproduces the measured profile errors it was fitted to, keeps the default --quick size at
25 and 28 deg and raises it toward atan(mu_2), where beyond 32 elements it refuses.
"""
import numpy as np
import pytest

from pfem_skfem.materials import MuIRheology, ZeroDilationMohrCoulomb
from pfem_skfem.discretisation.periodic import periodic_operators, periodic_tie
from pfem_skfem.drivers.strip import layer, strip_flow
from verification import inclined_plane_flow as ipf
from verification.inclined_plane_flow import bagnold_velocity, profile_error, time_unit

D, RHO_S, PHI, G = 0.53e-3, 2450.0, 0.6, 9.81
H = 20 * D
LAW = dict(mu_s=0.38, mu_2=0.64, I_0=0.279, d=D, phi=PHI, g=G)


def flow(theta, h, material, *, phi, **options):
    """The periodic layer of solid fraction phi (density phi rho_s)."""
    return strip_flow(theta, h, material, phi * material.rho_s, **options)


def test_friction_law_limits():
    m = MuIRheology()
    assert m.friction(0.0) == m.mu_s
    assert m.friction(m.I_0) == pytest.approx((m.mu_s + m.mu_2) / 2, rel=1e-15)
    assert m.friction(1e12) == pytest.approx(m.mu_2, rel=1e-10)


def test_viscosity_is_the_rate_part_of_the_friction():
    """eta gamma_dot = (mu(I) - mu_s) p at any rate and pressure above p_min."""
    m = MuIRheology()
    p = np.array([10.0, 100.0, 1000.0])
    rate = np.array([0.0, 5.0, 400.0])
    eta = m.viscosity(-p, 1.0, rate)
    mu = m.friction(m.inertial_number(rate, -p))
    np.testing.assert_allclose(eta * rate, (mu - m.mu_s) * p, rtol=1e-13)
    assert np.all(eta > 0)


@pytest.mark.parametrize("kwargs, word", [
    (dict(mu_s=0.0), "mu_s"), (dict(mu_2=0.3), "mu_2"), (dict(I_0=-1.0), "I_0"),
    (dict(d=0.0), "d"), (dict(rho_s=np.nan), "rho_s"), (dict(p_min=0.0), "p_min"),
    (dict(lag="explicit"), "lag")])
def test_bad_parameters_are_named(kwargs, word):
    with pytest.raises(ValueError, match=word):
        MuIRheology(**kwargs)


def _layer_run(material, theta=25.0, steps=6, ny=4, rho=PHI * RHO_S, solver="clarabel"):
    """A few steps of the periodic layer from rest (velocities of the x = 0 end)."""
    m = material
    t_end = steps * 0.02
    return flow(theta, H, m, ny=ny, steps=steps, t_end=t_end, phi=rho / m.rho_s, g=G,
                passes=2, solver=solver)


@pytest.mark.parametrize("lag", ["viscosity", "friction"])
def test_rate_independent_limit(lag):
    """mu_2 = mu_s: the zero-dilation Mohr-Coulomb of sin(phi) = mu_s, c = 0 (an
    accelerating layer, theta above atan(mu_s)); mu_2 = mu_s (1 + 1e-6): within 1e-5."""
    phi = np.degrees(np.arcsin(0.38))

    class Reference(ZeroDilationMohrCoulomb):        # the same law, rate-independent
        rho_s = RHO_S

    ref = _layer_run(Reference(c=0.0, phi=phi))
    same = _layer_run(MuIRheology(mu_s=0.38, mu_2=0.38, lag=lag))
    near = _layer_run(MuIRheology(mu_s=0.38, mu_2=0.38 * (1 + 1e-6), lag=lag))
    scale = np.abs(ref["u"]).max()
    assert scale > 0.05                                   # it flows
    assert np.abs(same["u"] - ref["u"]).max() < 1e-8 * scale
    assert np.abs(near["u"] - ref["u"]).max() < 1e-5 * scale


def _one_viscous_step(solver, lag="viscosity"):
    """One step of the layer at theta = 25 from a Bagnold-like profile, with its data."""
    from pfem_skfem.discretisation.fields import plastic_strain_increment, vertex_to_points
    from pfem_skfem.discretisation.static import body_force_vector
    from pfem_skfem.discretisation import ThetaMethod, dynamic_operators
    from pfem_skfem.problems.dynamic import dynamic_increment
    from pfem_skfem.problems.step_terms import step_terms

    m = MuIRheology(lag=lag)
    ny, rho, th = 4, PHI * RHO_S, np.radians(25.0)
    disc = layer(H, ny)
    T, kept = periodic_tie(disc, 0.0, H / ny)
    ops = periodic_operators(dynamic_operators(disc, rho, ThetaMethod(0.01)), T)
    f = T.T @ body_force_vector(disc, (rho * G * np.sin(th), -rho * G * np.cos(th)))
    xy = disc.basis_u.doflocs[:, kept]
    along = np.isin(kept, np.concatenate([disc.basis_u.nodal_dofs[0],
                                          disc.basis_u.facet_dofs[0]]))
    v = np.where(along, bagnold_velocity(xy[1], H, 25.0, **LAW), 0.0)
    base = np.flatnonzero(np.abs(xy[1]) < 1e-12)
    sm = vertex_to_points(disc, -rho * G * np.cos(th) * (H - disc.mesh.p[1]))
    scale = rho * G * H
    rate = plastic_strain_increment(disc, ops.B, v)
    viscous = m.viscous(sm, scale, rate, disc.weights)
    cone = m.cone(sm, scale, shear_rate=rate)
    inc = dynamic_increment(ops, f, f, np.zeros((disc.n_points, 4)), v, cone, fixed=base,
                            terms=step_terms(viscous=viscous), solver=solver)
    return disc, ops, inc, cone, viscous, sm, scale


def test_viscous_step_obeys_the_bingham_relation():
    """KKT of the viscous term: at a flowing point R(sigma) = k/2 + eta gamma_dot."""
    from pfem_skfem.discretisation.fields import plastic_strain_increment

    disc, ops, inc, cone, viscous, _, _ = _one_viscous_step("clarabel")
    rate = plastic_strain_increment(disc, ops.B, inc.du) / ops.theta.dt
    s = inc.sigma
    R = np.hypot((s[:, 0] - s[:, 1]) / 2, s[:, 3])
    flowing = rate > 1e-3 * rate.max()
    assert flowing.sum() > disc.n_points // 2
    expected = cone.k / 2 + viscous.eta * rate
    np.testing.assert_allclose(R[flowing], expected[flowing], rtol=1e-5)


def test_implicit_step_has_the_friction_of_its_own_rate():
    """KKT of the exponential-cone term: at a flowing point R(sigma) = mu(I) p with I from
    the step's own shear rate and the frozen pressure (no lag in the rate)."""
    from pfem_skfem.discretisation.fields import plastic_strain_increment

    disc, ops, inc, cone, _, sm, scale = _one_viscous_step("clarabel", "implicit")
    m = MuIRheology(lag="implicit")
    rate = plastic_strain_increment(disc, ops.B, inc.du) / ops.theta.dt
    s = inc.sigma
    R = np.hypot((s[:, 0] - s[:, 1]) / 2, s[:, 3])
    flowing = rate > 1e-3 * rate.max()
    assert flowing.sum() > disc.n_points // 2
    expected = m.friction(m.inertial_number(rate, sm, scale)) * (-sm)
    np.testing.assert_allclose(R[flowing], expected[flowing], rtol=1e-4)


@pytest.mark.parametrize("form", ["primal", "dual"])
@pytest.mark.parametrize("lag", ["viscosity", "implicit"])
def test_rate_step_cvxpy_and_direct_agree(lag, form):
    """Either form of the direct assembly; the implicit term's exponential cones are not
    self-dual: its step is stated in the primal form whatever the solver's form says."""
    solver = "clarabel-dual" if form == "dual" else "clarabel"
    _, _, a, _, _, _, _ = _one_viscous_step(solver, lag)
    _, _, b, _, _, _, _ = _one_viscous_step("cvxpy", lag)
    stated = "dual" if form == "dual" and lag == "viscosity" else "primal"
    assert a.info.extra.get("form", "primal") == stated
    tol = 1e-6 if lag == "viscosity" else 1e-5    # exponential cones: measured 1.4e-6
    assert np.abs(a.du - b.du).max() < tol * np.abs(a.du).max()
    assert np.abs(a.sigma - b.sigma).max() < tol * np.abs(a.sigma).max()


def test_implicit_and_lagged_agree_on_steady_shear():
    """The steady shear flow of the layer (ny = 4, run to a change below 1e-5 over the last
    tenth) is one fixed point for both statements: profiles within 2e-4."""
    unit = time_unit(H, 25.0, 0.38, 0.64, 0.279, D, G)
    runs = [flow(25.0, H, MuIRheology(lag=lag), ny=4, steps=60, t_end=8 * unit, phi=PHI,
                 g=G, passes=2) for lag in ("viscosity", "implicit")]
    for r in runs:
        assert abs(r["surface"][-1] / r["surface"][-6] - 1) < 1e-5
    a, b = runs[0]["u"], runs[1]["u"]
    assert np.abs(a - b).max() < 2e-4 * np.abs(a).max()


def test_periodic_tie_pairs_the_ends():
    disc = layer(1.0, 3)
    T, kept = periodic_tie(disc, 0.0, 1.0 / 3)
    xy = disc.basis_u.doflocs
    right = np.flatnonzero(np.abs(xy[0] - 1.0 / 3) < 1e-12)
    assert T.shape == (disc.n_u, disc.n_u - right.size)
    assert np.all(T.sum(axis=1) == 1)                     # every dof is one kept dof
    assert np.all(T[kept].toarray() == np.eye(kept.size))  # kept dofs map to themselves
    partner = np.asarray(T.argmax(axis=1)).ravel()        # column of each dof
    np.testing.assert_allclose(xy[1, kept[partner[right]]], xy[1, right], atol=1e-12)
    assert np.all(xy[0, kept[partner[right]]] == 0.0)
    u_r = np.random.default_rng(0).normal(size=kept.size)
    u = T @ u_r                                           # the two ends move alike
    np.testing.assert_array_equal(u[right], u[kept[partner[right]]])
    with pytest.raises(ValueError, match="pair up"):
        periodic_tie(disc, 0.0, 0.25)


def test_density_factor_two_is_bit_identical():
    """rho and rho_s doubled: p doubles, I and the velocities do not change at all."""
    a = _layer_run(MuIRheology(), steps=4)
    b = _layer_run(MuIRheology(rho_s=2 * RHO_S), steps=4, rho=2 * PHI * RHO_S)
    np.testing.assert_array_equal(a["u"], b["u"])


def test_inclined_plane_profile_small():
    """ny = 8: surface velocity within 3 %, profile within 6 % (L2) of Bagnold's."""
    m = MuIRheology()
    unit = time_unit(H, 25.0, 0.38, 0.64, 0.279, D, G)
    r = flow(25.0, H, m, ny=8, steps=40, t_end=3 * unit, phi=PHI, g=G, passes=2)
    u_ref = bagnold_velocity(H, H, 25.0, **LAW)
    assert r["u"][-1] == pytest.approx(u_ref, rel=0.03)
    assert profile_error(r["z"], r["u"], H) < 0.06


def test_profile_depends_on_J_not_on_I():
    """I_0 ten times larger (I ten times larger at the same slope and J = I / I_0): the
    layer run over the same number of its settling times has the same u / u_s to 1e-6."""
    def shape(I_0):
        unit = time_unit(H, 31.25, 0.38, 0.64, I_0, D, G)
        r = flow(31.25, H, MuIRheology(I_0=I_0), ny=4, steps=8, t_end=unit, phi=PHI, g=G,
                 passes=2)
        return r["u"] / r["u"][-1], r["u"][-1]
    (a, ua), (b, ub) = shape(0.279), shape(2.79)
    assert ub == pytest.approx(10 * ua, rel=1e-4)
    np.testing.assert_allclose(a, b, atol=1e-6)


#: measured (60 quick steps) profile L2 errors, theta -> {ny: error}; the rule's fit
MEASURED_PROFILE = {25.0: {12: 0.0234, 16: 0.0145, 24: 0.0075},
                    28.0: {12: 0.0232, 16: 0.0141, 24: 0.0072},
                    30.0: {12: 0.0309, 16: 0.0181, 24: 0.0088},
                    31.25: {12: 0.0579, 16: 0.0303, 20: 0.0191, 24: 0.0133},
                    32.0: {32: 0.0159}}


@pytest.mark.parametrize("theta", sorted(MEASURED_PROFILE))
def test_the_ny_rule_bounds_the_measured_profile_errors(theta):
    """The fit under-predicts no measured error by more than 0.1 % (absolute) and
    over-predicts by at most 0.7 % (32 deg, extrapolated from J = 6.8 to 16)."""
    J = ipf.steepness(theta, 0.38, 0.64)
    for ny, measured in MEASURED_PROFILE[theta].items():
        predicted = ipf.predicted_profile_error(J, ny)
        assert measured - 0.001 <= predicted <= measured + 0.007, (theta, ny, predicted)


@pytest.mark.parametrize("argv, ny", [
    (["--quick"], 12), ([], 16), (["--quick", "--theta", "28"], 12),
    (["--quick", "--theta", "30"], 16), (["--quick", "--theta", "31.25"], 20),
    (["--theta", "31.25"], 20), (["--quick", "--theta", "32"], 32),
    (["--quick", "--theta-2", "31.25"], 20), (["--quick", "--theta", "31.25", "--ny", "12"], 12)])
def test_the_script_takes_its_ny_from_the_slope(argv, ny):
    assert ipf.build_parser().parse_args(argv).ny == ny


def test_the_script_refuses_a_slope_beyond_its_resolution(capsys):
    """32.04 deg takes 32 elements; 32.05 would need more, and is refused before any work."""
    assert ipf.build_parser().parse_args(["--theta", "32.04"]).ny == 32
    with pytest.raises(SystemExit) as exit_:
        ipf.build_parser().parse_args(["--quick", "--theta", "32.05"])
    assert exit_.value.code == 2 and "--theta 32.05" in capsys.readouterr().err


def test_layer_stops_below_atan_mu_s():
    """theta = 18 < atan(0.38) = 20.8: a layer set moving at Bagnold's 25-degree profile
    comes to rest, within twice the time a block would, u_s / (g (mu_s cos - sin))."""
    m = MuIRheology()
    th = np.radians(18.0)
    u0 = bagnold_velocity(H, H, 25.0, **LAW)
    t_block = u0 / (G * (0.38 * np.cos(th) - np.sin(th)))
    r = flow(18.0, H, m, ny=6, steps=40, t_end=2 * t_block, phi=PHI, g=G, passes=2,
             v0=lambda z: bagnold_velocity(z, H, 25.0, **LAW))
    assert np.abs(r["u"]).max() < 1e-6 * u0
    assert r["surface"][0] == pytest.approx(u0)


def test_pfem_column_with_mu_2_equal_mu_s_is_the_zero_dilation_column():
    """Through the PFEM engine (remeshing, contacts, passes): a small column of mu(I) with
    mu_2 = mu_s follows the zero-dilation Mohr-Coulomb column of sin(phi) = mu_s; with
    mu_2 > mu_s it moves, and more slowly (more friction at every rate)."""
    from dataclasses import replace

    from pfem_skfem.drivers.pfem_loop import run
    from verification.granular_column_plane import granular_column

    mu_s = np.sin(np.radians(31.0))
    _, scene = granular_column(1.0, 6, phi=31.0)

    def column(material):
        region = replace(scene.regions[0], material=material)
        sc = replace(scene, regions=(region,))
        state, _ = run(sc.initial_state(), sc, 5)
        return state

    ref = column(ZeroDilationMohrCoulomb(c=0.0, phi=31.0))
    same = column(MuIRheology(mu_s=mu_s, mu_2=mu_s, d=0.01, rho_s=4.0))
    rate = column(MuIRheology(mu_s=mu_s, mu_2=mu_s + 0.3, d=0.01, rho_s=4.0))
    assert np.abs(ref.x - same.x).max() < 1e-8
    speed = lambda st: np.linalg.norm(st.v, axis=1).max()         # noqa: E731
    assert 0 < speed(rate) < speed(ref)


def test_a_scene_mixing_mu_i_with_another_material_is_refused():
    from types import SimpleNamespace

    from pfem_skfem.pfem.assemble import step_material
    scene = SimpleNamespace(regions=[SimpleNamespace(material=MuIRheology()),
                                     SimpleNamespace(material=ZeroDilationMohrCoulomb())])
    with pytest.raises(ValueError, match="rate-dependent"):
        step_material(scene, None, None)
