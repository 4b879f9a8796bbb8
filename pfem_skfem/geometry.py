"""Backwards compatibility (issue 37): import from pfem_skfem.discretisation.geometry.

This name is the same module object as the new one, so attributes and patches agree."""
import sys

from .discretisation import geometry as _module

sys.modules[__name__] = _module
