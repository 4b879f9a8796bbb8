"""The band-angle measurement of verification/biaxial_band.py on fields of known angle."""
import numpy as np
import pytest
from pytest import approx

from verification.biaxial_band import band_angle


@pytest.mark.parametrize("theta", [40.0, 45.0, 52.5, 60.0])   # Coulomb's 45 + phi / 2 and near
def test_a_straight_band_of_known_inclination_is_measured(theta):
    """A Gaussian ridge along a line at theta from the horizontal through the lower-left
    corner, on scattered points, plus a hot seed at the corner that must be left out.
    (A band below about 35 deg leaves this 1 x 2 specimen too low for enough slices.)"""
    rng = np.random.default_rng(7)
    points = rng.uniform([0, 0], [1, 2], size=(4000, 2))
    t = np.radians(theta)
    distance = np.abs(points[:, 0] * np.sin(t) - points[:, 1] * np.cos(t))
    gamma = np.exp(-0.5 * (distance / 0.03) ** 2)
    gamma[np.hypot(*points.T) < 0.15] += 5.0                  # the seed, far hotter
    angle, r2, centres = band_angle(points, gamma, h=0.05, above=0.2)
    assert angle == approx(theta, abs=0.5)
    assert r2 > 0.99 and len(centres) >= 5


def test_no_band_gives_no_angle():
    points = np.random.default_rng(1).uniform([0, 0], [1, 2], size=(500, 2))
    angle, r2, _ = band_angle(points, np.zeros(len(points)), h=0.05, above=0.2)
    assert np.isnan(angle) and np.isnan(r2)


def test_the_band_keeps_its_angle_on_a_taller_specimen():
    """The option audit's --height 2.5 (issue 56): the band from the seed to the right side
    does not depend on the specimen's height, but each height is another Triangle mesh. On
    the former quick mesh (h = 0.12 = W / 8.3) the band lay at 41.6 deg there (41.3-46.9
    over 8 heights); at h = 0.08 W, the coarsest the script accepts, at 46.0 (43.9-46.0 over
    12 meshes). Coulomb's 45 deg (Tresca) within the script's 3 deg."""
    from pfem_skfem.harness.report import run_script
    from verification import biaxial_band
    report = run_script(biaxial_band, "--quick", "--no-figures", "--height", "2.5")
    assert report.quantity("band_angle_deg").value == approx(45.0, abs=3.0)
    assert report.quantity("band_line_R2").value > 0.99
