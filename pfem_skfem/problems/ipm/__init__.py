"""The project's own interior point: one Cholesky of the displacement-sized matrix an
iteration (:mod:`.newton`), the cones vectorised (:mod:`.cones`), Mehrotra's
predictor-corrector (:mod:`.solver`)."""
from .solver import DEFAULTS, solve

__all__ = ["DEFAULTS", "solve"]
