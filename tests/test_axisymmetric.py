"""Axisymmetry (thesis Ch 7): operators (7.24)-(7.28), cones (7.10) and exact Mohr-Coulomb,
static, limit and dynamic problems, and the verification scripts at --quick size."""

import cvxpy as cp
import numpy as np
import pytest
import scipy.sparse as sp
from skfem import MeshTri

from pfem_skfem.discretisation.geometry import AXISYMMETRIC, THESIS_ORDER, to_thesis_order
from pfem_skfem.materials import (drucker_prager_match, drucker_prager_radius, Elastic,
                                  mohr_coulomb_pair_radii, MohrCoulombAxisymmetric,
                                  TrescaAxisymmetric, TrescaField3, VonMisesField)
from pfem_skfem.discretisation.static import (assemble_B, assemble_C, axis_dofs, body_force_vector,
                                  boundary_dofs, boundary_facets, consistent_mass, discretise,
                                  stiffness_matrix, stress_mass, traction_vector)
from pfem_skfem.discretisation.dynamic import (assemble_A, assemble_D, gravity_vector, mass_matrix,
                                          r_basis)
from verification import thick_cylinder
from pfem_skfem.problems.axisymmetric import (limit_analysis_axisymmetric,
                                              static_increment_axisymmetric, with_axis)



def perturbed_block(n=3, r0=0.0, seed=0):
    """[r0, r0 + 1] x [0, 1] with perturbed interior nodes; the axis side stays straight."""
    m = MeshTri.init_symmetric().refined(n)
    p = m.p.copy()
    interior = np.setdiff1d(np.arange(p.shape[1]), m.boundary_nodes())
    rng = np.random.default_rng(seed)
    p[:, interior] += 0.15 / 2 ** n * rng.uniform(-1, 1, (2, interior.size))
    p[0] += r0
    return MeshTri(p, m.t)


def radial_axial_dofs(disc):
    ur = np.concatenate([disc.basis_u.nodal_dofs[0], disc.basis_u.facet_dofs[0]])
    uz = np.concatenate([disc.basis_u.nodal_dofs[1], disc.basis_u.facet_dofs[1]])
    return ur, uz


def random_stresses(n, seed=1):
    return np.random.default_rng(seed).normal(size=(n, 4))


def principal(sigma):
    """Principal stresses (n, 3) of stored (s_rr, s_zz, s_tt, s_rz) stresses."""
    s = 0.5 * (sigma[:, 0] + sigma[:, 1])
    R = np.hypot(0.5 * (sigma[:, 0] - sigma[:, 1]), sigma[:, 3])
    return np.sort(np.stack([s + R, s - R, sigma[:, 2]], axis=1), axis=1)


# -- geometry and operators --------------------------------------------------
def test_volume_is_the_volume_of_revolution():
    """sum of the r-weighted stress-point weights = pi ((r0+1)^2 - r0^2) x height."""
    for r0 in (0.0, 0.7):
        disc = discretise(perturbed_block(2, r0), AXISYMMETRIC)
        assert np.isclose(disc.area, np.pi * ((r0 + 1) ** 2 - r0 ** 2), rtol=1e-13)


def test_stress_mass_is_diagonal_with_exact_row_sums():
    """w_p = (area / 3) 2 pi r_p = int N_p 2 pi r dA (a quadratic integrand)."""
    disc = discretise(perturbed_block(2, 0.3), AXISYMMETRIC)
    M = stress_mass(disc)
    assert abs(M - sp.diags(M.diagonal())).max() < 1e-14 * M.diagonal().max()
    # int N_p 2 pi r dA by a degree-4 rule
    from skfem import Basis, LinearForm
    from pfem_skfem.discretisation.elements import stress_element
    basis = Basis(disc.mesh, stress_element(), intorder=4)

    @LinearForm
    def weight(v, w):
        return v * 2 * np.pi * w.x[0]

    exact = weight.assemble(basis)
    assert np.allclose(disc.weights, exact, rtol=1e-12)


def test_patch_test_uniform_strain_and_stress_with_hoop_component():
    """u_r = a r, u_z = b z: strain (a, b, a, 0) at every point; the elastic increment
    with that motion on the boundary reproduces it inside, and the uniform stress with
    s_rr = s_tt (the only uniform states in equilibrium) exactly."""
    disc = discretise(perturbed_block(3, 0.0), AXISYMMETRIC)
    B = assemble_B(disc)
    x = disc.basis_u.doflocs
    ur, uz = radial_axial_dofs(disc)
    a, b = 2e-3, -1e-3
    u = np.zeros(disc.n_u)
    u[ur], u[uz] = a * x[0, ur], b * x[1, uz]
    eps = (B @ u).reshape(-1, 4) / disc.weights[:, None]
    assert np.abs(eps - [a, b, a, 0]).max() < 1e-13
    el = Elastic(1000.0, 0.3)
    boundary = lambda X: np.ones(X.shape[1], dtype=bool)        # noqa: E731
    bd = np.concatenate([boundary_dofs(disc, boundary, 0), boundary_dofs(disc, boundary, 1)])
    bd = np.unique(bd)
    res = static_increment_axisymmetric(
        disc, B, assemble_C(disc, el), np.zeros(disc.n_u), np.zeros((disc.n_points, 4)),
        TrescaAxisymmetric(1e3), fixed=(), prescribed=(bd, u[bd]))
    sigma_ref = np.linalg.solve(el.compliance(), [a, b, a, 0])
    assert np.isclose(sigma_ref[0], sigma_ref[2])              # s_rr = s_tt
    assert np.abs(res.sigma - sigma_ref).max() < 1e-7 * np.abs(sigma_ref).max()
    assert np.abs(res.du - u).max() < 1e-7 * np.abs(u).max()


def test_r_weighted_mass_identity():
    """A^T D^-1 A = int rho~ N_u^T N_u 2 pi r dA, the consistent mass (4.26)-(4.27), (7.27)-(7.28)."""
    disc = discretise(perturbed_block(2, 0.0), AXISYMMETRIC)
    rho = np.random.default_rng(3).uniform(1.0, 3.0, disc.mesh.nelements)
    basis_r = r_basis(disc)
    A, D = assemble_A(disc, basis_r), assemble_D(disc, rho, basis_r)
    M = mass_matrix(disc, rho)
    MA = A.T @ sp.csr_matrix(np.linalg.inv(D.toarray())) @ A
    assert abs(MA - M).max() < 1e-10 * abs(M).max()
    # and the mass of the body: u_z = 1 everywhere gives the total mass
    _, uz = radial_axial_dofs(disc)
    one = np.zeros(disc.n_u)
    one[uz] = 1.0
    from skfem import Functional
    total = Functional(lambda w: w.rho * 2 * np.pi * w.x[0]).assemble(
        disc.basis_u.with_element(disc.basis_u.elem), rho=np.repeat(rho[:, None], 3, axis=1))
    assert np.isclose(one @ M @ one, total, rtol=1e-12)


def test_weights_and_loads_carry_2_pi_r():
    """Self-weight, body force and a traction total the force on the body of revolution."""
    r0 = 0.5
    disc = discretise(perturbed_block(2, r0), AXISYMMETRIC)
    vol = np.pi * ((r0 + 1) ** 2 - r0 ** 2)
    _, uz = radial_axial_dofs(disc)
    assert np.isclose(gravity_vector(disc, 2.0, 9.8)[uz].sum(), -2.0 * 9.8 * vol, rtol=1e-13)
    assert np.isclose(body_force_vector(disc, (0.0, 3.0))[uz].sum(), 3.0 * vol, rtol=1e-13)
    top = boundary_facets(disc, lambda x: x[1] > 1 - 1e-9)
    t = traction_vector(disc, top, (0.0, -5.0))
    assert np.isclose(t[uz].sum(), -5.0 * vol, rtol=1e-13)
    M = consistent_mass(disc, 2.0)
    ones = np.zeros(disc.n_u)
    ones[uz] = 1.0
    assert np.isclose(ones @ M @ ones, 2.0 * vol, rtol=1e-13)


def test_axis_dofs_are_the_radial_dofs_on_r_zero():
    disc = discretise(perturbed_block(2, 0.0), AXISYMMETRIC)
    dofs = axis_dofs(disc)
    x = disc.basis_u.doflocs
    ur, _ = radial_axial_dofs(disc)
    assert np.all(np.isin(dofs, ur))
    assert np.all(x[0, dofs] == 0)
    assert dofs.size == np.sum(x[0, ur] == 0) == 2 * 4 + 1     # 5 corners, 4 midsides
    assert axis_dofs(discretise(perturbed_block(2, 0.0))).size == 0


def test_mixed_stiffness_tends_to_the_standard_axisymmetric_stiffness():
    """B^T C^-1 B is not the standard stiffness in axisymmetry (u_r / r is not linear), but
    their energies on a smooth field converge to each other with the mesh."""
    diffs = []
    for n in (1, 2, 3):
        disc = discretise(perturbed_block(n, 0.5), AXISYMMETRIC)
        el = Elastic(1.0, 0.3)
        B, C = assemble_B(disc), assemble_C(disc, el)
        Cinv = sp.kron(sp.diags(1 / stress_mass(disc).diagonal()),
                       np.linalg.inv(el.compliance()))
        x = disc.basis_u.doflocs
        ur, uz = radial_axial_dofs(disc)
        u = np.zeros(disc.n_u)
        u[ur] = np.sin(x[0, ur]) * x[1, ur]
        u[uz] = np.cos(x[1, uz]) * x[0, uz]
        e_mixed = u @ (B.T @ (Cinv @ (B @ u)))
        e_std = u @ (stiffness_matrix(disc, el) @ u)
        diffs.append(abs(e_mixed - e_std) / e_std)
    order = np.log2(diffs[0] / diffs[1]), np.log2(diffs[1] / diffs[2])
    assert diffs[2] < diffs[1] < diffs[0], diffs
    assert min(order) > 1.5, f"observed order {order}"


@pytest.mark.parametrize("p, message", [
    (np.array([[-0.1, 1.0, 0.0], [0.0, 0.0, 1.0]]), "r = 0"),      # crosses the axis
    (np.array([[-1.0, -0.5, -1.0], [0.0, 0.0, 1.0]]), "r < 0"),    # a node at r < 0
])
def test_bad_axisymmetric_meshes_are_refused(p, message):
    mesh = MeshTri(p, np.array([[0], [1], [2]]))
    with pytest.raises(ValueError, match=message):
        discretise(mesh, "axisymmetric")
    discretise(mesh)                                              # fine in plane strain


def test_bad_geometry_name_and_phi_are_refused():
    with pytest.raises(ValueError, match="geometry"):
        discretise(perturbed_block(1), "spherical")
    for phi in (-5.0, 90.0, 120.0):
        with pytest.raises(ValueError, match="phi"):
            MohrCoulombAxisymmetric(1.0, phi)
        with pytest.raises(ValueError, match="phi"):
            drucker_prager_match(1.0, phi)
    with pytest.raises(ValueError, match="match"):
        drucker_prager_match(1.0, 30.0, "plane")
    with pytest.raises(ValueError, match="axisymmetric"):
        with_axis(discretise(perturbed_block(1)), [])


def test_thesis_order():
    s = np.array([[1.0, 2.0, 3.0, 4.0]])                        # stored (rr, zz, tt, rz)
    assert np.all(to_thesis_order(s) == [[1.0, 3.0, 2.0, 4.0]])  # (7.5): (rr, tt, zz, rz)
    assert THESIS_ORDER == (0, 2, 1, 3)


# -- cones -------------------------------------------------------------------
@pytest.mark.parametrize("phi", [0.0, 20.0, 28.0, 30.0, 40.0])
def test_7_10_cone_equals_mohr_coulomb_in_triaxial_compression(phi):
    """On stress states with the two largest principal stresses equal (tension +), the
    (7.10) cone and Mohr-Coulomb give the same failure load: F_DP = 0 exactly when
    (s1 - s3) + (s1 + s3) sin(phi) = 2c cos(phi)."""
    c = 1.3
    dp = drucker_prager_match(c, phi)                             # (7.10) as printed
    sn, co = np.sin(np.radians(phi)), np.cos(np.radians(phi))
    assert np.isclose(dp.alpha, 2 * sn / (np.sqrt(3) * (3 - sn)))
    assert np.isclose(dp.k, 6 * c * co / (np.sqrt(3) * (3 - sn)))
    rng = np.random.default_rng(int(phi))
    s3 = rng.uniform(-10, 0, 50)                                # the minor stress
    # s1 = s2 at Mohr-Coulomb failure with s3
    s1 = (2 * c * co + s3 * (1 - sn)) / (1 + sn)
    for layout in ((s1, s3, s1), (s3, s1, s1), (s1, s1, s3)):   # which one is the hoop stress
        sigma = np.stack([layout[0], layout[1], layout[2], 0 * s1], axis=1)
        assert np.abs(dp.F(sigma)).max() < 1e-12 * max(1, np.abs(sigma).max())
        assert np.abs(MohrCoulombAxisymmetric(c, phi).F(sigma)).max() < 1e-12 * np.abs(
            sigma).max()
    # in triaxial extension (s1 > s2 = s3) the Mohr-Coulomb failure state lies strictly
    # inside the (7.10) cone for phi > 0: it is the outer cone (at phi = 0 both meridians
    # have the same radius)
    sigma = np.stack([s1, s3, s3, 0 * s3], axis=1)
    if phi > 0:
        assert np.all(dp.F(sigma) < -1e-3 * c)
    else:
        assert np.abs(dp.F(sigma)).max() < 1e-12 * np.abs(sigma).max()


@pytest.mark.parametrize("phi", [0.0, 15.0, 30.0, 45.0])
def test_three_cones_are_mohr_coulomb_on_principal_stresses(phi):
    """max of the three cones <= 0 iff (s1 - s3) + (s1 + s3) sin(phi) <= 2c cos(phi)."""
    c = 1.0
    crit = MohrCoulombAxisymmetric(c, phi)
    sigma = random_stresses(2000, seed=int(phi) + 1)
    ps = principal(sigma)
    sn, co = np.sin(np.radians(phi)), np.cos(np.radians(phi))
    f_mc = (ps[:, 2] - ps[:, 0]) + (ps[:, 2] + ps[:, 0]) * sn - 2 * c * co
    inside = crit.F(sigma) <= 0
    assert np.all(inside == (f_mc <= 0))
    assert crit.F(sigma).shape == (2000,)
    # on the surface: scale the deviatoric part of each state onto it
    mean = sigma[:, [0, 1, 2]].mean(axis=1)
    dev = sigma.copy()
    dev[:, :3] -= mean[:, None]
    dps = principal(dev)
    lam = (2 * c * co - 2 * mean * sn) / ((dps[:, 2] - dps[:, 0]) + (dps[:, 2] + dps[:, 0]) * sn)
    ok = lam > 0
    on = dev[ok] * lam[ok, None]
    on[:, :3] += mean[ok, None]
    assert np.abs(crit.F(on)).max() < 1e-12 * np.abs(on).max()


def test_tresca_axisymmetric_is_max_shear():
    sigma = random_stresses(500, seed=7)
    ps = principal(sigma)
    crit = TrescaAxisymmetric(0.9)
    assert np.all((crit.F(sigma) <= 0) == (ps[:, 2] - ps[:, 0] <= 1.8))


def test_cones_agree_in_cvxpy_and_on_arrays():
    """Push each stress state radially from the origin to the largest admissible multiple
    in cvxpy; on arrays F there is zero (the same cone_vector builds both)."""
    n = 12
    direction = random_stresses(n, seed=11)
    radii = np.abs(random_stresses(n, seed=12)[:, 0]) + 1.0
    for crit in (MohrCoulombAxisymmetric(1.5, 25.0), TrescaAxisymmetric(1.5),
                 VonMisesField(radii), TrescaField3(np.vstack([radii] * 3) * 2),
                 drucker_prager_match(1.5, 25.0)):
        lam = cp.Variable(n)
        S = cp.multiply(cp.reshape(lam, (n, 1), order="C"), direction)
        problem = cp.Problem(cp.Maximize(cp.sum(lam)), [crit.constraint(S), lam <= 1e3])
        problem.solve(solver=cp.CLARABEL)
        assert problem.status == cp.OPTIMAL
        on = lam.value[:, None] * direction
        bounded = lam.value < 1e3 - 1e-3
        assert np.abs(crit.F(on[bounded])).max() < 1e-6 * np.abs(on).max(), crit.name


def test_zero_dilation_radii_reproduce_the_cone_at_the_lagged_stress():
    """At the lagged stress itself the zero-dilation cones coincide with the originals:
    F_field(sigma) <= 0 iff F(sigma) <= 0 (and = 0 on the surface)."""
    c, phi = 1.0, 30.0
    sigma = random_stresses(300, seed=5)
    mc = MohrCoulombAxisymmetric(c, phi)
    field = TrescaField3(mohr_coulomb_pair_radii(c, phi, sigma, floor=1e-9))
    ok = np.all(mohr_coulomb_pair_radii(c, phi, sigma, floor=1e-9) > 1e-9, axis=0)
    assert np.all((field.F(sigma)[ok] <= 0) == (mc.F(sigma)[ok] <= 0))
    dp = drucker_prager_match(c, phi)
    vm = VonMisesField(drucker_prager_radius(dp, sigma, floor=1e-9))
    ok = dp.k - dp.alpha * sigma[:, :3].sum(axis=1) > 1e-9
    assert np.allclose(vm.F(sigma)[ok], dp.F(sigma)[ok], atol=1e-12)


# -- problems ----------------------------------------------------------------
def test_limit_analysis_under_pressure_is_bounded_by_the_rigid_bore():
    """Thick cylinder: the load-controlled limit analysis (uniform pressure on the bore)
    lies between the closed form and the displacement-controlled one (a rigid bore: its
    stress fields are admissible for the latter, so p_load <= p_disp on the same mesh)."""
    cyl = thick_cylinder
    model = cyl.cylinder_model(1.0, 2.0, 8)
    disc = model["disc"]
    bore = boundary_facets(disc, lambda x: x[0] < 1 + 1e-9)
    f_live = traction_vector(disc, bore, (1.0, 0.0))            # unit pressure, ring force
    crit = TrescaAxisymmetric(1.0)
    lim = limit_analysis_axisymmetric(disc, model["B"], f_live, crit, fixed=model["fixed"])
    p_disp, _ = cyl.limit_pressure(model, crit)
    assert 2 * np.log(2) <= lim.load_factor <= p_disp * (1 + 1e-7)
    assert p_disp <= 2 * np.log(2) * 1.001


# -- dynamics: (7.29) and (7.30) ---------------------------------------------
def granular_cylinder(nr=4, nz=6, r0=0.5, h0=1.0, wall=False, mu=np.tan(np.radians(30))):
    """A cylinder r <= r0, 0 <= z <= h0 on a rigid base (7.30); optionally a smooth wall at r0."""
    from pfem_skfem.problems.contact import RigidSegment, potential_contacts
    mesh = MeshTri.init_tensor(np.linspace(0, r0, nr + 1), np.linspace(0, h0, nz + 1))
    disc = discretise(mesh, AXISYMMETRIC)
    base = RigidSegment((-1.0, 0.0), (r0 + 1.0, 0.0), mu=mu)
    contacts = potential_contacts(disc, [base], search_distance=1e-9 * h0)
    fixed = boundary_dofs(disc, lambda x: x[0] > r0 - 1e-9, 0) if wall else np.zeros(0, int)
    return disc, contacts, fixed


def gravity_step(disc, contacts, fixed, criterion, solver, rho=2.0, g=9.8, dt=None):
    from pfem_skfem.problems.axisymmetric import dynamic_step_axisymmetric
    from pfem_skfem.problems.step_terms import Contact
    from pfem_skfem.discretisation import ThetaMethod, dynamic_operators
    dt = dt or 0.01 * np.sqrt(1.0 / g)
    ops = dynamic_operators(disc, rho, ThetaMethod(dt, 1.0, 1.0))
    f = gravity_vector(disc, rho, g)
    return dynamic_step_axisymmetric(disc, ops, f, f, np.zeros((disc.n_points, 4)),
                                     np.zeros(disc.n_u), criterion, fixed=fixed,
                                     terms=[Contact(contacts)], solver=solver), ops


@pytest.mark.parametrize("criterion", [drucker_prager_match(0.0, 30.0),
                                       MohrCoulombAxisymmetric(0.0, 30.0)],
                         ids=["dp_7_10", "mohr_coulomb_3_cones"])
@pytest.mark.parametrize("form", ["primal", "dual"])
def test_dynamic_step_with_contact_cvxpy_equals_direct_clarabel(criterion, form):
    """(7.30) for a collapsing granular cylinder on a rough base: the cvxpy statement and
    the direct Clarabel assembly give the same step. Unique in a rigid-plastic step: du,
    the dynamic forces r (strictly concave objective in r), the resultant base force;
    the stresses need not be unique, so each is checked admissible instead."""
    disc, contacts, fixed = granular_cylinder()
    ref, _ = gravity_step(disc, contacts, fixed, criterion, "cvxpy")
    out, _ = gravity_step(disc, contacts, fixed, criterion,
                          "clarabel-dual" if form == "dual" else "clarabel")
    assert out.info.status == ref.info.status == "optimal"
    assert out.info.extra.get("form", "primal") == form
    assert np.abs(out.du - ref.du).max() < 1e-5 * np.abs(ref.du).max()
    assert np.abs(out.r - ref.r).max() < 1e-5 * np.abs(ref.r).max()
    assert abs(out.p.sum() / ref.p.sum() - 1) < 1e-6
    assert abs(out.q.sum() - ref.q.sum()) < 1e-6 * ref.p.sum()
    for res in (ref, out):
        assert criterion.F(res.sigma).max() < 1e-6 * np.abs(res.sigma).max()
        assert np.all(res.du[axis_dofs(disc)] == 0)             # u_r = 0 on the axis


@pytest.mark.parametrize("solver", ["cvxpy", "clarabel"])
def test_confined_granular_cylinder_carries_its_weight(solver):
    """A rigid-plastic granular cylinder in a smooth-walled container on a rough base is at
    rest under gravity: the base reaction (ring forces of (7.30)) is rho g pi r0^2 h0."""
    r0, h0, rho, g = 0.5, 1.0, 2.0, 9.8
    disc, contacts, fixed = granular_cylinder(r0=r0, h0=h0, wall=True)
    step, _ = gravity_step(disc, contacts, fixed, MohrCoulombAxisymmetric(0.0, 30.0), solver,
                           rho=rho, g=g)
    weight = rho * g * np.pi * r0 ** 2 * h0
    assert abs(step.p.sum() / weight - 1) < 1e-6
    dt = 0.01 * np.sqrt(h0 / g)
    assert np.abs(step.du).max() < 1e-6 * g * dt ** 2              # at rest: no motion


def test_free_granular_cylinder_base_reaction_is_weight_plus_inertia():
    """Summing the vertical rows of (7.30): sum p - int r_z dV = rho g pi r0^2 h0 (the rigid
    translation has no strain), with the 2 pi r weight in gravity, A and the ring forces."""
    r0, h0, rho, g = 0.5, 1.0, 2.0, 9.8
    disc, contacts, fixed = granular_cylinder(r0=r0, h0=h0)
    step, ops = gravity_step(disc, contacts, fixed, drucker_prager_match(0.0, 30.0), "cvxpy",
                             rho=rho, g=g)
    _, uz = radial_axial_dofs(disc)
    inertia = (ops.A.T @ step.r)[uz].sum()
    weight = rho * g * np.pi * r0 ** 2 * h0
    assert abs((step.p.sum() - inertia) / weight - 1) < 1e-6
    assert step.p.sum() < weight                                # it starts to fall


def test_elastic_history_equals_the_theta_method_of_the_same_mesh():
    """Elastic (7.29) over 12 steps (theta1 = theta2 = 1/2) against the theta-method of
    (7.13) written as one linear solve per step, with K = B^T C^-1 B and scikit-fem's
    r-weighted consistent mass: the same discrete system, so to solver accuracy."""
    from pfem_skfem.problems.axisymmetric import dynamic_step_axisymmetric
    from pfem_skfem.discretisation import ThetaMethod, dynamic_operators
    mesh = MeshTri.init_tensor(np.linspace(0, 0.5, 4), np.linspace(0, 1.0, 7))
    disc = discretise(mesh, AXISYMMETRIC)
    el, rho = Elastic(3e3, 0.3), 1.0
    th1, th2, dt, n_steps = 0.5, 0.5, 0.02, 12
    ops = dynamic_operators(disc, rho, ThetaMethod(dt, th1, th2), el)
    fixed = with_axis(disc, np.concatenate([boundary_dofs(disc, lambda x: x[1] < 1e-9, 0),
                                            boundary_dofs(disc, lambda x: x[1] < 1e-9, 1)]))
    top = boundary_facets(disc, lambda x: x[1] > 1 - 1e-9)
    side = boundary_facets(disc, lambda x: x[0] > 0.5 - 1e-9)
    f_top, f_side = traction_vector(disc, top, (0.0, -1.0)), traction_vector(disc, side, (-1, 0))
    load = lambda t: min(t / (4 * dt), 1.0) * (f_top + 0.5 * f_side)     # noqa: E731
    # reference: [M/(th2 dt^2) + th1 K] du = M v/(th2 dt) + f_th - K u
    free = np.setdiff1d(np.arange(disc.n_u), fixed)
    B, C = assemble_B(disc), assemble_C(disc, el)
    K = (B.T @ sp.csr_matrix(np.linalg.inv(C.toarray())) @ B).tocsr()   # small: dense inverse
    M = consistent_mass(disc, rho)
    lhs = (M / (th2 * dt ** 2) + th1 * K)[free][:, free].toarray()
    u_ref, v_ref = np.zeros(disc.n_u), np.zeros(disc.n_u)
    u, v, sigma = np.zeros(disc.n_u), np.zeros(disc.n_u), np.zeros((disc.n_points, 4))
    scales, diffs, peak = None, [], 0.0
    for i in range(n_steps):
        f_n, f_next = load(i * dt), load((i + 1) * dt)
        rhs = M @ v_ref / (th2 * dt) + th1 * f_next + (1 - th1) * f_n - K @ u_ref
        du_ref = np.zeros(disc.n_u)
        du_ref[free] = np.linalg.solve(lhs, rhs[free])
        v_ref = (du_ref / dt - (1 - th2) * v_ref) / th2
        u_ref = u_ref + du_ref
        step = dynamic_step_axisymmetric(disc, ops, f_n, f_next, sigma, v, None, fixed=fixed,
                                         scaling=scales)
        u, v, sigma, scales = u + step.du, step.v, step.sigma, step.scales
        peak = max(peak, np.abs(u_ref).max())
        diffs.append(np.abs(u - u_ref).max())
    assert max(diffs) < 1e-6 * peak, max(diffs) / peak


def test_elastic_history_tends_to_the_standard_displacement_fe():
    """Against the standard axisymmetric displacement element (stiffness with u_r / r
    integrated exactly) the mixed element differs by its discretisation of the hoop
    strain: the theta-method histories converge to each other at order ~2 in h."""
    from scipy.sparse.linalg import splu
    from pfem_skfem.discretisation.dynamic import block_inverse
    el, rho, th, dt, n_steps = Elastic(3e3, 0.3), 1.0, 0.5, 0.02, 8
    diffs = []
    for n in (1, 2, 4):
        mesh = MeshTri.init_tensor(np.linspace(0, 0.5, 3 * n + 1), np.linspace(0, 1.0, 6 * n + 1))
        disc = discretise(mesh, AXISYMMETRIC)
        fixed = with_axis(disc, np.concatenate([
            boundary_dofs(disc, lambda x: x[1] < 1e-9, 0),
            boundary_dofs(disc, lambda x: x[1] < 1e-9, 1)]))
        top = boundary_facets(disc, lambda x: x[1] > 1 - 1e-9)
        f0 = traction_vector(disc, top, (0.0, -1.0))
        free = np.setdiff1d(np.arange(disc.n_u), fixed)
        B, C = assemble_B(disc), assemble_C(disc, el)
        K_mixed = B.T @ block_inverse(C, 4) @ B
        M = consistent_mass(disc, rho)
        histories = []
        for K in (K_mixed, stiffness_matrix(disc, el)):
            lhs = splu((M / (th * dt ** 2) + th * K).tocsc()[free][:, free].tocsc())
            u, v, hist = np.zeros(disc.n_u), np.zeros(disc.n_u), []
            for i in range(n_steps):
                load = th * min((i + 1) / 4, 1) + (1 - th) * min(i / 4, 1)
                rhs = M @ v / (th * dt) + load * f0 - K @ u
                du = np.zeros(disc.n_u)
                du[free] = lhs.solve(rhs[free])
                v, u = (du / dt - (1 - th) * v) / th, u + du
                hist.append(u)
            histories.append(np.array(hist))
        diffs.append(np.abs(histories[0] - histories[1]).max() / np.abs(histories[1]).max())
    orders = np.log2(np.array(diffs[:-1]) / np.array(diffs[1:]))
    assert diffs[-1] < 1e-4 and np.all(orders > 1.5), (diffs, orders)
