"""Statics: the element, the operators (3.41)-(3.43), the SOCP (3.45) and limit analysis."""
import cvxpy as cp
import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spl
from skfem import MeshTri

from pfem_skfem.materials import DruckerPrager, Elastic, MohrCoulomb, Tresca
from pfem_skfem.discretisation.static import (assemble_B, assemble_C, boundary_dofs, boundary_facets,
                                              discretise, dof_coordinates, stiffness_matrix,
                                              stress_mass, traction_vector)
from pfem_skfem.problems.conic import SolverError
from pfem_skfem.problems.static import limit_analysis, static_increment
from verification import strip_footing


def unstructured_square(n=4):
    """A square [0, 1]^2 with perturbed interior nodes (not aligned with any field)."""
    m = MeshTri.init_symmetric().refined(n)
    p = m.p.copy()
    interior = np.setdiff1d(np.arange(p.shape[1]), m.boundary_nodes())
    rng = np.random.default_rng(0)
    p[:, interior] += 0.15 / 2 ** n * rng.uniform(-1, 1, (2, interior.size))
    return MeshTri(p, m.t)


def block(elastic_nu=0.3):
    """Unit block on rollers (bottom u_y = 0, left u_x = 0), loaded on top."""
    disc = discretise(unstructured_square(3))
    fixed = np.concatenate([boundary_dofs(disc, lambda x: x[1] < 1e-9, 1),
                            boundary_dofs(disc, lambda x: x[0] < 1e-9, 0)])
    top = boundary_facets(disc, lambda x: x[1] > 1 - 1e-9)
    return disc, np.unique(fixed), top


# -- element and operators ----------------------------------------------------
def test_stress_mass_is_diagonal_with_a_third_of_each_area():
    disc = discretise(unstructured_square(2))
    M = stress_mass(disc)
    off = M - sp.diags(M.diagonal())
    assert abs(off).max() < 1e-14 * M.diagonal().max()
    p, t = disc.mesh.p, disc.mesh.t
    areas = 0.5 * np.abs((p[0, t[1]] - p[0, t[0]]) * (p[1, t[2]] - p[1, t[0]])
                         - (p[0, t[2]] - p[0, t[0]]) * (p[1, t[1]] - p[1, t[0]]))
    assert np.allclose(disc.weights[disc.basis_s.element_dofs], areas / 3, rtol=1e-12)


def test_C_is_block_diagonal_4x4_per_stress_point():
    disc = discretise(unstructured_square(2))
    C = assemble_C(disc, Elastic(100.0, 0.3)).tocoo()
    assert np.all(C.row // 4 == C.col // 4)
    block0 = C.tocsr()[:4, :4].toarray()
    assert np.allclose(block0, disc.weights[0] * Elastic(100.0, 0.3).compliance())


def test_stress_shape_functions_are_one_at_their_point_zero_at_the_others():
    disc = discretise(MeshTri())
    e = disc.basis_s.elem
    X = disc.basis_s.elem.doflocs.T
    for i in range(3):
        phi, _ = e.lbasis(X, i)
        assert np.allclose(phi, np.eye(3)[i])
    # the nodes are the points of the 3-point Gauss rule (intorder=2)
    assert np.allclose(np.sort(disc.basis_s.X, axis=1), np.sort(X, axis=1))


def test_B_C_reproduce_the_standard_stiffness():
    """B^T C^-1 B is the P2 stiffness: the strain of P2 lies in the stress space."""
    disc = discretise(unstructured_square(2))
    el = Elastic(1000.0, 0.3)
    B, C = assemble_B(disc), assemble_C(disc, el)
    Cinv = sp.kron(sp.diags(1 / stress_mass(disc).diagonal()), np.linalg.inv(el.compliance()))
    K = (B.T @ Cinv @ B).toarray()
    Kref = stiffness_matrix(disc, el).toarray()
    assert np.abs(K - Kref).max() < 1e-10 * np.abs(Kref).max()


# -- the static problem (3.45) ------------------------------------------------
def test_elastic_socp_equals_standard_fe():
    """Yield surface far away: (3.45) gives scikit-fem's P2 elasticity solution."""
    disc = discretise(unstructured_square(3))
    el = Elastic(1000.0, 0.3)
    B, C = assemble_B(disc), assemble_C(disc, el)
    f = traction_vector(disc, boundary_facets(disc, lambda x: x[0] > 1 - 1e-9), (0.3, -1.0))
    left = lambda x: x[0] < 1e-9  # noqa: E731
    fixed = np.concatenate([boundary_dofs(disc, left, 0), boundary_dofs(disc, left, 1)])
    res = static_increment(B, C, f, np.zeros((disc.n_points, 4)), Tresca(1e4), fixed=fixed)
    free = np.setdiff1d(np.arange(disc.n_u), fixed)
    K = stiffness_matrix(disc, el)
    u = np.zeros(disc.n_u)
    u[free] = spl.spsolve(K[free][:, free].tocsc(), f[free])
    assert np.abs(res.du - u).max() <= 1e-6 * np.abs(u).max()
    # equilibrium holds on the free dofs and the reactions balance the load
    support = [res.reactions[boundary_dofs(disc, left, k)].sum() for k in (0, 1)]
    assert np.allclose(support, [-0.3, 1.0], rtol=1e-6)


def test_patch_test_uniform_strain_gives_uniform_stress():
    """Prescribed linear displacement on the whole boundary: exact uniform stress."""
    disc = discretise(unstructured_square(2))
    el = Elastic(200.0, 0.25)
    eps = np.array([1e-3, -4e-4, 0.0, 6e-4])          # ex, ey, ez, 2exy
    x = dof_coordinates(disc)
    u_exact = np.zeros(disc.n_u)
    u_exact[0::2] = eps[0] * x[0, 0::2] + 0.5 * eps[3] * x[1, 0::2]
    u_exact[1::2] = eps[1] * x[1, 1::2] + 0.5 * eps[3] * x[0, 1::2]
    bnd = lambda x: np.ones(x.shape[1], dtype=bool)  # noqa: E731
    P = np.unique(np.concatenate([boundary_dofs(disc, bnd, 0), boundary_dofs(disc, bnd, 1)]))
    res = static_increment(assemble_B(disc), assemble_C(disc, el), np.zeros(disc.n_u),
                           np.zeros((disc.n_points, 4)), Tresca(10.0), fixed=[],
                           prescribed=(P, u_exact[P]))
    sigma_exact = np.linalg.solve(el.compliance(), eps)
    assert np.abs(res.sigma - sigma_exact).max() <= 1e-7 * np.abs(sigma_exact).max()
    assert np.abs(res.du - u_exact).max() <= 1e-7 * np.abs(u_exact).max()


@pytest.mark.parametrize("criterion, p_collapse", [
    (Tresca(2.0), 4.0),                                                   # p = 2 Su
    (MohrCoulomb(2.0, 30.0), 2 * 2.0 * np.tan(np.radians(45 + 15))),      # 2c tan(45 + phi/2)
    (DruckerPrager.plane_strain(2.0, 30.0), 2 * 2.0 * np.tan(np.radians(60))),  # (A.17) match
])
def test_limit_analysis_of_plane_strain_compression_is_exact(criterion, p_collapse):
    """Uniform stress and the homogeneous mechanism are both in the discrete spaces."""
    disc, fixed, top = block()
    f = traction_vector(disc, top, (0.0, -1.0))
    res = limit_analysis(assemble_B(disc), f, criterion, fixed=fixed)
    assert res.load_factor == pytest.approx(p_collapse, rel=1e-6)
    # the mechanism is normalised to unit load power, and its plastic dissipation
    # sigma^T B v equals the power of the collapse load (zero duality gap)
    B = assemble_B(disc)
    assert f @ res.velocity == pytest.approx(1.0, rel=1e-6)
    assert res.sigma.ravel() @ (B @ res.velocity) == pytest.approx(res.load_factor, rel=1e-6)
    assert np.all(res.velocity[boundary_dofs(disc, lambda x: x[1] > 1 - 1e-9, 1)] < 0)


def test_displacement_control_reaches_the_collapse_load_and_no_more():
    disc, fixed, top = block()
    el, crit = Elastic(1000.0, 0.3), MohrCoulomb(1.0, 20.0)
    P = boundary_dofs(disc, lambda x: x[1] > 1 - 1e-9, 1)
    B, C = assemble_B(disc), assemble_C(disc, el)
    sigma = np.zeros((disc.n_points, 4))
    p_exact = 2 * np.tan(np.radians(45 + 10))
    loads = []
    for _ in range(8):
        res = static_increment(B, C, np.zeros(disc.n_u), sigma, crit, fixed=fixed,
                               prescribed=(P, -1e-3 * np.ones(P.size)))
        sigma = res.sigma
        loads.append(-res.reactions[P].sum())
    assert max(loads) <= p_exact * (1 + 1e-6)
    assert loads[-1] == pytest.approx(p_exact, rel=1e-6)
    assert np.all(crit.F(sigma) <= 1e-6 * p_exact)


def test_kkt_conditions_of_the_footing_increment():
    """(3.47): C ds = B du at elastic points; plastic strain along grad F, multiplier >= 0."""
    model = strip_footing.footing_model(120)
    el, crit = Elastic(1e5, 0.3), Tresca(100.0)
    B, C, disc = model["B"], assemble_C(model["disc"], el), model["disc"]
    fp = model["footing"]
    sigma = np.zeros((disc.n_points, 4))
    for _ in range(2):
        res = static_increment(B, C, np.zeros(disc.n_u), sigma, crit, fixed=model["fixed"],
                               prescribed=(fp, -0.01 * np.ones(fp.size)))
        ds, sigma = res.sigma - sigma, res.sigma
    plastic_strain = (B @ res.du - C @ ds.ravel()).reshape(-1, 4)   # integrated
    scale = np.abs(B @ res.du).max()
    ratio = crit.yield_ratio(sigma)
    elastic = ratio < 0.99
    plastic = ratio > 0.9999
    assert elastic.sum() > 10 and plastic.sum() > 10
    assert np.abs(plastic_strain[elastic]).max() < 1e-5 * scale
    # normality at plastic points: dep = dlambda * grad F, grad F = ((sx-sy), -(sx-sy), 0, 4 sxy)/r
    s = sigma[plastic]
    r = np.sqrt((s[:, 0] - s[:, 1]) ** 2 + 4 * s[:, 3] ** 2)
    grad = np.stack([(s[:, 0] - s[:, 1]) / r, -(s[:, 0] - s[:, 1]) / r, 0 * r, 4 * s[:, 3] / r], 1)
    lam = res.plastic_multiplier[plastic]
    assert np.all(res.plastic_multiplier > -1e-6 * np.abs(res.plastic_multiplier).max())
    assert np.abs(plastic_strain[plastic] - lam[:, None] * grad).max() < 1e-4 * scale
    # complementarity: the multiplier vanishes away from the yield surface
    assert np.abs(res.plastic_multiplier[elastic]).max() < 1e-5 * np.abs(lam).max()


# -- yield cones -------------------------------------------------------------
@pytest.mark.parametrize("criterion", [Tresca(1.0), MohrCoulomb(1.0, 25.0),
                                       DruckerPrager.plane_strain(1.0, 25.0),
                                       DruckerPrager.compression_cone(1.0, 25.0)])
def test_cvxpy_cone_and_numpy_yield_function_agree(criterion):
    rng = np.random.default_rng(1)
    sigma = rng.normal(0, 1.5, (40, 4))
    F = criterion.F(sigma)
    inside = F < -1e-3
    outside = F > 1e-3
    # feasibility of all the inside points together; infeasibility of each outside point
    if inside.any():
        Si = cp.Variable((inside.sum(), 4))
        p = cp.Problem(cp.Minimize(0), [Si == sigma[inside], criterion.constraint(Si)])
        p.solve(solver=cp.CLARABEL)
        assert p.status == cp.OPTIMAL
    for j in np.flatnonzero(outside)[:5]:
        Sj = cp.Variable((1, 4))
        p = cp.Problem(cp.Minimize(0), [Sj == sigma[j:j + 1], criterion.constraint(Sj)])
        p.solve(solver=cp.CLARABEL)
        assert p.status == cp.INFEASIBLE
    assert np.all(criterion.yield_ratio(sigma)[inside] < 1)


def test_mohr_coulomb_values():
    mc = MohrCoulomb(c=10.0, phi=30.0)
    # pure shear of magnitude c cos(phi) / ... : F = 2 |tau| - 2c cos(phi) at zero mean stress
    tau = 10.0 * np.cos(np.radians(30.0))
    assert mc.F([[0, 0, 0, tau]])[0] == pytest.approx(0.0, abs=1e-12)
    assert mc.yield_ratio([[0, 0, 0, tau / 2]])[0] == pytest.approx(0.5)
    assert mc.F([[-1, -1, -1, 0]])[0] < mc.F([[1, 1, 1, 0]])[0]   # compression strengthens


# -- bad input ---------------------------------------------------------------
@pytest.mark.parametrize("make, word", [
    (lambda: Elastic(0.0, 0.3), "E"), (lambda: Elastic(-1.0, 0.3), "E"),
    (lambda: Elastic(1.0, 0.5), "nu"), (lambda: Elastic(1.0, -1.0), "nu"),
    (lambda: MohrCoulomb(-1.0, 10.0), "c"), (lambda: MohrCoulomb(1.0, 90.0), "phi"),
    (lambda: MohrCoulomb(1.0, -5.0), "phi"), (lambda: Tresca(-2.0), "c"),
    (lambda: DruckerPrager(-0.1, 1.0), "alpha"),
])
def test_bad_material_parameters_raise_naming_the_parameter(make, word):
    with pytest.raises(ValueError, match=word):
        make()


def test_empty_and_degenerate_meshes_raise():
    with pytest.raises(ValueError, match="empty"):
        discretise(MeshTri(np.zeros((2, 3)), np.zeros((3, 0), dtype=int)))
    with pytest.raises(ValueError, match="degenerate"):
        discretise(MeshTri(np.array([[0.0, 1.0, 2.0, 0.0], [0.0, 0.0, 0.0, 1.0]]),
                           np.array([[0, 0], [1, 1], [2, 3]])))


def test_load_beyond_collapse_reports_infeasible():
    disc, fixed, top = block()
    f = traction_vector(disc, top, (0.0, -5.0))        # Tresca Su = 2 collapses at p = 4
    with pytest.raises(SolverError, match="infeasible") as err:
        static_increment(assemble_B(disc), assemble_C(disc, Elastic(100.0, 0.3)), f,
                         np.zeros((disc.n_points, 4)), Tresca(2.0), fixed=fixed)
    assert err.value.status == cp.INFEASIBLE


def test_tresca_field_is_mohr_coulomb_at_the_lagged_mean_stress():
    """At sigma_m of the lagged stress the Tresca field and Mohr-Coulomb coincide."""
    from pfem_skfem.materials import TrescaField, mohr_coulomb_radius
    rng = np.random.default_rng(3)
    sigma = rng.normal(-5, 2, (30, 4))
    mc = MohrCoulomb(1.0, 30.0)
    k = mohr_coulomb_radius(1.0, 30.0, 0.5 * (sigma[:, 0] + sigma[:, 1]), floor=1e-3)
    field = TrescaField(k)
    assert np.allclose(field.F(sigma), mc.F(sigma), atol=1e-12)
    # where the lagged mean stress is tensile the radius is held at the floor
    assert np.all(mohr_coulomb_radius(1.0, 30.0, [10.0], floor=0.05) == 0.05)


def test_davis_reduction_for_zero_dilation():
    from pfem_skfem.materials import davis
    c_star, phi_star = davis(10.0, 30.0, 0.0)
    assert np.tan(np.radians(phi_star)) == pytest.approx(np.sin(np.radians(30.0)))
    assert c_star == pytest.approx(10.0 * np.cos(np.radians(30.0)))
    assert davis(10.0, 30.0, 30.0) == pytest.approx((10.0, 30.0))   # associated: unchanged
    with pytest.raises(ValueError, match="psi"):
        davis(10.0, 30.0, 35.0)


def test_prescribed_dofs_in_any_order_keep_their_values():
    """The prescribed values follow the order of the prescribed dofs given."""
    disc, fixed, top = block()
    P = boundary_dofs(disc, lambda x: x[1] > 1 - 1e-9, 1)
    B, C = assemble_B(disc), assemble_C(disc, Elastic(100.0, 0.3))
    values = -1e-3 * (1 + disc.basis_u.doflocs[0, P])           # a tilted platen
    order = np.random.default_rng(0).permutation(P.size)
    kw = dict(fixed=fixed, prescribed=(P, values))
    a = static_increment(B, C, np.zeros(disc.n_u), np.zeros((disc.n_points, 4)), Tresca(10.0), **kw)
    kw = dict(fixed=fixed, prescribed=(P[order], values[order]))
    b = static_increment(B, C, np.zeros(disc.n_u), np.zeros((disc.n_points, 4)), Tresca(10.0), **kw)
    assert np.allclose(a.du, b.du, rtol=1e-8, atol=1e-12)
    assert np.allclose(a.du[P], values)


def test_solver_error_survives_pickling():
    """A SolverError raised in a worker process (parallel sweeps) reaches the parent intact."""
    import pickle
    from pfem_skfem.problems.conic import SolverError
    err = pickle.loads(pickle.dumps(SolverError("step: solver status 'infeasible'", "infeasible")))
    assert isinstance(err, SolverError) and err.status == "infeasible"
    assert "infeasible" in str(err)
