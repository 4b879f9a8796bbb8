"""Periodic displacement dofs: a strip whose two ends x = x0 and x = x1 move alike.

Each dof on the end x = x1 is tied to the dof of the same component at the same height
on x = x0: u = T u_r, T (n_u, n_r) a 0/1 matrix whose columns are the kept dofs. The
step's operators become B T, A T and T^T M T, its loads T^T f (the tied ends' equilibrium
rows summed), so (4.23) is solved for u_r unchanged.
"""
from dataclasses import replace

import numpy as np
import scipy.sparse as sp


def periodic_tie(disc, x0, x1, *, tol=1e-9, axis=0):
    """(T, kept): T (n_u, n_r) tying the dofs on x = x1 to those on x = x0 (same component
    and y), kept (n_r,) the dof of each column of T (every dof not on x = x1). ``axis=1``
    ties the ends y = x1 to y = x0 instead (paired by x: a pipe periodic along its axis
    in axisymmetry).

    Raises ValueError if the two ends' dofs do not pair up one to one.
    """
    if axis not in (0, 1):
        raise ValueError(f"axis must be 0 (x) or 1 (y), got {axis!r}")
    basis = disc.basis_u
    xy = basis.doflocs[[axis, 1 - axis]]          # (along the tie, across it)
    n_u = disc.n_u
    component = np.empty(n_u, dtype=int)
    for k in range(2):
        component[basis.nodal_dofs[k]] = k
        component[basis.facet_dofs[k]] = k
    scale = tol * max(float(np.ptp(disc.mesh.p, axis=1).max()), 1.0)
    left = np.flatnonzero(np.abs(xy[0] - x0) <= scale)
    right = np.flatnonzero(np.abs(xy[0] - x1) <= scale)
    if left.size == 0 or left.size != right.size:
        raise ValueError(f"the ends x0 = {x0!r} and x1 = {x1!r} have {left.size} and "
                         f"{right.size} dofs: they must pair up")
    key = lambda dofs: np.lexsort((xy[1, dofs], component[dofs]))   # noqa: E731
    left, right = left[key(left)], right[key(right)]
    if (np.any(component[left] != component[right])
            or np.any(np.abs(xy[1, left] - xy[1, right]) > scale)):
        raise ValueError("the two ends' dofs are not at the same heights")
    target = np.arange(n_u)
    target[right] = left
    kept = np.setdiff1d(np.arange(n_u), right)
    column = np.full(n_u, -1)
    column[kept] = np.arange(kept.size)
    T = sp.csr_matrix((np.ones(n_u), (np.arange(n_u), column[target])), shape=(n_u, kept.size))
    return T, kept


def periodic_operators(ops, T):
    """The DynamicOperators of (4.23) on the tied dofs u_r: B T, A T, T^T M T."""
    return replace(ops, B=(ops.B @ T).tocsr(), A=(ops.A @ T).tocsr(),
                   M=(T.T @ ops.M @ T).tocsr())
