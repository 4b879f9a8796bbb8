"""Scenes: the description of a PFEM problem (regions, bodies, outlets, phases).

A scene is handed whole to the engine (:mod:`pfem_skfem.drivers.pfem_loop`)::

    scene = Scene(regions=[Region(polygon, material, rho, h, stress=Geostatic())],
                  bodies=[Body("base", RigidSegment(a, b, mu))],
                  config=PFEMConfig(theta=ThetaMethod(dt)))
    state, _ = run(scene.initial_state(), scene, steps)
"""
from .bodies import Body, ConstantVelocity, Fixed, FunctionMotion, Motion, PiecewiseLinear
from .outlets import HalfPlane, Outlet, PolygonZone
from .regions import Geostatic, Region, fill_region, geostatic_stress, polygon_area
from .scene import Output, Phase, Scene

__all__ = ["Body", "ConstantVelocity", "Fixed", "FunctionMotion", "Motion", "PiecewiseLinear",
           "HalfPlane", "Outlet", "PolygonZone", "Geostatic", "Region", "fill_region",
           "geostatic_stress", "polygon_area", "Output", "Phase", "Scene"]
