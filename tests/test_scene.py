"""Scenes: regions filled with particles, motions of rigid bodies, outlets, phases."""
import numpy as np
from scipy.spatial import cKDTree
import pytest

from pfem_skfem.materials import ZeroDilationMohrCoulomb
from pfem_skfem.pfem import alpha_shape
from pfem_skfem.problems.contact import RigidCircle, RigidSegment
from pfem_skfem.scene import (Body, ConstantVelocity, Geostatic, HalfPlane, PiecewiseLinear,
                              PolygonZone, Region, Scene, polygon_area)

SAND = ZeroDilationMohrCoulomb(0.0, 30.0)
HOUSE = ((0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.8), (0.0, 1.0))     # slanted roof
WINDOW = ((0.6, 0.4), (1.4, 0.4), (1.4, 0.9), (0.6, 0.9))


def test_a_rectangle_is_filled_edge_to_edge_on_its_lattice():
    h = 0.25
    x = Region(((0, 0), (1, 0), (1, 0.5), (0, 0.5)), SAND, 2.0, h).particles()
    X, Y = np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 0.5, 3))
    np.testing.assert_array_equal(x, np.column_stack([X.ravel(), Y.ravel()]))


@pytest.mark.parametrize("lattice", ["square", "triangular", "triangle"])
def test_the_alpha_shape_of_a_filled_region_is_the_region(lattice):
    """Particles on every edge and none in the window: the alpha-shape finds the polygon,
    its hole and its area, up to the four corners of the window, each of which it may cut
    by a triangle of two edges of length h at most (a corner the alpha-shape bridges)."""
    h = 0.1
    region = Region(HOUSE, SAND, 2.0, h, lattice=lattice, holes=(WINDOW,))
    x = region.particles()
    assert region.contains(x, tol=1e-9 * h).all()
    shape = alpha_shape(x, h, 1.3)
    assert shape.n_holes == 1
    assert abs(shape.area - region.area) <= 4 * 0.5 * h ** 2 * (1 + 1e-9)
    assert region.area == pytest.approx(polygon_area(HOUSE) - 0.4, rel=1e-12)


def test_each_region_shares_its_mass_and_starts_geostatic():
    rho, g = 2.0, 9.8
    region = Region(((0, 0), (1, 0), (1, 1), (0, 1)), SAND, rho, 0.1, stress=Geostatic(k0=0.5))
    scene = Scene(regions=(region,), gravity=(0.0, -g))
    state = scene.initial_state()
    assert state.total_mass == pytest.approx(rho * 1.0, rel=1e-14)
    # sigma_m = (sx + sy)/2 = (1 + K0)/2 sy with sy = -rho g (1 - y)
    np.testing.assert_allclose(state.sigma_m, -0.75 * rho * g * (1 - state.x[:, 1]))


def test_motions_are_functions_of_time():
    path = PiecewiseLinear((0.0, 80.0, 280.0), ((0, 0), (0, -0.8), (2.0, -0.8)))  # 6.4.1
    assert path(40.0) == pytest.approx([0.0, -0.4])
    assert path(180.0) == pytest.approx([1.0, -0.8])
    assert path(500.0) == pytest.approx([2.0, -0.8])
    assert ConstantVelocity((0.1, -0.2))(3.0) == pytest.approx([0.3, -0.6])
    pipe = Body("pipe", RigidCircle((0.0, 1.0), 0.5), path)
    assert pipe.at(80.0).center == pytest.approx((0.0, 0.2))
    assert pipe.reference_at(280.0) == pytest.approx([2.0, 0.2])
    with pytest.raises(ValueError, match="start at 0"):
        PiecewiseLinear((1.0, 2.0), ((0, 0), (1, 0)))
    with pytest.raises(ValueError, match=r"motion\(0\)"):
        Body("wall", RigidSegment((0, 0), (1, 0)), motion=lambda t: (1.0 + t, 0.0))


def test_outlet_zones():
    assert HalfPlane((0.0, 0.5), (0.0, -2.0)).contains([[0.0, 0.4], [0.0, 0.6]]).tolist() == \
        [True, False]
    zone = PolygonZone(((0, 0), (1, 0), (1, 1), (0, 1)))
    assert zone.contains([[0.5, 0.5], [1.5, 0.5]]).tolist() == [True, False]


def test_touching_regions_share_their_edge_without_duplicates():
    """A fine region (h/2) beside a coarse one: one particle per place on the common edge,
    one body for the alpha-shape, the area of both, each region's mass its own."""
    coarse = Region(((0, 0), (1, 0), (1, 1), (0, 1)), SAND, 2.0, 0.1, name="coarse")
    fine = Region(((1, 0), (1.5, 0), (1.5, 1), (1, 1)), SAND, 2.0, 0.05, name="fine")
    scene = Scene(regions=(coarse, fine))
    x, h, region = scene.particles()
    pairs = cKDTree(x).query_pairs(0.02)
    assert len(pairs) == 0
    shape = alpha_shape(x, h, 1.3)
    assert len(shape.body_area) == 1
    assert shape.area == pytest.approx(1.5, rel=1e-9)
    state = scene.initial_state()
    assert state.mass[state.region == 1].sum() == pytest.approx(2.0 * 0.5, rel=1e-12)
