"""The step of a non-associated material as associated problems in fixed-point passes.

The zero-dilation Mohr-Coulomb scheme of [80]
(:class:`~pfem_skfem.materials.ZeroDilationMohrCoulomb`) and the lagged contact
friction (:class:`~pfem_skfem.problems.contact.LaggedFriction`) each replace a
non-associated law by an associated one whose cone depends on a known quantity: the
mean stress sigma_m, the normal contact force p~. Each pass of :func:`lagged_step`
solves the dynamic step (4.23) + (5.12) with the cones of the previous pass's
solution (the first pass: the lagged values carried by the particles); at a fixed
point the associated problem is the non-associated one. With a pass tolerance the
passes stop once the fixed point is reached to it: a pass whose solution changes the
lagged quantities by less than the tolerance would leave the next pass's cones as they
were.
"""
from dataclasses import dataclass

import numpy as np

from ..discretisation.fields import plastic_strain_increment, smoothed_mean_stress, vertex_to_points
from .dynamic import dynamic_increment
from .step_scaling import estimate_scales
from .step_terms import step_terms


@dataclass
class LaggedStep:
    """The last pass of :func:`lagged_step`.

    Attributes
    ----------
    increment : its :class:`~pfem_skfem.problems.step_scaling.DynamicIncrement`.
    sigma_m : (n_vertices,) smoothed mean stress of its solution (for the next step).
    contacts : the contact set it was solved with (None without contacts).
    iterations, compile_time, solve_time : summed over the passes.
    inaccurate : passes Clarabel ended 'AlmostSolved' (accepted, and counted).
    passes : the passes solved.
    changes : after each pass, how much its solution changed what the next pass's cones
        are built from (:func:`lagged_change`; the first pass against the lagged input).
    """

    increment: object
    sigma_m: np.ndarray
    contacts: object
    iterations: int
    compile_time: float
    solve_time: float
    inaccurate: int
    passes: int = 1
    changes: tuple = ()


def least_passes(material_lagged, contact_rule):
    """The fewest passes a step needs: a lagged contact rule's first pass is smooth (no
    friction), so the friction needs a second; with a lagged material too, the mean
    stress must come from a pass with friction, a third (a cone built on the smooth
    pass's stresses has too little confinement: a stable wedge yields)."""
    needed = contact_rule.passes_needed
    return needed + 1 if material_lagged and needed > 1 else needed


MAX_PASSES = 1000       # more is a typo or a hang (a pass is a conic solve)


def check_passes(passes, pass_tolerance, contact_rule=None, *, lagged=None, rate=None):
    """The rule for the fixed-point passes of a step, written once (issue 37).

    ``passes`` in [1, MAX_PASSES]; ``pass_tolerance`` a number >= 0 (inf: the least passes
    only); 0 with a rate-dependent material, whose passes also update the shear rate,
    which the tolerance does not measure; ``passes`` >= :func:`least_passes` of the
    contact rule (skipped when ``contact_rule`` is None). ``lagged`` and ``rate`` name
    what is lagged or rate-dependent (a region, for the message), or are None.

    Raises
    ------
    ValueError
        naming ``passes`` or ``pass_tolerance``.
    """
    if not 1 <= int(passes) <= MAX_PASSES:
        raise ValueError(f"passes must be in [1, {MAX_PASSES}] (solves per step), got "
                         f"{passes!r}")
    if not (isinstance(pass_tolerance, (int, float, np.number))
            and not isinstance(pass_tolerance, bool)
            and pass_tolerance >= 0):               # nan refused; inf: the least passes
        raise ValueError(f"pass_tolerance must be >= 0 (0: every pass), got "
                         f"{pass_tolerance!r}")
    if rate is not None and pass_tolerance > 0:
        raise ValueError(f"pass_tolerance must be 0 with the rate-dependent material of "
                         f"{rate} (its passes also update the shear rate, which the "
                         f"tolerance does not measure); got pass_tolerance={pass_tolerance!r}")
    if contact_rule is None:
        return
    if int(passes) < contact_rule.passes_needed:
        raise ValueError(f"contact={contact_rule!r} needs passes >= "
                         f"{contact_rule.passes_needed} (the first pass finds the normal forces)")
    if lagged is not None and int(passes) < least_passes(True, contact_rule):
        raise ValueError(f"passes must be >= 3 with contact={contact_rule!r} and the lagged "
                         f"material of {lagged} (pass 1 is smooth, pass 2 has the friction, "
                         f"pass 3 the mean stress with it); got passes={passes!r}")


def lagged_change(sm_before, sm_after, p_before, p_after, stress_scale):
    """How far a pass moved the lagged quantities of the next pass's cones: the largest
    change of the smoothed mean stress in units of the scene's stress scale (rho g L), and
    with a lagged contact rule (``p_before`` not None) the largest change of the normal
    contact forces in units of the largest of them; the larger of the two. Both are
    ratios of quantities of one unit, so a c = 0 run's changes do not depend on density.
    """
    change = 0.0 if sm_before is None else float(np.max(np.abs(sm_after - sm_before))
                                                 / stress_scale)
    if p_before is not None and p_after.size:
        largest = float(np.max(np.abs(p_after)))
        if largest > 0:
            change = max(change, float(np.max(np.abs(p_after - p_before))) / largest)
    return change


@dataclass(frozen=True)
class StepStart:
    """What a step starts from: the velocities v (n_u,) and stresses sigma (n_points, 4) at
    t_n, the lagged mean stress sigma_m (n_vertices,) at the vertices, and the previous
    step's DynamicScales (None: a first step, scaled from an elastic predictor with the
    material's strength at sigma_m)."""

    v: np.ndarray
    sigma: np.ndarray
    sigma_m: np.ndarray
    scales: object = None


def lagged_step(ops, f, contacts, disc, material, start, *, config, stress_scale, fixed=(),
                terms=()):
    """Step 2a: (4.23) with (5.12) on the material's cone, in fixed-point passes.

    Parameters
    ----------
    ops, f : the step's DynamicOperators and load vector (3.42).
    contacts : ContactSet or None.  disc : the Discretisation.
    material : a :class:`~pfem_skfem.materials.PFEMMaterial`: each pass solves on its
        ``cone(sigma_m, stress_scale, shear_rate=...)`` with its ``viscous(...)`` stress and
        lags its ``mean_stress``; a ``rate_dependent`` one is given the shear rate at the
        points (counting the hoop strain if ``hoop``), that of v_n in the first pass, of
        du / dt of the previous pass after (None for the others).
    start : :class:`StepStart` (v_n, sigma_n, the lagged sigma_m, the scales).
    config : the run's numerics (a :class:`~pfem_skfem.scene.config.PFEMConfig`): its
        ``contact`` rule (:class:`~pfem_skfem.problems.contact.CoulombCones` or
        ``LaggedFriction``); ``passes``, the number of passes when the material or the
        contact rule is lagged (else 1), the most with ``pass_tolerance``: stop after a
        pass whose :func:`lagged_change` is below it, once :func:`least_passes` are done
        (0: always ``passes``; a rate-dependent material's passes also update the shear
        rate, which this does not measure: 0 only); ``solver``, the step's solver
        (:data:`~pfem_skfem.problems.backends.STEP_SOLVERS`).
    stress_scale : the scene's stress scale (the unit of the material's least radius).
    fixed : dofs held at zero increment (a held phase; in axisymmetry u_r on the axis).
    terms : further terms of the step, after the contacts and the rate stress (e.g. the
        pore pressure of a saturated scene, :mod:`pfem_skfem.pfem.pore`).

    Returns
    -------
    LaggedStep
    """
    contact_rule, passes, pass_tolerance = config.contact, config.passes, config.pass_tolerance
    v_n, sigma_n, sigma_m, scales = start.v, start.sigma, start.sigma_m, start.scales
    lagged_contact = contacts is not None and contact_rule.passes_needed > 1
    passes = int(passes) if material.lagged or lagged_contact else 1
    rate = material.rate_dependent
    check_passes(passes, pass_tolerance, rate="the step" if rate else None)
    least = least_passes(material.lagged, contact_rule) if lagged_contact else 1
    free = np.setdiff1d(np.arange(ops.B.shape[1]), fixed)     # ops may tie dofs (periodic)
    if scales is None:           # first step: scales from the strength at the lagged sigma_m
        k_scale = material.strength_scale(vertex_to_points(disc, sigma_m), stress_scale)
        f_rhs = ops.theta.equilibrium_rhs(f, f, ops.B, sigma_n)
        scales = estimate_scales(ops, f_rhs, v_n, sigma_n, free, _StrengthOnly(k_scale))
    iterations, compile_time, solve_time, inaccurate = 0, 0.0, 0.0, 0
    step_contacts = None if contacts is None else contact_rule.start(contacts)
    sm = sigma_m
    p_lag = np.zeros(contacts.size) if lagged_contact else None    # the smooth first pass
    changes = []
    gamma_dot = plastic_strain_increment(disc, ops.B, v_n, material.hoop) if rate else None
    for k in range(1, passes + 1):
        at_points = vertex_to_points(disc, sm)
        cone = material.cone(at_points, stress_scale, shear_rate=gamma_dot)
        viscous = material.viscous(at_points, stress_scale, gamma_dot, disc.weights)
        # Clarabel's 'AlmostSolved' is accepted and counted in the step record
        inc = dynamic_increment(ops, f, f, sigma_n, v_n, cone, fixed=fixed,
                                terms=step_terms(contacts=step_contacts, viscous=viscous) + tuple(terms),
                                scaling=scales, solver=config.solver, accept_inaccurate=True)
        inaccurate += inc.info.status != "optimal"
        iterations += inc.info.iterations
        compile_time += inc.info.compile_time
        solve_time += inc.info.solve_time
        sm_before, sm = sm, smoothed_mean_stress(disc, inc.sigma, material.mean_stress)
        p_now = np.maximum(inc.p, 0.0) if lagged_contact else None
        changes.append(lagged_change(sm_before if material.lagged else None, sm, p_lag,
                                     p_now, stress_scale))
        if rate:
            gamma_dot = plastic_strain_increment(disc, ops.B, inc.du,
                                                 material.hoop) / ops.theta.dt
        if lagged_contact:
            last_contacts = step_contacts
            step_contacts = contact_rule.update(contacts, inc.p)
            p_lag = p_now
        if k >= least and changes[-1] < pass_tolerance:     # the next cones as these
            break
    used = last_contacts if lagged_contact else step_contacts
    return LaggedStep(inc, sm, used, iterations, compile_time, solve_time, inaccurate,
                      passes=k, changes=tuple(changes))


@dataclass(frozen=True)
class _StrengthOnly:
    """What :func:`estimate_scales` reads of a criterion: its strength scale."""

    value: float

    def strength_scale(self):
        return self.value
