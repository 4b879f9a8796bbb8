"""Dynamics (thesis Ch 4): operators (4.21), identity (4.26)-(4.27), the SOCP (4.23)."""
import numpy as np
import pytest
import scipy.sparse.linalg as spl
from skfem import MeshTri

from pfem_skfem.drivers.dynamic import integrate
from pfem_skfem.materials import Elastic, Tresca
from pfem_skfem.discretisation.meshes import triangulate_polygon
from pfem_skfem.discretisation.static import (boundary_dofs, consistent_mass, discretise,
                                              stiffness_matrix)
from pfem_skfem.discretisation.dynamic import (assemble_A, assemble_D, block_cholesky,
                                               gravity_vector, mass_matrix, r_basis)
from pfem_skfem.discretisation import ThetaMethod, dynamic_operators
from pfem_skfem.problems.dynamic import dynamic_increment

# every test of this file on one xdist worker: its module fixture is computed once
pytestmark = pytest.mark.xdist_group("test_dynamics")

G = 9.8


@pytest.fixture(scope="module")
def block():
    """An unstructured mesh of a 2 x 1 block (Triangle)."""
    mesh = triangulate_polygon([(0, 0), (2, 0), (2, 1), (0, 1)], 0.4)
    return discretise(mesh)


# -- operators -----------------------------------------------------------------
def test_mass_identity(block):
    """(4.26)-(4.27): A^T D^-1 A is the consistent mass int rho~ N_u^T N_u dV."""
    rho_tilde = 2.0 / (0.5 * 0.5)
    A, D = assemble_A(block), assemble_D(block, rho_tilde)
    mass = A.T @ spl.spsolve(D.tocsc(), A.tocsc())
    M = consistent_mass(block, rho_tilde)
    assert abs(mass - M).max() <= 1e-10 * abs(M).max()


def test_mass_identity_per_element_density(block):
    rho = 1.0 + np.random.default_rng(0).random(block.mesh.nelements)
    A, D = assemble_A(block), assemble_D(block, rho)
    mass = A.T @ spl.spsolve(D.tocsc(), A.tocsc())
    M = mass_matrix(block, rho)
    assert abs(mass - M).max() <= 1e-10 * abs(M).max()


def test_D_block_diagonal_and_factor(block):
    """D couples only the 12 r dofs of one element; G^T G = D (cone form, App A)."""
    basis = r_basis(block)
    D = assemble_D(block, 3.0, basis)
    owner = np.empty(D.shape[0], dtype=int)
    owner[basis.element_dofs] = np.arange(block.mesh.nelements)[None, :]
    coo = D.tocoo()
    big = np.abs(coo.data) > 1e-14 * np.abs(coo.data).max()
    assert np.all(owner[coo.row[big]] == owner[coo.col[big]])
    Gm = block_cholesky(D, basis)
    assert abs(Gm.T @ Gm - D).max() <= 1e-12 * abs(D).max()


def test_stiffness_from_kkt_is_standard(block):
    """Eliminating sigma from the KKT conditions gives K = B^T C^-1 B, the P2 stiffness."""
    elastic = Elastic(1e4, 0.3)
    ops = dynamic_operators(block, 1.0, ThetaMethod(0.1), elastic)
    K = stiffness_matrix(block, elastic)
    assert abs(ops.K - K).max() <= 1e-10 * abs(K).max()


# -- the SOCP (4.23) ----------------------------------------------------------
MATERIALS = {"elastic": (Elastic(1e4, 0.3), None),
             "elastoplastic": (Elastic(1e4, 0.3), Tresca(10.0)),
             "rigid-plastic": (None, Tresca(10.0))}


@pytest.mark.parametrize("material", MATERIALS)
@pytest.mark.parametrize("theta1, theta2", [(1.0, 1.0), (0.5, 0.5), (1.0, 0.5)])
def test_free_fall(block, material, theta1, theta2):
    """An unsupported body falls freely: v_N = N g dt, u_N = g dt^2 (N(N-1)/2 + N theta2)."""
    elastic, criterion = MATERIALS[material]
    dt, n, rho = 0.1, 3, 2.0
    ops = dynamic_operators(block, rho, ThetaMethod(dt, theta1, theta2), elastic)
    weight = gravity_vector(block, rho, G)
    hist = integrate(ops, lambda t: weight, n, criterion=criterion)
    uy, vy = hist.u[1::2], hist.v[1::2]
    u_exact = -G * dt ** 2 * (n * (n - 1) / 2 + n * theta2)
    assert np.allclose(uy, u_exact, rtol=1e-6, atol=0)
    assert np.allclose(vy, -n * G * dt, rtol=1e-6, atol=0)
    assert np.abs(hist.u[0::2]).max() <= 1e-6 * G * dt ** 2


@pytest.mark.parametrize("theta1, theta2", [(1.0, 0.5), (0.5, 1.0), (0.75, 0.5)])
def test_free_fall_under_a_growing_load(block, theta1, theta2):
    """A free elastic body under a load growing in time, f(t) = m g (1 + c t): the step's load
    is f at t_n + theta1 dt (ThetaMethod.load), so v_N = g dt (N + c dt (N (N - 1)/2 + N theta1))
    and each step moves dt v_n + theta2 dt^2 a_theta. With theta1 != theta2 a load weighted by
    theta2 (or by 1) misses both."""
    dt, n, rho, c = 0.1, 3, 2.0, 4.0
    th = ThetaMethod(dt, theta1, theta2)
    assert np.allclose(th.load(1.0, 3.0), 1.0 + 2.0 * theta1)
    ops = dynamic_operators(block, rho, th, Elastic(1e4, 0.3))
    weight = gravity_vector(block, rho, G)
    hist = integrate(ops, lambda t: weight * (1 + c * t), n)
    a = [-G * (1 + c * (i + theta1) * dt) for i in range(n)]      # a at t_i + theta1 dt
    v_exact = dt * np.sum(a)
    u_exact = sum(dt * dt * np.sum(a[:i]) + theta2 * dt ** 2 * a[i] for i in range(n))
    assert np.allclose(hist.v[1::2], v_exact, rtol=1e-6, atol=0)
    assert np.allclose(hist.u[1::2], u_exact, rtol=1e-6, atol=0)
    assert np.abs(hist.v[0::2]).max() <= 1e-6 * G * dt


def test_kkt_conditions(block):
    """(4.25) with the signs of (4.22): dt^2 D r = A du and B^T sigma + M~ du/dt^2 = f~."""
    elastic = Elastic(1e3, 0.3)
    theta = ThetaMethod(0.05, 1.0, 0.5)
    ops = dynamic_operators(block, 2.0, theta, elastic)
    fixed = np.union1d(boundary_dofs(block, lambda x: x[1] < 1e-9, 0),
                       boundary_dofs(block, lambda x: x[1] < 1e-9, 1))
    free = np.setdiff1d(np.arange(block.n_u), fixed)
    rng = np.random.default_rng(1)
    v_n = rng.standard_normal(block.n_u) * 0.1
    v_n[fixed] = 0.0
    sigma_n = rng.standard_normal((block.n_points, 4))
    f = gravity_vector(block, 2.0, G)
    res = dynamic_increment(ops, f, 1.5 * f, sigma_n, v_n, Tresca(8.0), fixed=fixed)
    # r = rho~ v_n / dt + r' with dt^2 D r = A du  <=>  dt^2 D r' = A (du - dt v_n)
    lhs = theta.dt ** 2 * ops.D @ res.r
    rhs = ops.A @ (res.du - theta.dt * v_n)
    assert np.abs(lhs - rhs).max() <= 1e-6 * np.abs(rhs).max()
    # (4.26) on the free dofs
    f_tilde = theta.equilibrium_rhs(f, 1.5 * f, ops.B, sigma_n) + ops.M_tilde @ v_n / theta.dt
    residual = ops.B.T @ res.sigma.ravel() + ops.M_tilde @ res.du / theta.dt ** 2 - f_tilde
    assert np.abs(residual[free]).max() <= 1e-6 * np.abs(f_tilde[free]).max()
    assert np.all(Tresca(8.0).F(res.sigma) <= 1e-6 * 8.0)


def test_prescribed_motion_drags_a_stiff_body():
    """Base moved up by u = a t^2 / 2: a stiff body follows, the supports push with m a."""
    mesh = MeshTri.init_tensor(np.linspace(0, 1, 5), np.linspace(0, 1, 5))
    disc = discretise(mesh)
    rho, a, dt, n = 1.0, 2.0, 0.1, 4
    ops = dynamic_operators(disc, rho, ThetaMethod(dt, 0.5, 0.5), Elastic(1e7, 0.3))
    base = lambda x: x[1] < 1e-9                                   # noqa: E731
    P = boundary_dofs(disc, base, 1)
    hist = integrate(ops, lambda t: np.zeros(disc.n_u), n, fixed=boundary_dofs(disc, base, 0),
                     prescribed=(P, lambda t: np.full(P.size, 0.5 * a * t ** 2)))
    t = n * dt
    assert np.allclose(hist.u[1::2], 0.5 * a * t ** 2, rtol=1e-3)
    # work of the supports = kinetic + elastic energy gained (no loads, no damping)
    assert np.isclose(hist.work[-1], hist.energy[-1], rtol=1e-6)
    assert np.isclose(hist.kinetic[-1], 0.5 * rho * 1.0 * (a * t) ** 2, rtol=1e-3)


def test_rigid_plastic_shear_flow_ends_in_rigid_rotation():
    """A free rigid-plastic block set shearing, v = (V (y - 1/2), 0), flows plastically until
    its motion is rigid. Rigid-mode momenta are conserved (B R = 0 for a rigid field R), so
    the motion ends as the rotation with the initial angular momentum: K_end / K_0 = 1/2
    (I = rho/6, L = -rho V/12 for the unit square). With theta1 = theta2 = 1/2 the
    kinetic energy lost is the plastic dissipation."""
    disc = discretise(MeshTri.init_tensor(np.linspace(0, 1, 5), np.linspace(0, 1, 5)))
    ops = dynamic_operators(disc, 2.0, ThetaMethod(0.05, 0.5, 0.5), None)
    x, y = disc.basis_u.doflocs
    v0 = np.zeros(disc.n_u)
    v0[0::2] = y[0::2] - 0.5
    hist = integrate(ops, lambda t: np.zeros(disc.n_u), 20, criterion=Tresca(1.0),
                     initial=dict(v=v0))
    K0 = hist.kinetic[0]
    rotation = np.zeros(disc.n_u)
    rotation[0::2], rotation[1::2] = -(y[0::2] - 0.5), x[1::2] - 0.5
    translation_x = np.zeros(disc.n_u)
    translation_x[0::2] = 1.0
    for mode in (rotation, translation_x):
        p0, p1 = mode @ ops.M @ v0, mode @ ops.M @ hist.v
        assert abs(p1 - p0) <= 1e-8 * np.sqrt(2 * K0 * (mode @ ops.M @ mode))
    assert np.diff(hist.kinetic).max() <= 1e-9 * K0
    assert np.abs(hist.kinetic + hist.dissipation - K0).max() <= 1e-8 * K0
    assert hist.kinetic[-1] / K0 == pytest.approx(0.5, rel=0.01)


# -- bad input ----------------------------------------------------------------
@pytest.mark.parametrize("kwargs, name", [
    (dict(dt=0.0), "dt"), (dict(dt=-0.1), "dt"), (dict(dt=np.nan), "dt"),
    (dict(dt=0.1, theta1=0.4), "theta1"), (dict(dt=0.1, theta1=1.5), "theta1"),
    (dict(dt=0.1, theta2=0.0), "theta2"), (dict(dt=0.1, theta2=1.01), "theta2"),
])
def test_bad_theta_method(kwargs, name):
    with pytest.raises(ValueError, match=name):
        ThetaMethod(**kwargs)


@pytest.mark.parametrize("rho", [0.0, -1.0, np.inf])
def test_bad_density(block, rho):
    with pytest.raises(ValueError, match="rho"):
        dynamic_operators(block, rho, ThetaMethod(0.1), Elastic(1e4, 0.3))


def test_bad_problem_options(block):
    ops = dynamic_operators(block, 1.0, ThetaMethod(0.1), None)
    zero = np.zeros(block.n_u)
    with pytest.raises(ValueError, match="criterion"):
        dynamic_increment(ops, zero, zero, np.zeros((block.n_points, 4)), zero, None)
    with pytest.raises(ValueError, match="d_form"):
        dynamic_increment(ops, zero, zero, np.zeros((block.n_points, 4)), zero, Tresca(1.0),
                          d_form="dense")
