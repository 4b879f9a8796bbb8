"""Rigid frictional boundaries (5.10)-(5.12) in the static problem."""
import numpy as np
import pytest
from skfem import MeshTri

from pfem_skfem.materials import Elastic, Tresca
from pfem_skfem.discretisation.static import (assemble_B, assemble_C, body_force_vector, boundary_dofs,
                                              discretise)
from pfem_skfem.problems.conic import SolverError
from pfem_skfem.problems.contact import (RigidCircle, RigidSegment, potential_contacts,
                                         resultants)
from pfem_skfem.problems.static import static_increment
from verification import buried_pipe, sliding_box

RHO_G = 20.0           # unit weight [kN/m3]


def block_on_plane(mu):
    """Unit elastic block standing on a rigid plane y = 0, under its own weight."""
    disc = discretise(MeshTri.init_symmetric().refined(2))
    plane = RigidSegment((-1.0, 0.0), (2.0, 0.0), mu=mu)
    contacts = potential_contacts(disc, [plane], search_distance=1e-6)
    B, C = assemble_B(disc), assemble_C(disc, Elastic(1e4, 0.3))
    f = body_force_vector(disc, (0.0, -RHO_G))
    return disc, contacts, B, C, f


def test_smooth_plane_carries_the_weight_with_no_tangential_force():
    disc, contacts, B, C, f = block_on_plane(mu=0.0)
    # one x-dof fixed to remove the free horizontal translation of a smooth block
    corner = boundary_dofs(disc, lambda x: (x[0] < 1e-9) & (x[1] < 0.5), 0)[:1]
    res = static_increment(B, C, f, np.zeros((disc.n_points, 4)), Tresca(1e3),
                           fixed=corner, contacts=contacts)
    R = resultants(contacts, res.p, res.q)[0]
    assert R[1] == pytest.approx(-RHO_G * 1.0, rel=1e-6)      # weight of the unit block
    assert np.abs(res.q).max() < 1e-9 * RHO_G
    assert abs(R[0]) < 1e-8 * RHO_G
    assert np.all(res.p >= -1e-9 * RHO_G)
    # no penetration: the new gap g0 + n . du is non-negative
    gap = contacts.gap + np.einsum("jd,jd->j", contacts.normal, res.du[contacts.dofs])
    assert gap.min() > -1e-9


@pytest.mark.parametrize("push", [0.02, 0.05, 0.5])
def test_block_pushed_along_a_rough_plane_sticks_then_slides_at_mu_N(push):
    mu = 0.3
    disc, contacts, B, C, f = block_on_plane(mu=mu)
    left = boundary_dofs(disc, lambda x: x[0] < 1e-9, 0)
    W = RHO_G * 1.0
    res = static_increment(B, C, f, np.zeros((disc.n_points, 4)), Tresca(1e3), fixed=[],
                           prescribed=(left, push * 1e-3 * np.ones(left.size)),
                           contacts=contacts)
    H = res.reactions[left].sum()                               # force needed to push
    R = resultants(contacts, res.p, res.q)[0]
    assert R[1] == pytest.approx(-W, rel=1e-6)
    assert np.all(np.abs(res.q) <= mu * res.p + 1e-9 * W)        # Coulomb cone
    assert H <= mu * W * (1 + 1e-6)                              # never above mu N
    slip = res.du[contacts.dofs[:, 0]]
    if push >= 0.5:                                              # slides: H = mu N
        assert H == pytest.approx(mu * W, rel=1e-5)
        assert slip.min() > 0
    else:                                                        # sticks: H < mu N
        assert H < 0.99 * mu * W
        # away from the corners (where partial slip is physical) nothing slips
        inner = (contacts.x[:, 0] > 0.1) & (contacts.x[:, 0] < 0.8)
        assert np.abs(slip[inner]).max() < 1e-3 * push * 1e-3
    # (5.11): where a node slides, the associated rule lifts it by mu |slip|
    sliding = np.abs(res.q) > (1 - 1e-3) * mu * res.p
    lift = res.du[contacts.dofs[:, 1]]
    assert sliding.any()
    assert np.allclose(lift[sliding], mu * np.abs(slip[sliding]), rtol=1e-4,
                       atol=1e-6 * np.abs(slip).max())


def test_rigid_plastic_punch_through_contact_is_bounded_by_the_soil_strength():
    """A rigid plate pushed into a Tresca block by its motion: Prandtl load bounds it."""
    disc = discretise(MeshTri.init_symmetric().refined(3))
    su = 10.0
    # smooth plate above the block along the whole top: pure compression, p = 2 Su
    plate = RigidSegment((2.0, 1.0), (-1.0, 1.0), mu=0.0)    # solid below: walk in -x
    contacts = potential_contacts(disc, [plate], 1e-6, motions=[(0.0, -0.01)])
    bottom = boundary_dofs(disc, lambda x: x[1] < 1e-9, 1)
    left = boundary_dofs(disc, lambda x: x[0] < 1e-9, 0)
    res = static_increment(assemble_B(disc), None, np.zeros(disc.n_u),
                           np.zeros((disc.n_points, 4)), Tresca(su),
                           fixed=np.union1d(bottom, left), contacts=contacts)
    R = resultants(contacts, res.p, res.q)[0]
    assert R[1] == pytest.approx(2 * su * 1.0, rel=1e-6)   # uniaxial plane-strain collapse


def test_bad_contact_input():
    with pytest.raises(ValueError, match="mu"):
        RigidSegment((0, 0), (1, 0), mu=-0.1)
    with pytest.raises(ValueError, match="radius"):
        RigidCircle((0, 0), 0.0)
    disc = discretise(MeshTri())
    with pytest.raises(ValueError, match="no boundary node"):
        potential_contacts(disc, [RigidSegment((0, -5), (1, -5))], search_distance=0.1)
    with pytest.raises(ValueError, match="search_distance"):
        potential_contacts(disc, [RigidSegment((0, 0), (1, 0))], search_distance=0.0)


def test_circle_gap_and_normal():
    c = RigidCircle((1.0, 2.0), 0.5)
    g, n = c.gap([[1.0, 3.0], [2.0, 2.0]])
    assert np.allclose(g, [0.5, 0.5]) and np.allclose(n, [[0, 1], [1, 0]])
    seg = RigidSegment((0, 0), (1, 0))
    g, n = seg.gap([[0.5, 0.2], [2.0, 0.0]])
    assert np.allclose(g, [0.2, 0.0]) and np.allclose(n, [[0, 1], [0, 1]])


@pytest.mark.parametrize("point, gap, normal", [
    ((0.5, -0.2), 0.2, (0, -1)),          # under the footing: its normal, as before
    ((1.0, 0.0), 0.0, (0, -1)),           # its edge: on it
    ((1.5, 0.0), 0.5, (1, 0)),            # the surface beside it: no contact
    ((1.3, -0.4), 0.5, (0.6, -0.8)),      # below and beside: the distance to the edge
    ((-0.6, 0.8), 1.0, (-0.6, 0.8)),      # beyond the other end, on the far side
])
def test_a_sharp_ended_segment_ends_at_its_points(point, gap, normal):
    """A footing (a segment from (1, 0) to (0, 0), the soil below) with ``sharp_ends``:
    beyond an end the gap is the distance to the end point; without it the footing's line
    goes on, and the surface beside it lies on it (gap 0), a contact the footing pushes."""
    footing = RigidSegment((1, 0), (0, 0), sharp_ends=True)
    g, n = footing.gap([point])
    assert g[0] == pytest.approx(gap) and np.allclose(n[0], normal)
    assert footing.translated((0.0, -0.1)).sharp_ends
    if point == (1.5, 0.0):
        assert RigidSegment((1, 0), (0, 0)).gap([point])[0][0] == 0.0


def test_sharp_ends_must_be_a_bool():
    with pytest.raises(ValueError, match="sharp_ends"):
        RigidSegment((0, 0), (1, 0), sharp_ends="yes")


def test_block_heavier_than_friction_can_hold_is_reported_infeasible():
    """A horizontal load above mu N has no static equilibrium: the solver says infeasible."""
    disc, contacts, B, C, f = block_on_plane(mu=0.2)
    from pfem_skfem.discretisation.static import boundary_facets, traction_vector
    f = f + traction_vector(disc, boundary_facets(disc, lambda x: x[0] < 1e-9),
                            (0.3 * RHO_G, 0.0))
    with pytest.raises(SolverError, match="infeasible"):
        static_increment(B, C, f, np.zeros((disc.n_points, 4)), Tresca(1e3), fixed=[],
                         contacts=contacts)


def test_buried_pipe_dynamic_step_adds_only_the_inertia_of_the_soil():
    """The thesis' dynamic step (theta1 = theta2 = 1, from rest) at a slow pipe speed: the
    quasi-static resistance to 1e-3, and not less (inertia resists). The quasi-static
    benchmark itself runs in tests/test_verification.py; this holds on any mesh."""
    model = buried_pipe.pipe_model(300)
    F, _, _ = buried_pipe.pipe_resistance(model, su=50.0, rho=2.0, g=9.8)
    F_dyn, _, _ = buried_pipe.pipe_resistance(model, su=50.0, rho=2.0, g=9.8, dt=1.0)
    assert F_dyn == pytest.approx(F, rel=1e-3)
    assert F_dyn >= F * (1 - 1e-6)


# -- contact in the dynamic problem (5.12) -----------------------------------
def test_dynamic_block_at_rest_on_a_floor_stays_at_rest_and_carries_its_weight():
    from pfem_skfem.discretisation import ThetaMethod, dynamic_operators
    from pfem_skfem.problems.dynamic import dynamic_increment
    from pfem_skfem.problems.step_terms import Contact
    disc = discretise(MeshTri.init_tensor(np.linspace(0, 1, 5), np.linspace(0, 0.5, 3)))
    floor = RigidSegment((-1.0, 0.0), (2.0, 0.0), mu=0.3)
    ops = dynamic_operators(disc, 2.0, ThetaMethod(0.05, 1.0, 1.0), elastic=None)
    f = body_force_vector(disc, (0.0, -2.0 * 9.8))
    sigma, v, u = np.zeros((disc.n_points, 4)), np.zeros(disc.n_u), np.zeros(disc.n_u)
    for _ in range(3):
        contacts = potential_contacts(disc, [floor], 0.05, displacement=u)
        res = dynamic_increment(ops, f, f, sigma, v, Tresca(1e3), terms=[Contact(contacts)])
        sigma, v, u = res.sigma, res.v, u + res.du
        R = resultants(contacts, res.p, res.q)[0]
        assert R[1] == pytest.approx(-2.0 * 9.8 * 0.5, rel=1e-6)   # the weight
        assert abs(R[0]) < 1e-8
    g_dt2 = 9.8 * 0.05 ** 2                          # a free fall's first step
    assert np.abs(u).max() < 1e-6 * g_dt2 and np.abs(v).max() < 1e-6 * 9.8 * 0.05


@pytest.mark.parametrize("solver", ["cvxpy", "clarabel"])
@pytest.mark.parametrize("floor_travel", [0.004, 0.05])
def test_a_floor_moving_under_a_block_at_rest_drags_it_its_way(solver, floor_travel):
    """A rigid block at rest on a rough floor that moves by d = (floor_travel, 0) in the step
    (potential_contacts(motions=...): the slip n^ . (du - d) is relative to the floor).
    Friction can give the block (mass m, weight W) at most mu W: below m d / dt^2 it sticks
    and moves with the floor, du = d; above, it slides, dragged forwards less than the
    floor, and its friction on the floor holds the floor back. A slip of the wrong sign
    would drag it backwards."""
    from pfem_skfem.discretisation import ThetaMethod, dynamic_operators
    from pfem_skfem.problems.dynamic import dynamic_increment
    from pfem_skfem.problems.step_terms import Contact
    rho, g, dt, mu = 2.0, 9.8, 0.05, 0.5
    disc = discretise(MeshTri.init_tensor(np.linspace(0, 1, 5), np.linspace(0, 0.5, 3)))
    floor = RigidSegment((-1.0, 0.0), (2.0, 0.0), mu=mu)
    ops = dynamic_operators(disc, rho, ThetaMethod(dt, 1.0, 1.0), elastic=None)
    f = body_force_vector(disc, (0.0, -rho * g))
    contacts = potential_contacts(disc, [floor], 0.05, motions=[(floor_travel, 0.0)])
    res = dynamic_increment(ops, f, f, np.zeros((disc.n_points, 4)), np.zeros(disc.n_u),
                            Tresca(1e3), terms=[Contact(contacts)], solver=solver)
    du_x = res.du[0::2]
    R = resultants(contacts, res.p, res.q)[0]
    m, W = rho * 0.5, rho * g * 0.5
    if m * floor_travel / dt ** 2 < mu * W:                    # sticks: moves with the floor
        assert du_x == pytest.approx(floor_travel, rel=1e-6)
        assert R[0] == pytest.approx(-m * floor_travel / dt ** 2, rel=1e-5)
    else:                                                       # slides, dragged forwards
        assert 0.5 * mu * g * dt ** 2 < du_x.min() and du_x.max() < 0.5 * floor_travel
        assert R[0] < -0.5 * mu * W
    # the floor's normal is (0, 1), its tangent n^ = (-1, 0): its own slip n^ . d = -d_x
    assert np.allclose(contacts.slip, -floor_travel, rtol=1e-15)


def test_fe_block_slides_like_the_rigid_particle():
    """(5.12) on a rigid-plastic block reproduces (5.9) for the rigid particle."""
    fe, _ = sliding_box.slide_fe(0.98, 0.1, 9.8, 10, 1.0, 0.5)
    particle, _ = sliding_box.slide(0.98, 0.1, 9.8, 10, 1.0, 0.5)
    assert np.allclose(fe, particle, rtol=1e-6, atol=1e-8)
    assert fe[:, 1].min() > -1e-9                       # never below the floor


@pytest.mark.parametrize("steps", [5, 10])
def test_zero_dilation_contact_slides_the_fe_block_to_newton_without_lift(steps):
    """|q| <= mu p~ with p~ from a smooth first pass: the travel v0^2/(2 mu g) of Newton's law
    (exact for theta = 1/2 when the box stops at a step's end) and no lift-off at any dt."""
    v0, mu, g = 0.98, 0.1, 9.8
    path, _ = sliding_box.slide_fe(v0, mu, g, steps, v0 / (mu * g), 0.5,
                                   contact="zero-dilation")
    assert path[-1, 0] == pytest.approx(v0 ** 2 / (2 * mu * g), rel=1e-6)
    assert np.abs(path[:, 1]).max() < 1e-7 * v0


def test_friction_bound_caps_the_tangential_force_of_a_pushed_block():
    """Static (3.45) with a known friction bound: the block pushed harder than the bound
    is infeasible, pushed below it holds with q equal to the push."""
    from pfem_skfem.problems.contact import with_friction_bound
    disc, contacts, B, C, f = block_on_plane(mu=0.5)
    weight = RHO_G * 1.0
    bounded = with_friction_bound(contacts, np.full(contacts.size, weight / contacts.size))
    push = np.zeros(disc.n_u)
    left = boundary_dofs(disc, lambda x: x[0] < 1e-9, 0)
    push[left] = 0.3 * weight / len(left)          # below mu x (weight / nc) x nc = 0.5 W
    res = static_increment(B, C, f + push, np.zeros((disc.n_points, 4)), Tresca(1e6),
                           fixed=[], contacts=bounded)
    R = resultants(bounded, res.p, res.q)[0]
    assert R[0] == pytest.approx(0.3 * weight, rel=1e-5)
    assert np.abs(res.q).max() <= 0.5 * weight / contacts.size * (1 + 1e-6)
    push[left] = 0.6 * weight / len(left)
    with pytest.raises(SolverError):
        static_increment(B, C, f + push, np.zeros((disc.n_points, 4)), Tresca(1e6),
                         fixed=[], contacts=bounded)


def test_with_friction_bound_checks_its_input():
    from pfem_skfem.problems.contact import with_friction_bound
    _, contacts, *_ = block_on_plane(mu=0.5)
    with pytest.raises(ValueError, match="one value per contact"):
        with_friction_bound(contacts, np.ones(contacts.size + 1))
    with pytest.raises(ValueError, match="non-negative"):
        with_friction_bound(contacts, -np.ones(contacts.size))
