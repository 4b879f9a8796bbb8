"""Surface loads of a PFEM scene (:mod:`pfem_skfem.scene.loads`, issue 54).

The consistent P2 load of a uniform traction (1/6, 4/6, 1/6 of an edge's force), the
pressure along the inward normal against a traction fixed in direction, and the
equilibrium of a rigid-plastic column in a smooth container pressed by q on its top: the
floor carries q times the loaded width (q pi R^2 in axisymmetry) plus the weight, to the
solver's tolerance. A zone that misses the surface and a non-finite load are refused; a
scene without loads keeps its digest.
"""
from dataclasses import replace

import numpy as np
import pytest
from pytest import approx
from skfem import MeshTri

from pfem_skfem.discretisation.geometry import as_geometry
from pfem_skfem.discretisation.static import discretise
from pfem_skfem.discretisation.theta import ThetaMethod
from pfem_skfem.drivers.pfem_loop import run
from pfem_skfem.materials import CohesiveTresca, ZeroDilationMohrCoulombAxisymmetric
from pfem_skfem.problems.contact import RigidSegment
from pfem_skfem.scene import (Body, HalfPlane, PolygonZone, Region, Scene, SurfaceLoad,
                              scene_digest)
from pfem_skfem.scene.config import PFEMConfig
from pfem_skfem.scene.files import example_text, scene_from_toml

W, H, SPACING, RHO, G, Q = 1.0, 1.0, 0.25, 2.0, 9.8, 3.0
TOP = HalfPlane((0.0, H - 0.01), (0.0, 1.0))


def _xy(disc, f):
    b = disc.basis_u
    return (f[np.concatenate([b.nodal_dofs[0], b.facet_dofs[0]])].sum(),
            f[np.concatenate([b.nodal_dofs[1], b.facet_dofs[1]])].sum())


def test_a_uniform_pressure_gives_an_edge_s_nodes_one_sixth_four_sixths_one_sixth():
    disc = discretise(MeshTri.init_tensor([0.0, 2.0], [0.0, 1.0]))     # one top edge, 2 long
    f = SurfaceLoad(TOP, pressure=Q).vector(disc, 1e-9)
    y = disc.basis_u.doflocs
    top_y = np.flatnonzero((np.abs(y[1] - 1) < 1e-12) & (np.arange(disc.n_u) % 2 == 1))
    ends = top_y[np.abs(y[0, top_y] - 1) > 0.5]
    mid = top_y[np.abs(y[0, top_y] - 1) < 1e-12]
    np.testing.assert_allclose(f[ends], -Q * 2 / 6, rtol=1e-13)
    np.testing.assert_allclose(f[mid], -Q * 2 * 4 / 6, rtol=1e-13)
    assert np.abs(np.delete(f, top_y)).max() < 1e-13 * Q      # nothing else is loaded


@pytest.mark.parametrize("axisymmetric", [False, True])
def test_a_pressure_follows_the_inward_normal_a_traction_keeps_its_direction(axisymmetric):
    geometry = as_geometry("axisymmetric" if axisymmetric else "plane")
    mesh = MeshTri.init_tensor(np.linspace(1.0, 2.0, 3), np.linspace(0.0, 1.0, 3))
    disc = discretise(mesh, geometry)
    right = HalfPlane((1.99, 0.0), (1.0, 0.0))
    fx, fy = _xy(disc, SurfaceLoad(right, pressure=Q).vector(disc, 1e-9))
    ring = 2 * np.pi * 2.0 if axisymmetric else 1.0               # the side r = 2, 1 high
    assert (fx, fy) == approx((-Q * ring, 0.0), abs=1e-12 * Q)
    fx, fy = _xy(disc, SurfaceLoad(TOP, traction=(0.5, -Q)).vector(disc, 1e-9))
    ring = np.pi * (2.0 ** 2 - 1.0 ** 2) if axisymmetric else 1.0   # the top, 1 <= r <= 2
    assert (fx, fy) == approx((0.5 * ring, -Q * ring), rel=1e-13)


def _column(geometry="plane", g=G, loads=None, theta1=1.0):
    """A rigid-plastic column W x H (strength 100, far above q and its weight) on a smooth
    floor in a smooth container: it cannot move, the floor carries what presses on it."""
    axi = geometry == "axisymmetric"
    soil = (ZeroDilationMohrCoulombAxisymmetric(c=100.0, phi=0.0) if axi
            else CohesiveTresca(c=100.0))
    column = Region(((0, 0), (W, 0), (W, H), (0, H)), soil, RHO, SPACING, name="column")
    bodies = (Body("floor", RigidSegment((-5, 0), (5, 0), 0.0)),
              Body("right", RigidSegment((W, -SPACING), (W, 5), 0.0)))
    if not axi:
        bodies += (Body("left", RigidSegment((0, 5), (0, -SPACING), 0.0)),)
    loads = (SurfaceLoad(TOP, pressure=Q, name="top"),) if loads is None else loads
    return Scene(regions=(column,), bodies=bodies, gravity=(0.0, -g), loads=loads,
                 geometry=geometry, config=PFEMConfig(theta=ThetaMethod(0.01, theta1, 1.0)))


@pytest.mark.parametrize("geometry, g", [("plane", G), ("plane", 0.0), ("axisymmetric", G)])
def test_the_floor_carries_the_pressure_on_the_top_and_the_weight(geometry, g):
    scene = _column(geometry, g)
    state, _ = run(scene.initial_state(), scene, 2)
    area = np.pi * W ** 2 if geometry == "axisymmetric" else W       # q pi R^2, or q W
    weight = RHO * g * area * H
    for forces, loads in zip(state.history["forces"], state.history["loads"]):
        assert loads["top"] == approx([0.0, -Q * area], abs=1e-12 * Q * area)
        # to the solver's tolerance on the scene's force scale (stress scale x area);
        # measured 2e-10 (plane), 4e-11 (axisymmetric), 1.1e-8 (g = 0: the scale c = 100)
        assert forces["floor"][1] == approx(-(Q * area + weight),
                                            abs=1e-7 * scene.stress_scale * area)
    assert np.abs(state.x - scene.initial_state().x).max() < 1e-9 * H


def test_a_ramped_traction_is_the_theta_method_s_load_of_the_step():
    ramp = lambda t: t / 0.02            # noqa: E731  (full at the second step's end)
    load = SurfaceLoad(TOP, traction=(0.0, -Q), ramp=ramp, name="top")
    scene = _column(g=0.0, loads=(load,))
    state, _ = run(scene.initial_state(), scene, 2)
    for k, (forces, loads) in enumerate(zip(state.history["forces"], state.history["loads"])):
        expected = Q * W * ramp((k + 1) * 0.01)       # theta1 = 1: the load at t_{n+1}
        assert loads["top"][1] == approx(-expected, rel=1e-12)
        assert forces["floor"][1] == approx(-expected, abs=1e-7 * scene.stress_scale * W)


def test_a_zone_that_misses_the_surface_is_refused_before_any_step():
    with pytest.raises(ValueError, match="load 'top': its zone holds no surface edge"):
        _column(loads=(SurfaceLoad(HalfPlane((0, H + 0.1), (0, 1)), pressure=Q, name="top"),))
    inside = PolygonZone(((0.3, 0.3), (0.7, 0.3), (0.7, 0.7), (0.3, 0.7)))    # no surface
    with pytest.raises(ValueError, match="load 'core': its zone holds no surface edge"):
        _column(loads=(SurfaceLoad(inside, traction=(1.0, 0.0), name="core"),))


def test_a_non_finite_load_is_refused_by_name():
    with pytest.raises(ValueError, match="load 'top': traction must be a finite"):
        SurfaceLoad(TOP, traction=(np.nan, 1.0), name="top")
    with pytest.raises(ValueError, match="load 'top': pressure must be finite"):
        SurfaceLoad(TOP, pressure=np.inf, name="top")
    with pytest.raises(ValueError, match="load 'top': give one of traction"):
        SurfaceLoad(TOP, traction=(0.0, 1.0), pressure=1.0, name="top")
    blows_up = SurfaceLoad(TOP, pressure=Q, ramp=lambda t: 1 / (0.05 - t), name="top")
    with pytest.raises(ValueError, match="load 'top': ramp"):       # at t = 0.05, step 5
        replace(_column(), loads=(blows_up,), t_end=0.1)
    scene = replace(_column(), loads=(blows_up,), t_end=0.04)      # checked to t_end
    with pytest.raises(ValueError, match="load 'top': ramp"):       # the run's steps too
        run(scene.initial_state(), scene, 10)


def test_a_scene_without_loads_keeps_its_digest_and_a_load_changes_it():
    column = scene_from_toml(example_text("column"))
    # the digest stored before scenes had loads (main at 33c6ed8)
    assert scene_digest(column) == \
        "3c3d50396cae7bfc90ac127af3403507c4ccd307708c87cf984fb74dd6a83301"
    loaded = replace(column, loads=(SurfaceLoad(HalfPlane((0, 0.99), (0, 1)), pressure=1.0),))
    assert scene_digest(loaded) != scene_digest(column)
    assert scene_digest(replace(loaded, loads=(replace(loaded.loads[0], pressure=2.0),))) != \
        scene_digest(loaded)
