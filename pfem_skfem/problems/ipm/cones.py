"""The cones of the interior point, vectorised: every operation on all cones of one
dimension at once.

A group is the cones of one dimension d, their vectors an array of shape (m, d): a
second-order cone {(u0, u1): u0 >= ||u1||} for d >= 2, and the non-negative rows for
d = 1 (the same formulas with u1 empty: a second-order cone of dimension one *is* the
half line, so one code serves both). The notation is Vandenberghe's ("The CVXOPT linear
and quadratic cone program solvers", 2010, sections 2-4): J = diag(1, -1, ..., -1), the
Jordan product u o v = (u^T v, u0 v1 + v0 u1), its identity e = (1, 0, ..., 0), and the
Nesterov-Todd scaling W = beta (2 v v^T - J), the symmetric matrix with W z = W^-1 s
(= lambda, the scaled point where the primal s and the dual z meet).

The solver keeps a group's vectors in Fortran order (its cones' first components, then
their second, ...: the rows of its data ordered by component, :mod:`.solver`), so that
an operation on one component of every cone runs along contiguous memory; every
operation here works on either order and answers in its arguments' (a C-ordered (m, 3)
array costs about four times as much: each of its columns is strided).
"""
import numpy as np


def _sum_columns(u, v, first):
    """sum_j u_j v_j over the columns from ``first`` on, of each row, in column order."""
    if u.shape[1] <= first:
        return np.zeros(u.shape[0])
    out = u[:, first] * v[:, first]
    for j in range(first + 1, u.shape[1]):
        out += u[:, j] * v[:, j]
    return out


def rows_dot(u, v):
    """u . v of each row."""
    return _sum_columns(u, v, 0)


def jdot(u, v):
    """u^T J v of each row: u0 v0 - u1 . v1."""
    return u[:, 0] * v[:, 0] - _sum_columns(u, v, 1)


def identity(m, d):
    """e of m cones of dimension d."""
    e = np.zeros((m, d), order="F")
    e[:, 0] = 1.0
    return e


def product(u, v):
    """The Jordan product u o v of each row."""
    out = np.empty_like(u)
    out[:, 0] = rows_dot(u, v)
    out[:, 1:] = u[:, :1] * v[:, 1:] + v[:, :1] * u[:, 1:]
    return out


def divide(lam, v):
    """u with lam o u = v, each row (lam in the cone's interior): the inverse of the arrow
    matrix of lam applied to v, in closed form."""
    det = jdot(lam, lam)[:, None]
    l0, l1 = lam[:, :1], lam[:, 1:]
    l1v1 = _sum_columns(lam, v, 1)[:, None]
    out = np.empty_like(v)
    out[:, :1] = (l0 * v[:, :1] - l1v1) / det
    out[:, 1:] = v[:, 1:] / l0 + (l1v1 / l0 - v[:, :1]) * l1 / det
    return out


def shift_inside(u):
    """u moved into the cones' interior along e where it is not (CVXOPT's start): u + (1 +
    a) e with a = the largest eigenvalue of -u, per cone, where a >= 0."""
    u = u.copy(order="K")
    alpha = np.linalg.norm(u[:, 1:], axis=1) - u[:, 0]      # max eigenvalue of -u
    out = alpha >= 0
    u[out, 0] += 1.0 + alpha[out]
    return u


class Scaling:
    """The Nesterov-Todd scaling of each cone of a group at the pair (s, z), both interior:
    W = beta (2 v v^T - J) with beta = (s^T J s / z^T J z)^(1/4) and v built from the
    normalised scaling point w = (s/|s|_J + J z/|z|_J) / (2 gamma) (Vandenberghe 2010, 4.2)."""

    def __init__(self, s, z):
        ns, nz = np.sqrt(jdot(s, s)), np.sqrt(jdot(z, z))
        sb, zb = s / ns[:, None], z / nz[:, None]
        gamma = np.sqrt(0.5 * (1.0 + rows_dot(sb, zb)))
        w = sb
        w[:, 0] += zb[:, 0]
        w[:, 1:] -= zb[:, 1:]
        w /= 2.0 * gamma[:, None]
        v = w.copy(order="K")
        v[:, 0] += 1.0
        v /= np.sqrt(2.0 * (w[:, :1] + 1.0))
        self.beta, self.v = np.sqrt(ns / nz), v
        self._jv = v.copy(order="K")              # J v, and 1 / beta, for W^-1
        self._jv[:, 1:] *= -1.0
        self._inv_beta = 1.0 / self.beta
        self.lam = self.apply(z)                  # W z = W^-1 s

    def apply(self, u):
        """W u of each row."""
        v = self.v
        out = 2.0 * v * rows_dot(v, u)[:, None]
        out[:, 0] -= u[:, 0]
        out[:, 1:] += u[:, 1:]
        out *= self.beta[:, None]
        return out

    def inverse(self, u):
        """W^-1 u of each row: W^-1 = (2 J v v^T J - J) / beta."""
        jv, ib = self._jv, self._inv_beta
        out = jv * (2.0 * ib * rows_dot(jv, u))[:, None]
        out[:, 0] -= ib * u[:, 0]
        out[:, 1:] += ib[:, None] * u[:, 1:]
        return out

    def inverse_matrix(self):
        """W^-1 of each cone, shape (m, d, d)."""
        m, d = self.v.shape
        jv, ib = self._jv, self._inv_beta
        out = np.empty((m, d, d))
        for i in range(d):
            a = 2.0 * jv[:, i]
            for j in range(i, d):
                out[:, i, j] = a * jv[:, j]
            out[:, i, i] += -1.0 if i == 0 else 1.0
            out[:, i, i:] *= ib[:, None]
            out[:, i + 1:, i] = out[:, i, i + 1:]
        return out


def max_step(u, du):
    """The largest a >= 0 (inf where none binds) with u + a du in each cone, u interior:
    the first positive root of q(a) = (u + a du)^T J (u + a du), a quadratic with q(0) > 0
    (it cannot leave the cone without q crossing zero). For d = 1, q = u0^2 never
    changes sign: the half line's own bound, u0 + a du0 = 0."""
    step = np.full(len(u), np.inf)
    if u.shape[1] == 1:
        neg = du[:, 0] < 0
        step[neg] = -u[neg, 0] / du[neg, 0]
        return step
    a = jdot(du, du)
    b = 2.0 * jdot(u, du)
    c = jdot(u, u)
    disc = b * b - 4.0 * a * c
    real = disc >= 0
    root = np.sqrt(np.where(real, disc, 0.0))
    # the stable pair of roots: q1 = -(b + sign(b) root) / 2, roots q1 / a and c / q1
    q1 = -0.5 * (b + np.where(b >= 0, 1.0, -1.0) * root)
    with np.errstate(divide="ignore", invalid="ignore"):
        r1 = np.where(a != 0, q1 / a, np.inf)
        r2 = np.where(q1 != 0, c / q1, np.inf)
    for r in (r1, r2):
        hit = real & (r > 0) & np.isfinite(r)
        step[hit] = np.minimum(step[hit], r[hit])
    return step
