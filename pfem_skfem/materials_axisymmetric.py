"""Backwards compatibility (issue 37): import from pfem_skfem.materials.axisymmetric (the
cones) and pfem_skfem.materials.pfem (the PFEM materials of axisymmetry)."""
from .materials.axisymmetric import *  # noqa: F401,F403
from .materials.axisymmetric import _stack, _ThreeCones, mean_stress  # noqa: F401
from .materials.pfem import (ZeroDilationDruckerPrager,  # noqa: F401
                             ZeroDilationMohrCoulombAxisymmetric)
