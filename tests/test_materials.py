"""The PFEM materials' declared protocol (pfem_skfem.materials.pfem.PFEMMaterial): every
material has a TOML form or a stated refusal, a material missing what the engine needs is
refused when its class is made, one cone signature, and regions of different materials."""
import inspect

import numpy as np
import pytest

from pfem_skfem import materials
from pfem_skfem.materials import (CohesiveTresca, DavisMohrCoulomb, MuIRheology,
                                  MuIRheologyAxisymmetric, PFEMMaterial, RegionCones,
                                  TrescaField, VonMisesField, ZeroDilationDruckerPrager,
                                  ZeroDilationMohrCoulomb)
from pfem_skfem.scene import Region
from pfem_skfem.scene.files import MATERIAL


def _subclasses(cls=PFEMMaterial):
    out = []
    for sub in cls.__subclasses__():
        if sub.__module__.startswith("pfem_skfem."):
            out += [sub] + _subclasses(sub)
    return out


PFEM_MATERIALS = _subclasses()


def test_the_package_has_the_pfem_materials():
    names = {c.__name__ for c in PFEM_MATERIALS}
    assert names == {"ZeroDilationMohrCoulomb", "DavisMohrCoulomb", "CohesiveTresca",
                     "ZeroDilationDruckerPrager", "ZeroDilationMohrCoulombAxisymmetric",
                     "MuIRheology", "MuIRheologyAxisymmetric", "RegionCones",
                     "NewtonianFluid", "BinghamFluid", "NewtonianFluidAxisymmetric",
                     "BinghamFluidAxisymmetric", "SofteningTresca", "SofteningMohrCoulomb",
                     "SofteningStep", "SofteningTrescaAxisymmetric",
                     "SofteningMohrCoulombAxisymmetric"}
    for c in PFEM_MATERIALS:                     # importable from the package face
        assert getattr(materials, c.__name__) is c


@pytest.mark.parametrize("cls", PFEM_MATERIALS, ids=lambda c: c.__name__)
def test_every_pfem_material_has_a_toml_form_or_a_stated_refusal(cls):
    specs = [s for s in MATERIAL.specs.values() if s.cls is cls]
    if cls.__name__ in MATERIAL.refused:
        assert not specs and len(MATERIAL.refused[cls.__name__]) > 20
    else:
        assert len(specs) == 1, f"{cls.__name__} has no TOML Spec in scene/files.py"


@pytest.mark.parametrize("cls", PFEM_MATERIALS, ids=lambda c: c.__name__)
def test_every_pfem_material_declares_the_protocol(cls):
    assert isinstance(cls.name, str) and cls.name
    assert set(cls.geometries) <= {"plane", "axisymmetric"}
    if len(cls.geometries) == 1:
        assert cls.counterpart != PFEMMaterial.counterpart
    cone = inspect.signature(cls.cone).parameters
    assert list(cone)[:3] == ["self", "sigma_m" if "sigma_m" in cone else "p", "stress_scale"]
    assert cone["shear_rate"].kind is inspect.Parameter.KEYWORD_ONLY


@pytest.mark.parametrize("drop, words", [
    ("name", "name"), ("geometries", "geometries"), ("cone", "cone()"),
    ("strength_scale", "strength_scale()")])
def test_a_material_missing_what_the_engine_needs_is_refused_naming_it(drop, words):
    body = {"name": "mine", "geometries": ("plane", "axisymmetric"),
            "cone": lambda self, sigma_m, stress_scale=1.0, *, shear_rate=None: None,
            "strength_scale": lambda self, sigma_m, stress_scale=1.0: 1.0}
    del body[drop]
    with pytest.raises(TypeError, match=rf"Mine does not declare .*{inspect.re.escape(words)}"):
        type("Mine", (PFEMMaterial,), body)


def test_a_one_geometry_material_must_name_its_counterpart_and_geometries_are_checked():
    body = {"name": "mine", "cone": lambda self, s, k=1.0, *, shear_rate=None: None,
            "strength_scale": lambda self, s, k=1.0: 1.0}
    with pytest.raises(TypeError, match="counterpart"):
        type("Mine", (PFEMMaterial,), {**body, "geometries": ("plane",)})
    with pytest.raises(TypeError, match="geometries must be"):
        type("Mine", (PFEMMaterial,), {**body, "geometries": ("3d",)})
    mine = type("Mine", (PFEMMaterial,), {**body, "geometries": ("plane",),
                                          "counterpart": "Yours"})()
    assert (mine.lagged, mine.rate_dependent, mine.hoop, mine.elastic, mine.c, mine.phi) == \
        (False, False, False, None, 0.0, 0.0)
    assert mine.viscous(None, 1.0, None, None) is None


def test_a_region_refuses_an_object_that_is_not_a_pfem_material():
    class DuckCone:
        def cone(self, sigma_m, stress_scale=1.0):
            return None
    with pytest.raises(ValueError, match="PFEMMaterial"):
        Region(((0, 0), (1, 0), (1, 1)), DuckCone(), 1.0, 0.25)


def test_the_default_mean_stress_is_the_plane_one_bit_for_bit():
    sigma = np.random.default_rng(0).normal(size=(50, 4))
    plane = 0.5 * (sigma[:, 0] + sigma[:, 1])
    for m in (ZeroDilationMohrCoulomb(), CohesiveTresca(1.0), MuIRheology()):
        assert np.array_equal(m.mean_stress(sigma), plane)
    assert np.array_equal(ZeroDilationDruckerPrager().mean_stress(sigma), sigma[:, :3].sum(1) / 3)


def test_region_cones_stitch_each_regions_cone():
    sm = -np.linspace(0.1, 2.0, 6)
    region = np.array([0, 1, 0, 1, 1, 0])
    zd, tresca = ZeroDilationMohrCoulomb(phi=30.0), CohesiveTresca(0.4)
    both = RegionCones((zd, tresca), region)
    cone = both.cone(sm, 1.0)
    assert isinstance(cone, TrescaField)
    assert np.array_equal(cone.k[region == 0], zd.radius(sm[region == 0], 1.0))
    assert np.all(cone.k[region == 1] == 0.8)
    assert both.lagged and not both.rate_dependent and both.c == 0.4
    assert both.strength_scale(sm, 1.0) == float(np.median(cone.k)) / 2
    # a region with no point in the step (discharged) gives no cone
    assert np.array_equal(RegionCones((zd, tresca), np.zeros(6, int)).cone(sm, 1.0).k,
                          zd.cone(sm, 1.0).k)


def test_region_cones_mix_rate_dependent_and_axisymmetric_materials():
    p = -np.linspace(0.1, 2.0, 6)
    region = np.array([0, 0, 0, 1, 1, 1])
    rate = np.linspace(0.0, 5.0, 6)
    mu, dp = MuIRheologyAxisymmetric(lag="friction"), ZeroDilationDruckerPrager(phi=25.0)
    both = RegionCones((mu, dp), region)
    cone = both.cone(p, 1.0, shear_rate=rate)
    assert isinstance(cone, VonMisesField) and both.rate_dependent and both.hoop
    assert np.array_equal(cone.k[:3], mu.cone(p[:3], 1.0, shear_rate=rate[:3]).k)
    assert np.array_equal(cone.k[3:], dp.cone(p[3:], 1.0).k)
    assert both.viscous(p, 1.0, rate, np.ones(6)) is None
    sigma = np.random.default_rng(1).normal(size=(6, 4))
    assert np.array_equal(both.mean_stress(sigma), sigma[:, :3].sum(1) / 3)
    # the viscous stress of mu(I) (lag 'viscosity') must cover every region
    with pytest.raises(ValueError, match="rate-dependent material must cover every region"):
        RegionCones((MuIRheologyAxisymmetric(), dp), region)
    two = RegionCones((MuIRheology(), MuIRheology(mu_2=0.9)), region)
    eta = two.viscous(p, 1.0, rate, np.ones(6)).eta
    assert np.array_equal(eta[:3], MuIRheology().viscosity(p[:3], 1.0, rate[:3]))


def test_region_cones_refuse_cones_that_cannot_be_stitched():
    region = np.array([0, 1])
    with pytest.raises(ValueError, match="Davis reduction.*depends on the stress"):
        RegionCones((ZeroDilationMohrCoulomb(), DavisMohrCoulomb(phi=30.0, psi=5.0)), region)
    with pytest.raises(ValueError, match="different kinds"):
        RegionCones((ZeroDilationMohrCoulomb(), ZeroDilationDruckerPrager()), region)


def test_regions_of_a_cohesive_and_a_frictional_material_share_a_scene(monkeypatch):
    """A frictional block beside a Tresca clay (refused before RegionCones: the clay had no
    radius) runs; each step's material is RegionCones of the two."""
    from pfem_skfem.drivers import pfem_loop
    from pfem_skfem.drivers.pfem_loop import run
    from pfem_skfem.scene.config import PFEMConfig
    from pfem_skfem.problems.contact import RigidSegment
    from pfem_skfem.discretisation.theta import ThetaMethod
    from pfem_skfem.scene import Body, Scene
    seen = []
    step_material = pfem_loop.step_material
    monkeypatch.setattr(pfem_loop, "step_material",
                        lambda *a: seen.append(step_material(*a)) or seen[-1])
    sand = Region(((0, 0), (0.5, 0), (0.5, 0.5), (0, 0.5)), ZeroDilationMohrCoulomb(phi=30.0),
                  2.0, 0.125, name="sand")
    clay = Region(((0.5, 0), (1, 0), (1, 0.5), (0.5, 0.5)), CohesiveTresca(2.0), 2.0, 0.125,
                  name="clay")
    scene = Scene((sand, clay), (Body("base", RigidSegment((-1, 0), (2, 0), 0.5)),),
                  gravity=(0.0, -9.8), config=PFEMConfig(theta=ThetaMethod(0.01)))
    state, _ = run(scene.initial_state(), scene, 2)
    assert state.step == 2 and np.all(np.isfinite(state.x))
    assert seen and all(isinstance(m, RegionCones) for m in seen)
