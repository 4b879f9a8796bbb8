"""Bad input refused before any work, and the state's history its own (issue 36, items 10
and 12): each test is a case that ran silently, or failed late, before the check."""
import math
import time

import numpy as np
import pytest

from pfem_skfem.scene.config import PFEMConfig
from pfem_skfem.drivers.pfem_loop import run
from pfem_skfem.materials import (CohesiveTresca, DavisMohrCoulomb, MuIRheology,
                                  MuIRheologyAxisymmetric, ZeroDilationDruckerPrager,
                                  ZeroDilationMohrCoulomb, ZeroDilationMohrCoulombAxisymmetric)
from pfem_skfem.scene import (HalfPlane, Outlet, Region, Scene, SceneFileError, scene_digest,
                              scene_from_toml)
from pfem_skfem.scene.files import example_text
from pfem_skfem.scene.regions import check_polygon
from verification.granular_column_plane import granular_column

SAND = ZeroDilationMohrCoulomb(0.0, 30.0)
SQUARE = ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0))


def box(x0, y0, x1, y1):
    return ((x0, y0), (x1, y0), (x1, y1), (x0, y1))


def column(old, new):
    text = example_text("column")
    assert old in text
    return text.replace(old, new, 1)


# -- the history of a state ----------------------------------------------------------------
def test_two_runs_branched_from_one_state_have_their_own_histories():
    """Both runs used to append to one dict shared by every state: a, b and s all held
    steps [1, 2, 1, 2]."""
    s, scene = granular_column(1.0, 4)
    a, _ = run(s, scene, 2)
    b, _ = run(s, scene, 2)
    assert a.history["step"] == b.history["step"] == [1, 2]
    assert s.history == {}                                  # the input is not changed
    assert a.history["area_change"] == b.history["area_change"]    # the same two steps


def test_each_state_of_a_run_holds_the_records_of_its_own_steps_only():
    """The state handed on after step n (what an interrupted CLI saves) must not hold the
    record of step n + 1: a Ctrl-C in step 10's VTU write saved a step-9 checkpoint holding
    step 10, and a resume then recorded it twice."""
    s, scene = granular_column(1.0, 4)
    seen = []
    run(s, scene, 3, on_step=lambda state, rec, result: seen.append(state))
    assert [st.history["step"] for st in seen] == [[1], [1, 2], [1, 2, 3]]


# -- run's arguments -----------------------------------------------------------------------
@pytest.mark.parametrize("steps, error", [(-1, ValueError), (2.7, TypeError),
                                          (math.nan, TypeError), (None, TypeError),
                                          (True, TypeError), ("2", TypeError)])
def test_run_refuses_steps_that_are_not_a_non_negative_int(steps, error):
    s, scene = granular_column(1.0, 4)
    with pytest.raises(error, match="steps"):
        run(s, scene, steps)


def test_run_refuses_what_is_not_a_state_or_a_scene():
    """run(None, ...) and run(s, None, ...) gave raw Type/AttributeErrors."""
    s, scene = granular_column(1.0, 4)
    with pytest.raises(TypeError, match="state must be a PFEMState"):
        run(None, scene, 1)
    with pytest.raises(TypeError, match="scene must be a Scene"):
        run(s, None, 1)


def test_run_of_zero_steps_returns_the_state_itself():
    s, scene = granular_column(1.0, 4)
    out, snaps = run(s, scene, np.int64(0))
    assert out is s and snaps == {}


def test_run_refuses_a_state_of_another_scene():
    """run(state of scene A, scene B) ran silently (the mass of A, the records of B)."""
    s, scene = granular_column(1.0, 4)
    other = Scene(regions=(Region(box(0, 0, 2, 1), SAND, 2.0, 0.25),))
    with pytest.raises(ValueError, match="does not belong to the scene"):
        run(s, other, 1)
    two = Scene(regions=(Region(box(0, 0, 1, 1), SAND, 2.0, 0.25, name="a"),
                         Region(box(1, 0, 2, 1), SAND, 2.0, 0.25, name="b")))
    state = two.initial_state()
    with pytest.raises(ValueError, match="region 1"):
        run(state, Scene(regions=(Region(box(0, 0, 2, 1), SAND, 1.0, 0.25),)), 1)


def test_scene_digest_is_the_scene_s_identity():
    a = scene_from_toml(example_text("column"))
    assert scene_digest(a) == scene_digest(scene_from_toml(example_text("column")))
    assert len(scene_digest(a)) == 64
    assert scene_digest(a) != scene_digest(scene_from_toml(column("rho = 2.0", "rho = 2.5")))
    assert scene_digest(a) == scene_digest(scene_from_toml(column("\nt_end = 1.6",
                                                                  "\nt_end = 1.0")))


def test_a_field_added_later_leaves_the_digests_of_earlier_runs_unchanged():
    # a run checkpointed before PFEMConfig had ``solver`` stored the digest below (the
    # example column's, computed by the code of that time, commit b8a8191): the same
    # scene must still be recognised, and another solver must make it another scene
    from dataclasses import replace
    a = scene_from_toml(example_text("column"))
    assert scene_digest(a) == "3c3d50396cae7bfc90ac127af3403507c4ccd307708c87cf984fb74dd6a83301"
    qoco = replace(a, config=replace(a.config, solver="qoco"))
    assert scene_digest(qoco) != scene_digest(a)


@pytest.mark.parametrize("solver, digest", [
    ("cvxpy", "fb243c6ed3f26134265ae3ea258d109f6bb2a76d2b156ba78ca019a8566e97ab"),
    ("clarabel-dual", "9859eac1a4f4548b6a6348ec2ad15a96b0d41bff2c7dfdac92129e333f750b11"),
    ("qoco-dual", "5de8037bc6043862f3aed95d97e742df642c0f02ea4f1b833e54dd34bf5c106c"),
    ("cvxpy-qoco", "2fa66c42a5f9ee6c753b7043292594c366b85b5c2dbebe922362366a02ef527f"),
    ("cvxpy-scs", "8621cb0d718a643b988d1dd8cf4f9cb9d0400e3989253903ba4d90f8f11d2d55")])
def test_one_solver_name_keeps_the_digests_of_the_three_keys_it_replaced(solver, digest):
    # PFEMConfig's backend, solver and form became one solver name; the digests below are
    # the example column's with the three keys that chose the same step (backend 'cvxpy';
    # form 'dual'; solver 'qoco' with form 'dual'; backend 'cvxpy' with solver 'qoco';
    # solver 'scs', the cvxpy statement then), computed by the code of that time (commit bec35a2): a run
    # checkpointed then is still recognised
    from dataclasses import replace
    a = scene_from_toml(example_text("column"))
    assert scene_digest(replace(a, config=replace(a.config, solver=solver))) == digest


# -- materials and geometry ----------------------------------------------------------------
@pytest.mark.parametrize("material", [ZeroDilationMohrCoulomb(0.0, 31.0),
                                      CohesiveTresca(1.0), MuIRheology()])
def test_a_plane_material_in_axisymmetry_is_refused(material):
    """It ran: the hoop stress unbounded, the released column never moved (2e-13 m/s)."""
    with pytest.raises(ValueError, match=r"region 'column'.*Axisymmetric"):
        Scene(regions=(Region(SQUARE, material, 2.0, 0.25, name="column"),),
              geometry="axisymmetric")


@pytest.mark.parametrize("material", [ZeroDilationMohrCoulombAxisymmetric(0.0, 31.0),
                                      MuIRheologyAxisymmetric()])
def test_an_axisymmetric_material_in_plane_strain_is_refused(material):
    with pytest.raises(ValueError, match=r"region 'column'.*geometry 'axisymmetric'"):
        Scene(regions=(Region(SQUARE, material, 2.0, 0.25, name="column"),))


def test_the_column_file_with_geometry_axisymmetric_names_the_material_to_use():
    with pytest.raises(SceneFileError, match="ZeroDilationMohrCoulombAxisymmetric"):
        scene_from_toml(column("length = 1.0 ", 'geometry = "axisymmetric"\nlength = 1.0 '))
    # Drucker-Prager serves both geometries
    Scene(regions=(Region(SQUARE, ZeroDilationDruckerPrager(0.0, 30.0), 2.0, 0.25),),
          geometry="axisymmetric")


@pytest.mark.parametrize("c", [-1.0, math.nan, math.inf])
@pytest.mark.parametrize("make", [lambda c: ZeroDilationMohrCoulomb(c, 30.0),
                                  lambda c: DavisMohrCoulomb(c, 30.0),
                                  lambda c: ZeroDilationMohrCoulombAxisymmetric(c, 30.0),
                                  lambda c: ZeroDilationDruckerPrager(c, 30.0),
                                  lambda c: CohesiveTresca(c)])
def test_a_negative_or_non_finite_cohesion_is_refused(make, c):
    """c = -1 ran (c <= 0 was replaced by 1.0 before the check), c = nan failed at step 1."""
    with pytest.raises(ValueError, match=r"\bc\b"):
        make(c)


# -- regions -------------------------------------------------------------------------------
def test_a_hole_outside_its_polygon_is_refused():
    """It ran with mass 1.0 for 2.0 and particles along the hole's edges, far outside."""
    with pytest.raises(ValueError, match="hole 0.*inside"):
        Region(SQUARE, SAND, 2.0, 0.1, holes=(((5.0, 5.0), (6.0, 5.0), (6.0, 6.0)),))
    with pytest.raises(ValueError, match="hole 0.*inside"):     # half out
        Region(SQUARE, SAND, 2.0, 0.1, holes=(box(0.5, 0.25, 1.5, 0.75),))


def test_a_hole_equal_to_its_polygon_is_refused():
    """It ran: 28 particles of mass 0."""
    with pytest.raises(ValueError, match="hole 0"):
        Region(SQUARE, SAND, 2.0, 0.1, holes=(SQUARE,))


def test_a_hole_touching_the_polygon_s_edge_is_a_notch():
    r = Region(SQUARE, SAND, 2.0, 0.1, holes=(box(0.4, 0.0, 0.6, 0.5),))
    assert r.area == pytest.approx(0.9)


@pytest.mark.parametrize("second", [box(0.5, 0, 1.5, 1), box(0.25, 0.25, 0.75, 0.75), SQUARE,
                                    ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0))])
def test_overlapping_regions_are_refused_naming_both(second):
    """Half overlap gave mass 4.0 for 3.0; a region inside another 0 particles (and a
    divide-by-zero warning)."""
    with pytest.raises(ValueError, match="regions 'a' and 'b' overlap"):
        Scene(regions=(Region(SQUARE, SAND, 2.0, 0.1, name="a"),
                       Region(second, SAND, 2.0, 0.1, name="b")))


def test_regions_sharing_an_edge_or_filling_a_hole_keep_their_mass():
    inner = box(0.25, 0.25, 0.75, 0.75)
    scene = Scene(regions=(Region(SQUARE, SAND, 2.0, 0.125, name="a", holes=(inner,)),
                           Region(inner, SAND, 4.0, 0.125, name="core"),
                           Region(box(1, 0, 2, 1), SAND, 1.0, 0.125, name="side")))
    state = scene.initial_state()
    assert state.total_mass == pytest.approx(2.0 * 0.75 + 4.0 * 0.25 + 1.0, rel=1e-12)
    assert scene.mass == pytest.approx(state.total_mass, rel=1e-12)


# -- outlets -------------------------------------------------------------------------------
def test_an_outlet_with_its_normal_reversed_is_refused():
    """The silo's bottom row lies on the orifice's plane, so the strict "holds every
    particle" test passed a flipped normal: 406 of 409 particles left in step 1."""
    text = example_text("silo")
    assert "normal = [0.0, -1.0]" in text
    with pytest.raises(SceneFileError, match="outlet 'orifice' contains every particle"):
        scene_from_toml(text.replace("normal = [0.0, -1.0]", "normal = [0.0, 1.0]"))
    scene_from_toml(text)                                   # the right way round runs
    floor = HalfPlane((0.0, 0.0), (0.0, -1.0))               # below the base: right
    Scene(regions=(Region(SQUARE, SAND, 2.0, 0.25),), outlets=(Outlet("floor", floor),))
    with pytest.raises(ValueError, match="outlet 'floor'.*reversed"):
        Scene(regions=(Region(SQUARE, SAND, 2.0, 0.25),),
              outlets=(Outlet("floor", HalfPlane((0.0, 0.0), (0.0, 1.0))),))


# -- sizes and limits ----------------------------------------------------------------------
def test_a_million_particles_are_refused_before_any_is_placed(monkeypatch):
    """h = 0.001 was accepted and died of memory after 32 s."""
    monkeypatch.delenv("PFEM_SKFEM_MAX_PARTICLES", raising=False)
    t0 = time.perf_counter()
    with pytest.raises(ValueError, match=r"1,00\d,\d{3} particles.*max_particles"):
        Scene(regions=(Region(SQUARE, SAND, 2.0, 0.001),))
    assert time.perf_counter() - t0 < 1.0
    with pytest.raises(ValueError, match="limit of 50"):
        Scene(regions=(Region(SQUARE, SAND, 2.0, 0.1),), max_particles=50)
    monkeypatch.setenv("PFEM_SKFEM_MAX_PARTICLES", "50")
    with pytest.raises(ValueError, match="PFEM_SKFEM_MAX_PARTICLES"):
        Scene(regions=(Region(SQUARE, SAND, 2.0, 0.1),))
    assert Scene(regions=(Region(SQUARE, SAND, 2.0, 0.1),),
                 max_particles=200).initial_state().n == 121
    monkeypatch.delenv("PFEM_SKFEM_MAX_PARTICLES")
    with pytest.raises(SceneFileError, match="limit of 50 "):       # a scene file's key
        scene_from_toml(column("\nt_end = 1.6", "\nmax_particles = 50\nt_end = 1.6"))


def test_the_self_intersection_check_is_fast_and_names_a_bowtie():
    """O(k^2) in Python: 7 s at 2,000 vertices; a bowtie was reported as 'zero area'."""
    k = 10_000
    t = np.linspace(0, 2 * np.pi, k, endpoint=False)
    star = np.column_stack([np.cos(t), np.sin(t)]) * (1 + 0.3 * np.sin(40 * t))[:, None]
    t0 = time.perf_counter()
    check_polygon(star, "star")
    assert time.perf_counter() - t0 < 1.0
    star[5000] = (2.0, 0.0)                  # a spike across the neighbouring edges
    with pytest.raises(ValueError, match="intersects itself"):
        check_polygon(star, "star")
    with pytest.raises(ValueError, match="bowtie: the polygon intersects itself"):
        check_polygon(((0, 0), (1, 1), (1, 0), (0, 1)), "bowtie")


def test_a_region_too_small_for_its_spacing_is_refused():
    """A 1e-9 square gave a 'mesh is empty' traceback at step 1."""
    with pytest.raises(ValueError, match="region 'dot'.*h"):
        Scene(regions=(Region(box(0, 0, 1e-9, 1e-9), SAND, 2.0, 0.1, name="dot"),))
    with pytest.raises(SceneFileError, match="regions.*h"):
        scene_from_toml(column("[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]",
                               "[[0.0, 0.0], [1e-9, 0.0], [1e-9, 1e-9], [0.0, 1e-9]]"))


@pytest.mark.parametrize("value", ["inf", "1e400", "nan"])
def test_a_non_finite_end_time_is_refused(value):
    """t_end = inf gave an OverflowError traceback when the steps were counted."""
    with pytest.raises(SceneFileError, match="t_end"):
        scene_from_toml(column("\nt_end = 1.6", f"\nt_end = {value}"))


def test_passes_has_an_upper_bound():
    """passes = 99999999999999999999 was accepted and hung."""
    with pytest.raises(SceneFileError, match="passes"):
        scene_from_toml(column("passes = 2 ", "passes = 99999999999999999999 "))
    with pytest.raises(ValueError, match="passes"):
        PFEMConfig(passes=1001)
    PFEMConfig(passes=1000)


def test_mistyped_arguments_are_refused_naming_the_parameter():
    """These gave numpy TypeErrors naming no parameter, or (a class) were accepted."""
    with pytest.raises(ValueError, match="rho"):
        Region(SQUARE, SAND, "2", 0.1)
    with pytest.raises(ValueError, match="h must"):
        Region(SQUARE, SAND, 2.0, None)
    with pytest.raises(ValueError, match="phi"):
        ZeroDilationMohrCoulomb(0.0, "31")
    with pytest.raises(ValueError, match="material"):
        Region(SQUARE, ZeroDilationMohrCoulomb, 2.0, 0.1)
    with pytest.raises(ValueError, match="polygon"):
        Region(((0, 0), (1, 0, 2), (1, 1)), SAND, 2.0, 0.1)
    with pytest.raises(ValueError, match="outlets must be a list"):
        Scene(regions=(Region(SQUARE, SAND, 2.0, 0.25),),
              outlets=Outlet("o", HalfPlane((0.0, 0.0), (0.0, -1.0))))


def test_a_tensile_geostatic_k0_is_refused():
    """k0 = -0.5 ran: a lateral tension in a cohesionless column."""
    from pfem_skfem.scene import Geostatic
    with pytest.raises(ValueError, match="k0"):
        Geostatic(k0=-0.5)
    assert Geostatic(k0=0.0).k0 == 0.0
