"""Moving rigid bodies in the PFEM: critical taper theory and the wedge stability test
(Buiter et al. 2016, Exp 1), the check of thesis 6.4.2's wedge that has an exact answer."""
import numpy as np
import pytest

from verification.accretionary_wedge import (DEFORMS, RIGID, critical_taper, dahlen_F,
                                             stability_test, wedge_length)


def test_critical_taper_satisfies_dahlen_s_identity():
    """On the lower branch tan(alpha_c) = F(psi_0, phi) and tan(phi_b) = F(psi_b, phi),
    psi_b = alpha_c + psi_0 (Dahlen 1984, beta = 0), for several phi, phi_b."""
    for phi, phi_b in ((30, 15), (36, 10), (30, 25), (40, 30)):
        low, high = critical_taper(phi, phi_b)
        a, p = np.radians(low), np.radians(phi)
        psi0 = 0.5 * (np.arcsin(np.sin(a) / np.sin(p)) - a)
        assert np.tan(a) == pytest.approx(dahlen_F(psi0, p), abs=1e-12)
        assert np.tan(np.radians(phi_b)) == pytest.approx(dahlen_F(a + psi0, p), abs=1e-12)
        assert 0 < low < high <= phi


def test_critical_taper_limits():
    """A frictionless base needs no taper, a rougher base a steeper one; a stronger wedge a
    gentler one (Dahlen 1984, Fig 3)."""
    assert critical_taper(30, 0)[0] == pytest.approx(0, abs=1e-10)
    lows = [critical_taper(30, b)[0] for b in (5, 10, 15, 20, 25)]
    assert np.all(np.diff(lows) > 0)
    assert critical_taper(40, 15)[0] < critical_taper(30, 15)[0]


def test_mass_balance_length():
    """A triangle of taper alpha and area A: length sqrt(2 A / tan alpha)."""
    L = wedge_length(0.5 * 0.3 * 0.3 * np.tan(np.radians(10)), 10.0)
    assert L == pytest.approx(0.3, rel=1e-12)


@pytest.mark.parametrize("taper", [15.0, 3.0])
def test_a_wedge_slides_undeformed_only_inside_the_stable_field(taper):
    """Pushed by a smooth wall on a base of friction tan 15 deg (alpha_c = 5.38 deg): the
    15 deg wedge slides as one rigid block (plastic strain below RIGID du/H, the wall's push
    mu_b W to 1 %); the 3 deg wedge deforms at the wall (above DEFORMS du/H) and the push
    stays below what would slide it."""
    low, high = critical_taper(30.0, 15.0)
    r = stability_test(taper, phi_b=15.0, steps=4, layers=5)
    if low < taper < high:
        assert r["plastic_max"] < RIGID
        assert r["wall_force_over_mu_b_W"] == pytest.approx(1.0, rel=0.01)
    else:
        assert r["plastic_max"] > DEFORMS
        assert r["wall_force_over_mu_b_W"] < 1.0
