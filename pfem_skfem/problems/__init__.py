"""One module per optimisation problem of the thesis; ``conic`` holds what they share.

static (3.45) and limit analysis, dynamic (4.23) (its scaling ``step_scaling``, its terms
``step_terms``, the backends that state and solve it ``backends/``), contact (5.10)-(5.12),
particle (5.1)-(5.9), bar (B.12); beyond the thesis, consolidation (C.1) of a saturated soil
and its term of the dynamic step ``pore_term``.
"""
from .conic import AlmostSolvedWarning, Scaling, SolveInfo, SolverError, solve  # noqa: F401
from .contact import (RigidCircle, RigidPolyline, RigidSegment,  # noqa: F401
                      potential_contacts, resultants)
from .dynamic import dynamic_increment  # noqa: F401
from .static import LimitLoad, StaticIncrement, limit_analysis, static_increment  # noqa: F401
