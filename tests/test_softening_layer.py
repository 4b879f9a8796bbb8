"""The softening layer's quick run (verification/softening_layer.py): the slope of each
computed post-peak branch against the closed form d delta / d tau = L / G - h / |H|
(local: h the row's height; regularised: ell in place of h), stated here."""
import numpy as np
import pytest
from pytest import approx

L, G, H, ELL = 1.0, 2000.0, -20.0, 0.2          # the script's defaults
C_W, C_R = 19.85, 5.0


def branch_slope(curve):
    """d delta / d tau fitted on the computed softening branch (10 % clear of both ends)."""
    delta, tau = np.asarray(curve["delta"]), np.asarray(curve["tau"])
    post = np.arange(len(tau)) > np.argmax(tau)
    inner = post & (tau > C_R + 0.1 * (C_W - C_R)) & (tau < C_W - 0.1 * (C_W - C_R))
    assert inner.sum() >= 10, "too few points on the softening branch"
    return np.polyfit(tau[inner], delta[inner], 1)[0]


@pytest.mark.xdist_group("softening_layer")
@pytest.mark.parametrize("rows", [10, 20, 40])
def test_the_local_branch_falls_at_L_over_G_minus_h_over_H(rows, quick_run):
    report, _ = quick_run("softening_layer")
    slope = branch_slope(report.extra["curves"][f"local_rows{rows}"])
    assert slope == approx(L / G - (L / rows) / -H, rel=0.02)


@pytest.mark.xdist_group("softening_layer")
@pytest.mark.parametrize("rows", [10, 20, 40])
def test_the_regularised_branch_does_not_depend_on_h(rows, quick_run):
    report, _ = quick_run("softening_layer")
    slope = branch_slope(report.extra["curves"][f"regularised_rows{rows}"])
    assert slope == approx(L / G - ELL / -H, rel=0.02)
