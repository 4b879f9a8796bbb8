"""The direct Clarabel assembly of (4.23)+(5.12) against the cvxpy statement (the reference)."""
import numpy as np
import pytest
from skfem import MeshTri

from pfem_skfem.materials import Elastic, Tresca, TrescaField
from pfem_skfem.operators import boundary_dofs, discretise
from pfem_skfem.operators_dynamic import gravity_vector
from pfem_skfem.problems.contact import (RigidSegment, potential_contacts, resultants,
                                         with_friction_bound)
from pfem_skfem.problems.dynamic import ThetaMethod, dynamic_increment, dynamic_operators

G = 9.8


@pytest.fixture(scope="module")
def block():
    return discretise(MeshTri.init_tensor(np.linspace(0, 1, 5), np.linspace(0, 0.5, 3)))


def both(*args, **kwargs):
    return (dynamic_increment(*args, **kwargs),
            dynamic_increment(*args, backend="clarabel", **kwargs))


def close(a, b, tol=1e-5):
    return np.abs(a - b).max() <= tol * max(np.abs(a).max(), 1e-300)


@pytest.mark.parametrize("elastic", [None, Elastic(1e3, 0.3)])
@pytest.mark.parametrize("theta1, theta2", [(1.0, 1.0), (0.5, 0.5)])
def test_free_fall_is_exact(block, elastic, theta1, theta2):
    dt = 0.1
    ops = dynamic_operators(block, 2.0, ThetaMethod(dt, theta1, theta2), elastic)
    f = gravity_vector(block, 2.0, G)
    res = dynamic_increment(ops, f, f, np.zeros((block.n_points, 4)), np.zeros(block.n_u),
                            Tresca(5.0), backend="clarabel")
    assert np.allclose(res.du[1::2], -G * dt ** 2 * theta2, rtol=1e-6)
    assert np.abs(res.du[0::2]).max() <= 1e-6 * G * dt ** 2


def test_kkt_and_agreement_with_cvxpy_elastoplastic_with_supports_and_prescribed(block):
    theta = ThetaMethod(0.05, 1.0, 0.5)
    ops = dynamic_operators(block, 2.0, theta, Elastic(1e3, 0.3))
    base = lambda x: x[1] < 1e-9                                    # noqa: E731
    fixed = boundary_dofs(block, base, 0)
    P = boundary_dofs(block, base, 1)
    rng = np.random.default_rng(3)
    v_n = 0.1 * rng.standard_normal(block.n_u)
    v_n[fixed] = 0.0
    sigma_n = rng.standard_normal((block.n_points, 4))
    f = gravity_vector(block, 2.0, G)
    du_P = np.full(P.size, 1e-3)
    ref, res = both(ops, f, f, sigma_n, v_n, Tresca(6.0), fixed=fixed, prescribed=P,
                    du_prescribed=du_P)
    assert res.info.status == "optimal"
    # an elastoplastic step is unique: stresses, increments, multipliers agree
    for name in ("du", "sigma", "r", "reactions"):
        assert close(getattr(ref, name), getattr(res, name)), name
    assert np.allclose(res.du[P], du_P)
    lhs = theta.dt ** 2 * ops.D @ res.r
    rhs = ops.A @ (res.du - theta.dt * v_n)
    assert np.abs(lhs - rhs).max() <= 1e-6 * np.abs(rhs).max()


@pytest.mark.parametrize("bound", [False, True])
def test_sliding_rigid_plastic_block_with_contact_agrees_with_cvxpy(block, bound):
    ops = dynamic_operators(block, 2.0, ThetaMethod(0.05, 1.0, 1.0), None)
    f = gravity_vector(block, 2.0, G)
    floor = RigidSegment((-5.0, 0.0), (5.0, 0.0), mu=0.3)
    contacts = potential_contacts(block, [floor], 0.05)
    if bound:
        contacts = with_friction_bound(contacts, np.full(contacts.size, 0.5))
    v_n = np.zeros(block.n_u)
    v_n[0::2] = 2.0
    k = TrescaField(np.full(block.n_points, 50.0))
    ref, res = both(ops, f, f, np.zeros((block.n_points, 4)), v_n, k, contacts=contacts)
    assert close(ref.du, res.du) and close(ref.r, res.r)
    # the resultant contact force (the rigid block's m a) is unique even where p, q are not
    assert close(resultants(contacts, ref.p, ref.q), resultants(contacts, res.p, res.q))
    assert np.all(res.p >= -1e-9 * np.abs(res.p).max())
    assert np.all(np.abs(res.q) <= (0.5 if bound else 0.3 * res.p) + 1e-6)


def test_unsupported_options_are_refused(block):
    ops = dynamic_operators(block, 2.0, ThetaMethod(0.05), Elastic(1e3, 0.3))
    z = np.zeros(block.n_u)
    with pytest.raises(ValueError, match="backend"):
        dynamic_increment(ops, z, z, np.zeros((block.n_points, 4)), z, Tresca(1.0),
                          backend="mosek")
    with pytest.raises(ValueError, match="quad_form"):
        dynamic_increment(ops, z, z, np.zeros((block.n_points, 4)), z, None, backend="clarabel")
