"""What is measured on a particle cloud: the deposit, its height at a wall, its centre of
mass, its front, its surface's height profile, its radial mass distribution.

The verification scripts measure their runs with these (granular columns, plane and of
revolution; the landslide); each takes a :class:`~pfem_skfem.pfem.state.PFEMState` or plain
arrays and returns numbers, so a script states what it measures, not how.
"""
import numpy as np

from .alpha_shape import alpha_shape

__all__ = ["deposit_extent", "wall_height", "centre_of_mass", "front", "surface_height",
           "mass_within", "mass_moved"]


def deposit_extent(state, alpha, alpha_advected=0.0):
    """Height and toe (largest x) of the main body: the detected body of largest area.

    Particles splashed off the body (free, or in a small separate body) are left out,
    as an experimentalist measures the deposit, not its outliers. The body is detected as
    the engine detects it (:func:`~pfem_skfem.drivers.pfem_loop.detect_domain`): with
    ``alpha_advected`` > 0 (``PFEMConfig.alpha_advected``) the state's mesh keeps the
    stretched triangles the run kept, which the plain alpha-shape would cut off the deposit.

    Returns
    -------
    (height, toe, main-body particle indices)
    """
    advected = None if state.mesh_p is None else (state.mesh_p, state.mesh_t)
    shape = alpha_shape(state.x, state.h, alpha, advected=advected,
                        alpha_advected=alpha_advected)
    main = int(np.argmax(shape.body_area))
    idx = np.unique(shape.triangles[shape.body == main])
    return float(state.x[idx, 1].max()), float(state.x[idx, 0].max()), idx


def wall_height(state, particles, wall_x=0.0):
    """Height of the deposit at the wall x = ``wall_x``: the highest of ``particles`` within
    one spacing h of it (Lube et al. 2005 and Lagree et al. 2011 measure the final height
    there, where the deposit is thickest)."""
    idx = np.asarray(particles)
    near = idx[np.abs(state.x[idx, 0] - wall_x) <= state.h[idx]]
    if near.size == 0:
        raise ValueError(f"no particle of the deposit lies within one spacing of x = {wall_x}")
    return float(state.x[near, 1].max())


def centre_of_mass(state):
    """The particles' centre of mass, (2,)."""
    return state.mass @ state.x / state.mass.sum()


def front(state):
    """The front: the largest x of the mesh's vertices (of the mass, not a flying particle)."""
    return float(np.max(state.mesh_p[:, 0]))


def surface_height(state, x):
    """The height of the mesh's top above each abscissa of ``x``: the largest y at which the
    vertical line through x crosses an edge of the state's mesh (its vertices moved to t_n,
    straight-sided), so the piecewise-linear free surface of a deposit on a floor. -inf
    where no element lies above x (a gap in the body, or beyond its ends)."""
    p, t = np.asarray(state.mesh_p), np.asarray(state.mesh_t)
    edges = np.vstack([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    (x1, y1), (x2, y2) = p[edges[:, 0]].T, p[edges[:, 1]].T
    x = np.asarray(x, dtype=float)[:, None]
    vertical = x2 == x1                      # a vertical edge's top is a vertex of another edge
    w = (x - x1) / np.where(vertical, 1.0, x2 - x1)
    crossed = (x >= np.minimum(x1, x2)) & (x <= np.maximum(x1, x2)) & ~vertical
    return np.where(crossed, y1 + w * (y2 - y1), -np.inf).max(axis=1)


def mass_within(r, m):
    """(radii in increasing order, share of the mass within each): the radial mass
    distribution F of particles at radii ``r`` of masses ``m``."""
    r, m = np.asarray(r, dtype=float), np.asarray(m, dtype=float)
    order = np.argsort(r, kind="stable")
    return r[order], np.cumsum(m[order]) / np.sum(m)


def mass_moved(r_a, m_a, r_b, m_b):
    """The largest share of the material that two deposits put on opposite sides of one
    radius: max over r of |F_a(r) - F_b(r)|, F(r) the share of the mass within radius r
    (:func:`mass_within`; particles at radii ``r_a`` of masses ``m_a``, and ``r_b``,
    ``m_b``; the Kolmogorov-Smirnov distance of the radial mass distributions). 0 for the
    same deposit, 1 for two that do not overlap; a thin tail that slides further moves
    only its own mass, where the farthest particle moves by the tail's whole reach."""
    grid = np.union1d(r_a, r_b)

    def share_at_grid(r, m):
        radii, share = mass_within(r, m)
        return np.concatenate([[0.0], share])[np.searchsorted(radii, grid, side="right")]
    return float(np.max(np.abs(share_at_grid(r_a, m_a) - share_at_grid(r_b, m_b))))
