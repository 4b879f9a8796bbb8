"""Displacement control of a softening material: (3.45) increments with the strength as data.

Each increment solves the convex problem (3.45) with the strength of the start of the
increment (:meth:`~pfem_skfem.materials.softening.SofteningTresca.criterion`), then updates
gamma^p and the strength from the increment's plastic strain
(:mod:`pfem_skfem.materials.softening`). The update lags by one increment, by as much
strength as an increment spends; so the step control caps it: an increment whose plastic
strain at a point still above c_r, times the law's steepest rate abs(dc/dgamma^p) (abs(H), or
3 (c_p - c_r) / gamma_95: a bound on the strength drop, equal to it for the linear law),
exceeds ``max_drop`` (c_p - c_r) is re-solved from the same start with half the displacement,
again until it does not (at most :data:`MAX_HALVINGS` times in a row); after an increment
below a quarter of the cap the next is doubled again, up to the base increment.
"""
from dataclasses import dataclass

import numpy as np

from ..materials.softening import plastic_strain_increment, shear_invariant
from ..problems.static import static_increment

#: re-solves at half the displacement before an increment is taken over the cap (counted)
MAX_HALVINGS = 12


@dataclass
class SofteningHistory:
    """The accepted increments of :func:`softening_control`.

    factors : (k+1,) fraction of the prescribed displacement reached (0 first);
    reactions : (k+1, n_u) reactions after each increment;
    dissipation : (k+1,) plastic work sum_p w_p sigma_{n+1} . Delta eps^p, accumulated;
    gamma_p, strength : (n_points,) at the end;  sigma : (n_points, 4) at the end;
    u : (n_u,) total displacements;  solves : the solves made (re-solves included);
    uncapped : accepted increments that still dropped the strength by more than the cap.
    """

    factors: np.ndarray
    reactions: np.ndarray
    dissipation: np.ndarray
    gamma_p: np.ndarray
    strength: np.ndarray
    sigma: np.ndarray
    u: np.ndarray
    solves: int
    uncapped: int


def point_sizes(weights):
    """Element size at each stress point of a plane-strain mesh: sqrt(2 A), A = 3 w the area of
    its element (three points of equal weight): the side of a square cell of two triangles."""
    return np.sqrt(6.0 * np.asarray(weights, dtype=float))


def softening_control(B, C, material, *, fixed, prescribed, n_increments, size, weights,
                      gamma0=None, average=None, max_drop=0.01, **solver_settings):
    """Impose ``prescribed`` = (dofs, total displacements) in ``n_increments`` base increments
    on a softening material, with the step control of the module's docstring.

    Parameters
    ----------
    B, C : the operators (3.41), (3.43) (C of ``material.elastic``).
    material : :class:`~pfem_skfem.materials.softening.SofteningTresca` (or Mohr-Coulomb).
    fixed : dofs with zero displacement.  size, weights : (n_points,) element size and
        integration weight of each stress point.
    gamma0 : (n_points,) initial plastic shear strain (a seed of weakness), default zero.
    average : (n_points, n_points) sparse, or None: each increment of gamma^p is replaced by
        ``average @`` it (a nonlocal average over neighbouring points).
    max_drop : the cap on the strength drop of an increment (at the steepest rate), a fraction
        of c_p - c_r.
    solver_settings : passed to :func:`~pfem_skfem.problems.static.static_increment`.

    Returns
    -------
    SofteningHistory
    """
    dofs, total = prescribed
    if int(n_increments) != n_increments or n_increments < 1:
        raise ValueError(f"n_increments must be a positive integer, got {n_increments!r}")
    if not np.isfinite(max_drop) or not 0 < max_drop <= 1:
        raise ValueError(f"max_drop (cap on the strength drop per increment, a fraction of "
                         f"c_p - c_r) must lie in (0, 1], got {max_drop!r}")
    n_s, n_u = B.shape
    n = n_s // 4
    weights, size = np.asarray(weights, dtype=float), np.asarray(size, dtype=float)
    gamma = np.zeros(n) if gamma0 is None else np.array(gamma0, dtype=float)
    if gamma.shape != (n,) or np.any(~np.isfinite(gamma)) or np.any(gamma < 0):
        raise ValueError(f"gamma0 must be ({n},) finite and >= 0")
    span = material.law.c_p - material.law.c_r
    step = np.asarray(total, dtype=float) / n_increments
    sigma, u, f = np.zeros((n, 4)), np.zeros(n_u), np.zeros(n_u)
    c = material.strength(gamma, size)
    rate = material.law.steepest_rate / material.scale(size)     # abs(dc/dgamma^p) at its largest
    factors, reactions, dissipation = [0.0], [np.zeros(n_u)], [0.0]
    done, trial, solves, uncapped, halvings = 0.0, 1.0, 0, 0, 0
    while done < n_increments * (1 - 1e-12):
        part = min(trial, n_increments - done)
        criterion = material.criterion(gamma, size, 0.5 * (sigma[:, 0] + sigma[:, 1]),
                                       material.law.c_p)
        res = static_increment(B, C, f, sigma, criterion, fixed=fixed,
                               prescribed=(dofs, part * step), **solver_settings)
        solves += 1
        deps = plastic_strain_increment(B, res.du, C, res.sigma, sigma, weights)
        dgamma = shear_invariant(deps)
        gamma_new = gamma + (dgamma if average is None else average @ dgamma)
        c_new = material.strength(gamma_new, size)
        softening = c > material.law.c_r * (1 + 1e-12)
        drop = (float(np.max(rate[softening] * (gamma_new - gamma)[softening], initial=0.0))
                / span if span > 0 else 0.0)
        if drop > max_drop and halvings < MAX_HALVINGS:
            trial, halvings = trial / 2, halvings + 1      # the same start, half the motion
            continue
        uncapped += drop > max_drop
        work = float(np.sum(weights * np.einsum("pk,pk->p", res.sigma, deps)))
        sigma, u, gamma, c = res.sigma, u + res.du, gamma_new, c_new
        done += part
        factors.append(done / n_increments)
        reactions.append(res.reactions)
        dissipation.append(dissipation[-1] + work)
        halvings = 0
        if drop < max_drop / 4:
            trial = min(1.0, 2 * trial)
    return SofteningHistory(np.array(factors), np.array(reactions), np.array(dissipation),
                            gamma, c, sigma, u, solves, uncapped)
