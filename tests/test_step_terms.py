"""The step (4.23) as terms (problems/step_terms.py): a term added to the step states itself
in cvxpy and in the direct assembly, and each statement meets the term's closed form; the
static increment (3.45) states the same terms (those marked ``static``)."""
import numpy as np
import pytest
from skfem import MeshTri

from pfem_skfem.discretisation import ThetaMethod, dynamic_operators
from pfem_skfem.discretisation.static import (assemble_B, assemble_C, body_force_vector,
                                              boundary_dofs, discretise)
from pfem_skfem.materials import Elastic, Tresca
from pfem_skfem.problems.backends.standard_form import Layout
from pfem_skfem.problems.dynamic import dynamic_increment
from pfem_skfem.problems.static import static_increment
from pfem_skfem.problems.step_terms import ElasticSupport, StepTerm

RHO, G, W, H = 2.0, 9.8, 1.0, 0.5


def block_on_springs(k, dt, solver):
    """One step from rest of a rigid block (W x H, Tresca far above its stresses) standing on
    springs of stiffness k under each base node's vertical dof; nothing else holds it."""
    disc = discretise(MeshTri.init_tensor(np.linspace(0, W, 5), np.linspace(0, H, 3)))
    ops = dynamic_operators(disc, RHO, ThetaMethod(dt, 1.0, 1.0), None)
    f = body_force_vector(disc, (0.0, -RHO * G))
    base_y = boundary_dofs(disc, lambda x: x[1] < 1e-9, 1)
    base_x = boundary_dofs(disc, lambda x: x[1] < 1e-9, 0)
    springs = ElasticSupport(base_y, k)
    inc = dynamic_increment(ops, f, f, np.zeros((disc.n_points, 4)), np.zeros(disc.n_u),
                            Tresca(1e3 * RHO * G * H), fixed=base_x, terms=[springs],
                            solver=solver)
    return inc, disc, base_y


@pytest.mark.parametrize("solver", ["cvxpy", "clarabel", "clarabel-dual", "qoco"])
@pytest.mark.parametrize("dt", [0.01, 1.0])
def test_a_rigid_block_on_springs_moves_as_one_mass_on_one_spring(solver, dt):
    """Backward Euler from rest: m du / dt^2 = -m g - K du for the rigid block, so every node
    moves du = -m g / (m / dt^2 + K), K the springs' total stiffness; the springs carry
    k du each (to 1e-6). dt = 1 is nearly static (du -> -m g / K)."""
    if solver == "qoco":
        pytest.importorskip("qoco")
    k = 40.0
    inc, disc, base_y = block_on_springs(k, dt, solver)
    m, K = RHO * W * H, k * base_y.size
    expected = -m * G / (m / dt ** 2 + K)
    tol = 1e-4 if solver == "qoco" else 1e-6
    assert np.abs(inc.du[1::2] / expected - 1).max() < tol
    assert np.abs(inc.du[0::2]).max() < tol * abs(expected)
    np.testing.assert_allclose(inc.parts["spring_forces"], k * inc.du[base_y], rtol=tol)


def test_bad_springs_are_refused_before_any_work():
    with pytest.raises(ValueError, match="stiffness"):
        ElasticSupport([1, 3], [1.0, -1.0])
    with pytest.raises(ValueError, match="repeat"):
        ElasticSupport([1, 1], 1.0)
    with pytest.raises(ValueError, match="out of range"):
        block_on_springs_out_of_range()


def block_on_springs_out_of_range():
    disc = discretise(MeshTri.init_tensor(np.linspace(0, 1, 3), np.linspace(0, 1, 3)))
    ops = dynamic_operators(disc, RHO, ThetaMethod(0.1, 1.0, 1.0), None)
    z = np.zeros(disc.n_u)
    dynamic_increment(ops, z, z, np.zeros((disc.n_points, 4)), z, Tresca(1.0),
                      terms=[ElasticSupport([disc.n_u], 1.0)], solver="clarabel")


def test_a_layout_names_each_block_once():
    layout = Layout()
    assert layout.add("sigma", 8) == slice(0, 8) and layout.add("r", 3) == slice(8, 11)
    assert list(layout) == ["sigma", "r"] and layout.size == 11
    with pytest.raises(ValueError, match="already"):
        layout.add("r", 2)


def test_a_stiff_block_on_springs_settles_by_its_weight_over_their_stiffness_statically():
    """The static increment (3.45) with the same ElasticSupport term: a block far stiffer
    than its springs settles uniformly by m g / K (to 1e-6), and the springs carry its
    weight (to 1e-8)."""
    k = 40.0
    disc = discretise(MeshTri.init_tensor(np.linspace(0, W, 5), np.linspace(0, H, 3)))
    base_y = boundary_dofs(disc, lambda x: x[1] < 1e-9, 1)
    base_x = boundary_dofs(disc, lambda x: x[1] < 1e-9, 0)
    f = body_force_vector(disc, (0.0, -RHO * G))
    inc = static_increment(assemble_B(disc), assemble_C(disc, Elastic(1e10, 0.3)), f,
                           np.zeros((disc.n_points, 4)), Tresca(1e3 * RHO * G * H),
                           fixed=base_x, terms=[ElasticSupport(base_y, k)])
    m, K = RHO * W * H, k * base_y.size
    assert np.abs(inc.du[1::2] / (-m * G / K) - 1).max() < 1e-6
    assert inc.parts["spring_forces"].sum() == pytest.approx(-m * G, rel=1e-8)


def test_the_static_increment_refuses_a_term_of_the_dynamic_step_only():
    class Rate(StepTerm):
        name = "a rate"
    disc = discretise(MeshTri.init_tensor(np.linspace(0, 1, 3), np.linspace(0, 1, 3)))
    z = np.zeros(disc.n_u)
    with pytest.raises(ValueError, match="a rate: a term of the dynamic step only"):
        static_increment(assemble_B(disc), assemble_C(disc, Elastic(1e4, 0.3)), z,
                         np.zeros((disc.n_points, 4)), Tresca(1.0), fixed=[], terms=[Rate()])
