"""Contact dynamics of one rigid particle against rigid boundaries (thesis 5.2, (5.1)-(5.9)).

The teaching form of the contact scheme: a rigid body without rotation (mass m,
velocity v) meets rigid boundaries at contact points j with gaps g0_j, normals n_j
(from the boundary towards the body) and friction mu_j. The theta-method (5.2)
gives m_bar du / dt^2 = f_bar + sum_j (n_j p_j + n^_j q_j) with::

    m_bar = m / theta,   f_bar = f_ext + m_bar v_n / dt                (5.4)

and the step is the cone program (5.9), re-derived from (5.6)-(5.8) (the printed
(5.9) is garbled; see shared/thesis/MAP.md)::

    maximise   - dt^2 / 2  r^T m_bar^-1 r - sum_j g0_j p_j
    subject to r = f_bar + sum_j (n_j p_j + n^_j q_j)
               |q_j| <= mu_j p_j

with the dynamic force r = m_bar du / dt^2 (5.8). Its KKT conditions are (5.5):
no penetration (g0_j + n_j . du >= 0), p_j >= 0, complementarity, and the
associated sliding rule, whose dilation mu * ``|slip|`` vanishes as dt -> 0.
"""
from dataclasses import dataclass

import cvxpy as cp
import numpy as np

from .conic import solve


def check_time_step(dt, theta, *, theta_min=0.0):
    """Validate a time step and a theta-method parameter."""
    if not np.isfinite(dt) or dt <= 0:
        raise ValueError(f"dt (time step) must be positive, got {dt!r}")
    if not np.isfinite(theta) or not theta_min < theta <= 1:
        raise ValueError(f"theta must lie in ({theta_min:g}, 1], got {theta!r}")


@dataclass
class ParticleStep:
    """du (2,), v (2,) at t_{n+1}, contact forces p, q (nc,) and the solver report."""

    du: np.ndarray
    v: np.ndarray
    p: np.ndarray
    q: np.ndarray
    info: object


def rigid_particle_step(m, v_n, f_ext, dt, theta, gaps, normals, mu, *, solver="clarabel",
                        **solver_settings):
    """One step of (5.9) for a rigid particle.

    Parameters
    ----------
    m : mass (> 0).  v_n : (2,) velocity at t_n.  f_ext : (2,) external force.
    dt : time step.  theta : theta-method parameter in (0, 1].
    gaps : (nc,) g0_j.  normals : (nc, 2) unit n_j.  mu : (nc,) friction coefficients.
    solver : the conic solver (:data:`~pfem_skfem.problems.conic.SOLVERS`; 'clarabel').
    """
    if not np.isfinite(m) or m <= 0:
        raise ValueError(f"m (mass) must be positive, got {m!r}")
    check_time_step(dt, theta)
    v_n, f_ext = np.asarray(v_n, float), np.asarray(f_ext, float)
    g0 = np.atleast_1d(np.asarray(gaps, float))
    n = np.atleast_2d(np.asarray(normals, float))
    mu = np.broadcast_to(np.asarray(mu, float), g0.shape)
    if np.any(mu < 0):
        raise ValueError("mu (friction coefficient) must be >= 0")
    t = np.stack([-n[:, 1], n[:, 0]], axis=1)                 # n^ = (-n2, n1)

    m_bar = m / theta
    f_bar = f_ext + m_bar * v_n / dt                          # (5.4)
    # scales: the displacement of a free step and the force that moves m_bar by it
    # in dt (not the gaps: a distant boundary must not shrink the other data)
    u_ref = max(np.linalg.norm(v_n) * dt, np.linalg.norm(f_ext) * dt ** 2 / m)
    if u_ref == 0:                                  # at rest and unloaded
        u_ref = max(np.abs(g0).max(initial=0.0), 1.0)
    f_ref = m_bar * u_ref / dt ** 2

    r = cp.Variable(2)                                        # r = m_bar du / dt^2 (5.8)
    p, q = cp.Variable(g0.size), cp.Variable(g0.size)
    objective = cp.Maximize(-0.5 * cp.sum_squares(r) - (g0 / u_ref) @ p)
    constraints = [
        r == f_bar / f_ref + n.T @ p + t.T @ q,               # momentum balance
        cp.abs(q) <= cp.multiply(mu, p),                      # |q_j| - mu p_j <= 0
        p >= 0,
    ]
    info = solve(cp.Problem(objective, constraints), what="rigid particle step (5.9)",
                 solver=solver, **solver_settings)
    du = r.value * f_ref * dt ** 2 / m_bar                    # (5.8)
    v = (du / dt - (1 - theta) * v_n) / theta                 # (5.3)
    return ParticleStep(du, v, p.value * f_ref, q.value * f_ref, info)


def free_particles_step(x, v, acceleration, dt, theta, bodies):
    """One step of point particles under a body force, with frictional contact without dilation.

    The PFEM's free particles (in no element, Section 2.2) move by the theta-method
    (5.2)-(5.3): v_{n+1} = v_n + a dt, du = dt (theta v_{n+1} + (1 - theta) v_n). A
    particle whose trial move would close its gap g0 to a rigid body ends on its
    surface: n . du = -g0 fixes the normal velocity, the normal impulse per unit mass
    J = n . (v_{n+1} - v*) >= 0, and friction takes at most mu J off the tangential
    velocity (Coulomb's law for the impulse of the step, no lift-off: the closed form
    of (5.9) for one particle and one contact with the friction bounded by mu J).

    Parameters
    ----------
    x, v : (m, 2) positions and velocities at t_n.  acceleration : (2,) body force per mass.
    dt, theta : time step and theta in (0, 1].  bodies : rigid bodies with ``gap`` and ``mu``.

    Returns x, v at t_{n+1} (new arrays).
    """
    check_time_step(dt, theta)
    x, v = np.array(x, dtype=float), np.array(v, dtype=float)
    v_new = v + np.asarray(acceleration, dtype=float) * dt
    for body in bodies:
        g0, n = body.gap(x)
        du = dt * (theta * v_new + (1 - theta) * v)
        closing = g0 + np.einsum("id,id->i", du, n) < 0
        if not closing.any():
            continue
        n, t = n[closing], np.stack([-n[closing, 1], n[closing, 0]], axis=1)
        vs, vo = v_new[closing], v[closing]
        vn = (-g0[closing] / dt - (1 - theta) * np.einsum("id,id->i", vo, n)) / theta
        impulse = np.maximum(vn - np.einsum("id,id->i", vs, n), 0.0)
        vt = np.einsum("id,id->i", vs, t)
        vt = np.sign(vt) * np.maximum(np.abs(vt) - body.mu * impulse, 0.0)
        v_new[closing] = vn[:, None] * n + vt[:, None] * t
    return x + dt * (theta * v_new + (1 - theta) * v), v_new
