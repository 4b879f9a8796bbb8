"""Certified 'AlmostSolved' ends (pfem_skfem/problems/conic.py: ``certify``) and the
status hints of an over-constrained scene.

The thick hollow sphere a <= |x| <= b = 2a under internal pressure, in axisymmetry
(a quarter annulus in (r, z), u_z = 0 on z = 0, u_r = 0 on the axis, P2 geometry
following both circles). Closed forms of its collapse pressure (Hill 1950, ch. V;
research notes ``chapters-6-8.md``): Tresca 4 c ln(b/a); Mohr-Coulomb
c cot(phi) [(b/a)^(4 sin(phi)/(1 + sin(phi))) - 1]; the (7.10) cone equals
Mohr-Coulomb on the sphere's triaxial-compression states (the two hoop stresses equal
and larger than the radial one, tension positive), so the same closed form.
On the meshes below Clarabel stops 'AlmostSolved' (measured, book/axisymmetry.md).
"""
import warnings
from dataclasses import replace

import cvxpy as cp
import numpy as np
import pytest
from skfem import MeshTri2

from pfem_skfem.materials import MohrCoulombAxisymmetric, TrescaAxisymmetric, drucker_prager_match
from pfem_skfem.discretisation.meshes import triangulate_polygon
from pfem_skfem.discretisation.static import (assemble_B, boundary_dofs, boundary_facets, discretise,
                                  traction_vector)
from pfem_skfem.problems.axisymmetric import limit_analysis_axisymmetric
from pfem_skfem.problems.conic import CERTIFY, AlmostSolvedWarning, SolverError

A, B_OVER_A, C, PHI = 1.0, 2.0, 1.0, 30.0


def sphere_model(h):
    """The quarter annulus meshed by Triangle at size h, curved onto both circles;
    (disc, B, unit internal pressure f, fixed dofs)."""
    b = A * B_OVER_A
    n_in, n_out = int(np.ceil(np.pi / 2 * A / h)), int(np.ceil(np.pi / 2 * b / h))
    outer = [(b * np.cos(t), b * np.sin(t)) for t in np.linspace(0, np.pi / 2, n_out + 1)]
    inner = [(A * np.cos(t), A * np.sin(t)) for t in np.linspace(np.pi / 2, 0, n_in + 1)]
    points = np.array(outer + inner)
    points[np.abs(points) < 1e-14] = 0.0                        # exactly on the axes
    mesh = triangulate_polygon(points, h)
    m2 = MeshTri2.from_mesh(mesh)
    doflocs = m2.doflocs.copy()
    radius = np.linalg.norm(mesh.p, axis=0)
    for R in (A, b):                            # midside nodes of the arcs onto the circle
        on = np.abs(radius - R) < 1e-9
        dofs = m2.dofs.get_facet_dofs(np.flatnonzero(on[mesh.facets].all(axis=0))).flatten()
        d = doflocs[:, dofs]
        doflocs[:, dofs] = R * d / np.linalg.norm(d, axis=0)
    disc = discretise(replace(m2, doflocs=doflocs), "axisymmetric")
    fixed = boundary_dofs(disc, lambda x: x[1] < 1e-9, 1)              # u_z = 0 on z = 0
    bore = boundary_facets(disc, lambda x: np.hypot(x[0], x[1]) < A + 0.1 * h)
    f = traction_vector(disc, bore, lambda x: x / np.hypot(x[0], x[1]))   # unit pressure
    return disc, assemble_B(disc), f, fixed


def closed_form(criterion):
    if criterion == "tresca":
        return 4 * C * np.log(B_OVER_A)
    s = np.sin(np.radians(PHI))
    return C / np.tan(np.radians(PHI)) * (B_OVER_A ** (4 * s / (1 + s)) - 1)


CRITERIA = {"tresca": TrescaAxisymmetric(C), "mohr_coulomb": MohrCoulombAxisymmetric(C, PHI),
            "dp_7_10": drucker_prager_match(C, PHI)}


# (size, elements, criterion): ends measured 'AlmostSolved' (book/axisymmetry.md)
ALMOST_SOLVED = [(0.11, 701, "mohr_coulomb"), (0.11, 701, "dp_7_10"),
                 (0.09, 1046, "dp_7_10"), (0.072, 1638, "dp_7_10")]


@pytest.mark.parametrize("h, elements, criterion", ALMOST_SOLVED)
def test_sphere_limit_load_returns_certified_and_right(h, elements, criterion):
    """Every solve returns; the load factor is the closed form to 1e-5 (the
    discretisation's 1e-6 and the certified gap's bound 1e-5); an AlmostSolved end
    warns, stating its measures, which are within the bounds."""
    disc, B, f, fixed = sphere_model(h)
    assert disc.mesh.t.shape[1] == elements
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        lim = limit_analysis_axisymmetric(disc, B, f, CRITERIA[criterion], fixed=fixed)
    assert abs(lim.load_factor / closed_form(criterion) - 1) < 1e-5
    certified = [w for w in caught if issubclass(w.category, AlmostSolvedWarning)]
    assert len(certified) == (lim.info.status == cp.OPTIMAL_INACCURATE)
    measures = lim.info.extra["measures"]
    assert all(measures[name] <= bound for name, bound in CERTIFY.items())
    for w in certified:
        assert "relative gap" in str(w.message) and "primal residual" in str(w.message)
        assert f"{measures['gap_rel']:.1e}" in str(w.message)


def test_solved_sphere_does_not_warn_and_matches_the_closed_form():
    """A Solved end (Tresca on the same mesh) is returned as before, without a warning;
    its info carries Clarabel's measures, within Clarabel's full tolerances (1e-8)."""
    disc, B, f, fixed = sphere_model(0.11)
    with warnings.catch_warnings():
        warnings.simplefilter("error", AlmostSolvedWarning)
        lim = limit_analysis_axisymmetric(disc, B, f, CRITERIA["tresca"], fixed=fixed)
    assert lim.info.status == cp.OPTIMAL
    assert abs(lim.load_factor / closed_form("tresca") - 1) < 1e-5
    measures = lim.info.extra["measures"]
    assert measures["status"] == "Solved"
    assert max(measures["res_primal"], measures["res_dual"]) <= 1e-8
    assert min(measures["gap_rel"], measures["gap_abs"]) <= 1e-8


def test_uncertified_almost_solved_raises_naming_status_and_measures():
    """Reduced tolerances loosened to 1 and 5 iterations: Clarabel calls its fifth
    iterate 'AlmostSolved' with residuals and gap far beyond the bounds (measured: dual
    residual 1.1e-4, relative gap 0.11); it must be raised, the message naming the
    status and the measures, not returned."""
    disc, B, f, fixed = sphere_model(0.2)
    loose = dict(max_iter=5, reduced_tol_feas=1.0, reduced_tol_gap_abs=1.0,
                 reduced_tol_gap_rel=1.0, reduced_tol_ktratio=1.0)
    with pytest.raises(SolverError) as err:
        limit_analysis_axisymmetric(disc, B, f, CRITERIA["mohr_coulomb"], fixed=fixed, **loose)
    assert err.value.status == cp.OPTIMAL_INACCURATE
    message = str(err.value)
    assert "'optimal_inaccurate'" in message and "do not certify" in message
    assert "primal residual" in message and "relative gap" in message
    assert err.value.measures is not None
    assert any(err.value.measures[name] > bound for name, bound in CERTIFY.items())


def test_iteration_capped_solve_raises_naming_status_and_measures():
    """An iteration cap (Clarabel 'MaxIterations') is never returned; the message gives
    the measures."""
    disc, B, f, fixed = sphere_model(0.2)
    with pytest.raises(SolverError) as err:
        limit_analysis_axisymmetric(disc, B, f, CRITERIA["mohr_coulomb"], fixed=fixed,
                                    max_iter=2)
    assert err.value.status not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE)
    assert f"'{err.value.status}'" in str(err.value) and "primal residual" in str(err.value)


# -- an over-constrained scene: the status names what cannot be met ----------
def closed_box_squeeze(solver):
    """A cohesionless block filling a closed box whose right wall moves in: no
    displacement field keeps the (zero-dilation) block inside, the motion is impossible
    (../shared/RELIABILITY.md, section 4)."""
    from pfem_skfem.scene.config import PFEMConfig
    from pfem_skfem.materials import ZeroDilationMohrCoulomb
    from pfem_skfem.problems.contact import RigidSegment
    from pfem_skfem.discretisation import ThetaMethod
    from pfem_skfem.scene import Body, ConstantVelocity, Geostatic, Region, Scene

    block = Region([(0, 0), (1, 0), (1, 0.5), (0, 0.5)], ZeroDilationMohrCoulomb(c=0, phi=30),
                   rho=2.0, h=0.125, stress=Geostatic())
    bodies = [Body("base", RigidSegment((-1, 0), (3, 0), mu=0.0)),
              Body("lid", RigidSegment((3, 0.5), (-1, 0.5), mu=0.0)),
              Body("left", RigidSegment((0, 2), (0, -1), mu=0.0)),
              Body("right", RigidSegment((1, -1), (1, 2), mu=0.0),
                   motion=ConstantVelocity((-0.5, 0.0)))]
    config = PFEMConfig(theta=ThetaMethod(dt=0.02), solver=solver)
    # one step: the scene refuses a run to 0.2 s, whose box closes to 90 % of the block
    # (pfem_skfem.scene.enclosure); the first step's 1 % is left to the solver to name
    return Scene(regions=[block], bodies=bodies, config=config, t_end=0.02)


@pytest.mark.parametrize("solver", ["clarabel", "clarabel-dual", "cvxpy"])
def test_closed_box_squeeze_names_the_impossible_motion(solver):
    """The step's stated problem is the stress form: its displacement (dual) form is
    infeasible, so the stress form is unbounded, whichever form Clarabel is handed. The
    message must name the over-constrained motion, not 'a mechanism with no resistance'
    (that is the reading of an infeasible stress form)."""
    from pfem_skfem.drivers.pfem_loop import run

    scene = closed_box_squeeze(solver)
    with pytest.raises(SolverError) as err:
        run(scene.initial_state(), scene, 1)
    message = str(err.value)
    assert err.value.status == cp.UNBOUNDED
    assert "the prescribed motions cannot be met" in message
    assert "over-constrained" in message and "closed box" in message
    assert "no resistance" not in message


def test_load_beyond_collapse_names_the_stress_form_infeasible():
    """The other reading: a pressure 1.01 times the sphere's collapse load has no
    admissible stress field (an elastoplastic increment, (3.45)); the message says so."""
    from pfem_skfem.materials import Elastic
    from pfem_skfem.discretisation.static import assemble_C
    from pfem_skfem.problems.axisymmetric import static_increment_axisymmetric

    disc, B, f, fixed = sphere_model(0.2)
    with pytest.raises(SolverError) as err:
        static_increment_axisymmetric(disc, B, assemble_C(disc, Elastic(100.0, 0.3)),
                                      1.01 * closed_form("tresca") * f,
                                      np.zeros((disc.n_points, 4)), CRITERIA["tresca"],
                                      fixed=fixed)
    assert err.value.status == cp.INFEASIBLE
    assert "no admissible stress field equilibrates the loads" in str(err.value)
    assert "stress form is infeasible" in str(err.value)
