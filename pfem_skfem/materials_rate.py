"""Backwards compatibility (issue 37): import from pfem_skfem.materials.rate."""
from .materials.rate import *  # noqa: F401,F403
from .materials.rate import (LAGS, MuIRheology, MuIRheologyAxisymmetric,  # noqa: F401
                             RateDissipation, ViscousStress)
