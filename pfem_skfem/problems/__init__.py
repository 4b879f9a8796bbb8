"""One module per optimisation problem of the thesis; ``conic`` holds what they share.

static (3.45) and limit analysis, dynamic (4.23), contact (5.10)-(5.12),
particle (5.1)-(5.9), bar (B.12).
"""
from .conic import AlmostSolvedWarning, Scaling, SolveInfo, SolverError, solve  # noqa: F401
from .contact import (RigidCircle, RigidPolyline, RigidSegment,  # noqa: F401
                      potential_contacts, resultants)
from ..discretisation.dynamic import dynamic_operators  # noqa: F401
from ..discretisation.theta import ThetaMethod  # noqa: F401
from .dynamic import dynamic_increment  # noqa: F401
from .static import LimitLoad, StaticIncrement, limit_analysis, static_increment  # noqa: F401
