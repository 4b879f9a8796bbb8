"""One module per optimisation problem of the thesis; ``conic`` holds what they share."""
from .conic import Scaling, SolveInfo, SolverError, solve  # noqa: F401
from .static import LimitLoad, StaticIncrement, limit_analysis, static_increment  # noqa: F401
