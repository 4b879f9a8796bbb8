"""The columns with mu(I) (verification/granular_column_mu_i.py): the quick case and its
checks, the direction of the rate effect, the axisymmetric material's rate-independent limit."""
import numpy as np
import pytest

from pfem_skfem.materials import MuIRheology, MuIRheologyAxisymmetric, ZeroDilationDruckerPrager
from pfem_skfem.materials.axisymmetric import mean_stress

# every test of this file on one xdist worker, with the columns' case of test_verification:
# they read one quick run (tests/conftest.py)
pytestmark = pytest.mark.xdist_group("granular_column_mu_i")


@pytest.fixture(scope="module")
def quick(quick_run):
    report, _ = quick_run("granular_column_mu_i", "--workers", "1")
    return report


def _row(report, geometry, law):
    return next(r for r in report.extra["columns"]
                if r["geometry"] == geometry and r["law"] == law)


def test_quick_case_runs_and_its_checks_pass(quick):
    failed = [(q.name, q.value) for q in quick.quantities if not q.passed]
    assert quick.passed, failed
    names = {q.name for q in quick.quantities}
    for geometry, a in (("plane", 1), ("axisymmetric", 0.5)):
        for law in ("mu(I)", "mu_s"):
            assert f"{geometry}_{law}_a{a:g}_mass_error" in names
    assert {"density_runout", "density_height"} <= names


def test_mu_i_column_runs_shorter_and_stands_higher_than_its_rate_independent_limit(quick):
    """mu(I) >= mu_s at every flowing point: the plane mu(I) column (a = 1) dissipates more
    and spreads less than the column of friction mu_s (mu_2 -> mu_s). Not a theorem of
    inertial flow but the direction of the rate effect; it fails if mu(I) is not applied
    (the two would be one run)."""
    rate, static = _row(quick, "plane", "mu(I)"), _row(quick, "plane", "mu_s")
    assert rate["runout"] < static["runout"]
    assert rate["height"] > static["height"]


def test_density_invariance_is_exact_when_rho_s_scales_with_rho(quick):
    q = {q.name: q for q in quick.quantities}
    assert q["density_runout"].value == q["density_runout"].reference
    assert q["density_height"].value == q["density_height"].reference


def test_axisymmetric_mu_i_with_mu_2_equal_mu_s_is_the_drucker_prager_twin():
    """sqrt(J2) <= mu_s p, p = -I1/3: the zero-dilation Drucker-Prager cone with
    alpha = sin(phi) / 3, sin(phi) = mu_s, and no rate term."""
    rng = np.random.default_rng(0)
    sigma = -rng.uniform(0.1, 2.0, (50, 4))
    p = mean_stress(sigma)
    mu_s = 0.38
    rate = MuIRheologyAxisymmetric(mu_s=mu_s, mu_2=mu_s)
    twin = ZeroDilationDruckerPrager(c=0.0, phi=float(np.degrees(np.arcsin(mu_s))),
                                     match="plane-strain-psi0")
    assert np.allclose(rate.mean_stress(sigma), p, rtol=0, atol=0)
    k = rate.cone(p, 1.0, shear_rate=rng.uniform(0, 10, 50)).k
    assert np.allclose(k, twin.cone(p, 1.0).k, rtol=1e-14, atol=0)
    assert rate.viscous(p, 1.0, np.ones(50), np.ones(50)) is None


def test_axisymmetric_mu_i_cone_is_half_the_plane_radius():
    """The plane cone bounds sqrt((sx - sy)^2 + 4 txy^2) = 2R by 2 mu p, the axisymmetric
    one sqrt(J2) (= R in simple shear) by mu p: the same friction mu."""
    p = -np.linspace(0.1, 1.0, 7)
    for lag in ("viscosity", "friction"):
        rate = np.linspace(0.0, 50.0, 7)
        plane = MuIRheology(lag=lag).cone(p, 1.0, shear_rate=rate).k
        axisym = MuIRheologyAxisymmetric(lag=lag).cone(p, 1.0, shear_rate=rate).k
        assert np.allclose(plane, 2 * axisym, rtol=1e-14, atol=0)
