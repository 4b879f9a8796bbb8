"""Water at rest in a box (issue 56, item 1): the spurious current and the law that sets it.

The dam break's column held by its gate, stepped from rest by the PFEM loop
(benchmarks/water_at_rest.py; book/water_and_mud.md, "Water at rest"). The residual speed
is the interior-point solver's, through the two degenerate contacts where the free surface
meets the walls (force and gap both zero at the solution): ~ sqrt(tol) g dt, not round-off.
Holding those two corners' normal velocity takes it to ~ tol g dt.
"""
import numpy as np
import pytest

from benchmarks import water_at_rest as bench

NX, DT = 8, 0.005           # 8 particles across, about the quick dam break's dt (0.004 s)


def test_first_step_residual_is_sqrt_of_the_tolerance():
    # measured (nx 8, 12, 16; dt 0.005 to 0.00125): 1.4 to 5.7 sqrt(tol) g dt at 1e-8
    default = bench.at_rest(NX, DT, 1)["speed"][0]
    tight = bench.at_rest(NX, DT, 1, tol=1e-10)["speed"][0]
    assert 0.5 * np.sqrt(1e-8) < default < 10 * np.sqrt(1e-8)          # 1.75e-4
    assert 0.5 * np.sqrt(1e-10) < tight < 10 * np.sqrt(1e-10)          # 1.64e-5
    # a hundredth of the tolerance, a tenth of the speed: sqrt (linear would be 100)
    assert 3 < default / tight < 30


def test_corners_held_leave_the_water_at_rest():
    # the cause: with the two top corners a bilateral support, the residual is ~ tol
    # (5e-10 at 1e-8, 5e-12 at 1e-10; 1.6e-9 after 10 steps)
    held = bench.at_rest(NX, DT, 10, held=True)
    assert held["speed"][0] < 0.1 * 1e-8
    assert max(held["speed"]) < 1e-8
    assert bench.at_rest(NX, DT, 1, tol=1e-10, held=True)["speed"][0] < 0.1 * 1e-10
    assert held["iterations"] < 13                      # 10-11; 15-16 with the corners free


def test_the_current_grows_from_step_to_step():
    # the corners are pushed off the walls every step: 7.3e-4 after 10 steps (4-11 sqrt(tol)
    # over the measured h and dt), 1.4e-2 after 100, 0.21 after 300 (the book's table)
    speed = bench.at_rest(NX, DT, 10)["speed"]
    assert speed[-1] > 2 * speed[0]
    assert speed[-1] < 20 * np.sqrt(1e-8)


def test_top_corners_pick_the_wall_nodes_not_the_surface():
    from types import SimpleNamespace
    # two walls (bodies 0 and 1) and a floor (2); the surface's node at x = 0.5 is within
    # the search distance of the left wall (gap 0.5) and as high as the corner
    contacts = SimpleNamespace(
        normal=np.array([[1, 0], [1, 0], [1, 0], [-1, 0], [-1, 0], [0, 1]], float),
        x=np.array([[0, 0.5], [0, 2.0], [0.5, 2.0], [1, 2.0], [1, 1.0], [0.5, 0]]),
        gap=np.array([0, 0, 0.5, 0, 0, 0.0]), body=np.array([0, 0, 0, 1, 1, 2]),
        dofs=np.arange(12).reshape(6, 2))
    assert bench.top_corners(contacts).tolist() == [2, 6]


def test_tolerance_setting_is_given_back():
    from pfem_skfem.problems.backends import direct
    before = direct.SETTINGS
    with bench.step_tolerance(1e-10):
        assert direct.SETTINGS["tol_gap_rel"] == 1e-10
    assert direct.SETTINGS is before
    with pytest.raises(RuntimeError), bench.corners_held():
        raise RuntimeError
    from pfem_skfem.drivers import pfem_loop
    from pfem_skfem.pfem.assemble import held_dofs
    assert pfem_loop.held_dofs is held_dofs
