"""Displacement control of a softening material: (3.45) increments with the strength as data.

Each increment solves the convex problem (3.45) with the strength of the start of the
increment (:meth:`~pfem_skfem.materials.softening.SofteningTresca.criterion`), then updates
gamma^p and the strength from the increment's plastic strain
(:mod:`pfem_skfem.materials.softening`). The update lags by one increment, by as much
strength as an increment spends; so the step control caps it: an increment whose plastic
strain at a point still above c_r, times the law's steepest rate abs(dc/dgamma^p) (abs(H), or
3 (c_p - c_r) / gamma_95: a bound on the strength drop, equal to it for the linear law;
:func:`~pfem_skfem.materials.softening.strength_drop` with ``steepest``, the function of the
dynamic step control, which takes the exponential law's exact drop instead), exceeds
``max_drop`` (c_p - c_r) is re-solved from the same start with half the displacement, again
until it does not (at most :data:`MAX_HALVINGS` times in a row); after an increment below a
quarter of the cap the next is doubled again, up to the base increment. The bound, not the
exponential law's exact drop: the lag of a static curve is measured in strain, and the exact
drop lets the increments of the law's flat tail grow up to the base increment.

With ``passes`` > 1 an increment is solved again from the same start with the strength at
its trial end, c(gamma^p_n + Delta gamma^p of the last pass), until Delta gamma^p stops
changing (a fixed point: the strength the step used is the strength it leaves; each pass
convex). Under displacement control of a softening band the passes contract by
(L / G) abs(H) / h per pass, below one exactly when the band does not snap back.
"""
from dataclasses import dataclass

import numpy as np

from ..materials.softening import (NonlocalAverage, plastic_strain_increment,
                                   point_sizes, strength_drop)  # noqa: F401 (point_sizes)
from ..problems.static import static_increment

#: re-solves at half the displacement before an increment is taken over the cap (counted)
MAX_HALVINGS = 12
#: a fixed point: the passes' Delta gamma^p agree to this fraction of the law's strain scale
PASS_TOLERANCE = 1e-6


@dataclass(frozen=True)
class StepControl:
    """How :func:`softening_control` steps: ``max_drop``, the cap on an increment's strength
    drop (at the law's steepest rate, :func:`~pfem_skfem.materials.softening.strength_drop`)
    as a fraction of c_p - c_r; ``passes``, the most fixed-point passes of an increment (1:
    the explicit update); ``average``, a sparse (n_points, n_points) operator applied to each
    increment of gamma^p (a nonlocal average,
    :func:`~pfem_skfem.materials.softening.nonlocal_average`), or None."""

    max_drop: float = 0.01
    passes: int = 1
    average: object = None

    def __post_init__(self):
        if not np.isfinite(self.max_drop) or not 0 < self.max_drop <= 1:
            raise ValueError(f"max_drop (cap on the strength drop per increment, a fraction of "
                             f"c_p - c_r) must lie in (0, 1], got {self.max_drop!r}")
        if int(self.passes) != self.passes or self.passes < 1:
            raise ValueError(f"passes (fixed-point passes per increment) must be a positive "
                             f"integer, got {self.passes!r}")


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


def softening_control(B, C, material, *, fixed, prescribed, n_increments, size, weights,
                      gamma0=None, control=StepControl(), **solver_settings):
    """Impose ``prescribed`` = (dofs, total displacements) in ``n_increments`` base increments
    on a softening material, with the step control of the module's docstring.

    Parameters
    ----------
    B, C : the operators (3.41), (3.43) (C of ``material.elastic``).
    material : :class:`~pfem_skfem.materials.softening.SofteningTresca` (or Mohr-Coulomb, or
        their axisymmetric counterparts: B, C of an axisymmetric discretisation).
    fixed : dofs with zero displacement.  size, weights : (n_points,) element size and
        integration weight of each stress point.
    gamma0 : (n_points,) initial plastic shear strain (a seed of weakness), default zero.
    control : :class:`StepControl`: the cap, the fixed-point passes, the nonlocal average.
    solver_settings : passed to :func:`~pfem_skfem.problems.static.static_increment`.

    Returns
    -------
    SofteningHistory
    """
    dofs, total = prescribed
    if int(n_increments) != n_increments or n_increments < 1:
        raise ValueError(f"n_increments must be a positive integer, got {n_increments!r}")
    if not isinstance(control, StepControl):
        raise ValueError(f"control must be a StepControl, got {type(control).__name__}")
    if material.eta:
        raise ValueError(f"eta (Bingham viscosity) = {material.eta!r}: static increments have "
                         f"no time step for a viscous stress; a viscous softening material "
                         f"runs in dynamic steps (the PFEM loop)")
    if isinstance(material.regularisation, NonlocalAverage):
        raise ValueError("a NonlocalAverage regularisation is for PFEM runs: static increments "
                         "take their average from StepControl(average=nonlocal_average(...))")
    max_drop, average = control.max_drop, control.average
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
    factors, reactions, dissipation = [0.0], [np.zeros(n_u)], [0.0]
    done, trial, solves, uncapped, halvings = 0.0, 1.0, 0, 0, 0
    tolerance = PASS_TOLERANCE * span / material.law.steepest_rate     # of gamma_r (gamma_95 / 3)
    while done < n_increments * (1 - 1e-12):
        part = min(trial, n_increments - done)
        gamma_new = gamma                   # the first pass: the strength of the start
        for _ in range(int(control.passes)):
            criterion = material.criterion(gamma_new, size, material.mean_stress(sigma),
                                            material.law.c_p)
            res = static_increment(B, C, f, sigma, criterion, fixed=fixed,
                                   prescribed=(dofs, part * step), **solver_settings)
            solves += 1
            deps = plastic_strain_increment(B, res.du, C, res.sigma, sigma, weights)
            dgamma = material.shear_strain(deps)
            trial_end, gamma_new = gamma_new, gamma + (dgamma if average is None
                                                       else average @ dgamma)
            if np.max(np.abs(gamma_new - trial_end)) <= tolerance:
                break                       # the strength used is the strength left
        c_new = material.strength(gamma_new, size)
        drop = strength_drop(material, gamma, gamma_new, size, steepest=True)
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
