"""Axisymmetric problems (thesis Ch 7): static increment, limit analysis, dynamic step (7.29)-(7.30).

The thesis states each axisymmetric problem as its plane-strain counterpart with
the operators of (7.25)-(7.28): B, f, A, D integrated over dOmega = 2 pi r dr dz
with the hoop strain u_r / r. In this package the operators know their geometry
(:func:`~pfem_skfem.discretisation.static.discretise` with ``geometry="axisymmetric"``), so
each problem here is the plane-strain statement, the same cvxpy (or direct
Clarabel) code, on axisymmetric operators, plus what the axis demands:

* u_r = 0 on every node of the axis r = 0 (:func:`~pfem_skfem.discretisation.static.axis_dofs`),
  added to the fixed dofs unless the caller prescribes them;
* forces are ring forces: a reaction summed over a boundary is the force on the
  whole body of revolution (no 2 pi to add).

The stress rows are (s_rr, s_zz, s_tt, s_rz) (:mod:`pfem_skfem.discretisation.geometry`); the
yield criteria that read the hoop stress are the Drucker-Prager cones of
:func:`~pfem_skfem.materials.axisymmetric.drucker_prager_match` ((7.10) by default)
and the exact three-cone Mohr-Coulomb / Tresca
(:class:`~pfem_skfem.materials.axisymmetric.MohrCoulombAxisymmetric`).

Clarabel ends these problems 'AlmostSolved' more often than the plane ones (the thick
sphere's limit analyses, book/axisymmetry.md). As every static
problem, such an end is certified by Clarabel's own residuals and relative gap and
returned with an :class:`~pfem_skfem.problems.conic.AlmostSolvedWarning`, or raised
(:func:`~pfem_skfem.problems.conic.certify`).
"""
import numpy as np

from ..discretisation.static import axis_dofs
from .dynamic import dynamic_increment
from .static import limit_analysis, static_increment


def _check_axisymmetric(disc, B=None):
    if not getattr(disc.geometry, "axisymmetric", False):
        raise ValueError("disc must be an axisymmetric discretisation: "
                         "discretise(mesh, geometry='axisymmetric')")
    if B is not None and B.shape != (4 * disc.n_points, disc.n_u):
        raise ValueError(f"B has shape {B.shape}, the discretisation needs "
                         f"{(4 * disc.n_points, disc.n_u)}: assemble it from the same disc")


def with_axis(disc, fixed, prescribed=()):
    """``fixed`` dofs joined by the radial dofs of the axis (u_r = 0 on r = 0).

    Axis dofs the caller already prescribes (a rough footing's centre, say) stay
    prescribed.
    """
    _check_axisymmetric(disc)
    axis = np.setdiff1d(axis_dofs(disc), np.asarray(prescribed, dtype=int))
    return np.union1d(np.asarray(fixed, dtype=int), axis)


def static_increment_axisymmetric(disc, B, C, f, sigma_n, criterion, *, fixed,
                                  prescribed=((), ()), **kwargs):
    """One increment of the axisymmetric static problem: (3.45) with (7.25)-(7.26).

    .. math::
        \\max_{\\sigma}\\; -\\tfrac12 \\Delta\\sigma^T C \\Delta\\sigma
          + \\Delta\\bar u_P^T (B_P^T \\sigma - f_P)
        \\quad \\text{s.t.}\\quad B_F^T \\sigma = f_F,\\quad F(\\sigma_j) \\le 0

    with B = int N_sigma^T B_u 2 pi r dA (hoop row included), C the r-weighted
    compliance, F the free dofs (u_r = 0 on the axis excluded). ``C=None`` is the
    displacement-controlled rigid-plastic limit analysis. Arguments and result as
    :func:`~pfem_skfem.problems.static.static_increment`.

    Returns
    -------
    StaticIncrement
    """
    _check_axisymmetric(disc, B)
    return static_increment(B, C, f, sigma_n, criterion,
                            fixed=with_axis(disc, fixed, prescribed[0]), prescribed=prescribed,
                            **kwargs)


def limit_analysis_axisymmetric(disc, B, f_live, criterion, *, fixed, **kwargs):
    """Load-controlled limit analysis of a body of revolution.

    .. math::
        \\max_{\\alpha, \\sigma}\\; \\alpha \\quad \\text{s.t.}\\quad
        B_F^T \\sigma = \\alpha f_F + f^0_F,\\quad F(\\sigma_j) \\le 0

    :func:`~pfem_skfem.problems.static.limit_analysis` on the axisymmetric B with
    u_r = 0 on the axis.

    Returns
    -------
    LimitLoad

    Warns
    -----
    AlmostSolvedWarning
        An 'AlmostSolved' end certified by its measures; uncertified, SolverError.
    """
    _check_axisymmetric(disc, B)
    return limit_analysis(B, f_live, criterion, fixed=with_axis(disc, fixed), **kwargs)


def dynamic_step_axisymmetric(disc, ops, f_n, f_next, sigma_n, v_n, criterion=None, *,
                              fixed=(), prescribed=((), ()), **kwargs):
    """One time step of the axisymmetric dynamic problem (7.29), with contact (7.30).

    .. math::
        \\max_{\\sigma, r, \\rho}\\; -\\tfrac12 \\Delta t^2 r^T D r - \\sum_j g_{0j} p_j
        \\quad\\text{s.t.}\\quad B^T\\sigma + A^T r + E^T\\rho = f,\\quad
        F(\\sigma_i) \\le 0,\\quad |q_j| \\le \\mu p_j

    with p_j = -n_j^T rho_j, q_j = -n^_j^T rho_j the normal and tangential ring
    forces at the contact nodes, B, A, D of (7.25), (7.27) (N_r on both sides),
    (7.28) over 2 pi r dA, and u_r = 0 on the axis. ``ops`` comes from
    :func:`~pfem_skfem.problems.dynamic.dynamic_operators` on an axisymmetric
    ``disc``; everything else (elastic or rigid-plastic, the theta-method data b~
    and t~ of (7.15)-(7.17), the terms (contacts: ``terms=step_terms(contacts=...)``), the
    solver: 'cvxpy', the reference, or 'clarabel') is
    :func:`~pfem_skfem.problems.dynamic.dynamic_increment`.

    Returns
    -------
    DynamicIncrement
    """
    _check_axisymmetric(disc, ops.B)
    return dynamic_increment(ops, f_n, f_next, sigma_n, v_n, criterion,
                             fixed=with_axis(disc, fixed, prescribed[0]), prescribed=prescribed,
                             **kwargs)


def zero_dilation(solve_pass, criterion, *, floor, measure=None, passes=40, relaxation=0.5,
                  rtol=1e-8):
    """Zero-dilation flow by the scheme of [80]: fixed-point passes of an associated problem.

    Pass 0 solves ``solve_pass(criterion)`` (associated flow) and takes its stresses
    as the lagged stresses; every further pass solves the problem on
    :func:`~pfem_skfem.materials.axisymmetric.zero_dilation_cone` of ``criterion`` at the lagged
    stresses, which then move a fraction ``relaxation`` towards the new ones, until
    ``measure`` changes by less than ``rtol`` (relative) or ``passes`` are done.
    The stresses themselves are no measure of convergence: those of a rigid-plastic
    solution need not be unique (the intermediate principal stress). Without
    relaxation (``relaxation=1``) the passes were measured to oscillate.

    Parameters
    ----------
    solve_pass : callable(cone) -> a result with ``sigma`` (n_points, 4) and
        ``info.objective``, e.g. a :func:`static_increment_axisymmetric` or
        :func:`dynamic_step_axisymmetric` with everything but the criterion fixed.
    criterion : the yield criterion (DruckerPrager or MohrCoulombAxisymmetric).
    floor : smallest cone radius (a stress; keep it relative to the problem's stresses).
    measure : callable(result) -> float, the quantity whose convergence ends the
        passes (a load, a reaction); by default the norm of the reactions.
    relaxation : in (0, 1], the step of the lagged stresses towards each pass's.

    Returns
    -------
    (result, changes) : the last pass's result and the relative change of
    ``measure`` at each pass.
    """
    from ..materials.axisymmetric import zero_dilation_cone

    if int(passes) != passes or passes < 1:
        raise ValueError(f"passes must be a positive integer, got {passes!r}")
    if not 0 < relaxation <= 1:
        raise ValueError(f"relaxation must lie in (0, 1], got {relaxation!r}")
    measure = measure or (lambda result: float(np.linalg.norm(result.reactions)))
    res = solve_pass(criterion)
    lagged = res.sigma
    changes = []
    for _ in range(int(passes)):
        new = solve_pass(zero_dilation_cone(criterion, lagged, floor))
        old_value, value = measure(res), measure(new)
        changes.append(abs(value - old_value) / max(abs(value), 1e-300))
        res = new
        lagged = relaxation * new.sigma + (1 - relaxation) * lagged
        if changes[-1] < rtol:
            break
    return res, changes
