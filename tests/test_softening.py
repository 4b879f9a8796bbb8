"""The softening laws, the plastic strain increment and the regularisation
(pfem_skfem.materials.softening), and the step control's refusals (drivers.softening)."""
import numpy as np
import pytest
from pytest import approx
from skfem import MeshTri

from pfem_skfem.discretisation.static import assemble_B, assemble_C, discretise
from pfem_skfem.drivers.softening import StepControl, point_sizes, softening_control
from pfem_skfem.materials import Elastic
from pfem_skfem.materials.softening import (ExponentialSoftening, FractureEnergy,
                                            LinearSoftening, SofteningMohrCoulomb,
                                            SofteningTresca, nonlocal_average,
                                            plastic_strain_increment, shear_invariant,
                                            strength_drop)

LINEAR = LinearSoftening(c_p=20.0, c_r=5.0, gamma_r=0.75)
EXPONENTIAL = ExponentialSoftening(c_p=20.0, c_r=5.0, gamma_95=2.0)


def test_the_linear_law_falls_at_H_to_c_r_and_stays():
    g = np.array([0.0, 0.25, 0.75, 3.0])
    assert LINEAR.strength(g) == approx([20.0, 20.0 - 15.0 / 0.75 * 0.25, 5.0, 5.0])
    assert LINEAR.steepest_rate == approx(20.0)                # |H| = (c_p - c_r) / gamma_r
    # a scale stretches the strain axis: the same strength at scale times the strain
    assert LINEAR.strength(0.5, scale=2.0) == approx(LINEAR.strength(0.25))


def test_the_exponential_law_has_lost_95_percent_at_gamma_95():
    # exp(-3) = 0.0498: 95.0 % of c_p - c_r spent at gamma_95
    spent = (20.0 - EXPONENTIAL.strength(2.0)) / 15.0
    assert spent == approx(1 - np.exp(-3.0), rel=1e-12) and spent == approx(0.95, abs=1e-3)
    assert EXPONENTIAL.strength(0.0) == approx(20.0)
    # the initial slope is its steepest: -3 (c_p - c_r) / gamma_95
    d = 1e-7
    assert (EXPONENTIAL.strength(0.0) - EXPONENTIAL.strength(d)) / d == \
        approx(EXPONENTIAL.steepest_rate, rel=1e-6)


def test_the_exponential_laws_step_drop_is_its_closed_form_on_a_point():
    """One point from gamma_0 by Delta gamma^p: the drop over c_p - c_r is
    exp(-3 gamma_0 / gamma_95) (1 - exp(-3 Delta / gamma_95)), c before minus c after; not the
    steepest-rate bound 3 Delta / gamma_95 the control took before (issue: it kept halving dt
    for remoulded debris). gamma_95 = 2, element size 1, no regularisation."""
    material = SofteningTresca(EXPONENTIAL, Elastic(1e4, 0.3))
    size = np.ones(1)
    for g0, dg in ((0.0, 0.1), (0.5, 0.2), (4.0, 0.3), (12.0, 1.0)):
        exact = np.exp(-3 * g0 / 2.0) * (1 - np.exp(-3 * dg / 2.0))
        drop = strength_drop(material, np.array([g0]), np.array([g0 + dg]), size)
        assert drop == approx(exact, rel=1e-13)
        c = material.strength(np.array([g0, g0 + dg]), np.ones(2))
        assert drop == approx((c[0] - c[1]) / 15.0, rel=1e-9)
        assert drop < 3 * dg / 2.0                      # below the old bound, far below it
    # remoulded debris (gamma^p = 12 = 6 gamma_95: c - c_r = 1.5e-8 (c_p - c_r)) drops
    # next to nothing, however far it shears in the step
    assert strength_drop(material, np.array([12.0]), np.array([112.0]), size) < 2e-8
    # the largest over the points; a fracture energy's scale ell / h stretches gamma_95
    g0, g1 = np.array([0.0, 1.0, 6.0]), np.array([0.05, 1.5, 9.0])
    drops = np.exp(-1.5 * g0) * -np.expm1(-1.5 * (g1 - g0))
    assert strength_drop(material, g0, g1, np.ones(3)) == approx(drops.max(), rel=1e-13)
    stretched = SofteningTresca(EXPONENTIAL, Elastic(1e4, 0.3), FractureEnergy(0.5))
    assert strength_drop(stretched, g0, g1, np.full(3, 0.25)) == approx(
        (np.exp(-0.75 * g0) * -np.expm1(-0.75 * (g1 - g0))).max(), rel=1e-13)


def test_the_linear_laws_step_drop_is_H_times_delta_at_the_points_above_c_r():
    """abs(H) Delta gamma^p / (c_p - c_r) = Delta / gamma_r on the slope (the measure of before,
    to the bit), the law's exact drop there; a point that reaches c_r within the step keeps
    the bound (the linear law's recorded runs stand), its exact drop the c_old - c_r left;
    0 at c_r."""
    material = SofteningTresca(LINEAR, Elastic(1e4, 0.3))
    one = np.ones(1)
    on_slope = strength_drop(material, np.array([0.2]), np.array([0.5]), one)
    assert on_slope == (LINEAR.steepest_rate / 1.0 * (0.5 - 0.2)) / 15.0
    assert on_slope == approx(0.3 / 0.75, rel=1e-14)
    assert LINEAR.drop(0.2, 0.5) / 15.0 == on_slope
    assert strength_drop(material, np.array([0.6]), np.array([2.0]), one) == \
        approx(1.4 / 0.75, rel=1e-12)                   # crosses c_r: the bound, kept
    assert LINEAR.drop(0.6, 2.0) == approx(15.0 * 0.15 / 0.75, rel=1e-12)   # exact: 3 kPa
    assert strength_drop(material, np.array([0.75]), np.array([2.0]), one) == 0.0
    assert LINEAR.drop(0.75, 2.0) == 0.0


def uniform_shear(material, gamma0, max_drop):
    """One base increment of simple shear u = (Delta y, 0) imposed at every node of the unit
    square (two elements, all dofs prescribed): each stress point its own problem.
    Delta = 0.5 + c(gamma0) / G: taken at once, the shear stress c(gamma0) and
    Delta gamma^p = 0.5."""
    disc = discretise(MeshTri())
    G = material.elastic.E / (2 * (1 + material.elastic.nu))
    delta = 0.5 + material.law.strength(gamma0) / G
    total = delta * disc.basis_u.doflocs[1]         # at u_x, the even dofs (interleaved)
    total[1::2] = 0.0
    n = disc.n_points
    return softening_control(assemble_B(disc), assemble_C(disc, material.elastic), material,
                             fixed=[], prescribed=(np.arange(disc.n_u), total),
                             n_increments=1, size=point_sizes(disc.weights),
                             weights=disc.weights, gamma0=np.full(n, gamma0),
                             control=StepControl(max_drop=max_drop))


def test_the_steepest_drop_is_the_laws_steepest_rate_times_delta_above_c_r_on_a_point():
    """strength_drop(steepest=True), the static increments' measure: 3 Delta / gamma_95 for
    the exponential law wherever c > c_r, remoulded or not (the bound the dynamic control
    left); the linear law's own measure, to the bit."""
    material = SofteningTresca(EXPONENTIAL, Elastic(1e4, 0.3))
    one = np.ones(1)
    for g0, dg in ((0.0, 0.1), (4.0, 0.3), (12.0, 1.0)):
        bound = strength_drop(material, np.array([g0]), np.array([g0 + dg]), one,
                              steepest=True)
        assert bound == approx(3 * dg / 2.0, rel=1e-13)
        assert bound >= strength_drop(material, np.array([g0]), np.array([g0 + dg]), one)
    stretched = SofteningTresca(EXPONENTIAL, Elastic(1e4, 0.3), FractureEnergy(0.5))
    assert strength_drop(stretched, np.array([1.0]), np.array([1.2]), np.full(1, 0.25),
                         steepest=True) == approx(3 * 0.2 / (2.0 * 2.0), rel=1e-13)
    linear = SofteningTresca(LINEAR, Elastic(1e4, 0.3))
    for g0, g1 in ((0.2, 0.5), (0.6, 2.0), (0.75, 2.0)):
        assert strength_drop(linear, np.array([g0]), np.array([g1]), one, steepest=True) == \
            strength_drop(linear, np.array([g0]), np.array([g1]), one)


@pytest.mark.parametrize("law, g0", [(LINEAR, 0.0), (EXPONENTIAL, 0.0), (EXPONENTIAL, 12.0)],
                         ids=["linear", "exponential", "exponential-remoulded"])
def test_the_static_control_halves_an_increment_over_the_steepest_drop(law, g0):
    """One increment of Delta gamma^p = 0.5 at every point, cap 0.6: the steepest-rate
    measure is 0.5 / 0.75 = 0.667 (linear) or 3 x 0.5 / 2 = 0.75 (exponential, from the peak
    or remoulded at gamma_0 = 6 gamma_95, where the exact drop is 1e-8): re-solved at half
    the motion and taken in two halves. Closed forms at each point: the first half yields at
    c_0 = c(gamma_0) and leaves gamma_1 = gamma_0 + Delta / 2 - c_0 / G; the second ends at
    tau = c(gamma_1), gamma^p = gamma_0 + Delta - c(gamma_1) / G."""
    material = SofteningTresca(law, Elastic(1e4, 0.3))
    run = uniform_shear(material, g0, 0.6)
    assert run.solves == 3 and run.uncapped == 0 and list(run.factors) == [0.0, 0.5, 1.0]
    G = 1e4 / 2.6
    c0 = law.strength(g0)
    delta = 0.5 + c0 / G
    c1 = law.strength(g0 + delta / 2 - c0 / G)
    gamma = g0 + delta - c1 / G
    assert run.gamma_p == approx(np.full(6, gamma), rel=1e-9)
    assert run.sigma[:, 3] == approx(np.full(6, c1), rel=1e-7)
    assert run.strength == approx(law.strength(np.full(6, gamma)), rel=1e-8)


@pytest.mark.parametrize("law", [LINEAR, EXPONENTIAL], ids=["linear", "exponential"])
def test_strain_at_inverts_strength(law):
    c = np.array([19.9, 12.0, 5.5])
    assert law.strength(law.strain_at(c, 1.7), 1.7) == approx(c, rel=1e-12)


@pytest.mark.parametrize("law", [LINEAR, EXPONENTIAL], ids=["linear", "exponential"])
def test_fracture_energy_makes_the_band_energy_independent_of_h(law):
    """h x (energy per unit volume at scale ell / h) = ell x (energy at scale 1): G_f."""
    reg, ell = FractureEnergy(0.1), 0.1
    for h in (0.1, 0.05, 0.025, 0.2):
        assert h * law.softening_energy(reg.scale(h)) == approx(ell * law.softening_energy())
    # the linear law's G_f = ell gamma_r (c_p - c_r) / 2
    assert 0.1 * LINEAR.softening_energy() == approx(0.1 * 0.75 * 15.0 / 2)


@pytest.mark.parametrize("make, word", [
    (lambda: LinearSoftening(5.0, 20.0, 0.75), "c_r (residual strength)"),
    (lambda: LinearSoftening(20.0, 5.0, 0.0), "gamma_r"),
    (lambda: LinearSoftening(20.0, 5.0, -1.0), "gamma_r"),
    (lambda: LinearSoftening(0.0, 0.0, 1.0), "c_p (peak strength)"),
    (lambda: LinearSoftening(20.0, -1.0, 1.0), "c_r (residual strength)"),
    (lambda: ExponentialSoftening(20.0, 5.0, 0.0), "gamma_95"),
    (lambda: ExponentialSoftening(20.0, 25.0, 1.0), "c_r (residual strength)"),
    (lambda: FractureEnergy(0.0), "length"),
    (lambda: SofteningTresca("linear", Elastic(1e4, 0.3)), "law"),
    (lambda: SofteningTresca(LINEAR, None), "elastic"),
    (lambda: SofteningTresca(LINEAR, Elastic(1e4, 0.3), 0.1), "regularisation"),
    (lambda: SofteningMohrCoulomb(LINEAR, Elastic(1e4, 0.3), phi=95.0), "phi"),
])
def test_bad_parameters_are_refused_naming_them(make, word):
    with pytest.raises(ValueError, match=word.replace("(", r"\(").replace(")", r"\)")):
        make()


def small_mesh():
    mesh = MeshTri.init_tensor(np.linspace(0, 1, 3), np.linspace(0, 1, 3))
    return discretise(mesh)


def test_an_elastic_increment_has_no_plastic_strain_and_a_rigid_plastic_one_all():
    disc = small_mesh()
    elastic = Elastic(1e4, 0.3)
    B, C, w = assemble_B(disc), assemble_C(disc, elastic), disc.weights
    du = np.random.default_rng(1).normal(size=disc.n_u) * 1e-3
    strain = (B @ du).reshape(-1, 4) / w[:, None]
    sigma = strain @ np.linalg.inv(elastic.compliance()).T       # D eps at every point
    sigma0 = np.ones_like(sigma)
    elastic_part = plastic_strain_increment(B, du, C, sigma + sigma0, sigma0, w)
    assert np.abs(elastic_part).max() < 1e-12 * np.abs(strain).max()
    assert plastic_strain_increment(B, du, None, sigma, sigma0, w) == approx(strain)


def test_the_shear_invariant_is_the_engineering_shear_strain_in_any_frame():
    # simple shear gamma; pure shear (e, -e) is simple shear 2e at 45 degrees
    assert shear_invariant([[0, 0, 0, 0.3]]) == approx([0.3])
    assert shear_invariant([[0.1, -0.1, 0, 0]]) == approx([0.2])
    eps = np.array([[2e-3, -1e-3], [-1e-3, 5e-4]])          # tensor: exy = -1e-3
    for a in np.radians([0, 17, 45, 120]):
        R = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
        e = R @ eps @ R.T
        assert shear_invariant([[e[0, 0], e[1, 1], 0, 2 * e[0, 1]]]) == \
            approx(shear_invariant([[eps[0, 0], eps[1, 1], 0, 2 * eps[0, 1]]]))


def test_the_criterion_carries_each_points_strength():
    material = SofteningTresca(LINEAR, Elastic(1e4, 0.3), FractureEnergy(0.1))
    gamma, size = np.array([0.0, 0.375, 0.375]), np.array([0.1, 0.1, 0.05])
    # at h = ell the law itself; at h = ell / 2 gamma_r doubles: half the drop
    assert material.criterion(gamma, size).k == approx(2 * np.array([20.0, 12.5, 16.25]))
    mc = SofteningMohrCoulomb(LINEAR, Elastic(1e4, 0.3), phi=30.0)
    k = mc.criterion(gamma, size, sigma_m=np.array([0.0, -10.0, 0.0])).k
    c = LINEAR.strength(gamma)
    assert k == approx(2 * c * np.cos(np.radians(30)) + np.array([0, 20 * 0.5, 0]))


def test_point_sizes_are_the_square_cells_side():
    disc = small_mesh()                       # 2 x 2 squares of side 1/2, two triangles each
    assert point_sizes(disc.weights) == approx(np.full(disc.n_points, 0.5))


@pytest.mark.parametrize("change, word", [({"control": 0.01}, "StepControl"),
                                          ({"n_increments": 0}, "n_increments"),
                                          ({"gamma0": np.ones(2)}, "gamma0")])
def test_the_step_control_refuses_bad_settings(change, word):
    for bad, name in (({"max_drop": 0.0}, "max_drop"), ({"passes": 0}, "passes"),
                      ({"passes": 1.5}, "passes")):
        with pytest.raises(ValueError, match=name):
            StepControl(**bad)
    disc = small_mesh()
    material = SofteningTresca(LINEAR, Elastic(1e4, 0.3))
    kwargs = dict(dict(fixed=np.arange(4), prescribed=([5], [1e-3]), n_increments=2,
                       size=point_sizes(disc.weights), weights=disc.weights), **change)
    with pytest.raises(ValueError, match=word):
        softening_control(assemble_B(disc), assemble_C(disc, material.elastic), material,
                          **kwargs)


def test_the_nonlocal_average_keeps_constants_and_interior_linear_fields():
    x, y = np.meshgrid(np.linspace(0, 1, 41), np.linspace(0, 1, 41))
    points = np.c_[x.ravel(), y.ravel()]
    A = nonlocal_average(points, np.ones(len(points)), 0.1)
    assert A @ np.full(len(points), 3.0) == approx(3.0)
    # a symmetric neighbourhood keeps a linear field (the average of a line is its centre)
    field = 2 * points[:, 0] - points[:, 1]
    inner = np.all((points > 0.1 + 1e-9) & (points < 0.9 - 1e-9), axis=1)
    assert (A @ field)[inner] == approx(field[inner], abs=1e-12)
    # a peak spreads over the length, its weighted sum kept on a uniform grid
    peak = np.zeros(len(points))
    peak[np.argmin(np.hypot(*(points - 0.5).T))] = 1.0
    spread = A @ peak
    assert spread.max() < 0.2 and spread.sum() == approx(1.0, rel=1e-9)
    assert np.all(spread[np.hypot(*(points - 0.5).T) >= 0.1] == 0)


def test_the_nonlocal_average_weighs_each_point_itself_once():
    """Two points 0.05 apart, ell = 0.1: phi = (1 - 1/4)^2 = 9/16 for the other, 1 for itself
    (scipy lists each point's zero distance to itself: it once counted twice)."""
    A = nonlocal_average(np.array([[0.0, 0.0], [0.05, 0.0]]), np.ones(2), 0.1).toarray()
    phi = (1 - 0.25) ** 2
    assert A == approx(np.array([[1, phi], [phi, 1]]) / (1 + phi), abs=1e-15)


def test_a_nonlocal_length_below_the_spacing_is_warned_and_averages_nothing():
    points = np.c_[np.linspace(0, 1, 11), np.zeros(11)]
    with pytest.warns(UserWarning, match="below the points' spacing"):
        A = nonlocal_average(points, np.ones(11), 0.05)
    assert A.toarray() == approx(np.eye(11))
    with pytest.raises(ValueError, match="length"):
        nonlocal_average(points, np.ones(11), 0.0)


def test_a_softening_mohr_coulomb_layer_peaks_and_softens_at_c_cos_phi():
    """Simple shear keeps sx = sy = 0 (u_y = 0, isochoric flow), so the zero-dilation cone's
    radius is 2 c cos(phi): the weak row peaks at tau = c_w cos(phi), and its strength falls
    at H cos(phi): d delta / d tau = L / G - h / (|H| cos(phi)) on the softening branch."""
    from verification.softening_layer import layer_model
    rows, L, G, phi = 10, 1.0, 2000.0, 30.0
    m = layer_model(rows, L, G, 0.3)
    material = SofteningMohrCoulomb(LINEAR, m["elastic"], phi=phi)
    h, cos = m["h"], np.cos(np.radians(phi))
    weak = (m["y"] > 5 * h) & (m["y"] < 6 * h)
    gamma0 = np.where(weak, 0.01 * LINEAR.gamma_r, 0.0)            # c_w = 19.85
    run = softening_control(m["B"], m["C"], material, fixed=[0],
                            prescribed=([m["top"]], [0.06]), n_increments=10, size=m["size"], weights=m["weights"],
                            gamma0=gamma0, control=StepControl(max_drop=0.01))
    tau, delta = run.reactions[:, m["top"]] / h, run.factors * 0.06
    assert tau.max() == approx(19.85 * cos, rel=1e-6)
    branch = (np.arange(len(tau)) > np.argmax(tau)) & (tau > 8 * cos) & (tau < 18 * cos)
    slope = np.polyfit(tau[branch], delta[branch], 1)[0]
    assert slope == approx(L / G - h / (20.0 * cos), rel=0.02)
    assert np.abs(run.sigma[:, :3]).max() < 1e-6 * tau.max()      # sx = sy = sz = 0
