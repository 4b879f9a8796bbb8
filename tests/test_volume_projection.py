"""The volume projection of the move stage (pfem/volume_projection.py): closed forms on a
square patch in plane strain and in axisymmetry, its convergence order, a rotation, no
shift without motion, held and pressed vertices, the engine."""
from types import SimpleNamespace

import numpy as np
import pytest
from skfem import MeshTri

from pfem_skfem.discretisation.fields import vertex_dofs
from pfem_skfem.discretisation.static import discretise
from pfem_skfem.pfem.volume_projection import (patch_volume_gradient, patch_volumes,
                                               step_constraint, volume_shift)

STRAINS = (0.1, 0.05, 0.025)


def square(geometry="plane", n=9, origin=(0.0, 0.0)):
    mesh = MeshTri.init_tensor(np.linspace(0, 1, n) + origin[0], np.linspace(0, 1, n) + origin[1])
    return discretise(mesh, geometry)


def linear_field(disc, matrix):
    """The P2 dofs of du(x) = matrix @ x (exact in P2)."""
    du = np.zeros(disc.n_u)
    X = disc.basis_u.doflocs
    for c in range(2):
        dofs = np.concatenate([disc.basis_u.nodal_dofs[c], disc.basis_u.facet_dofs[c]])
        du[dofs] = matrix[c, 0] * X[0, dofs] + matrix[c, 1] * X[1, dofs]
    return du


def axis_radial_dofs(disc):
    on_axis = np.abs(disc.mesh.p[0]) < 1e-12
    return disc.basis_u.nodal_dofs[0][on_axis]


def volumes_after(disc, du, fixed=(), correct=True):
    """(volume at t_n, volume moved by du, the moved one corrected, the constraint, shift)."""
    c = step_constraint(disc, fixed=fixed)
    p = disc.mesh.p.T
    x = p + du[vertex_dofs(disc)]
    total = lambda y: patch_volumes(y, c.triangles, c.orientation, c.axisymmetric).sum()  # noqa
    w = volume_shift(c, x)
    return total(p), total(x), total(x + w), c, w


def order(errors):
    return np.polyfit(np.log(STRAINS), np.log(errors), 1)[0]


def test_isochoric_extension_loses_exactly_its_second_order_area_and_the_shift_restores_it():
    """du = (e x, -e y): the moved square has area (1 + e)(1 - e) = 1 - e^2; corrected, the
    error is of fourth order (one Newton step on the patch constraints)."""
    disc = square()
    errors = []
    for e in STRAINS:
        before, moved, corrected, _, _ = volumes_after(disc, linear_field(disc, np.diag([e, -e])))
        assert moved / before - 1 == pytest.approx(-e ** 2, rel=1e-10)
        errors.append(abs(corrected / before - 1))
    assert all(err < 0.01 * e ** 2 for err, e in zip(errors, STRAINS))    # 1 % of the loss
    assert order(errors) > 3.5, f"observed order {order(errors):.2f}, expected 4"


def test_axisymmetric_isochoric_extension_with_the_hoop_strain():
    """du = (e r, -2 e z) is isochoric with the hoop strain u_r / r: the moved cylinder of
    revolution has volume (1 + e)^2 (1 - 2 e) = 1 - 3 e^2 - 2 e^3 times the old; corrected,
    fourth order, and the vertices on the axis stay on it."""
    disc = square("axisymmetric")
    axis = np.abs(disc.mesh.p[0]) < 1e-12
    errors = []
    for e in STRAINS:
        du = linear_field(disc, np.diag([e, -2 * e]))
        before, moved, corrected, _, w = volumes_after(disc, du, fixed=axis_radial_dofs(disc))
        assert moved / before - 1 == pytest.approx(-3 * e ** 2 - 2 * e ** 3, rel=1e-10)
        assert np.all(w[axis, 0] == 0.0)
        errors.append(abs(corrected / before - 1))
    assert all(err < 0.01 * 3 * e ** 2 for err, e in zip(errors, STRAINS))
    assert order(errors) > 3.5, f"observed order {order(errors):.2f}, expected 4"


@pytest.mark.parametrize("geometry", ["plane", "axisymmetric"])
def test_every_patch_meets_its_target_to_second_order_in_the_shift(geometry):
    disc = square(geometry)
    residuals = []
    for e in STRAINS:
        du = linear_field(disc, np.array([[e, 0.3 * e], [0.2 * e, -e]]))
        fixed = axis_radial_dofs(disc) if geometry == "axisymmetric" else ()
        before, _, _, c, w = volumes_after(disc, du, fixed=fixed)
        x = disc.mesh.p.T + du[vertex_dofs(disc)] + w
        residuals.append(np.abs(c.volumes(x) - c.target(x - w)).max() / before)
    assert order(residuals) > 3.5, f"observed order {order(residuals):.2f}, expected 4"


@pytest.mark.parametrize("geometry", ["plane", "axisymmetric"])
def test_the_target_is_the_integral_of_the_linearised_strain(geometry):
    """V_i* - V_i(x_n) = int phi_i tr eps(d) dV, tr eps = div d (+ d_r / r in axisymmetry):
    for d = e x, 2 e (3 e) times the patch volume."""
    disc = square(geometry)
    e = 0.01
    c = step_constraint(disc)
    p = disc.mesh.p.T
    strain = 3 * e if geometry == "axisymmetric" else 2 * e
    assert np.allclose(c.target(p * (1 + e)) - c.volumes(p), strain * c.volumes(p),
                       rtol=1e-12, atol=0)


def test_dilation_is_kept_as_the_linearised_strain_states():
    """du = e x (div du = 2 e): the target is the area plus the integral of tr eps(du),
    (1 + 2 e) A, not the moved (1 + e)^2 A; corrected, it is met to fourth order."""
    disc = square()
    errors = []
    for e in STRAINS:
        du = linear_field(disc, np.diag([e, e]))
        before, moved, corrected, _, _ = volumes_after(disc, du)
        assert moved / before == pytest.approx((1 + e) ** 2, rel=1e-12)
        errors.append(abs(corrected / before - (1 + 2 * e)))
    assert order(errors) > 3.5, f"observed order {order(errors):.2f}, expected 4"


def test_a_small_rotation_is_only_shifted_at_second_order():
    """du = theta (-y, x) (the linearised rotation, tr eps = 0) grows the area by theta^2;
    the shift that takes it back is of second order in theta (a first-order motion is left
    alone) and the area error of fourth order."""
    disc = square(origin=(-0.5, -0.5))
    shifts, errors = [], []
    for theta in STRAINS:
        du = linear_field(disc, np.array([[0.0, -theta], [theta, 0.0]]))
        before, moved, corrected, _, w = volumes_after(disc, du)
        assert moved / before - 1 == pytest.approx(theta ** 2, rel=1e-10)
        shifts.append(np.abs(w).max())
        errors.append(abs(corrected / before - 1))
    assert 1.8 < order(shifts) < 2.2, f"shift order {order(shifts):.2f}, expected 2"
    assert order(errors) > 3.5, f"observed order {order(errors):.2f}, expected 4"


@pytest.mark.parametrize("geometry", ["plane", "axisymmetric"])
def test_no_motion_no_shift(geometry):
    disc = square(geometry)
    _, _, _, _, w = volumes_after(disc, np.zeros(disc.n_u))
    assert np.all(w == 0.0)


@pytest.mark.parametrize("geometry", ["plane", "axisymmetric"])
def test_patch_volume_gradient_is_the_derivative_of_the_patch_volumes(geometry):
    disc = square(geometry, n=5)
    p, t = disc.mesh.p.T, disc.mesh.t.T
    s = np.ones(len(t))
    axi = geometry == "axisymmetric"
    G = patch_volume_gradient(p, t, s, axi)
    d = np.random.default_rng(0).normal(size=p.shape) * 1e-6
    central = (patch_volumes(p + d, t, s, axi) - patch_volumes(p - d, t, s, axi)) / 2
    assert np.abs(G @ d.ravel() - central).max() < 1e-9 * np.abs(central).max()


def test_held_vertices_stay_and_pressed_vertices_slide_along_the_wall():
    """Held dofs (a phase) get no shift; vertices pressed on a body (here the base y = 0)
    no shift along its normal, so the projection does not push them into it: the free
    vertices take the whole correction, and the volume is still restored."""
    disc = square()
    p = disc.mesh.p.T
    vd = vertex_dofs(disc)
    left = np.flatnonzero(p[:, 0] < 1e-12)
    base = np.flatnonzero((p[:, 1] < 1e-12) & (p[:, 0] > 1e-12))
    contacts = SimpleNamespace(dofs=vd[base], normal=np.tile([0.0, -1.0], (len(base), 1)))
    e = 0.05
    du = linear_field(disc, np.diag([e, -e]))
    c = step_constraint(disc, fixed=vd[left].ravel(), contacts=contacts,
                        pressed=np.ones(len(base), dtype=bool))
    x = p + du[vd]
    w = volume_shift(c, x)
    assert np.all(w[left] == 0.0)
    assert np.abs(w[base, 1]).max() < 1e-15 and np.abs(w[base, 0]).max() > 0
    total = lambda y: patch_volumes(y, c.triangles, c.orientation, False).sum()  # noqa
    assert abs(total(x + w) - 1.0) < 0.01 * e ** 2


def collapse(volume_correction, steps=12):
    from pfem_skfem.scene.columns import granular_column_axisymmetric
    from pfem_skfem.drivers.pfem_loop import run
    state, scene = granular_column_axisymmetric(2.0, 5, dt=0.04 * np.sqrt(2.0 / 9.8),
                                                volume_correction=volume_correction)
    state, _ = run(state, scene, steps)
    return state


def test_the_engine_option_reduces_the_volume_loss_and_keeps_walls_and_axis():
    """A collapsing column of revolution: with the correction the volume lost is smaller
    than without, no particle is below the base and the axis particles stay at r = 0."""
    off, on = collapse(False), collapse(True)
    lost_off = abs(off.history["area_change"][-1])
    lost_on = abs(on.history["area_change"][-1])
    assert lost_off > 1e-3                     # there is a loss to correct
    assert lost_on < 0.5 * lost_off
    assert on.x[:, 1].min() >= -1e-12
    assert np.all(on.x[:, 0] >= 0.0)
    x0 = collapse(True, steps=0).x
    axis0 = np.flatnonzero(x0[:, 0] == 0.0)
    assert np.all(on.x[axis0, 0] == 0.0)


def test_the_engine_option_changes_a_step_at_second_order():
    """One step of the collapse with and without the correction: the particles differ by
    a fraction of the step's displacement that falls with dt (the shift is quadratic in
    the displacement gradient), halving dt dividing it by more than 3."""
    from pfem_skfem.scene.columns import granular_column_axisymmetric
    from pfem_skfem.drivers.pfem_loop import pfem_step
    ratios = []
    for dt in (0.04, 0.02):
        state, scene = granular_column_axisymmetric(2.0, 5, dt=dt * np.sqrt(2.0 / 9.8))
        _, corrected = granular_column_axisymmetric(2.0, 5, dt=dt * np.sqrt(2.0 / 9.8),
                                                    volume_correction=True)
        for _ in range(3):                                  # under way
            state, _, _ = pfem_step(state, scene)
        plain, _, _ = pfem_step(state, scene)
        shifted, _, _ = pfem_step(state, corrected)
        ratios.append(np.abs(shifted.x - plain.x).max() / np.abs(plain.x - state.x).max())
    assert 0 < ratios[1] < ratios[0] / 3, ratios


def test_the_option_is_off_by_default():
    from pfem_skfem.scene.config import PFEMConfig
    assert PFEMConfig().volume_correction is False


@pytest.mark.parametrize("geometry", ["plane", "axisymmetric"])
def test_a_growth_target_scales_the_domain_to_it_at_second_order(geometry):
    """keep_area's target: no motion and a domain to shrink by g: the shifted domain has
    (1 + g) times the volume, the residual of second order in g; held and axis vertices
    stay; the growth is the one that reaches the volume asked for."""
    from pfem_skfem.pfem.volume_projection import area_growth
    disc = square(geometry)
    fixed = axis_radial_dofs(disc) if geometry == "axisymmetric" else ()
    before = step_constraint(disc, fixed=fixed).volumes(disc.mesh.p.T).sum()
    residuals = []
    for g in (-0.04, -0.02, -0.01):
        c = step_constraint(disc, fixed=fixed, volume=(1 + g) * before)
        assert c.growth == pytest.approx(g, rel=1e-12)
        x = disc.mesh.p.T
        w = volume_shift(c, x)
        residuals.append(abs(c.volumes(x + w).sum() / ((1 + g) * before) - 1))
        if geometry == "axisymmetric":
            assert np.all(w[np.abs(x[:, 0]) < 1e-12, 0] == 0.0)
    assert residuals[-1] < 1e-4
    slope = np.polyfit(np.log([0.04, 0.02, 0.01]), np.log(residuals), 1)[0]
    assert slope > 1.8, f"observed order {slope:.2f}, expected 2"
    with pytest.raises(ValueError, match="target volume"):
        area_growth(step_constraint(disc), -1.0)


def test_a_growth_limit_gives_back_at_most_that_much_a_step():
    """keep_area_step: a domain asked to grow or shrink by 4 % with a limit of 1 % grows
    or shrinks by 1 % (the sign kept), within the limit as asked; the limit is checked
    and needs keep_area."""
    from pfem_skfem.scene.config import PFEMConfig
    disc = square("plane")
    before = step_constraint(disc).volumes(disc.mesh.p.T).sum()
    for g, expected in ((0.04, 0.01), (-0.04, -0.01), (0.005, 0.005), (-0.005, -0.005)):
        c = step_constraint(disc, volume=(1 + g) * before, growth_limit=0.01)
        assert c.growth == pytest.approx(expected, rel=1e-12)
    c = step_constraint(disc, volume=1.04 * before)                     # no limit
    assert c.growth == pytest.approx(0.04, rel=1e-12)
    for bad in (-0.1, np.nan, np.inf):
        with pytest.raises(ValueError, match="keep_area_step"):
            PFEMConfig(volume_correction=True, keep_area=True, keep_area_step=bad)
    with pytest.raises(ValueError, match="needs keep_area"):
        PFEMConfig(keep_area_step=0.01)


def test_keep_area_gives_back_what_the_remeshing_adds():
    """A block of water sliding into a tank breaks its surface, and each remeshing's alpha
    shape closes gaps: without keep_area the detected area grows step after step; with
    it, the domain each step leaves (the moved mesh) has its first area to the second
    order of a step's gain (the flow is isochoric), and the detected area stays near it."""
    from verification.soil_and_water import tank_scene
    areas = {}
    for keep in (False, True):
        state, scene, _ = tank_scene(beta=30.0, mu_slope=0.2, mu_floor=0.0, d=0.4, L=2.0,
                                     block=(0.4, 0.2), c=2000.0, rho_w=1000.0, rho_c=1800.0,
                                     g=9.81, h=0.1, dt=0.03, keep_area=keep, thin=0.0)
        from pfem_skfem.drivers.pfem_loop import run
        state, _ = run(state, scene, 40)
        areas[keep] = (np.array(state.history["area_change"]),
                       np.array(state.history["moved_area"]) / state.history["area"][0] - 1)
    grown, _ = areas[False]
    detected, moved = areas[True]
    assert grown[-1] > 0.03                       # the gain is there to give back
    assert np.abs(moved).max() < 0.1 * grown[-1]
    assert np.abs(detected).max() < 0.5 * grown[-1]


def test_keep_area_needs_the_volume_projection_and_refuses_elastic_regions():
    from pfem_skfem.materials import Elastic, NewtonianFluid
    from pfem_skfem.scene.config import PFEMConfig
    assert PFEMConfig().keep_area is False
    with pytest.raises(ValueError, match="keep_area=True needs volume_correction=True"):
        PFEMConfig(keep_area=True)
    from pfem_skfem.materials import ZeroDilationMohrCoulomb
    from pfem_skfem.scene import column_scene
    with pytest.raises(ValueError, match="keep_area"):
        column_scene(ZeroDilationMohrCoulomb(phi=30, elastic=Elastic(1e6, 0.3)), 1.0, 1.0, 0.25,
                     rho=1.0, g=9.8, dt=0.01, volume_correction=True, keep_area=True)
    column_scene(NewtonianFluid(0.0), 1.0, 1.0, 0.25, rho=1.0, g=9.8, dt=0.01,
                 volume_correction=True, keep_area=True)


def test_a_shift_larger_than_the_motion_is_refused():
    """The vertices of the clay block sliding into the tank (soil_and_water.py at spacing
    0.04), step 214, when the shift was still applied: a pile of particles crowded into the
    floor's corner, two triangles inverted by the step, and the linearised projection asks
    a vertex to move 18.6 m up the wall for a motion of 0.05 m. The shift is refused (the
    positions stay) and said so; a healthy step's shift, far below its motion, is kept."""
    from pathlib import Path
    from pfem_skfem.pfem.alpha_shape import triangle_areas
    from pfem_skfem.pfem.volume_projection import VolumeConstraint, bounded_shift
    data = np.load(Path(__file__).parent / "data" / "tank_step_214_volume.npz")
    c = VolumeConstraint(data["triangles"], data["orientation"].astype(float), data["start"],
                         data["allowed"], False, float(data["growth"]))
    x, motion = data["x"], float(data["motion"])
    inverted = np.sign(triangle_areas(c.start, c.triangles)) != np.sign(
        triangle_areas(x, c.triangles))
    assert inverted.sum() == 2                   # the failed linearisation's cause
    w = volume_shift(c, x)
    assert np.linalg.norm(w, axis=1).max() > 100 * motion
    w, size, refused = bounded_shift(c, x, motion)
    assert refused and size > 100 * motion and not w.any()
    # a healthy step (an isochoric extension by 5 %): its shift, far below its motion, kept
    disc = square()
    e = 0.05
    du = linear_field(disc, np.diag([e, -e]))
    healthy = step_constraint(disc)
    moved = disc.mesh.p.T + du[vertex_dofs(disc)]
    w, size, refused = bounded_shift(healthy, moved, e)
    assert not refused and 0 < size < e and np.array_equal(w, volume_shift(healthy, moved))


def test_keep_area_leaves_out_the_volume_of_drops_flying_free():
    """The domain is asked for its first area less the volume m / rho of the particles
    outside the step's mesh (a splash's drops, each of its own region's density), times
    the fraction of the mass not discharged; without keep_area, nothing is asked."""
    from pfem_skfem.drivers.pfem_loop import kept_area
    scene = SimpleNamespace(config=SimpleNamespace(keep_area=True),
                            regions=(SimpleNamespace(rho=1800.0), SimpleNamespace(rho=1000.0)))
    state = SimpleNamespace(region=np.array([0, 0, 1, 1, 1]),
                            mass=np.array([18.0, 36.0, 10.0, 20.0, 0.0]),
                            discharged={}, total_mass=84.0)
    meshed = np.array([True, False, True, False, False])
    assert kept_area(state, scene, 2.0, meshed) == pytest.approx(2.0 - 36 / 1800 - 20 / 1000)
    assert kept_area(state, scene, 2.0, np.ones(5, bool)) == 2.0
    state.discharged = {"out": [84.0 / 3, 3]}           # a quarter of the first mass gone
    assert kept_area(state, scene, 2.0, np.ones(5, bool)) == pytest.approx(1.5)
    scene.config.keep_area = False
    assert kept_area(state, scene, 2.0, meshed) is None
