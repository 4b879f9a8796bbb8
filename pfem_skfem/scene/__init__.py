"""Scenes: the description of a PFEM problem (regions, bodies, outlets, phases, loads).

A scene is handed whole to the engine (:mod:`pfem_skfem.drivers.pfem_loop`)::

    scene = Scene(regions=[Region(polygon, material, rho, h, stress=Geostatic())],
                  bodies=[Body("base", RigidSegment(a, b, mu))],
                  config=PFEMConfig(theta=ThetaMethod(dt)))
    state, _ = run(scene.initial_state(), scene, steps)

The same scene as a TOML file: :func:`scene_to_toml` / :func:`scene_from_toml`
(``pfem-skfem run SCENE.toml`` runs one). :func:`column_scene` builds the released column
on a floor against a wall of the column collapse, dam break and slump benchmarks.
"""
from .bodies import Body, ConstantVelocity, Fixed, FunctionMotion, Motion, PiecewiseLinear
from .outlets import HalfPlane, Outlet, PolygonZone
from .regions import Geostatic, Region, fill_region, geostatic_stress, polygon_area
from .scene import MAX_PARTICLES, Output, Phase, Scene, scene_digest
from .water import Drained, Water
from .loads import SurfaceLoad
from .columns import column_scene
from .files import SceneFileError, load_scene, scene_from_toml, scene_to_toml

__all__ = ["Body", "ConstantVelocity", "Fixed", "FunctionMotion", "Motion", "PiecewiseLinear",
           "HalfPlane", "Outlet", "PolygonZone", "Geostatic", "Region", "fill_region",
           "geostatic_stress", "polygon_area", "Output", "Phase", "Scene", "SceneFileError",
           "load_scene", "scene_from_toml", "scene_to_toml", "scene_digest", "MAX_PARTICLES",
           "column_scene", "Drained", "Water", "SurfaceLoad"]
