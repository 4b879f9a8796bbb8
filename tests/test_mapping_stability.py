"""Stress mapping under repeated remeshing: the bounded UEM and patch recovery (Section 2.5).

Facts checked: which methods keep constant and linear fields exact, the discrete maximum
principle of the bounded UEM, its convergence under refinement, and that its error
grows at most linearly over round trips between two unrelated meshes, whereas the
classical UEM's grows geometrically.
"""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from pfem_skfem.discretisation.meshes import triangulate_polygon
from pfem_skfem.discretisation.static import discretise
from pfem_skfem.pfem.alpha_shape import alpha_shape
from pfem_skfem.pfem.mapping import SCHEMES, locate, map_stress, recover_nodal
from pfem_skfem.pfem.remesh import alpha_mesh, quality_remesh

SQUARE = [(0, 0), (1, 0), (1, 1), (0, 1)]


def smooth(p):
    """sin(pi x) cos(pi y / 2): exact values in [0, 1] on the unit square."""
    return np.sin(np.pi * p[:, 0]) * np.cos(0.5 * np.pi * p[:, 1])


def linear(p):
    a = np.array([[1.0, 2.0, -3.0], [4.0, 0.5, 6.0], [-7.0, 8.0, 0.0], [1.0, -1.0, 0.5]])
    return a[:, 0] + p[:, :1] * a[:, 1] + p[:, 1:] * a[:, 2]


def unrelated_meshes():
    old = discretise(triangulate_polygon(SQUARE, 0.2))
    # partly outside the old mesh: extrapolated points too
    new = discretise(triangulate_polygon([(-0.1, -0.05), (1.1, 0), (1.05, 1.1), (0, 1)], 0.13))
    return old, new


def surrounded_vertices(disc):
    """Interior vertices inside the convex hull of the stress points of the elements around them."""
    mesh, owner = disc.mesh, disc.point_element
    ok = np.ones(mesh.p.shape[1], bool)
    ok[mesh.boundary_nodes()] = False
    for v in np.flatnonzero(ok):
        d = disc.points[np.isin(owner, np.flatnonzero((mesh.t == v).any(axis=0)))] - mesh.p[:, v]
        angle = np.sort(np.arctan2(d[:, 1], d[:, 0]))
        ok[v] = np.diff(angle, append=angle[0] + 2 * np.pi).max() < np.pi   # no empty half-plane
    return ok


def interior_element_points(old, x):
    """Points x whose old element has only surrounded vertices (no boundary vertex)."""
    element, inside, _ = locate(old.mesh, x)
    return inside & surrounded_vertices(old)[old.mesh.t[:, element]].all(axis=0)


@pytest.mark.parametrize("method", SCHEMES)
def test_every_method_keeps_a_constant(method):
    old, new = unrelated_meshes()
    const = np.tile([1.0, -2.0, 3.0, 0.25], (old.n_points, 1))
    np.testing.assert_allclose(map_stress(old, const, new, method),
                               np.tile(const[0], (new.n_points, 1)), atol=1e-12)


@pytest.mark.parametrize("method", ["uem", "spr"])
def test_uem_and_patch_recovery_keep_a_linear_field_everywhere(method):
    old, new = unrelated_meshes()
    np.testing.assert_allclose(map_stress(old, linear(old.points), new, method),
                               linear(new.points), atol=1e-11)


def test_bounded_uem_keeps_a_linear_field_away_from_the_boundary():
    old, new = unrelated_meshes()
    mapped = map_stress(old, linear(old.points), new, "uem_bounded")
    away = interior_element_points(old, new.points)
    assert away.sum() > new.n_points / 4
    np.testing.assert_allclose(mapped[away], linear(new.points)[away], atol=1e-11)
    # at the boundary the limiter cuts the gradient: not exact there
    assert np.abs(mapped - linear(new.points)).max() > 1e-3


def test_patch_recovery_is_exact_at_vertices_for_a_linear_field():
    old, _ = unrelated_meshes()
    np.testing.assert_allclose(recover_nodal(old, linear(old.points)), linear(old.mesh.p.T),
                               atol=1e-12)


def test_bounded_uem_obeys_a_local_maximum_principle():
    """Every mapped value within the old values of the elements around its old element."""
    old, new = unrelated_meshes()
    sigma = np.random.default_rng(5).normal(size=(old.n_points, 4))
    mapped = map_stress(old, sigma, new, "uem_bounded")
    element, _, _ = locate(old.mesh, new.points)
    t, owner = old.mesh.t, old.point_element
    for n, e in enumerate(element):
        around = np.isin(t[:, owner], t[:, e]).any(axis=0)     # points of elements touching e
        assert np.all(sigma[around].min(axis=0) <= mapped[n] + 1e-12)
        assert np.all(mapped[n] <= sigma[around].max(axis=0) + 1e-12)
    plain = map_stress(old, sigma, new, "uem")                  # the classical UEM overshoots
    assert plain.max() > sigma.max() and plain.min() < sigma.min()


def flipped(mesh, facet):
    """``mesh`` with the diagonal ``facet`` of the quadrilateral of its two triangles flipped."""
    from skfem import MeshTri
    a, b = mesh.facets[:, facet]
    e, f = mesh.f2t[:, facet]
    c, d = (np.setdiff1d(mesh.t[:, k], (a, b))[0] for k in (e, f))
    t = mesh.t.copy()
    t[:, e], t[:, f] = (a, d, c), (b, c, d)
    return MeshTri(mesh.p, t)


def test_bounded_uem_keeps_the_stresses_of_the_elements_a_remeshing_keeps():
    """Onto its own mesh a field maps unchanged, at the boundary too (before, the clip to
    the recovered vertex range moved the noise by up to 3.1, at 98 % of the points), and a
    remesh that flips one diagonal changes only the two flipped elements' points."""
    old, _ = unrelated_meshes()
    noise = np.random.default_rng(3).normal(size=(old.n_points, 4))
    np.testing.assert_allclose(map_stress(old, noise, old, "uem_bounded"), noise, atol=1e-12)
    interior = np.flatnonzero(old.mesh.f2t[1] >= 0)
    facet = interior[len(interior) // 2]
    new = discretise(flipped(old.mesh, facet))
    mapped = map_stress(old, noise, new, "uem_bounded")
    kept = ~np.isin(new.point_element, old.mesh.f2t[:, facet])   # the same triangles, in order
    np.testing.assert_allclose(mapped[kept], noise[kept], atol=1e-12)
    assert np.abs(mapped[~kept] - noise[~kept]).max() > 1e-2


def lattice(n, other):
    """The unit square's n x n squares, each cut by one diagonal or (``other``) the other."""
    from skfem import MeshTri
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    v = lambda a, b: ((i + a) * (n + 1) + j + b).ravel()             # noqa: E731
    x = np.linspace(0, 1, n + 1)
    p = np.array(np.meshgrid(x, x, indexing="ij")).reshape(2, -1)
    if other:
        t = np.hstack([[v(0, 0), v(1, 0), v(0, 1)], [v(1, 0), v(1, 1), v(0, 1)]])
    else:
        t = np.hstack([[v(0, 0), v(1, 0), v(1, 1)], [v(0, 0), v(1, 1), v(0, 1)]])
    return discretise(MeshTri(p, t))


def test_bounded_uem_with_regions_keeps_a_field_linear_in_each_region():
    """A field linear in each of two regions, its gradient ten times steeper in the upper one
    (a heavy fill on a soil), mapped onto the lattice's other diagonals: exact with the
    regions (the patch fits one per side of the interface), as the plain UEM; one fit per
    vertex smears the kink, and the clip moves values near it (by 0.068, measured)."""
    old, new = lattice(6, False), lattice(6, True)
    upper = lambda d: d.mesh.p[1][d.mesh.t].mean(axis=0) > 0.5          # noqa: E731
    kinked = lambda y, up: np.where(up, 0.5 + 10 * (y - 0.5), y)         # noqa: E731
    sigma = kinked(old.points[:, 1], upper(old)[old.point_element])
    exact = kinked(new.points[:, 1], upper(new)[new.point_element])
    np.testing.assert_allclose(map_stress(old, sigma, new, "uem_bounded",
                                          regions=upper(old).astype(int)), exact, atol=1e-12)
    np.testing.assert_allclose(map_stress(old, sigma, new, "uem"), exact, atol=1e-12)
    assert np.abs(map_stress(old, sigma, new, "uem_bounded") - exact).max() > 0.05
    with pytest.raises(ValueError, match="one label per old element"):
        map_stress(old, sigma, new, "uem_bounded", regions=[0, 1])


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(10, 120), st.floats(1.0, 3.0))
def test_bounded_uem_between_random_remeshes(seed, n, alpha):
    """Alpha mesh of a random cloud <-> its Triangle remesh: within the data, exact inside."""
    rng = np.random.default_rng(seed)
    x = rng.uniform(0, 1, (n, 2))
    s = alpha_shape(x, 1 / np.sqrt(n), alpha)
    if len(s.triangles) == 0:
        return
    a, q = discretise(alpha_mesh(s).mesh), discretise(quality_remesh(s, size=0.7).mesh)
    # on the quality mesh every interior vertex is surrounded by its patch
    interior = np.ones(q.mesh.p.shape[1], bool)
    interior[q.mesh.boundary_nodes()] = False
    np.testing.assert_array_equal(surrounded_vertices(q), interior)
    for old, new in ((a, q), (q, a)):
        noise = rng.normal(size=old.n_points)
        mapped = map_stress(old, noise, new, "uem_bounded")
        assert noise.min() - 1e-12 <= mapped.min() and mapped.max() <= noise.max() + 1e-12
        mapped = map_stress(old, linear(old.points), new, "uem_bounded")
        away = interior_element_points(old, new.points)
        np.testing.assert_allclose(mapped[away], linear(new.points)[away], rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("method, norm, lowest", [
    ("uem_bounded", "max", 1.2),     # first order only where the limiter meets the boundary
    ("uem_bounded", "L2", 1.8),
    ("spr", "max", 1.7),
])
def test_convergence_under_refinement(method, norm, lowest):
    sizes = np.array([0.2, 0.1, 0.05, 0.025])
    errors = []
    for h in sizes:
        old = discretise(triangulate_polygon(SQUARE, h))
        new = discretise(triangulate_polygon(SQUARE, 0.77 * h))
        e = map_stress(old, smooth(old.points), new, method) - smooth(new.points)
        errors.append(np.abs(e).max() if norm == "max" else np.sqrt(new.weights @ e**2))
    rate = np.polyfit(np.log(sizes), np.log(errors), 1)[0]
    assert rate >= lowest, f"{method}: observed {norm}-norm rate {rate:.2f} < {lowest}"


def round_trips(method, trips=12):
    old = discretise(triangulate_polygon(SQUARE, 0.1))
    new = discretise(triangulate_polygon(SQUARE, 0.077))
    s, errors = smooth(old.points), []
    for _ in range(trips):
        s = map_stress(new, map_stress(old, s, new, method), old, method)
        errors.append(np.abs(s - smooth(old.points)).max())
    return np.array(errors), s


def test_bounded_uem_error_grows_at_most_linearly_over_round_trips():
    errors, s = round_trips("uem_bounded")
    assert 0 <= s.min() and s.max() <= 1                      # the exact range of the field
    assert errors[-1] <= 12 * errors[0], f"after 12 trips {errors[-1]:.3g}, one trip {errors[0]:.3g}"


def test_classical_uem_error_grows_geometrically_over_round_trips():
    errors, _ = round_trips("uem")
    growth = (errors[-1] / errors[3]) ** (1 / 8)              # per trip, trips 4 -> 12
    assert growth > 1.5, f"UEM round-trip error grows by {growth:.2f} per trip"


def test_new_methods_reject_bad_input():
    old, new = unrelated_meshes()
    for method in ("uem_bounded", "spr"):
        with pytest.raises(ValueError, match="rows"):
            map_stress(old, np.zeros(old.n_points - 1), new, method)


def test_only_ida_keeps_stresses_at_yield_admissible():
    """IDA is a convex combination, so it keeps a convex yield set; the box bounds do not."""
    from pfem_skfem.materials import MohrCoulomb
    old, new = unrelated_meshes()
    mc, rng = MohrCoulomb(1.0, 30.0), np.random.default_rng(0)
    p_mean, theta = rng.uniform(-3, 0, old.n_points), rng.uniform(0, 2 * np.pi, old.n_points)
    radius = np.cos(np.radians(30)) - p_mean * np.sin(np.radians(30))
    at_yield = np.c_[p_mean + radius * np.cos(theta), p_mean - radius * np.cos(theta),
                     0.6 * p_mean, radius * np.sin(theta)]
    assert np.abs(mc.F(at_yield)).max() < 1e-12                # all on the yield surface
    assert mc.F(map_stress(old, at_yield, new, "ida")).max() < 1e-12
    assert mc.F(map_stress(old, at_yield, new, "uem_bounded")).max() > 1e-3


def test_a_vertex_of_a_sliver_only_takes_its_patch_mean():
    """A vertex whose only element is a sliver (its three stress points nearly on a line)
    has no plane fit: recover_nodal gives the mean of its points, finite, and leaves the
    other vertices' fits (exact for a linear field) as they were."""
    from skfem import MeshTri
    from pfem_skfem.discretisation.static import discretise
    from pfem_skfem.pfem.mapping import recover_nodal

    p = np.array([[0.0, 1.0, 0.0, 1.0, 1.0 + 1e-9], [0.0, 0.0, 1.0, 1.0, 0.5]])   # 4: a sliver
    t = np.array([[0, 1, 2], [1, 3, 2], [1, 4, 3]]).T
    disc = discretise(MeshTri(p, t))
    xy = disc.points
    sigma = 1.0 + 2.0 * xy[:, 0] - 3.0 * xy[:, 1]            # a linear field
    nodal = recover_nodal(disc, sigma)
    assert np.all(np.isfinite(nodal))
    lonely = disc.point_element == 2
    assert nodal[4] == pytest.approx(sigma[lonely].mean(), rel=1e-12)
    assert nodal[0] == pytest.approx(1.0, abs=1e-9)           # a vertex with a real patch
