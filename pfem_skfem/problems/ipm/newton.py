"""The Newton system of the interior point, reduced to the displacements (and the
pressures).

The problem (Clarabel's standard form, the rows split by cone, :mod:`.structure`):

    min 1/2 x^T P x + c^T x   s.t.   E x = b_E  (the zero cone: equilibrium),
                                     G x + s = h, s in K  (the yield, contact cones).

An iteration solves, for a Nesterov-Todd scaling W of each cone (:mod:`.cones`), in its
scaled form (dzt = W dz; W applied once, never squared: W^2's condition number passes
1e16 as the gap closes):

    P dx + E^T dy + G^T W^-1 dzt = bx,    E dx = by,    W^-1 G dx - dzt = bzt.     (N)

Every cone sits on one block of variables (:mod:`.structure`), so eliminating dzt leaves
the block-diagonal H = P + G^T W^-2 G = M^T M, M = [L_P; W^-1 G_b] stacked per block.
H is inverted block by block on its range from the SVD of M (batched over the blocks of
one size; M's singular values are resolved where H's eigenvalues, their squares, are
not), and eliminating dx leaves, for the displacements dy and the pressures p (the
blocks' null directions N, which H does not see),

    [ E H^+ E^T   E N      ] [ dy ]   [ E H^+ rx - by ]
    [ N^T E^T    -delta I  ] [ -p ] = [ N^T rx        ],   rx = bx + G^T W^-1 bzt,

    dx = H^+ (rx - E^T dy) + N p,    dzt = W^-1 G dx - bzt.

Without null directions (a step with compliance or inertia on every stress: the
elastoplastic step) this is one symmetric positive definite matrix of the size of the
free displacements with the stiffness pattern, factorised by CHOLMOD's supernodal
Cholesky; with them (a rigid-plastic zero-dilation or Tresca point, a fluid's pressure)
it is quasi-definite (Vanderbei 1995), factorised by CHOLMOD's LDL^T. Either once an
iteration (:mod:`.cholesky`): the predictor and the corrector share it. delta
(:data:`REGULARISATION`) on both diagonals keeps the matrix quasi-definite (a
displacement that no stress reaches, a pressure); iterative refinement on (N) removes it.
"""
import numpy as np

#: the regularisation delta of the pressures' block (Clarabel's static regularisation on
#: its order-one data), removed by the refinement
REGULARISATION = 1e-8

#: the regularisation of the displacements' diagonal, relative to its largest entry
DOF_REGULARISATION = 1e-14

#: refinement stops when (N)'s residual is below this, relative to the right-hand side
REFINE_TOL = 1e-13


class Newton:
    """The factorised Newton system (N) at one scaling: :meth:`solve` answers (dx, dy,
    dzt) for right-hand sides (bx, by, bzt), bzt per cone group."""

    def __init__(self, structure, scalings, cholesky):
        st = self.st = structure
        self.W = scalings
        M = {size: np.zeros((len(p), st.M_rows[size], size)) for size, p in st.P_blocks.items()}
        for size, root in st.P_roots.items():
            M[size][:, :size] = root
        for d, cones_k, size, blk, dense, offset in st.cone_parts:
            rows = np.einsum("mrs,msj->mrj", scalings[d].inverse_matrix()[cones_k], dense)
            M[size][blk[:, None], offset[:, None] + np.arange(d)] = rows
        self.Hinv, values = {}, st.EN_values.copy()
        for size, Mb in M.items():
            Vr = st.range_[size]
            null = st.null[size][1]
            _, sig, Vt = np.linalg.svd(Mb @ Vr, full_matrices=False)
            k = null.sum(axis=1)                  # the k smallest are the null columns'
            drop = np.arange(size)[None, :] >= (size - k)[:, None]
            inv2 = np.where(drop, 0.0, 1.0 / np.where(drop, 1.0, sig) ** 2)
            Hinv = np.einsum("mki,mk,mkj->mij", Vt, inv2, Vt)
            self.Hinv[size] = np.einsum("mij,mjk,mlk->mil", Vr, Hinv, Vr)
            dense, rows = st.E_parts[size]
            S_b = np.einsum("mri,mij,msj->mrs", dense, self.Hinv[size], dense)
            values += np.bincount(st.S_slots[size], weights=S_b[st.S_mask[size]],
                                  minlength=st.K_nnz)
        nE = st.E.shape[0]
        values[st.diag_slots[:nE]] += DOF_REGULARISATION * values[st.diag_slots[:nE]].max()
        values[st.diag_slots[nE:]] -= REGULARISATION
        self.chol = cholesky
        cholesky.factor(values)
        if st.free.size:                 # the free variables' dense Schur complement
            self.Ef = st.E[:, st.free].toarray()
            self.Z = cholesky.solve(np.vstack([self.Ef, np.zeros((st.n_p, st.free.size))]))
            self.schur_f = np.linalg.cholesky(self.Ef.T @ self.Z[:nE])

    def _blocks_apply(self, mats, x):
        """y with y_b = mats_b x_b for every block (x, y of the full variable length)."""
        y = np.zeros_like(x)
        for size, vars_ in self.st.blocks.items():
            y[vars_] = np.einsum("mij,mj->mi", mats[size], x[vars_])
        return y

    def _solve_reduced(self, rx, ry):
        """(dx, dy) of [H E^T; E 0] (dx, dy) = (rx, ry) through the reduced matrix."""
        st = self.st
        nE = st.E.shape[0]
        rhs = np.empty(st.n_reduced)
        rhs[:nE] = st.E @ self._blocks_apply(self.Hinv, rx) - ry
        for size, vars_ in st.blocks.items():          # N^T rx
            p = st.pressure[size]
            if (p >= 0).any():
                Vn = st.null[size][0]
                rhs[nE + p[p >= 0]] = np.einsum("mji,mj->mi", Vn, rx[vars_])[p >= 0]
        sol = self.chol.solve(rhs)
        dx = np.zeros_like(rx)
        if st.free.size:
            w = sol[:nE]
            L = self.schur_f
            dxf = np.linalg.solve(L.T, np.linalg.solve(L, rx[st.free] - self.Ef.T @ w))
            sol = sol + self.Z @ dxf
            dx[st.free] = dxf
        dy = sol[:nE]
        dxb = self._blocks_apply(self.Hinv, rx - st.E.T @ dy)
        for size, vars_ in st.blocks.items():          # + N p, p = -sol's pressures
            p = st.pressure[size]
            if (p >= 0).any():
                coeff = np.zeros(p.shape)
                coeff[p >= 0] = -sol[nE + p[p >= 0]]
                dxb[vars_] += np.einsum("mij,mj->mi", st.null[size][0], coeff)
        blocked = np.ones(rx.size, bool)
        blocked[st.free] = False
        blocked[st.dead] = False
        dx[blocked] = dxb[blocked]
        return dx, dy

    def _rhs_x(self, bx, bzt):
        """bx + G^T W^-1 bzt."""
        r = bx.copy()
        for d, G in self.st.G.items():
            r += G.T @ self.W[d].inverse(bzt[d]).ravel()
        return r

    def _once(self, bx, by, bzt):
        """(dx, dy, dzt) of (N) by the reduction, unrefined."""
        dx, dy = self._solve_reduced(self._rhs_x(bx, bzt), by)
        dzt = {d: self.W[d].inverse((G @ dx).reshape(-1, d)) - bzt[d]
               for d, G in self.st.G.items()}
        return dx, dy, dzt

    def _residual(self, bx, by, bzt, dx, dy, dzt):
        """The residual of (N), unregularised, and its largest entry."""
        st = self.st
        rx = bx - st.P @ dx - st.E.T @ dy
        rz = {}
        for d, G in st.G.items():
            w = self.W[d]
            rx -= G.T @ w.inverse(dzt[d]).ravel()
            rz[d] = bzt[d] - w.inverse((G @ dx).reshape(-1, d)) + dzt[d]
        ry = by - st.E @ dx
        if st.dead.size:
            rx[st.dead] = 0.0                  # a dead variable's row is empty
        norm = max(np.abs(rx).max(initial=0), np.abs(ry).max(initial=0),
                   *(np.abs(r).max(initial=0) for r in rz.values()))
        return rx, ry, rz, norm

    def solve(self, bx, by, bzt, refine=10):
        """(dx, dy, dzt) of (N); iterative refinement (at most ``refine`` steps) while its
        residual falls. ``self.residual``: the last residual relative to the data."""
        dx, dy, dzt = self._once(bx, by, bzt)
        scale = max(1.0, np.abs(bx).max(initial=0), np.abs(by).max(initial=0),
                    *(np.abs(b).max(initial=0) for b in bzt.values()))
        ex, ey, ez, norm = self._residual(bx, by, bzt, dx, dy, dzt)
        for _ in range(refine):
            if norm <= REFINE_TOL * scale:
                break
            cx, cy, cz = self._once(ex, ey, ez)
            nx_, ny_ = dx + cx, dy + cy
            nz_ = {d: dzt[d] + cz[d] for d in dzt}
            fx, fy, fz, new = self._residual(bx, by, bzt, nx_, ny_, nz_)
            if new >= norm:
                break
            dx, dy, dzt, ex, ey, ez, norm = nx_, ny_, nz_, fx, fy, fz, new
        self.residual = norm / scale
        return dx, dy, dzt
