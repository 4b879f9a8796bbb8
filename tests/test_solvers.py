"""The conic solver as a choice (issue 40, item 1): QOCO (and MOSEK where licensed) against
Clarabel on the footing's limit analysis, an elastoplastic increment, the bounds of the
cut and a PFEM step; unknown names, unsupported cones and unavailable solvers refused
before any work; an inaccurate end certified or refused by the rule of conic.py.

Tolerances: the certification rule's own (:data:`~pfem_skfem.problems.conic.CERTIFY`,
1e-5 on each measure), widened by the conditioning of each quantity. Measured with QOCO
0.3.2 against Clarabel 0.11.1: the footing's load factor 1.2e-5 (QOCO ends 'solved
inaccurate', certified: relative gap 3.2e-6), the increments' loads 5.6e-8, the stresses
and displacement increments of the last (at collapse) 1.3e-5 and 2.1e-5 of their largest; the cut's bounds 2.3e-7 (lower) and 7e-8
(upper); the buried pipe's resistance 2.1e-8 (quasi-static) and 1.0e-5 (one dynamic step);
an elastoplastic dynamic step, Clarabel's direct assembly against QOCO's cvxpy
statement, 2.3e-8 (du, sigma, r', reactions).
"""
import warnings

import cvxpy as cp
import numpy as np
import pytest
from skfem import MeshTri

from pfem_skfem.discretisation import ThetaMethod, dynamic_operators
from pfem_skfem.discretisation.dynamic import gravity_vector
from pfem_skfem.discretisation.static import (assemble_B, assemble_C, boundary_dofs,
                                              discretise)
from pfem_skfem.materials import Elastic, MohrCoulomb, Tresca
from pfem_skfem.problems import conic
from pfem_skfem.discretisation.meshes import triangulate_polygon
from pfem_skfem.problems.bounds import LimitProblem, Support, lower_bound, upper_bound
from pfem_skfem.problems.conic import (SOLVERS, AlmostSolvedWarning, SolverError, cone_kinds,
                                       solve)
from pfem_skfem.problems.dynamic import dynamic_increment
from pfem_skfem.problems.static import limit_analysis, static_increment
from pfem_skfem.scene.config import PFEMConfig
from verification import strip_footing

needs_qoco = pytest.mark.skipif(SOLVERS["qoco"].unavailable() is not None,
                                reason="QOCO is not installed (pip install qoco)")
quiet = pytest.mark.filterwarnings("ignore::pfem_skfem.problems.conic.AlmostSolvedWarning")


def rel(a, b):
    return float(np.abs(np.asarray(a) - np.asarray(b)).max() / np.abs(np.asarray(b)).max())


def mosek_or_skip():
    pytest.importorskip("mosek", reason="MOSEK is not installed")
    why = SOLVERS["mosek"].unavailable()
    if why is not None:
        pytest.skip(f"MOSEK is not usable here: {why}")


def block():
    """The unit square on rollers (bottom u_y = 0, left u_x = 0)."""
    disc = discretise(MeshTri.init_tensor(np.linspace(0, 1, 5), np.linspace(0, 1, 5)))
    fixed = np.concatenate([boundary_dofs(disc, lambda x: x[1] < 1e-9, 1),
                            boundary_dofs(disc, lambda x: x[0] < 1e-9, 0)])
    return disc, np.unique(fixed)


# -- agreement with Clarabel ---------------------------------------------------------------
@needs_qoco
@quiet
@pytest.mark.parametrize("solver", ["qoco", "mosek"])
def test_footing_limit_analysis_agrees_with_clarabel(solver):
    if solver == "mosek":
        mosek_or_skip()
    model = strip_footing.footing_model(200)
    f = np.zeros(model["disc"].n_u)
    f[model["footing"]] = -1.0
    ref = limit_analysis(model["B"], f, Tresca(1.0), fixed=model["fixed"])
    res = limit_analysis(model["B"], f, Tresca(1.0), fixed=model["fixed"], solver=solver)
    assert res.info.status in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE)
    assert abs(res.load_factor / ref.load_factor - 1) <= 5e-5


@needs_qoco
@pytest.mark.parametrize("solver", ["qoco", "mosek"])
def test_elastoplastic_increments_agree_with_clarabel(solver):
    """Displacement control of a Mohr-Coulomb block into collapse: four increments."""
    if solver == "mosek":
        mosek_or_skip()
    disc, fixed = block()
    top = boundary_dofs(disc, lambda x: x[1] > 1 - 1e-9, 1)
    B, C = assemble_B(disc), assemble_C(disc, Elastic(1000.0, 0.3))
    runs = {}
    for name in ("clarabel", solver):
        sigma, loads = np.zeros((disc.n_points, 4)), []
        for _ in range(4):
            res = static_increment(B, C, np.zeros(disc.n_u), sigma, MohrCoulomb(1.0, 20.0),
                                   fixed=fixed, prescribed=(top, np.full(top.size, -1e-3)), solver=name)
            sigma = res.sigma
            loads.append(-res.reactions[top].sum())
        runs[name] = (np.array(loads), sigma, res.du)
    (l0, s0, u0), (l1, s1, u1) = runs["clarabel"], runs[solver]
    assert rel(l1, l0) <= 1e-6
    assert rel(s1, s0) <= 1e-4 and rel(u1, u0) <= 1e-4


def cut(size=0.15):
    """The vertical cut of height 1 (tests/test_bounds.py's): free face x = 0 and top,
    smooth back x = 2, rough base; the live load is gravity."""
    return LimitProblem(triangulate_polygon([(0, 0), (2, 0), (2, 1), (0, 1)], size),
                        Tresca(1.0), supports=(Support(lambda x: x[0] > 2 - 1e-9, "x"),
                                               Support(lambda x: x[1] < 1e-9, "xy")),
                        body_live=(0.0, -1.0))


@needs_qoco
@quiet
@pytest.mark.parametrize("bound", [lower_bound, upper_bound])
def test_bounds_of_the_cut_agree_with_clarabel(bound):
    problem = cut()
    ref, res = bound(problem), bound(problem, solver="qoco")
    assert res.info.extra["bound"]["violation"] <= 1e-6
    assert abs(res.load / ref.load - 1) <= 1e-5


def elastoplastic_step():
    """The arguments of an elastoplastic dynamic step of a block on a rough base (Tresca,
    random start), and its supports and prescribed increment."""
    disc = discretise(MeshTri.init_tensor(np.linspace(0, 1, 5), np.linspace(0, 0.5, 3)))
    theta = ThetaMethod(0.05, 1.0, 0.5)
    ops = dynamic_operators(disc, 2.0, theta, Elastic(1e3, 0.3))
    base = lambda x: x[1] < 1e-9                                    # noqa: E731
    fixed, P = boundary_dofs(disc, base, 0), boundary_dofs(disc, base, 1)
    rng = np.random.default_rng(3)
    v_n = 0.1 * rng.standard_normal(disc.n_u)
    v_n[fixed] = 0.0
    sigma_n = rng.standard_normal((disc.n_points, 4))
    f = gravity_vector(disc, 2.0, 9.8)
    args = (ops, f, f, sigma_n, v_n, Tresca(6.0))
    return args, dict(fixed=fixed, prescribed=(P, np.full(P.size, 1e-3)))


@needs_qoco
@pytest.mark.parametrize("solver", ["qoco", "qoco-dual", "cvxpy-qoco"])
def test_dynamic_step_with_qoco_agrees_with_the_direct_clarabel_step(solver):
    """QOCO handed the direct assembly (primal or dual form) or the cvxpy statement: the
    step of Clarabel's direct assembly, to 1e-6."""
    args, kw = elastoplastic_step()
    ref = dynamic_increment(*args, solver="clarabel", **kw)
    res = dynamic_increment(*args, solver=solver, **kw)
    if solver == "cvxpy-qoco":
        assert res.info.extra["measures"]["solver"] == "QOCO"
    else:
        assert res.info.extra["engine"] == "qoco"
        assert res.info.extra.get("form", "primal") == ("dual" if "dual" in solver
                                                        else "primal")
    for name in ("du", "sigma", "r", "reactions"):
        assert rel(getattr(res, name), getattr(ref, name)) <= 1e-6, name


@needs_qoco
@quiet
@pytest.mark.parametrize("dt, tol", [(None, 1e-6), (1.0, 5e-5)])
def test_buried_pipe_with_contacts_agrees_with_clarabel(dt, tol):
    """The pipe's resistance (rigid-plastic, contact cones (5.12)), quasi-static and one
    dynamic step; measured 2.1e-8 and 1.0e-5 (QOCO 'solved inaccurate', certified)."""
    from verification import buried_pipe
    model = buried_pipe.pipe_model(300)
    forces = [buried_pipe.pipe_resistance(model, su=50.0, rho=2.0, g=9.8, dt=dt,
                                          solver=solver)[0] for solver in ("clarabel", "qoco")]
    assert abs(forces[1] / forces[0] - 1) <= tol


@needs_qoco
def test_a_c0_pfem_run_with_qoco_is_density_invariant_bit_for_bit():
    """c = 0: every force scales with rho, and a factor of two scales every number exactly,
    so the scaled problems QOCO is given are identical (tests/test_engine.py's, Clarabel)."""
    from pfem_skfem.drivers.pfem_loop import run
    from verification.granular_column_plane import granular_column

    def column(rho):
        state, scene = granular_column(1.0, 5, rho=rho, dt=0.05 * np.sqrt(1.0 / 9.8),
                                       solver="qoco")
        assert scene.config.solver == "qoco"
        return run(state, scene, 3)[0]
    a, b = column(2.0), column(4.0)
    np.testing.assert_array_equal(a.x, b.x)
    np.testing.assert_array_equal(a.v, b.v)
    assert np.abs(a.v).max() > 0


@needs_qoco
@quiet
@pytest.mark.parametrize("geometry", ["plane", "axisymmetric"])
@pytest.mark.parametrize("statement", ["direct", "direct-dual", "cvxpy"])
def test_pfem_steps_with_qoco_agree_with_clarabel(geometry, statement, monkeypatch):
    """The first PFEM step of a collapsing column (plane: the thesis' Fig 6.11 column;
    axisymmetric: its 7.4 column, Drucker-Prager), one pass, Clarabel's direct assembly
    against QOCO handed the same direct assembly (primal, or its dual: the displacement
    form) or the cvxpy statement: the particles' velocities within 1e-4 of their largest
    (measured 5e-6 - 1e-5; QOCO's du is within 3.6e-8 - 1.1e-6 of a tight reference,
    Clarabel's within 7e-6 - 1.3e-4, benchmarks/gpu_solve.py) and their positions within
    1e-6 of the column's height. One step and one pass, so that both solve the same
    problem: a later pass or step lags the mean stress of rigid zones, which is not unique
    (measured 3e-4 after two steps, tests/test_pfem_loop.py)."""
    from pfem_skfem.drivers.pfem_loop import run
    if geometry == "plane":
        from verification.granular_column_plane import granular_column as column
    else:
        from pfem_skfem.scene.columns import granular_column_axisymmetric as column
    from pfem_skfem.problems.backends import ENGINES
    direct_solves = []                  # QOCO's solves of the direct assembly
    engine_solve = ENGINES["qoco"].solve
    monkeypatch.setattr(ENGINES["qoco"], "solve",
                        lambda *a, **k: direct_solves.append(1) or engine_solve(*a, **k))
    states = []
    qoco = {"direct": "qoco", "direct-dual": "qoco-dual", "cvxpy": "cvxpy-qoco"}[statement]
    for solver in ("clarabel", qoco):
        state, scene = column(1.0, 6, dt=0.05 * np.sqrt(1.0 / 9.8), solver=solver, passes=1)
        states.append(run(state, scene, 1)[0])
    assert (len(direct_solves) > 0) == statement.startswith("direct")
    a, b = states
    assert np.abs(a.v).max() > 0
    assert rel(b.v, a.v) < 1e-4
    assert np.abs(b.x - a.x).max() < 1e-6 * 1.0


# -- refusals before any work ---------------------------------------------------------------
def small_problem(exp=False):
    x = cp.Variable(3)
    cones = [cp.constraints.ExpCone(x[0], x[1], x[2])] if exp else [cp.SOC(x[0] + 2, x[1:])]
    return cp.Problem(cp.Minimize(cp.sum(x)), cones + [x >= -5, x <= 5])


@pytest.fixture
def no_solve(monkeypatch):
    def refuse(*args, **kwargs):
        raise AssertionError("a solve was started")
    monkeypatch.setattr(cp.Problem, "solve", refuse)


def test_unknown_solver_names_are_refused_listing_the_known_ones(no_solve):
    with pytest.raises(ValueError, match="clarabel.*qoco.*mosek"):
        solve(small_problem(), solver="gurobi")
    disc, fixed = block()
    with pytest.raises(ValueError, match="solver must be one of"):
        limit_analysis(assemble_B(disc), np.ones(disc.n_u), Tresca(1.0), fixed=fixed,
                       solver="ecos")
    with pytest.raises(ValueError, match="solver must be one of"):
        lower_bound(None, solver="copt")             # refused before the problem is read
    with pytest.raises(ValueError, match="solver"):
        PFEMConfig(solver="cplex")


def test_unsupported_cones_are_refused_by_name(no_solve):
    assert cone_kinds(small_problem()) == {"soc", "nonneg"}
    assert cone_kinds(small_problem(exp=True)) == {"exp", "nonneg"}
    x = cp.Variable(2)
    assert "exp" in cone_kinds(cp.Problem(cp.Minimize(cp.sum(cp.exp(x)))))
    with pytest.raises(ValueError, match=r"'qoco'.*exp"):
        solve(small_problem(exp=True), solver="qoco")
    with pytest.raises(ValueError, match=r"'qoco'.*exp"):
        conic.solver_backend("qoco", cones={"exp"})   # as dynamic_increment asks for mu(I)


def test_an_unavailable_mosek_is_refused_saying_why(no_solve):
    if SOLVERS["mosek"].unavailable() is None:
        pytest.skip("MOSEK is licensed here")
    with pytest.raises(SolverError, match="MOSEK.*not available") as err:
        solve(small_problem(), solver="mosek")
    assert err.value.status == "unavailable"


def test_clarabel_is_the_default_everywhere():
    assert PFEMConfig().solver == "clarabel"
    info = solve(small_problem())
    assert "solver" not in info.extra["measures"]        # Clarabel's measures, unchanged


# -- an inaccurate QOCO end: certified or refused -------------------------------------------
@needs_qoco
def test_an_inaccurate_qoco_end_is_certified_by_its_measures_or_refused():
    """QOCO stops at its iteration cap 'solved inaccurate' when its reduced tolerances are
    met: near the optimum its measures certify it; far from it they do not."""
    problem = small_problem()
    exact = solve(problem).objective
    stop = dict(abstol=1e-15, reltol=1e-15)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        info = solve(problem, solver="qoco", max_iters=30, abstol_inacc=1e-6,
                     reltol_inacc=1e-6, **stop)
    assert info.status == cp.OPTIMAL_INACCURATE
    assert any(issubclass(w.category, AlmostSolvedWarning) and "QOCO" in str(w.message)
               for w in caught)
    assert abs(info.objective - exact) <= 1e-5 * max(1.0, abs(exact))
    # stopped after 6 iterations with a loose reduced tolerance: the gap is far too large
    model = strip_footing.footing_model(200)
    f = np.zeros(model["disc"].n_u)
    f[model["footing"]] = -1.0
    early = dict(solver="qoco", max_iters=6, abstol_inacc=10.0, reltol_inacc=10.0)
    with pytest.raises(SolverError, match="do not certify.*QOCO") as err:
        limit_analysis(model["B"], f, Tresca(1.0), fixed=model["fixed"], **early)
    assert err.value.status == cp.OPTIMAL_INACCURATE
    assert err.value.measures["solver"] == "QOCO" and err.value.measures["gap_rel"] > 1e-5
    # the caller that counts such ends takes them as they are
    loose = limit_analysis(model["B"], f, Tresca(1.0), fixed=model["fixed"],
                           accept_inaccurate=True, **early)
    assert loose.info.status == cp.OPTIMAL_INACCURATE


@needs_qoco
def test_a_numerical_error_is_retried_with_qoco_s_retries_and_clarabel_s_raised(monkeypatch):
    real, calls = cp.Problem.solve, []

    def flaky(self, *args, **kwargs):
        calls.append(kwargs.get("kkt_static_reg_A"))
        if len(calls) == 1:
            raise cp.error.SolverError("a numerical error")
        return real(self, *args, **kwargs)
    monkeypatch.setattr(cp.Problem, "solve", flaky)
    info = solve(small_problem(), solver="qoco")
    assert calls == [None, conic.QOCO_RETRIES[0]["kkt_static_reg_A"]]
    assert info.extra["retry"] == conic.QOCO_RETRIES[0] and info.status == cp.OPTIMAL
    calls.clear()
    with pytest.raises(SolverError, match="Clarabel failed") as err:
        solve(small_problem())
    assert err.value.status == "solver_error" and len(calls) == 1


def test_the_solver_option_names_the_registry_and_reaches_the_footing_script():
    from pfem_skfem.harness.options import SOLVER_NAMES, STEP_SOLVER_NAMES
    from pfem_skfem.problems.backends import STEP_SOLVERS
    assert SOLVER_NAMES == tuple(SOLVERS)
    assert STEP_SOLVER_NAMES == tuple(STEP_SOLVERS)
    args = strip_footing.build_parser().parse_args(["--solver", "qoco"])
    assert args.solver == "qoco"
    assert strip_footing.build_parser().parse_args([]).solver == "clarabel"
    with pytest.raises(SystemExit):
        strip_footing.build_parser().parse_args(["--solver", "gurobi"])


def test_a_mu_i_step_refuses_qoco_before_any_work(no_solve):
    """mu(I)'s rate term needs exponential cones: refused by name, no problem stated."""
    from pfem_skfem.materials.rate import RateDissipation
    from pfem_skfem.problems.step_terms import MuIRate
    disc = discretise(MeshTri.init_tensor(np.linspace(0, 1, 3), np.linspace(0, 0.5, 2)))
    ops = dynamic_operators(disc, 2.0, ThetaMethod(0.05, 1.0, 1.0), None)
    ones, z = np.ones(disc.n_points), np.zeros(disc.n_u)
    rate = RateDissipation(c=ones, tau_max=ones, weights=ones)
    with pytest.raises(ValueError, match=r"'qoco'.*exp"):
        dynamic_increment(ops, z, z, np.zeros((disc.n_points, 4)), z, Tresca(1.0),
                          terms=[MuIRate(rate)], solver="qoco")


def test_qoco_engine_answers_in_clarabels_rows_and_signs():
    """QOCO handed Clarabel's standard form with its cones interleaved (zero, non-negative,
    second-order, zero again: a fluid's zero-radius points come after the SOCs) answers
    with Clarabel's x, z (rows back in Clarabel's order, Clarabel's sign) and s, to solver
    tolerance; both satisfy the KKT stationarity P x + c + A^T z = 0."""
    import clarabel
    import scipy.sparse as sp
    from pfem_skfem.problems.backends import ENGINES
    rng = np.random.default_rng(3)
    n = 6
    M = rng.normal(size=(n, n))
    P = sp.csc_matrix(M @ M.T + np.eye(n))
    c = rng.normal(size=n)
    cones = [clarabel.ZeroConeT(2), clarabel.NonnegativeConeT(3),
             clarabel.SecondOrderConeT(3), clarabel.ZeroConeT(1), clarabel.NonnegativeConeT(2)]
    A = sp.csc_matrix(rng.normal(size=(11, n)))
    x0 = rng.normal(size=n)                # b chosen so that x0 with a cone-interior s is feasible
    s0 = np.concatenate([np.zeros(2), np.ones(3), [2.0, 0.5, 0.5], [0.0], np.ones(2)])
    b = A @ x0 + s0
    answers = {}
    for name in ("clarabel", "qoco"):
        engine = ENGINES[name]
        changes = dict(tol_gap_abs=1e-10, tol_gap_rel=1e-10, tol_feas=1e-10) \
            if name == "clarabel" else dict(abstol=1e-10, reltol=1e-10)
        sol = engine.solve(sp.triu(P, format="csc"), c, A, b, cones, engine.settings(changes))
        assert sol.status == "Solved"
        assert np.abs(P @ sol.x + c + A.T @ sol.z).max() < 1e-7
        assert np.abs(A @ sol.x + sol.s - b).max() < 1e-7
        answers[name] = sol
    ref, q = answers["clarabel"], answers["qoco"]
    for key in ("x", "z", "s"):
        assert rel(getattr(q, key), getattr(ref, key)) < 1e-6
    assert np.all(ref.z[[0, 1, 8]] != 0)   # the equalities carry multipliers: signs checked


def test_qoco_engine_refuses_exponential_cones():
    import clarabel
    from pfem_skfem.problems.backends.qoco import row_order
    with pytest.raises(ValueError, match="ExponentialConeT"):
        row_order([clarabel.ZeroConeT(1), clarabel.ExponentialConeT()])


def test_the_form_of_a_pfem_run_is_its_config_s_solver(monkeypatch):
    """``PFEMConfig(solver='clarabel-dual')`` states every step in the dual form (every solve
    goes through solve_dual), the default none; the primal form's run differs (a different
    solve) within solver tolerance; an unknown solver is refused by name, naming the
    choices."""
    from pfem_skfem.drivers.pfem_loop import run
    from pfem_skfem.problems.backends import direct
    from pfem_skfem.scene.config import PFEMConfig
    from verification.granular_column_plane import granular_column as column
    duals, real = [], direct.solve_dual
    monkeypatch.setattr(direct, "solve_dual", lambda *a, **k: duals.append(1) or real(*a, **k))
    dt = 0.05 * np.sqrt(1.0 / 9.8)
    dual_step = run(*column(1.0, 6, dt=dt, solver="clarabel-dual", passes=1), 1)[0]
    assert len(duals) == 1
    primal_step = run(*column(1.0, 6, dt=dt, passes=1), 1)[0]
    assert len(duals) == 1
    # one step, one pass: the same problem (later passes lag a non-unique mean stress)
    assert not np.array_equal(dual_step.v, primal_step.v)
    assert rel(dual_step.v, primal_step.v) < 1e-4
    with pytest.raises(ValueError, match="clarabel-dual"):
        PFEMConfig(solver="displacement")


@pytest.mark.parametrize("engine", ["clarabel", "qoco"])
def test_non_finite_conic_data_is_refused_before_the_solve(engine):
    """NaN or infinity in the data (a step whose positions went non-finite) is refused,
    naming the block, before the solver is asked (Clarabel would end 'NumericalError',
    naming no cause; QOCO raised nothing)."""
    import scipy.sparse as sp
    import clarabel
    from pfem_skfem.problems.backends import ENGINES
    P = sp.csc_matrix((2, 2))
    A = sp.csc_matrix(np.eye(2))
    cones = [clarabel.NonnegativeConeT(2)]
    solver = ENGINES[engine]
    solved = solver.solve(P, -np.ones(2), A, np.ones(2), cones, solver.settings({}))
    assert solved.status == "Solved"                     # max x1 + x2 with x <= 1: x = 1
    np.testing.assert_allclose(solved.x, 1.0, atol=1e-6)
    for name, data in (("c", (P, np.array([-1.0, np.nan]), A, np.ones(2))),
                       ("b", (P, -np.ones(2), A, np.array([np.inf, 1.0]))),
                       ("A", (P, -np.ones(2), sp.csc_matrix(np.diag([1.0, np.nan])),
                              np.ones(2)))):
        with pytest.raises(ValueError, match=f"conic problem's {name} holds 1 non-finite"):
            solver.solve(*data, cones, solver.settings({}))


@pytest.mark.parametrize("solver", ["scs", "scs-dual"])
def test_scs_as_an_engine_of_the_direct_assembly_agrees_with_clarabel(solver):
    """SCS (first order) handed the direct assembly, primal or dual form, at its tolerances
    of 1e-9: the elastoplastic step with supports and prescribed increments of Clarabel's
    direct assembly, to 1e-5 (an engine whose rows or signs were wrong is an O(1) miss)."""
    pytest.importorskip("scs")
    disc = discretise(MeshTri.init_tensor(np.linspace(0, 1, 5), np.linspace(0, 0.5, 3)))
    ops = dynamic_operators(disc, 2.0, ThetaMethod(0.05, 1.0, 0.5), Elastic(1e3, 0.3))
    base = lambda x: x[1] < 1e-9                                    # noqa: E731
    fixed, P = boundary_dofs(disc, base, 0), boundary_dofs(disc, base, 1)
    rng = np.random.default_rng(3)
    v_n = 0.1 * rng.standard_normal(disc.n_u)
    v_n[fixed] = 0.0
    args = (ops, *(2 * [gravity_vector(disc, 2.0, 9.8)]), rng.standard_normal((disc.n_points, 4)),
            v_n, Tresca(6.0))
    kw = dict(fixed=fixed, prescribed=(P, np.full(P.size, 1e-3)))
    ref = dynamic_increment(*args, solver="clarabel", **kw)
    res = dynamic_increment(*args, solver=solver, **kw)
    assert res.info.extra["engine"] == "scs"
    assert res.info.extra.get("form", "primal") == ("dual" if "dual" in solver else "primal")
    for name in ("du", "sigma", "r"):
        assert rel(getattr(res, name), getattr(ref, name)) <= 1e-5, name
