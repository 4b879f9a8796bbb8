"""Load and displacement control for static problems: a sequence of (3.45) increments."""
from dataclasses import dataclass, field
import sys

import numpy as np
from tqdm import tqdm

from ..problems.static import static_increment


@dataclass
class IncrementalHistory:
    """Result of an incremental static analysis.

    factors : (n+1,) load or displacement factor after each increment (0 first);
    u : (n_u,) total displacements at the end;  sigma : (n_points, 4) final stresses;
    reactions : (n+1, n_u) reactions after each increment;
    plastic_multiplier : (n_points,) integrated multipliers of the last increment;
    iterations, solve_times : solver reports per increment.
    """

    factors: np.ndarray
    u: np.ndarray
    sigma: np.ndarray
    reactions: np.ndarray
    plastic_multiplier: np.ndarray
    iterations: list = field(default_factory=list)
    solve_times: list = field(default_factory=list)


def displacement_control(B, C, criterion, *, fixed, prescribed, n_increments, f=None,
                         sigma0=None, scaling=None, progress=False, **solver_settings):
    """Impose a displacement on some dofs in equal increments.

    Each increment solves (3.45) from the stresses of the previous one.

    Parameters
    ----------
    prescribed : (dofs, displacements): the dofs and their total prescribed displacements.
    n_increments : number of equal increments (>= 1).
    f : constant external forces (default zero).  sigma0 : initial stresses.
    progress : False, or a progress bar (tqdm) on stderr: increments, solver iterations,
        time left; a string labels it.
    """
    prescribed, displacement = prescribed
    if int(n_increments) != n_increments or n_increments < 1:
        raise ValueError(f"n_increments must be a positive integer, got {n_increments!r}")
    n_s, n_u = B.shape
    sigma = np.zeros((n_s // 4, 4)) if sigma0 is None else np.array(sigma0, dtype=float)
    f = np.zeros(n_u) if f is None else np.asarray(f, dtype=float)
    step = np.asarray(displacement, dtype=float) / n_increments
    u = np.zeros(n_u)
    factors, reactions = [0.0], [np.zeros(n_u)]
    iterations, times = [], []
    multiplier = np.zeros(n_s // 4)
    label = progress if isinstance(progress, str) else None
    bar = tqdm(total=int(n_increments), desc=label or None, unit="increment", file=sys.stderr,
               disable=not progress, dynamic_ncols=True)
    for i in range(1, int(n_increments) + 1):
        res = static_increment(B, C, f, sigma, criterion, fixed=fixed,
                               prescribed=(prescribed, step), scaling=scaling, **solver_settings)
        sigma, u = res.sigma, u + res.du
        multiplier = res.plastic_multiplier
        factors.append(i / n_increments)
        reactions.append(res.reactions)
        iterations.append(res.info.iterations)
        times.append(res.info.solve_time)
        bar.set_postfix_str(f"iterations {res.info.iterations}", refresh=False)
        bar.update(1)
    bar.close()
    return IncrementalHistory(np.array(factors), u, sigma, np.array(reactions), multiplier,
                              iterations, times)
