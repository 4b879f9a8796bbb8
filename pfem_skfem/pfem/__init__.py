"""PFEM geometry: particles, alpha-shape detection, remeshing, state mapping (thesis Ch 2).

One PFEM step (Section 2.2), each arrow a function::

    Particles --alpha_shape--> AlphaShape --alpha_mesh / quality_remesh--> ParticleMesh
        --discretise--> P2 mesh --map_stress / map_nodal--> state on the new mesh
"""
from .alpha_shape import AlphaShape, adaptive_alpha, alpha_shape
from .mapping import (ida, interpolate, locate, map_nodal, map_stress, recover_nodal, spr,
                      uem, uem_bounded)
from .particles import Particles, nodal_spacing, thin_cloud
from .remesh import ParticleMesh, alpha_mesh, mesh_quality, quality_remesh

__all__ = ["AlphaShape", "adaptive_alpha", "alpha_shape", "ida", "interpolate", "locate",
           "map_nodal", "map_stress", "recover_nodal", "spr", "uem", "uem_bounded", "Particles", "nodal_spacing", "thin_cloud", "ParticleMesh",
           "alpha_mesh", "mesh_quality", "quality_remesh"]
