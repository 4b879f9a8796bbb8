"""The direct Clarabel assembly of (4.23)+(5.12) against the cvxpy statement (the reference),
in its primal form and in its dual (displacement) form."""
import numpy as np
import pytest
from skfem import MeshTri

from pfem_skfem.materials import Elastic, Tresca, TrescaField
from pfem_skfem.discretisation.static import boundary_dofs, discretise
from pfem_skfem.discretisation.dynamic import gravity_vector
from pfem_skfem.problems.contact import (RigidSegment, potential_contacts, resultants,
                                         with_friction_bound)
from pfem_skfem.discretisation import ThetaMethod, dynamic_operators
from pfem_skfem.problems.dynamic import dynamic_increment
from pfem_skfem.problems.step_terms import Contact

# every test of this file on one xdist worker: its module fixture is computed once
pytestmark = pytest.mark.xdist_group("test_clarabel_direct")

G = 9.8


@pytest.fixture(scope="module")
def block():
    return discretise(MeshTri.init_tensor(np.linspace(0, 1, 5), np.linspace(0, 0.5, 3)))


def direct(form):
    """The step solver of the direct assembly with Clarabel in ``form``."""
    return "clarabel" if form == "primal" else "clarabel-dual"


def both(*args, form="primal", **kwargs):
    return (dynamic_increment(*args, **kwargs),
            dynamic_increment(*args, solver=direct(form), **kwargs))


def close(a, b, tol=1e-5):
    return np.abs(a - b).max() <= tol * max(np.abs(a).max(), 1e-300)


@pytest.mark.parametrize("elastic", [None, Elastic(1e3, 0.3)])
@pytest.mark.parametrize("theta1, theta2", [(1.0, 1.0), (0.5, 0.5)])
def test_free_fall_is_exact(block, elastic, theta1, theta2):
    dt = 0.1
    ops = dynamic_operators(block, 2.0, ThetaMethod(dt, theta1, theta2), elastic)
    f = gravity_vector(block, 2.0, G)
    res = dynamic_increment(ops, f, f, np.zeros((block.n_points, 4)), np.zeros(block.n_u),
                            Tresca(5.0), solver="clarabel")
    assert np.allclose(res.du[1::2], -G * dt ** 2 * theta2, rtol=1e-6)
    assert np.abs(res.du[0::2]).max() <= 1e-6 * G * dt ** 2


@pytest.mark.parametrize("form", ["primal", "dual"])
def test_kkt_and_agreement_with_cvxpy_elastoplastic_with_supports_and_prescribed(block, form):
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
    ref, res = both(ops, f, f, sigma_n, v_n, Tresca(6.0), fixed=fixed, prescribed=(P, du_P),
                    form=form)
    assert res.info.status == "optimal"
    assert res.info.extra.get("form", "primal") == form
    # an elastoplastic step is unique: stresses, increments, multipliers agree
    for name in ("du", "sigma", "r", "reactions"):
        assert close(getattr(ref, name), getattr(res, name)), name
    assert np.allclose(res.du[P], du_P)
    lhs = theta.dt ** 2 * ops.D @ res.r
    rhs = ops.A @ (res.du - theta.dt * v_n)
    assert np.abs(lhs - rhs).max() <= 1e-6 * np.abs(rhs).max()


def sliding_block(block, contact, form, k=50.0, reference=True):
    """One step of a rigid-plastic block (Tresca k) sliding at 2 on a floor (contact: 'rough'
    mu = 0.3, 'smooth', 'bound' a friction bound 0.5, 'moving' the rough floor moving by
    0.01): (cvxpy or None, direct in ``form``, the operators, the forces, the contacts)."""
    ops = dynamic_operators(block, 2.0, ThetaMethod(0.05, 1.0, 1.0), None)
    f = gravity_vector(block, 2.0, G)
    floor = RigidSegment((-5.0, 0.0), (5.0, 0.0), mu=0.0 if contact == "smooth" else 0.3)
    motions = [(0.01, 0.0)] if contact == "moving" else None
    contacts = potential_contacts(block, [floor], 0.05, motions=motions)
    if contact == "bound":
        contacts = with_friction_bound(contacts, np.full(contacts.size, 0.5))
    v_n = np.zeros(block.n_u)
    v_n[0::2] = 2.0
    args = (ops, f, f, np.zeros((block.n_points, 4)), v_n, TrescaField(np.full(block.n_points, k)))
    res = dynamic_increment(*args, terms=[Contact(contacts)], solver=direct(form))
    ref = dynamic_increment(*args, terms=[Contact(contacts)]) if reference else None
    return ref, res, ops, f, contacts


@pytest.mark.parametrize("form", ["primal", "dual"])
@pytest.mark.parametrize("contact", ["rough", "smooth", "bound", "moving"])
def test_sliding_rigid_plastic_block_with_contact_agrees_with_cvxpy(block, contact, form):
    ref, res, ops, f, contacts = sliding_block(block, contact, form)
    if contact == "moving":
        assert contacts.slip is not None
    assert close(ref.du, res.du)
    # r' (zero on the smooth floor: a free slide) as the force A^T r' against the weight
    assert np.abs(ops.A.T @ (ref.r - res.r)).max() <= 1e-5 * np.abs(f).max()
    # the resultant contact force (the rigid block's m a) is unique even where p, q are not
    assert close(resultants(contacts, ref.p, ref.q), resultants(contacts, res.p, res.q))
    assert np.all(res.p >= -1e-9 * np.abs(res.p).max())
    bound = {"bound": 0.5, "smooth": 0.0}.get(contact, 0.3 * res.p)
    assert np.all(np.abs(res.q) <= bound + 1e-6)


def test_dual_form_recovers_the_rigid_plastic_stresses_and_contact_forces(block):
    """The dual's recovery, each part with its sign, on a flowing block (Tresca k = 3): the
    rigid-plastic stresses and contact forces (x_0 = -the dual's multipliers of
    A_0^T z = -c_0) equilibrate the step's r' (x_r = -P_r^-1 (c_r + A_r^T z)) and loads and
    lie in the yield cone (s = the dual's cone multipliers); du, r', the plastic
    multipliers (z) and the objective are the primal form's (to 1e-4: the two forms stop
    at different points within Clarabel's tolerances, 2e-5 apart on du)."""
    from pfem_skfem.problems.contact import contact_matrix
    _, primal, _, _, _ = sliding_block(block, "rough", "primal", k=3.0, reference=False)
    _, res, ops, f, contacts = sliding_block(block, "rough", "dual", k=3.0, reference=False)
    assert res.info.extra["form"] == "dual" and "form" not in primal.info.extra
    assert primal.plastic_multiplier.max() > 1e-3                  # the block flows
    for name in ("du", "r", "plastic_multiplier"):
        assert close(getattr(primal, name), getattr(res, name), 1e-4), name
    assert res.info.objective == pytest.approx(primal.info.objective, rel=1e-6)
    internal = ops.B.T @ res.sigma.ravel() + ops.A.T @ res.r \
        - contact_matrix(contacts, block.n_u) @ np.concatenate([res.p, res.q])
    f_eq = ops.theta.equilibrium_rhs(f, f, ops.B, np.zeros((block.n_points, 4)))
    assert np.abs(internal - f_eq).max() <= 1e-6 * np.abs(f_eq).max()
    k = TrescaField(np.full(block.n_points, 3.0))
    assert k.F(res.sigma).max() <= 1e-6 * np.abs(res.sigma).max()
    assert close(resultants(contacts, primal.p, primal.q), resultants(contacts, res.p, res.q),
                 1e-4)


@pytest.mark.parametrize("factor, exact", [(2.0, True), (3.0, False)])
def test_dual_form_scales_with_the_density_of_a_cohesionless_step(block, factor, exact):
    """c = 0 (here: Tresca k scaled with the density) and every force scales with rho; a
    factor of two scales every floating-point number exactly (the blocks of P inverted
    exactly too): du bit-identical, sigma, r', p doubled; another factor to tolerance."""
    def step(rho):
        ops = dynamic_operators(block, rho, ThetaMethod(0.05, 1.0, 1.0), None)
        f = gravity_vector(block, rho, G)
        contacts = potential_contacts(block, [RigidSegment((-5.0, 0.0), (5.0, 0.0), mu=0.3)],
                                      0.05)
        v_n = np.zeros(block.n_u)
        v_n[0::2] = 2.0
        k = TrescaField(np.full(block.n_points, 1.5 * rho))
        return dynamic_increment(ops, f, f, np.zeros((block.n_points, 4)), v_n, k,
                                 terms=[Contact(contacts)], solver="clarabel-dual")
    one, other = step(2.0), step(2.0 * factor)
    assert other.info.extra["form"] == "dual"
    if exact:
        np.testing.assert_array_equal(other.du, one.du)
        for name in ("sigma", "r", "p", "q"):
            np.testing.assert_array_equal(getattr(other, name), factor * getattr(one, name))
    else:
        assert close(one.du, other.du)
        assert close(factor * one.r, other.r) and close(factor * one.sigma, other.sigma, 1e-4)


# -- solve_dual on small problems: the recovery, the status, what it refuses -------------------
def small_conic_problem(seed=0):
    """(P upper, c, A, b, cones) of a feasible problem with P blocks of 3, 3, 1, 2 (shuffled)
    and three columns without P; zero, nonnegative and second-order cones."""
    import clarabel
    import scipy.sparse as sp
    rng = np.random.default_rng(seed)
    blocks = []
    for k in (3, 3, 1, 2):
        Q = rng.standard_normal((k, k))
        blocks.append(Q @ Q.T + 0.1 * np.eye(k))
    P = sp.block_diag(blocks + [sp.csr_matrix((3, 3))], format="csc")
    perm = rng.permutation(P.shape[0])
    P = P[perm][:, perm]
    A = sp.csc_matrix(rng.standard_normal((13, P.shape[0])))
    s = np.concatenate([np.zeros(2), rng.random(4), [2.0, 0.3, 0.2], [3.0, 0.5, 0.5, 0.1]])
    b = A @ rng.standard_normal(P.shape[0]) + s
    cones = [clarabel.ZeroConeT(2), clarabel.NonnegativeConeT(4), clarabel.SecondOrderConeT(3),
             clarabel.SecondOrderConeT(4)]
    return sp.triu(P, format="csc"), rng.standard_normal(P.shape[0]), A, b, cones


def settings():
    import clarabel
    opts = clarabel.DefaultSettings()
    opts.verbose = False
    return opts


@pytest.mark.parametrize("seed", [0, 1])
def test_solve_dual_recovers_the_primal_solution(seed):
    """x (both parts), z, s and the objective of the primal, from the dual's solution: a
    sign error in any recovery formula is an O(1) difference."""
    import clarabel

    from pfem_skfem.problems.backends.dual_form import solve_dual
    P, c, A, b, cones = small_conic_problem(seed)
    primal = clarabel.DefaultSolver(P, c, A, b, cones, settings()).solve()
    dual = solve_dual(P, c, A, b, cones, settings())
    assert str(primal.status) == dual.status == "Solved"
    for name in ("x", "z", "s"):
        ref = np.asarray(getattr(primal, name))
        assert close(ref, getattr(dual, name)), name
    assert dual.obj_val == pytest.approx(primal.obj_val, rel=1e-6)
    assert np.all(dual.s[:2] == 0.0)                                  # the zero cone's rows


def test_solve_dual_reads_the_status_as_the_primal():
    """x = 1 and x = 2: the primal is infeasible, its dual unbounded (Clarabel's
    DualInfeasible of the dual), reported as the primal's PrimalInfeasible."""
    import clarabel
    import scipy.sparse as sp

    from pfem_skfem.problems.backends.dual_form import solve_dual
    P = sp.csc_matrix(np.ones((1, 1)))
    A = sp.csc_matrix(np.ones((2, 1)))
    out = solve_dual(P, np.zeros(1), A, np.array([1.0, 2.0]), [clarabel.ZeroConeT(2)],
                     settings())
    assert out.status == "PrimalInfeasible"


def test_solve_dual_refuses_cones_that_are_not_self_dual_and_singular_blocks():
    import clarabel
    import scipy.sparse as sp

    from pfem_skfem.problems.backends.dual_form import solve_dual
    P = sp.csc_matrix(np.eye(3))
    A = sp.csc_matrix(np.eye(3))
    with pytest.raises(ValueError, match="self-dual"):
        solve_dual(P, np.zeros(3), A, np.ones(3), [clarabel.ExponentialConeT()], settings())
    singular = sp.triu(sp.csc_matrix(np.ones((3, 3))), format="csc")
    with pytest.raises(ValueError, match="singular"):
        solve_dual(singular, np.zeros(3), A, np.ones(3), [clarabel.NonnegativeConeT(3)],
                   settings())


def test_unsupported_options_are_refused(block):
    ops = dynamic_operators(block, 2.0, ThetaMethod(0.05), Elastic(1e3, 0.3))
    z = np.zeros(block.n_u)
    with pytest.raises(ValueError, match="solver must be one of"):
        dynamic_increment(ops, z, z, np.zeros((block.n_points, 4)), z, Tresca(1.0),
                          solver="clarabel-adjoint")
    with pytest.raises(ValueError, match="needs a yield criterion"):
        dynamic_increment(ops, z, z, np.zeros((block.n_points, 4)), z, None, solver="clarabel")
    with pytest.raises(ValueError, match="quad_form"):
        dynamic_increment(ops, z, z, np.zeros((block.n_points, 4)), z, Tresca(1.0),
                          solver="clarabel", d_form="cone")


# -- the data clean-up before the call (benchmarks/iteration_cost.py) ---------------------------
def test_drop_roundoff_keeps_the_couplings_and_is_invariant_under_scaling():
    import scipy.sparse as sp
    from pfem_skfem.problems.backends.standard_form import drop_roundoff
    rng = np.random.default_rng(1)
    Q = rng.standard_normal((6, 6))
    blocks = [Q @ Q.T, sp.csr_matrix((3, 3))]                     # an SPD block, a zero one
    P = sp.triu(sp.block_diag(blocks), format="coo")
    noise = sp.coo_matrix(([1e-17, -3e-18, 0.0], ([0, 2, 7], [4, 5, 8])), shape=P.shape)
    messy = sp.coo_matrix((np.concatenate([P.data, noise.data]),
                           (np.concatenate([P.row, noise.row]),
                            np.concatenate([P.col, noise.col]))), shape=P.shape)
    messy.sum_duplicates()
    clean = drop_roundoff(messy.tocsc())
    assert clean.nnz == P.nnz and abs(clean - P.tocsc()).max() == 0.0
    for factor in (2.0 ** -7, 2.0, 2.0 ** 9):                     # a density scaling: exact
        scaled = drop_roundoff((factor * messy).tocsc())
        assert (scaled != factor * clean).nnz == 0
        np.testing.assert_array_equal(scaled.indices, clean.indices)


def test_cleaned_data_give_the_same_step(block, monkeypatch):
    """The stored zeros of A and P's round-off dropped: the same problem, the same optimum
    to the solver's tolerance."""
    import clarabel

    from pfem_skfem.problems.backends import direct as direct_module
    theta = ThetaMethod(0.05, 1.0, 0.5)
    ops = dynamic_operators(block, 2.0, theta, Elastic(1e3, 0.3))
    base = lambda x: x[1] < 1e-9                                    # noqa: E731
    fixed = np.union1d(boundary_dofs(block, base, 0), boundary_dofs(block, base, 1))
    rng = np.random.default_rng(5)
    v_n = 0.3 * rng.standard_normal(block.n_u)
    v_n[fixed] = 0.0
    sigma_n = rng.standard_normal((block.n_points, 4))
    f = gravity_vector(block, 2.0, G)
    seen, solver = [], clarabel.DefaultSolver

    def recording(P, q, A, b, cones, settings):
        seen.append((P.copy(), A.copy()))
        return solver(P, q, A, b, cones, settings)

    monkeypatch.setattr(clarabel, "DefaultSolver", recording)
    out = {}
    for clean in (False, True):
        monkeypatch.setattr(direct_module, "CLEAN_DATA", clean)
        out[clean] = dynamic_increment(ops, f, f, sigma_n, v_n, Tresca(3.0), fixed=fixed,
                                       solver="clarabel")
    (P0, A0), (P1, A1) = seen
    assert (A0.data == 0).any() and not (A1.data == 0).any()     # the yield block's zeros
    assert A1.nnz == np.count_nonzero(A0.data) and abs(A1 - A0).max() == 0.0
    assert abs(P1 - P0).max() <= 1e-12 * abs(P0).max()
    assert out[True].info.status == out[False].info.status == "optimal"
    for name in ("du", "sigma", "r"):
        assert close(getattr(out[False], name), getattr(out[True], name)), name
    assert out[True].info.objective == pytest.approx(out[False].info.objective, rel=1e-7)


@pytest.mark.parametrize("failure", ["NumericalError", "InsufficientProgress"])
def test_a_failed_solve_is_solved_once_more_without_equilibration(monkeypatch, failure):
    """A 'NumericalError' or an 'InsufficientProgress' of the primal form: the step is
    solved again with RETRY (equilibration off), its iterations counted with the first
    attempt's and the retry recorded; the answer is the retry's (here the same problem
    solved well: the du of a step solved without the fault, to 1e-6)."""
    import clarabel
    import pfem_skfem.problems.backends.clarabel as engine

    real = clarabel.DefaultSolver
    calls = []

    class FirstFails:
        def __init__(self, P, q, A, b, cones, settings):
            calls.append(settings.equilibrate_enable)
            self.inner = real(P, q, A, b, cones, settings)

        def solve(self):
            sol = self.inner.solve()
            if len(calls) == 1:
                class Failed:                       # the first attempt's report
                    status, iterations, x, z, s, obj_val = (failure, 7, sol.x,
                                                            sol.z, sol.s, sol.obj_val)
                return Failed()
            return sol

        def __getattr__(self, name):
            return getattr(self.inner, name)

    from test_fluids import _column_step
    from pfem_skfem.materials import BinghamFluid
    mud = BinghamFluid(tau_y=200.0, mu=0.5)
    reference = _column_step(mud, False, "clarabel")
    monkeypatch.setattr(engine.clarabel, "DefaultSolver", FirstFails)
    retried = _column_step(mud, False, "clarabel")
    assert calls == [True, False]
    assert retried.info.extra["retried"] == {"equilibrate_enable": False}
    assert retried.info.iterations > 7
    assert np.abs(retried.du - reference.du).max() < 1e-6 * np.abs(reference.du).max()
