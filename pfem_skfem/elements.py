"""Backwards compatibility (issue 37): import from pfem_skfem.discretisation.elements.

This name is the same module object as the new one, so attributes and patches agree."""
import sys

from .discretisation import elements as _module

sys.modules[__name__] = _module
