"""Substitutions before the interior point: a variable fixed or defined by one equality.

An equality of one or two entries is not equilibrium: cvxpy states a cone on an
expression by a new variable t and t = a x; a fluid point's deviatoric stress is held at
zero by s_xy = 0 and s_xx - s_yy = 0. Counted as equilibrium rows by the reduced Newton
system (:mod:`.structure`) they join blocks and put rows of one point into the
displacements' matrix. Substituting t = (b_r - a_x x) / a_t, or t = b_r / a_t for a row of
one entry, everywhere (x = T x' + t0: P' = T^T P T, c' = T^T (c + P t0), A' = A T,
b' = b - A t0, the row dropped) gives the same problem on fewer variables, and the
answer is mapped back (:meth:`Substitution.recover`): t from x, the dropped row's
multiplier from t's stationarity, (P x + c + A^T z)_t = 0 (the other rows' multipliers
first: t is in no other dropped row). The interior point measures the substituted problem
against the given one's scales (:attr:`Substitution.given`): its objective with the
constant c^T t0 + 1/2 t0^T P t0 that the substitution drops, and the norms of the given b
and c where they are smaller than the substituted ones.
"""
import numpy as np
import scipy.sparse as sp

from .structure import full_symmetric


class Substitution:
    """The substitutions of one problem (none where no row qualifies)."""

    def __init__(self, P, c, A, b, cones):
        A = sp.csr_matrix(A)
        n = A.shape[1]
        zero = np.zeros(A.shape[0], bool)
        start = 0
        for cone in cones:
            if type(cone).__name__ == "ZeroConeT":
                zero[start:start + int(cone.dim)] = True
            start += int(cone.dim)
        rows = np.flatnonzero(zero)
        count = np.diff(A.indptr)[rows]
        used = np.zeros(n, bool)
        drop, t_of, x_of, a_t, a_x = [], [], [], [], []
        for r in rows[(count == 1) | (count == 2)]:
            cols = A.indices[A.indptr[r]:A.indptr[r + 1]]
            vals = A.data[A.indptr[r]:A.indptr[r + 1]]
            if cols.size == 1:                       # t = b_r / a_t: fixed
                if vals[0] != 0 and not used[cols[0]]:
                    used[cols[0]] = True
                    drop.append(r), t_of.append(cols[0]), x_of.append(-1)
                    a_t.append(vals[0]), a_x.append(0.0)
                continue
            for k in (0, 1):
                t, x = cols[k], cols[1 - k]
                if not used[t] and not used[x] and vals[k] != 0:
                    used[t] = used[x] = True
                    drop.append(r), t_of.append(t), x_of.append(x)
                    a_t.append(vals[k]), a_x.append(vals[1 - k])
                    break
        self.any = bool(drop)
        if not self.any:
            return
        self.t, self.rows = np.array(t_of), np.array(drop)
        self.a_t = np.array(a_t)
        keep = np.ones(n, bool)
        keep[self.t] = False
        self.keep = np.flatnonzero(keep)
        new = np.full(n, -1)
        new[self.keep] = np.arange(self.keep.size)
        # T: identity on the kept variables, t = -a_x / a_t x (+ b_r / a_t in t0)
        x_of = np.array(x_of)
        pair = x_of >= 0                              # a fixed t has no column
        Ti = np.r_[self.keep, self.t[pair]]
        Tj = np.r_[np.arange(self.keep.size), new[x_of[pair]]]
        Tv = np.r_[np.ones(self.keep.size), -np.array(a_x)[pair] / self.a_t[pair]]
        self.T = sp.csr_matrix((Tv, (Ti, Tj)), shape=(n, self.keep.size))
        self.t0 = np.zeros(n)
        self.t0[self.t] = b[self.rows] / self.a_t
        rows_kept = np.ones(A.shape[0], bool)
        rows_kept[self.rows] = False
        self.rows_kept = np.flatnonzero(rows_kept)
        self.n_rows = A.shape[0]
        self.P_full = full_symmetric(P)
        self.A, self.c = A, np.asarray(c, dtype=float)
        # what the measures need of the given problem (Clarabel's, measured on the data it
        # is given): the objective's constant, dropped from the substituted one, and the
        # norms of b and c
        self.given = dict(offset=float(self.c @ self.t0 + 0.5 * self.t0 @ (self.P_full @ self.t0)),
                          norm_b=_inf(b), norm_c=_inf(self.c))
        self.problem = (sp.csc_matrix(self.T.T @ self.P_full @ self.T),
                        self.T.T @ (self.c + self.P_full @ self.t0),
                        sp.csc_matrix(A[self.rows_kept] @ self.T),
                        b[self.rows_kept] - A[self.rows_kept] @ self.t0,
                        _fewer_zero_rows(cones, self.rows))

    def recover(self, x, z, s):
        """(x, z, s) of the original problem from the substituted one's."""
        x_full = self.T @ x + self.t0
        z_full, s_full = np.zeros(self.n_rows), np.zeros(self.n_rows)
        z_full[self.rows_kept], s_full[self.rows_kept] = z, s
        grad = self.P_full @ x_full + self.c + self.A.T @ z_full      # row r's z still 0
        z_full[self.rows] = -grad[self.t] / self.a_t
        return x_full, z_full, s_full


def _inf(v):
    return float(np.abs(v).max()) if np.size(v) else 0.0


def _fewer_zero_rows(cones, dropped):
    """The cone list with the dropped (zero-cone) rows taken out of their zero cones."""
    import clarabel
    out, start = [], 0
    dropped = np.sort(dropped)
    for cone in cones:
        dim = int(cone.dim)
        if type(cone).__name__ == "ZeroConeT":
            gone = np.searchsorted(dropped, start + dim) - np.searchsorted(dropped, start)
            if dim - gone:
                out.append(clarabel.ZeroConeT(int(dim - gone)))
        else:
            out.append(cone)
        start += dim
    return out
