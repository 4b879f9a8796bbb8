"""Time stepping with the dynamic SOCP (4.23): one :func:`dynamic_increment` per step.

Energy book-keeping. Multiplying the discrete momentum balance
M (v_{n+1} - v_n)/dt = f_theta - B^T sigma_theta + R_theta by
du = dt (theta2 v_{n+1} + (1 - theta2) v_n) gives::

    dK + dW_el = dW_ext - dD_p - (theta2 - 1/2) |dv|_M^2 - (theta1 - 1/2) |dsigma|_C^2

with dW_ext = du^T f_theta (+ the work of the supports on prescribed dofs),
dD_p = sigma_theta^T (B du - C dsigma) >= 0 the plastic dissipation, and the
last two terms the numerical damping of the theta-method (zero for
theta1 = theta2 = 1/2). The history records K, W_el, W_ext and D_p.
"""
from dataclasses import dataclass, field
import sys

import numpy as np
from tqdm import tqdm

from ..problems.dynamic import dynamic_increment


@dataclass
class DynamicHistory:
    """Result of :func:`integrate`.

    times : (n+1,);  u, v, sigma : final displacements, velocities, stresses;
    monitor : (n+1, k) values of ``monitor(u, v, sigma)`` at every time;
    kinetic, elastic : (n+1,) energies 1/2 v^T M v and 1/2 sigma^T C sigma;
    work : (n+1,) cumulative work of the external forces and supports;
    dissipation : (n+1,) cumulative plastic dissipation;
    iterations, solve_times : solver reports per step.
    """

    times: np.ndarray
    u: np.ndarray
    v: np.ndarray
    sigma: np.ndarray
    monitor: np.ndarray
    kinetic: np.ndarray
    elastic: np.ndarray
    work: np.ndarray
    dissipation: np.ndarray
    iterations: list = field(default_factory=list)
    solve_times: list = field(default_factory=list)

    @property
    def energy(self):
        """Kinetic + elastic energy at every time."""
        return self.kinetic + self.elastic


def _energy(ops, v, sigma):
    kinetic = 0.5 * float(v @ (ops.M @ v))
    s = sigma.ravel()
    elastic = 0.5 * float(s @ (ops.C @ s)) if ops.C is not None else 0.0
    return kinetic, elastic


def integrate(ops, load, n_steps, *, criterion=None, fixed=(), prescribed=((), None),
              initial=None, monitor=None, scaling=None, progress=False, **solver_settings):
    """Integrate the dynamic problem over ``n_steps`` steps of ``ops.theta.dt``.

    Parameters
    ----------
    ops : :class:`~pfem_skfem.discretisation.dynamic.DynamicOperators`.
    load : callable t -> (n_u,) external force vector (3.42) at time t (gravity,
        time-dependent tractions).
    n_steps : number of time steps (>= 1).
    criterion : yield criterion, or None for an elastic material.
    fixed : dofs held at zero.  prescribed : (dofs, u(t)): dofs whose displacement is
        u(t), a callable returning one value per prescribed dof.
    initial : the initial state, a mapping with any of t (0 by default), u, v, sigma (zero
        by default).
    monitor : callable (u, v, sigma) -> array of values recorded every step.
    scaling : :class:`~pfem_skfem.problems.step_scaling.DynamicScales` of the first step
        (estimated by default); each later step is scaled by its predecessor's solution.
    progress : False, or a progress bar (tqdm) on stderr: steps, time, solver iterations,
        time left; a string labels it.
    solver_settings : the step's ``solver`` (the cvxpy statement by default), ``d_form``
        and the solver's settings (:func:`~pfem_skfem.problems.dynamic.dynamic_increment`).

    Returns
    -------
    DynamicHistory
    """
    if int(n_steps) != n_steps or n_steps < 1:
        raise ValueError(f"n_steps must be a positive integer, got {n_steps!r}")
    th = ops.theta
    n_s, n_u = ops.B.shape
    prescribed, u_prescribed = np.asarray(prescribed[0], dtype=int), prescribed[1]
    if prescribed.size and u_prescribed is None:
        raise ValueError("prescribed dofs need u(t): prescribed=(dofs, u)")
    initial = dict(initial or {})
    unknown = set(initial) - {"t", "u", "v", "sigma"}
    if unknown:
        raise ValueError(f"initial: unknown keys {sorted(unknown)} (t, u, v, sigma)")
    t0 = float(initial.get("t", 0.0))
    u = np.array(initial.get("u", np.zeros(n_u)), dtype=float)
    v = np.array(initial.get("v", np.zeros(n_u)), dtype=float)
    sigma = np.array(initial.get("sigma", np.zeros((n_s // 4, 4))), dtype=float)
    monitor = monitor or (lambda u, v, s: np.zeros(0))

    times, mon = [t0], [np.atleast_1d(monitor(u, v, sigma))]
    k, e = _energy(ops, v, sigma)
    kinetic, elastic, work, dissipation = [k], [e], [0.0], [0.0]
    iterations, solve_times = [], []
    f_n = np.asarray(load(t0), dtype=float)
    label = progress if isinstance(progress, str) else None
    bar = tqdm(total=int(n_steps), desc=label or None, unit="step", file=sys.stderr,
               disable=not progress, dynamic_ncols=True)
    for i in range(1, int(n_steps) + 1):
        t_n, t_next = t0 + (i - 1) * th.dt, t0 + i * th.dt
        f_next = np.asarray(load(t_next), dtype=float)
        du_P = (np.asarray(u_prescribed(t_next)) - np.asarray(u_prescribed(t_n))
                if prescribed.size else ())
        res = dynamic_increment(ops, f_n, f_next, sigma, v, criterion, fixed=fixed,
                                prescribed=(prescribed, du_P), scaling=scaling,
                                **solver_settings)
        scaling = res.scales                     # this step's magnitudes scale the next one
        # energy book-keeping (module docstring)
        sigma_theta = (th.theta1 * res.sigma + (1 - th.theta1) * sigma).ravel()
        strain = ops.B @ res.du
        if ops.C is not None:
            strain = strain - ops.C @ (res.sigma - sigma).ravel()
        dissipation.append(dissipation[-1] + float(sigma_theta @ strain))
        work.append(work[-1] + float(res.du @ th.load(f_n, f_next))
                    + th.theta1 * float(res.du @ res.reactions))
        u, v, sigma, f_n = u + res.du, res.v, res.sigma, f_next
        k, e = _energy(ops, v, sigma)
        kinetic.append(k)
        elastic.append(e)
        times.append(t_next)
        mon.append(np.atleast_1d(monitor(u, v, sigma)))
        iterations.append(res.info.iterations)
        solve_times.append(res.info.solve_time)
        bar.set_postfix_str(f"t = {t_next:.4g}, iterations {res.info.iterations}",
                            refresh=False)
        bar.update(1)
    bar.close()
    return DynamicHistory(np.array(times), u, v, sigma, np.array(mon), np.array(kinetic),
                          np.array(elastic), np.array(work), np.array(dissipation),
                          iterations, solve_times)

