"""The consolidation step (C.1) of a saturated soil (issue 54): bad data refused, closed
forms of the undrained, hydrostatic and axisymmetric columns, and the Terzaghi script's
checks failing when the physics breaks (a wrong permeability, a missing storage term)."""
import numpy as np
import pytest
from pytest import approx
from skfem import MeshTri

from pfem_skfem.discretisation.pressure import inflow_vector, pressure_field
from pfem_skfem.discretisation.static import (assemble_B, assemble_C, axis_dofs, body_force_vector,
                                              boundary_dofs, boundary_facets, discretise,
                                              traction_vector)
from pfem_skfem.materials import Elastic, Tresca
from pfem_skfem.problems import consolidation
from pfem_skfem.problems.consolidation import (Hydraulic, PoreState, SaturatedSoil,
                                               consolidation_increment)

ELASTIC = Elastic(1e4, 0.3)
E_OED = ELASTIC.lame_lambda + 2 * ELASTIC.shear_modulus


def confined_column(n=6, H=1.0, geometry="plane"):
    """n square elements stacked, rollers on both sides, fixed base; the top's facets."""
    h = H / n
    mesh = MeshTri.init_tensor(np.array([0.0, h]), np.linspace(0.0, H, n + 1))
    disc = discretise(mesh, geometry)
    eps = 1e-9
    fixed = np.union1d(boundary_dofs(disc, lambda x: x[1] < eps, 1),
                       boundary_dofs(disc, lambda x: (x[0] < eps) | (x[0] > h - eps), 0))
    fixed = np.union1d(fixed, axis_dofs(disc))
    top = boundary_facets(disc, lambda x: x[1] > H - eps)
    return disc, pressure_field(disc), fixed, top


@pytest.mark.parametrize("data, words", [
    (dict(k=-1.0), "k (hydraulic conductivity)"),
    (dict(k=np.nan), "k (hydraulic conductivity)"),
    (dict(k=1.0, M=0.0), "M (Biot's modulus)"),
    (dict(k=1.0, M=-5.0), "M (Biot's modulus)"),
    (dict(k=1.0, alpha=0.0), "alpha (Biot's coefficient)"),
    (dict(k=1.0, alpha=1.5), "alpha (Biot's coefficient)"),
    (dict(k=1.0, gamma_w=0.0), "gamma_w"),
    (dict(k=1.0, water_weight=(0.0, -5.0)), "water_weight"),
])
def test_bad_soil_data_is_refused_by_name(data, words):
    with pytest.raises(ValueError, match=words.replace("(", r"\(").replace(")", r"\)")):
        SaturatedSoil(None, **data)


def test_a_drained_face_must_be_on_the_boundary():
    disc, pressure, fixed, top = confined_column()
    inner = np.setdiff1d(np.arange(disc.mesh.facets.shape[1]), disc.mesh.boundary_facets())
    with pytest.raises(ValueError, match="not on the boundary"):
        Hydraulic.drained_faces(pressure, inner[:2])
    with pytest.raises(ValueError, match="not on the boundary"):
        inflow_vector(pressure, inner[:1], 1.0)
    # dofs given by hand: an interior vertex is refused before any work
    block = discretise(MeshTri.init_tensor(np.linspace(0, 1, 3), np.linspace(0, 1, 3)))
    field = pressure_field(block)
    centre = int(np.argmin(np.hypot(*(block.mesh.p - 0.5))))
    with pytest.raises(ValueError, match="drained dofs must be vertices on the boundary"):
        consolidation_increment(assemble_B(block), assemble_C(block, ELASTIC),
                                np.zeros(block.n_u), PoreState.zero(block, field),
                                SaturatedSoil(None, k=1.0), field, 1.0,
                                fixed=boundary_dofs(block, lambda x: x[1] < 1e-9, 1),
                                hydraulic=Hydraulic(((centre,), (0.0,))))


def test_a_negative_time_step_is_refused():
    disc, pressure, fixed, top = confined_column()
    with pytest.raises(ValueError, match="dt"):
        consolidation_increment(assemble_B(disc), assemble_C(disc, ELASTIC), np.zeros(disc.n_u),
                                PoreState.zero(disc, pressure), SaturatedSoil(None, k=1.0),
                                pressure, -1.0, fixed=fixed)


@pytest.mark.parametrize("geometry", ["plane", "axisymmetric"])
@pytest.mark.parametrize("skeleton", [None, Tresca(1e3)])
def test_an_undrained_confined_column_carries_the_load_in_its_water(geometry, skeleton):
    """Oedometer, incompressible constituents, every face impermeable: p = q everywhere, no
    settlement, no effective stress (closed form; with or without an inactive cone)."""
    disc, pressure, fixed, top = confined_column(geometry=geometry)
    q = 100.0
    f = traction_vector(disc, top, (0.0, -q))
    res = consolidation_increment(assemble_B(disc), assemble_C(disc, ELASTIC), f,
                                  PoreState.zero(disc, pressure), SaturatedSoil(skeleton, k=1e-8),
                                  pressure, 0.0, fixed=fixed)
    assert res.p == approx(q * np.ones(pressure.n_p), rel=1e-7)
    assert np.abs(res.du).max() < 1e-7 * q / E_OED
    assert np.abs(res.sigma).max() < 1e-6 * q


def test_storage_shares_the_load_between_water_and_skeleton():
    """1/M > 0: the undrained p = M q / (E_oed + M) (closed form, alpha = 1)."""
    disc, pressure, fixed, top = confined_column()
    q, M = 100.0, 0.5 * E_OED
    f = traction_vector(disc, top, (0.0, -q))
    res = consolidation_increment(assemble_B(disc), assemble_C(disc, ELASTIC), f,
                                  PoreState.zero(disc, pressure),
                                  SaturatedSoil(None, k=1e-8, M=M), pressure, 0.0, fixed=fixed)
    assert res.p == approx(M * q / (E_OED + M) * np.ones(pressure.n_p), rel=1e-6)


def test_gravity_keeps_hydrostatic_water_at_rest():
    """A weightless skeleton under water: p = gamma_w (H - y) with the water's weight as the
    body force stays, with no flow and no motion, whatever dt (V6)."""
    disc, pressure, fixed, top = confined_column(H=2.0)
    gw = 9.81
    soil = SaturatedSoil(None, k=1e-6, gamma_w=gw, water_weight=(0.0, -gw))
    p_n = gw * (2.0 - pressure.basis.doflocs[1])
    f = body_force_vector(disc, (0.0, -gw))
    for dt in (0.0, 1.0, 1e4):
        res = consolidation_increment(assemble_B(disc), assemble_C(disc, ELASTIC), f,
                                      PoreState(np.zeros((disc.n_points, 4)), p_n), soil,
                                      pressure, dt, fixed=fixed,
                                      hydraulic=Hydraulic.drained_faces(pressure, top))
        assert res.p == approx(p_n, abs=1e-7 * gw)
        assert np.abs(res.flux).max() < 1e-7 * soil.k
        assert np.abs(res.du).max() < 1e-7 * gw / E_OED


def test_inflow_is_the_mass_balance_of_the_step():
    """Water let in through the base of a drained column in one step: with the skeleton at
    rest (undrained loading absent) the mass balance says the outflow at the top equals the
    inflow, and the steady p is linear, q_in gamma_w / k per unit height (Darcy)."""
    disc, pressure, fixed, top = confined_column(H=1.0)
    base = boundary_facets(disc, lambda x: x[1] < 1e-9)
    k, gw, q_in = 1e-5, 9.81, 2e-6
    soil = SaturatedSoil(None, k=k, gamma_w=gw)
    res = consolidation_increment(assemble_B(disc), assemble_C(disc, ELASTIC), np.zeros(disc.n_u),
                                  PoreState.zero(disc, pressure), soil, pressure, 1e9,
                                  fixed=fixed, hydraulic=Hydraulic.drained_faces(
                                      pressure, top, inflow=inflow_vector(pressure, base, q_in)))
    y = pressure.basis.doflocs[1]
    assert res.p == approx(q_in * gw / k * (1.0 - y), rel=1e-6, abs=1e-9 * q_in * gw / k)
    assert res.flux[:, 1] == approx(q_in, rel=1e-6)


@pytest.mark.xdist_group("consolidation")
def test_the_quick_run_passes_and_reports_its_studies(quick_run):
    report, _ = quick_run("consolidation")
    assert report.passed
    rows = report.tables["oscillation"]["rows"]
    # below the limit dt ~ h^2 / (6 c_v) the early pressures overshoot p0 (Vermeer &
    # Verruijt 1981); well above it they do not
    assert rows[0][1] > 1.01 and rows[-1][1] < 1 + 1e-6


def _terzaghi_errors(*extra):
    """max |U - series| and max |p_base / p0 - series| of the script's quick column to T_v = 1."""
    from verification import consolidation as script
    args = script.build_parser().parse_args(["--quick", *extra])
    result = script.consolidate(script.column(args.n, args.H), args, script.schedule(args.dTv, 1))
    return script.report_errors(result, args)


def test_a_wrong_permeability_moves_U_off_terzaghi(monkeypatch):
    """Darcy's term with twice the permeability: U(T_v) leaves the script's band of 0.005."""
    assert max(_terzaghi_errors()) <= 0.005
    monkeypatch.setattr(SaturatedSoil, "k_over_gamma_w", property(lambda s: 2 * s.k / s.gamma_w))
    assert _terzaghi_errors()[0] > 0.005


def test_a_missing_storage_term_moves_U_off_terzaghi(monkeypatch):
    """1/M = 1/E_oed: Terzaghi with c_v = (k / gamma_w) / (1/M + 1/E_oed) and p0 = q / 2 holds
    to 0.005; with the storage term dropped from the step it does not."""
    storage = ("--M-inv", f"{1 / E_OED!r}")
    assert max(_terzaghi_errors(*storage)) <= 0.005
    real = consolidation.SaturatedSoil.__init__

    def no_storage(self, *a, **kw):
        real(self, *a, **{**kw, "M": np.inf})
    monkeypatch.setattr(consolidation.SaturatedSoil, "__init__", no_storage)
    assert min(_terzaghi_errors(*storage)) > 0.005


# -- the pore pressure as a term of the dynamic step (4.23) ---------------------------------
def _dynamic_column(dt, theta1=1.0, geometry="plane"):
    from pfem_skfem.discretisation import ThetaMethod, dynamic_operators
    disc, pressure, fixed, top = confined_column(geometry=geometry)
    ops = dynamic_operators(disc, 2.0, ThetaMethod(dt, theta1, 1.0), ELASTIC)
    return disc, pressure, fixed, top, ops


@pytest.mark.parametrize("geometry", ["plane", "axisymmetric"])
@pytest.mark.parametrize("solver", ["cvxpy", "clarabel", "clarabel-dual"])
def test_a_sudden_undrained_load_on_a_confined_column_moves_nothing(solver, geometry):
    """k = 0, incompressible constituents, every face impermeable: whatever the inertia (a
    step of 1e-4 s), the column cannot move; its water carries the load, p = q (closed form)."""
    from pfem_skfem.problems.dynamic import dynamic_increment
    from pfem_skfem.problems.pore_term import PorePressureTerm
    disc, pressure, fixed, top, ops = _dynamic_column(1e-4, geometry=geometry)
    q, criterion = 100.0, Tresca(1e4)
    f = traction_vector(disc, top, (0.0, -q))
    soil = SaturatedSoil(criterion, k=0.0)
    inc = dynamic_increment(ops, f, f, np.zeros((disc.n_points, 4)), np.zeros(disc.n_u),
                            criterion, fixed=fixed, solver=solver,
                            terms=[PorePressureTerm(soil, pressure, np.zeros(pressure.n_p))])
    assert inc.parts["pore_pressure"] == approx(q * np.ones(pressure.n_p), rel=1e-6)
    assert np.abs(inc.du).max() < 1e-6 * q / E_OED


@pytest.mark.parametrize("solver", ["cvxpy", "clarabel", "clarabel-dual"])
def test_the_dynamic_step_at_consolidation_times_is_the_static_one(solver):
    """Steps of T_v = 0.01 (dt about 730 s, inertia 1e-10 of the stiffness): the dynamic step
    with the pore-pressure term gives the consolidation step (C.1), verified against
    Terzaghi, to 1e-8 (p, du, sigma') over three steps."""
    from pfem_skfem.problems.dynamic import dynamic_increment
    from pfem_skfem.problems.pore_term import PorePressureTerm
    criterion = Tresca(1e4)
    soil = SaturatedSoil(criterion, k=1e-8)
    dt = 0.01 / soil.consolidation_coefficient(ELASTIC)
    disc, pressure, fixed, top, ops = _dynamic_column(dt)
    q = 100.0
    f = traction_vector(disc, top, (0.0, -q))
    hydraulic = Hydraulic.drained_faces(pressure, top)
    static = PoreState.zero(disc, pressure)
    sigma, p, v = static.sigma, static.p, np.zeros(disc.n_u)
    for _ in range(3):
        inc = dynamic_increment(ops, f, f, sigma, v, criterion, fixed=fixed, solver=solver,
                                terms=[PorePressureTerm(soil, pressure, p, hydraulic)])
        static = consolidation_increment(ops.B, ops.C, f, static, soil, pressure, dt,
                                         fixed=fixed, hydraulic=hydraulic)
        sigma, p, v = inc.sigma, inc.parts["pore_pressure"], inc.v
        assert p == approx(static.p, abs=1e-8 * q)
        assert inc.du == approx(static.du, abs=1e-8 * np.abs(static.du).max())
        assert sigma == approx(static.sigma, abs=1e-8 * q)
    assert 0 < p.max() < q                          # it consolidates


def test_the_pore_pressure_term_refuses_bad_data_before_any_work():
    from pfem_skfem.problems.dynamic import dynamic_increment
    from pfem_skfem.problems.pore_term import PorePressureTerm
    disc, pressure, fixed, top, ops = _dynamic_column(1.0, theta1=0.5)
    soil = SaturatedSoil(Tresca(1e4), k=1e-8)
    with pytest.raises(ValueError, match="p_n"):
        PorePressureTerm(soil, pressure, np.zeros(pressure.n_p + 1))
    z = np.zeros(disc.n_u)
    with pytest.raises(ValueError, match="theta1 = 1"):
        dynamic_increment(ops, z, z, np.zeros((disc.n_points, 4)), z, Tresca(1e4), fixed=fixed,
                          terms=[PorePressureTerm(soil, pressure, np.zeros(pressure.n_p))])


def _undrained_compression(criterion, increments=12, c=10.0):
    """Plane-strain compression of an undrained unit block (k = 0, dt = 0, alpha = 1, 1/M = 0;
    top shortened 2e-3 an increment, sides free): the top's load and the mean p after each."""
    disc = discretise(MeshTri.init_tensor(np.linspace(0, 1, 3), np.linspace(0, 1, 3)))
    pressure, eps = pressure_field(disc), 1e-9
    fixed = np.union1d(boundary_dofs(disc, lambda x: x[1] < eps, 1),
                       boundary_dofs(disc, lambda x: (x[1] < eps) & (x[0] < eps), 0))
    top = boundary_dofs(disc, lambda x: x[1] > 1 - eps, 1)
    B, C = assemble_B(disc), assemble_C(disc, ELASTIC)
    state, load, p = PoreState.zero(disc, pressure), [], []
    for _ in range(increments):
        state = consolidation_increment(B, C, np.zeros(disc.n_u), state,
                                        SaturatedSoil(criterion, k=0.0), pressure, 0.0,
                                        fixed=fixed, prescribed=(top, -2e-3 * np.ones(top.size)))
        load.append(-state.reactions[top].sum())
        p.append(state.p.mean())
    return np.array(load), np.array(p)


def test_undrained_tresca_fails_at_twice_its_strength():
    """Tresca in effective stress (c' = s_u): undrained plane-strain compression carries
    2 s_u and no more (the closed form), increment after increment."""
    load, _ = _undrained_compression(Tresca(10.0))
    assert load == approx(20.0 * np.ones(load.size), rel=1e-6)


def test_undrained_associated_mohr_coulomb_never_fails():
    """The pitfall of an associated cone: Mohr-Coulomb phi' = 30 dilates as it yields; the
    undrained block cannot, so its pore pressure falls (suction), its effective mean stress
    rises and its load grows without bound: beyond four times its drained unconfined
    strength 2 c cos(phi) / (1 - sin(phi)) after 12 increments, still rising."""
    from pfem_skfem.materials import MohrCoulomb
    load, p = _undrained_compression(MohrCoulomb(10.0, 30.0))
    drained = 2 * 10.0 * np.cos(np.radians(30)) / (1 - np.sin(np.radians(30)))
    assert load[-1] > 4 * drained and np.all(np.diff(load) > 0.1 * drained)
    assert p[-1] < 0


def test_an_undrained_elastic_block_is_incompressible_with_the_skeleton_s_shear_modulus():
    """Elastic skeleton, undrained, plane strain, shortened by eps: the homogeneous answer
    (in the element space, so exact) has no volume change, sigma_v = -4 G eps (the lateral
    total stress zero) and p = 2 G eps (+ the skeleton's mean, nil): to 1e-6."""
    load, p = _undrained_compression(None, increments=1)
    G, eps = ELASTIC.shear_modulus, 2e-3
    assert load[0] == approx(4 * G * eps, rel=1e-6)
    assert p[0] == approx(2 * G * eps, rel=1e-6)


@pytest.mark.parametrize("criterion", [Tresca(10.0), None], ids=["tresca", "elastic"])
def test_a_drained_step_is_the_static_step(criterion):
    """Every vertex drained (p = 0): (C.1) is the static elastoplastic step (3.45), its
    stresses and reactions over three increments of plane-strain compression to 1e-6."""
    from pfem_skfem.problems.static import static_increment
    disc = discretise(MeshTri.init_tensor(np.linspace(0, 1, 3), np.linspace(0, 1, 2)))
    pressure, eps = pressure_field(disc), 1e-9
    assert np.isin(np.arange(pressure.n_p), disc.mesh.facets[:, disc.mesh.boundary_facets()]).all()
    fixed = np.union1d(boundary_dofs(disc, lambda x: x[1] < eps, 1),
                       boundary_dofs(disc, lambda x: (x[1] < eps) & (x[0] < eps), 0))
    top = boundary_dofs(disc, lambda x: x[1] > 1 - eps, 1)
    B, C = assemble_B(disc), assemble_C(disc, ELASTIC)
    drained = Hydraulic.drained_faces(pressure, disc.mesh.boundary_facets())
    state = PoreState.zero(disc, pressure)
    sigma = state.sigma
    for _ in range(3):
        motion = (top, -1e-3 * np.ones(top.size))
        state = consolidation_increment(B, C, np.zeros(disc.n_u), state,
                                        SaturatedSoil(criterion, k=1e-8), pressure, 1.0,
                                        fixed=fixed, prescribed=motion, hydraulic=drained)
        ref = static_increment(B, C, np.zeros(disc.n_u), sigma, criterion or Tresca(1e6),
                               fixed=fixed, prescribed=motion)
        sigma = ref.sigma
        assert state.sigma == approx(ref.sigma, abs=1e-6 * np.abs(ref.sigma).max())
        assert state.reactions == approx(ref.reactions, abs=1e-6 * np.abs(ref.reactions).max())
        assert np.abs(state.p).max() < 1e-9 * np.abs(ref.sigma).max()


def test_the_undrained_references_hold_for_a_compressible_fluid():
    """``consolidation --M-inv`` away from 0 (the option audit): the first step of the strip
    load matches the P2/P1 mixed solve with the storage block M_p / M (1e-5, as at 1/M = 0),
    and Skempton's B and nu_u go from (1, 1/2) at 1/M = 0 to (0, nu') as 1/M grows."""
    from verification import consolidation as script
    args = script.build_parser().parse_args(["--quick", "--M-inv", "1e-4"])
    du_err, p_err = script.undrained_strip(args)
    assert du_err <= 1e-5 and p_err <= 1e-5
    B, nu_u = script.undrained_moduli(args)
    K = args.E / (3 * (1 - 2 * args.nu))
    assert B == approx(1e4 / (K + 1e4), rel=1e-12)                  # M / (K + M)
    assert args.nu < nu_u < 0.5
    assert script.undrained_moduli(script.build_parser().parse_args(["--quick"])) == (1.0, 0.5)
    soft = script.build_parser().parse_args(["--quick", "--M-inv", "1e6"])
    assert script.undrained_moduli(soft)[0] < 1e-9
    assert script.undrained_moduli(soft)[1] == approx(soft.nu, abs=1e-6)
