"""The detection with the advected domain as predicate (PFEMConfig.alpha_advected)."""
import numpy as np
import pytest
from scipy.spatial import Delaunay

from pfem_skfem.scene.config import PFEMConfig
from pfem_skfem.pfem.alpha_shape import (alpha_shape, circumradius, in_triangles, notches,
                                         triangle_areas)


def test_in_triangles_is_point_location_for_either_orientation():
    rng = np.random.default_rng(0)
    p = rng.random((60, 2))
    t = Delaunay(p).simplices
    x = rng.uniform(-0.2, 1.2, (2000, 2))
    expected = Delaunay(p).find_simplex(x) >= 0
    assert np.array_equal(in_triangles(p, t, x), expected)
    assert np.array_equal(in_triangles(p, t[:, [0, 2, 1]], x), expected)
    # vertices and edge midpoints are on the mesh; a zero-area triangle contains nothing
    assert in_triangles(p, t, p).all()
    assert in_triangles(p, t, 0.5 * (p[t[:, 0]] + p[t[:, 1]])).all()
    flat = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    assert not in_triangles(flat, [[0, 1, 2]], [[1.0, 0.0]]).any()
    assert not in_triangles(p, np.empty((0, 3), int), x).any()


def layer(stretch, height, n=12):
    """Two staggered rows of particles ``height`` apart, spaced ``stretch``: a layer that
    spreads and thins flattens its triangles."""
    x0 = np.arange(n, dtype=float)
    lower = np.column_stack([x0 * stretch, np.zeros(n)])
    upper = np.column_stack([(x0[:-1] + 0.5) * stretch, np.full(n - 1, height)])
    return np.vstack([lower, upper])


def test_a_stretched_layer_stays_one_body_only_inside_its_advected_mesh():
    p0 = layer(1.0, np.sqrt(0.75))
    before = alpha_shape(p0, 1.0, 1.6)
    assert before.n_bodies == 1 and before.free.sum() == 0
    p1 = layer(2.0, 0.3)                     # the same particles, spread and thinned
    t_moved = before.triangles               # the previous mesh moved with its particles
    r = circumradius(p1, t_moved)
    assert r.min() > 1.6 and r.max() < 2.5   # every triangle now fails alpha = 1.6
    plain = alpha_shape(p1, 1.0, 1.6)
    kept = alpha_shape(p1, 1.0, 1.6, advected=(p1, t_moved), alpha_advected=2.5)
    assert plain.area < 0.5 * kept.area
    # the kept domain is the advected one: the same area, one body, no free particle
    area_moved = np.abs(triangle_areas(p1, t_moved)).sum()
    assert kept.area == pytest.approx(area_moved, rel=1e-12)
    assert kept.n_bodies == 1 and kept.free.sum() == 0
    # stretched beyond alpha_advected, the layer is cut as before
    cut = alpha_shape(p1, 1.0, 1.6, advected=(p1, t_moved), alpha_advected=1.8)
    assert cut.area == pytest.approx(plain.area, rel=1e-12)


def test_a_gap_between_two_bodies_is_judged_by_alpha_alone():
    block = np.array([[i, j] for i in range(4) for j in range(4)], dtype=float)
    left, right = block, block + [6.5, 0.0]        # a gap of 3.5 spacings
    p = np.vstack([left, right])
    bodies = [alpha_shape(b, 1.0, 1.6) for b in (left, right)]
    t_moved = np.vstack([bodies[0].triangles, bodies[1].triangles + len(left)])
    # the triangles across the gap have R/h in (1.6, 4): alpha_advected would take them
    across = Delaunay(p).simplices
    r = circumradius(p, across)
    assert np.any((r > 1.6) & (r < 4.0))
    shape = alpha_shape(p, 1.0, 1.6, advected=(p, t_moved), alpha_advected=4.0)
    assert shape.n_bodies == 2
    assert shape.area == pytest.approx(18.0, rel=1e-12)


def test_a_notch_of_the_surface_is_not_filled():
    """A surface particle sinks between its two neighbours: the plain alpha-shape fills
    the notch with a triangle of area 0.5 (R/h = 1.25); with the advected mesh, whose two
    boundary edges bound the notch, the domain keeps the moved mesh's area."""
    block = np.array([[i, j] for j in range(3) for i in range(5)], dtype=float)
    old = alpha_shape(block, 1.0, 1.6)
    moved = block.copy()
    moved[12] = (2.0, 1.5)                       # the top row's middle particle, 0.5 down
    t_moved = old.triangles
    area_moved = np.abs(triangle_areas(moved, t_moved)).sum()
    plain = alpha_shape(moved, 1.0, 1.6)
    assert plain.area == pytest.approx(area_moved + 0.5, rel=1e-12)
    shape = alpha_shape(moved, 1.0, 1.6, advected=(moved, t_moved), alpha_advected=2.5)
    assert shape.area == pytest.approx(area_moved, rel=1e-12)
    assert notches(moved, plain.delaunay, plain.kept, moved, t_moved, np.ones(15)).size == 1


def test_a_particle_added_on_a_surface_edge_splits_it_and_fills_no_notch():
    """A particle added on the stretched surface edge 12-13 (off its chord, as a P2
    midside node) next to the notch 12-13-14: the plain alpha-shape fills the notch with
    the triangle (new, 13, 14); with the advected mesh only the new particle's own sliver
    (12, new, 13) is added to the moved mesh's area."""
    block = np.array([[i, j] for j in range(3) for i in range(5)], dtype=float)
    old = alpha_shape(block, 1.0, 1.6)
    moved = block.copy()
    moved[13] = (3.0, 1.5)
    area_moved = np.abs(triangle_areas(moved, old.triangles)).sum()
    points = np.vstack([moved, [[2.5, 1.78]]])                      # particle 15
    plain = alpha_shape(points, 1.0, 1.6)
    assert any(set(t) == {15, 13, 14} for t in plain.triangles)
    shape = alpha_shape(points, 1.0, 1.6, advected=(moved, old.triangles), alpha_advected=2.5)
    sliver = abs(triangle_areas(points, np.array([[12, 15, 13]]))[0])
    assert shape.area == pytest.approx(area_moved + sliver, rel=1e-12)


def test_off_or_not_larger_than_alpha_is_the_plain_alpha_shape():
    rng = np.random.default_rng(1)
    p = rng.random((200, 2)) * 10
    plain = alpha_shape(p, 1.0, 1.6)
    t = Delaunay(p).simplices
    for a_adv in (0.0, 1.6, 1.2):
        s = alpha_shape(p, 1.0, 1.6, advected=(p, t), alpha_advected=a_adv)
        assert np.array_equal(s.kept, plain.kept)


def test_the_advected_domain_only_adds_triangles_inside_it():
    """Kept with the predicate = kept by alpha, less the notches of the advected mesh's
    surface (outside it), plus triangles whose centroid lies in the advected mesh and
    whose circumradius is at most alpha_advected h; nothing else."""
    added = 0
    for seed in range(5):
        rng = np.random.default_rng(seed)
        p_old = rng.random((150, 2)) * 8
        before = alpha_shape(p_old, 0.7, 1.6)
        p = p_old + 0.25 * rng.standard_normal(p_old.shape)          # moved, same particles
        plain = alpha_shape(p, 0.7, 1.6)
        shape = alpha_shape(p, 0.7, 1.6, advected=(p, before.triangles), alpha_advected=2.5)
        assert np.array_equal(plain.delaunay, shape.delaunay)
        removed = np.flatnonzero(plain.kept & ~shape.kept)      # notches of its surface
        assert np.array_equal(removed, notches(p, plain.delaunay, plain.kept, p,
                                               before.triangles, np.full(len(p), 0.7)))
        assert not in_triangles(p, before.triangles,
                                p[shape.delaunay[removed]].mean(axis=1)).any()
        extra = shape.kept & ~plain.kept
        assert np.all(shape.radius[extra] <= 2.5)
        assert in_triangles(p, before.triangles, p[shape.delaunay[extra]].mean(axis=1)).all()
        missed = ~shape.kept & (shape.radius <= 2.5) & (shape.radius > 1.6)
        assert not in_triangles(p, before.triangles,
                                p[shape.delaunay[missed]].mean(axis=1)).any()
        added += extra.sum()
    assert added > 0


@pytest.mark.parametrize("value", [-1.0, np.nan, np.inf])
def test_config_refuses_a_bad_alpha_advected(value):
    with pytest.raises(ValueError, match="alpha_advected"):
        PFEMConfig(alpha_advected=value)


def test_a_deposit_is_measured_on_the_domain_the_run_detects():
    """A block with a thin tail that has spread (every tail triangle fails alpha): the
    plain alpha-shape cuts the tail off the deposit, the run's detection with the advected
    mesh keeps it, and the deposit measured with it reaches the tail's end."""
    from types import SimpleNamespace
    from pfem_skfem.pfem.measure import deposit_extent

    block = np.array([[i, j] for j in range(4) for i in range(6)], dtype=float)
    before = np.vstack([block, layer(1.0, np.sqrt(0.75)) + [6.0, 0.0]])
    t_moved = alpha_shape(before, 1.0, 1.6).triangles      # one body: block and tail
    after = np.vstack([block, layer(2.0, 0.3) + [7.0, 0.0]])
    state = SimpleNamespace(x=after, h=np.ones(len(after)), mesh_p=after, mesh_t=t_moved)
    assert circumradius(after, t_moved).max() < 3.0
    height, toe, body = deposit_extent(state, 1.6)
    assert toe < 8.0 and len(body) < len(after)               # the tail cut off
    height, toe, body = deposit_extent(state, 1.6, alpha_advected=3.0)
    assert (height, toe) == (3.0, after[:, 0].max()) and len(body) == len(after)
