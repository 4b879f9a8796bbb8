"""The Newton system of the interior point, reduced to the displacements.

The problem (Clarabel's standard form, the rows split by cone, :mod:`.structure`):

    min 1/2 x^T P x + c^T x   s.t.   E x = b_E  (the zero cone: equilibrium),
                                     G x + s = h, s in K  (the yield, contact cones).

An iteration solves, for a Nesterov-Todd scaling W of each cone (:mod:`.cones`), in its
scaled form (dzt = W dz; W applied once, never squared: W^2's condition number passes
1e16 as the gap closes):

    P dx + E^T dy + G^T W^-1 dzt = bx,    E dx = by,    W^-1 G dx - dzt = bzt.     (N)

Every cone sits on one block of variables (:mod:`.structure`), so eliminating dzt leaves
the block-diagonal H = P + G^T W^-2 G = M^T M, M = [L_P; W^-1 G_b] stacked per block.
H is inverted block by block on its range from the QR factorisation of M (Householder,
batched over the blocks of one size: H = R^T R, and R is as well conditioned as M, the
square root of H's condition number, which passes 1e16 as the gap closes). The null
directions N of the blocks (which H does not see: the mean stress of a
rigid-plastic zero-dilation or Tresca point, a fluid's pressure) carry the "pressures"
p, multipliers of E_N^T dy = N^T rx (the incompressibility of the increment there);
regularised by -delta I (1 / delta = :data:`PENALTY`) and eliminated, they add the constant
E_N E_N^T / delta. What is left is one symmetric positive definite matrix of the size of
the free displacements with the stiffness matrix's pattern,

    S = E H^+ E^T + E_N E_N^T / delta,     S dy = E H^+ rx - by + E_N N^T rx / delta,

    rx = bx + G^T W^-1 bzt,  p = (N^T rx - E_N^T dy) / delta,
    dx = H^+ (rx - E^T dy) + N p,          dzt = W^-1 G dx - bzt,

factorised by CHOLMOD's supernodal Cholesky once an iteration (:mod:`.cholesky`): the
predictor and the corrector share it. Iterative refinement on (N) itself (unregularised)
removes delta's error (it is the iterated penalty method for the pressures).
"""
import numpy as np

from .structure import component_major, from_component_major

#: the penalty 1 / delta of the pressures (the data are of order one: the step's
#: scaling, :class:`~pfem_skfem.problems.conic.Scaling`); the refinement removes its error
PENALTY = 1e10

#: the regularisation of S's diagonal, relative to its largest entry (a displacement that
#: no stress reaches)
DOF_REGULARISATION = 1e-14

#: the most refinement steps of a Newton solve, and the residual of (N), relative to its
#: right-hand side, that stops them (as does a step that gains less than half); a solve may
#: ask for less (``tol``: an inexact Newton direction, far from the solution)
REFINE_STEPS = 10
REFINE_TOL = 1e-8


def upper_inverse(R):
    """The inverses of a stack (m, s, s) of upper triangular matrices: back substitution
    vectorised over the stack, a row at a time (LAPACK's general inverse costs four times
    more on the 3 x 3 blocks of a stress point, by its call per matrix)."""
    m, s, _ = R.shape
    if s > 16:
        return np.linalg.inv(R)
    diag = np.arange(s)
    d = 1.0 / R[:, diag, diag]
    X = np.zeros_like(R)
    X[:, diag, diag] = d
    for i in range(s - 2, -1, -1):          # X_i,i+1: = -R_i,i+1: X_i+1:,i+1: / R_ii
        X[:, i, i + 1:] = -d[:, i, None] * np.einsum("mj,mjk->mk", R[:, i, i + 1:],
                                                      X[:, i + 1:, i + 1:])
    return X


def triangular_factor(M):
    """R of M = Q R for a stack (m, r, s) of small tall matrices (r >= s): Householder
    reflections vectorised over the stack, laid out with the stack index last (each
    operation on contiguous rows of length m; LAPACK's call per matrix costs twice as
    much on the 3 x 3 blocks of a stress point). A zero column (a null direction) keeps a
    zero diagonal. R's rows may differ from LAPACK's in sign; R^T R = M^T M."""
    m, r, s = M.shape
    if s > 16 or r < s:
        return np.linalg.qr(M, mode="r")
    A = np.ascontiguousarray(M.transpose(1, 2, 0))          # (r, s, m)
    R = np.zeros((s, s, m))
    for k in range(s):
        x = A[k:, k]                                        # column k below the diagonal
        norm = np.sqrt(np.einsum("im,im->m", x, x))
        alpha = np.copysign(norm, -x[0])                    # the reflection's image of x
        v = x.copy()
        v[0] -= alpha
        half = norm * (norm + np.abs(x[0]))                 # |v|^2 / 2
        tau = np.divide(1.0, half, out=np.zeros_like(half), where=half > 0)
        R[k, k] = alpha
        if k + 1 < s:                                       # reflect the columns after k
            B = A[k:, k + 1:]
            B -= v[:, None, :] * (np.einsum("im,ijm->jm", v, B) * tau)[None]
            R[k, k + 1:] = B[0]
    return np.ascontiguousarray(R.transpose(2, 0, 1))


class Newton:
    """The factorised Newton system (N) at one scaling: :meth:`solve` answers (dx, dy,
    dzt) for right-hand sides (bx, by, bzt), bzt per cone group; ``residual`` the last
    solve's residual of (N) relative to its right-hand side."""

    #: the reduction satisfies (N)'s third row by construction (:meth:`_residual`)
    third_by_construction = True

    #: a refinement step that leaves more than this of the residual is the last
    slow = 0.5

    #: the residual below which the refinement never goes, whatever a solve asks: the
    #: reduced system's own refinement stalls there (:data:`REFINE_TOL`)
    refine_tol = REFINE_TOL

    def __init__(self, structure, scalings, cholesky):
        st = self.st = structure
        self.W = scalings
        MV = {size: st.MV_fixed[size].copy() for size in st.coned}      # M V_r
        for d, cones_k, size, blk, dense_V, offset, whole in st.cone_parts_V:
            Wi = scalings[d].inverse_matrix()
            if whole:                       # each block's one cone, in order
                MV[size][:, offset[0]:offset[0] + d] = Wi @ dense_V
            else:
                MV[size][blk[:, None], offset[:, None] + np.arange(d)] = Wi[cones_k] @ dense_V
        self.gamma = PENALTY                                # 1 / delta
        if st.penalised is None or st.penalised[0] != self.gamma:   # S's constant part
            st.penalised = (self.gamma, st.S_fixed + self.gamma * st.S_pressures)
        self.U, values = {}, st._buffer("S", st.penalised[1].shape)
        np.copyto(values, st.penalised[1])     # factor() copies it: the buffer is free after
        for size, MVb in MV.items():
            # V_r: the range's columns first (the null ones last, zero columns): M V_r =
            # Q R with R = [[R_11, 0], [0, 0]], the null block set to I, and
            # H^+ = V_r R^-1 R^-T V_r^T = U U^T, U = V_r R^-1 (the null columns that all
            # blocks share left out: :meth:`.structure.Structure._rotated`)
            Vr = st.Vr[size]
            R = triangular_factor(MVb)
            kept = np.arange(R.shape[2])
            R[:, kept, kept] += st.null_last[size]            # R_22 = I
            U = self.U[size] = Vr @ upper_inverse(R)
            st.scatter(size, U, values)
        # the constant blocks' H^+ (no cone: P's alone); the coned ones are applied by
        # their factors, U (U^T t) (:meth:`_H`), never as U U^T
        self.Hmat = st.block_matrix({size: np.zeros((U.shape[0], U.shape[1], U.shape[1]))
                                     for size, U in self.U.items()})
        diag = values[st.diag_slots]                        # the stiffest, pressures aside
        stiffest = max((diag - self.gamma * st.S_pressures[st.diag_slots]).max(initial=0.0),
                       1e-300)
        values[st.diag_slots] = diag + DOF_REGULARISATION * stiffest
        self.chol = cholesky
        cholesky.factor(values)
        if st.free.size:                 # the free variables' dense Schur complement
            self.Ef = st.E[:, st.free].toarray()
            self.Z = cholesky.solve(self.Ef)
            self.schur_f = np.linalg.cholesky(self.Ef.T @ self.Z)

    def _H(self, v):
        """H^+ v: the constant blocks by their matrix, the coned blocks by their factors,
        U_b (U_b^T v_b). A coned block's H^+ = U_b U_b^T formed is not used: near the
        solution a block's H can be as ill-conditioned as 1e17 (a contact opening: one
        friction row active, W^-2 ~ 1e6 on it, ~1e-11 on the others) and the explicit
        H^+, its entries ~1e10, loses the stiff direction's 1e-6 to rounding; the
        reduced direction then missed (N) by 1e-3 of its right-hand side, and the
        refinement stalled, at a gap of ~1e-7 on the 512-element PFEM step."""
        out = self.Hmat @ v
        for size in self.U:
            flat = self.st.coned_parts[size][0]
            out[flat] = self._coned(size, v[flat].reshape(-1, size)).ravel()
        return out

    def _coned(self, size, t):
        """The coned blocks' H^+ t of one size, (m, size), by their factors: U (U^T t)."""
        U = self.U[size]
        return np.einsum("msr,mr->ms", U, np.einsum("msr,ms->mr", U, t))

    def _dy(self, rx, ry):
        """dy of [H E^T; E 0] (dx, dy) = (rx, ry), the pressures regularised; N^T rx and
        the free variables' dx (None without)."""
        st = self.st
        rN = st.NT @ rx
        dy = self.chol.solve(st.E @ self._H(rx) - ry + self.gamma * (st.EN @ rN))
        dxf = None
        if st.free.size:                 # the free variables beside S
            L = self.schur_f
            dxf = np.linalg.solve(L.T, np.linalg.solve(L, rx[st.free] - self.Ef.T @ dy))
            dy = dy + self.Z @ dxf
        return dy, rN, dxf

    def _solve_reduced(self, rx, ry):
        """(dx, dy, E^T dy) of [H E^T; E 0] (dx, dy) = (rx, ry), the pressures regularised
        (E^T dy, which dx is made of, is also the residual's: :meth:`_residual`)."""
        st = self.st
        dy, rN, dxf = self._dy(rx, ry)
        p = self.gamma * (rN - st.EN.T @ dy)
        ETdy = st.ET @ dy
        dx = self._H(rx - ETdy) + st.N @ p             # zero off the blocks
        if st.free.size:
            dx[st.free] = dxf
        return dx, dy, ETdy

    def _rhs_x(self, bx, bzt):
        """bx + G^T W^-1 bzt."""
        r = bx.copy()
        for d, GT in self.st.GcT.items():
            r += GT @ component_major(self.W[d].inverse(bzt[d]))
        return r

    def _predict(self, bx, by, bzt):
        """dzt of (N), unrefined, for the predictor (its direction sets only the
        centring): dx is formed on the coned blocks alone, block by block (H_b^+ dense), since
        G sees no other variable and none of the null directions (the pressures p are
        not formed: G N p is round-off)."""
        st = self.st
        rx = self._rhs_x(bx, bzt)
        dy = self._dy(rx, by)[0]
        Gdx = {d: np.zeros(G.shape[0]) for d, G in st.Gc.items()}
        for size, (flat, ET, Gs) in st.coned_parts.items():
            t = (rx[flat] - ET @ dy).reshape(-1, size)
            dxs = self._coned(size, t).ravel()
            for d, G in Gs.items():
                Gdx[d] += G @ dxs
        return {d: self.W[d].inverse(from_component_major(Gdx[d], d)) - bzt[d] for d in Gdx}

    def _once(self, bx, by, bzt):
        """(dx, dy, dzt) of (N) by the reduction, unrefined, G dx per group and E^T dy."""
        dx, dy, ETdy = self._solve_reduced(self._rhs_x(bx, bzt), by)
        Gdx = {d: from_component_major(G @ dx, d) for d, G in self.st.Gc.items()}
        dzt = {d: self.W[d].inverse(Gdx[d]) - bzt[d] for d in Gdx}
        return dx, dy, dzt, (Gdx, ETdy)

    def _residual(self, bx, by, bzt, dx, dy, dzt, third=False, ETdy=None):
        """The residual of (N), unregularised, its largest entry, and the products it is
        made of (P dx, A^T dz with dz = (dy, W^-1 dzt), E dx). Its third row holds by
        construction (dzt = W^-1 G dx - bzt, refinement included: round-off), so it is
        computed only when asked (``third``: a check, or :mod:`.augmented`'s solve,
        which does not hold it), else zero. ``ETdy``: E^T dy where the solve made it."""
        st = self.st
        Pdx = st.P @ dx
        ATdz = st.ET @ dy if ETdy is None else ETdy.copy()
        rz = {}
        for d, G in st.Gc.items():
            w = self.W[d]
            ATdz += st.GcT[d] @ component_major(w.inverse(dzt[d]))
            rz[d] = bzt[d] - w.inverse(from_component_major(G @ dx, d)) + dzt[d] if third \
                else np.zeros_like(bzt[d])
        Edx = st.E @ dx
        rx = bx - Pdx - ATdz
        ry = by - Edx
        rx[st.dead] = 0.0                       # a dead variable's row is empty
        norm = max(np.abs(rx).max(initial=0), np.abs(ry).max(initial=0),
                   *(np.abs(r).max(initial=0) for r in rz.values()))
        return rx, ry, rz, norm, (Pdx, ATdz, Edx)

    def solve(self, bx, by, bzt, refine=True, tol=REFINE_TOL):
        """(dx, dy, dzt) of (N), refined (:data:`REFINE_STEPS`) to the residual ``tol``
        (relative; at least ``refine_tol``, :data:`REFINE_TOL` here), or not (``refine=False``: the
        predictor's direction sets only the centring: dzt alone, dx and dy None). A refined
        solve leaves in ``products`` its direction's P dx, A^T dz, E dx and G dx per group (what the
        measures of the next iterate are updated by, :mod:`.solver`)."""
        tol = max(tol, self.refine_tol)
        if not refine:
            return None, None, self._predict(bx, by, bzt)
        dx, dy, dzt, (Gdx, ETdy) = self._once(bx, by, bzt)
        scale = max(1.0, np.abs(bx).max(initial=0), np.abs(by).max(initial=0),
                    *(np.abs(b).max(initial=0) for b in bzt.values()))
        third = not self.third_by_construction
        ex, ey, ez, norm, made = self._residual(bx, by, bzt, dx, dy, dzt, third, ETdy)
        for _ in range(REFINE_STEPS):
            if norm <= tol * scale:
                break
            cx, cy, cz, (Gcx, ETcy) = self._once(ex, ey, ez)
            new = (dx + cx, dy + cy, {d: dzt[d] + cz[d] for d in dzt})
            fx, fy, fz, new_norm, new_made = self._residual(bx, by, bzt, *new, third,
                                                            None if ETcy is None else ETdy + ETcy)
            if new_norm >= norm:
                break
            slow = new_norm > self.slow * norm        # more steps would gain little
            (dx, dy, dzt), (ex, ey, ez), norm, made = new, (fx, fy, fz), new_norm, new_made
            Gdx = {d: Gdx[d] + Gcx[d] for d in Gdx}
            ETdy = None if ETcy is None else ETdy + ETcy
            if slow:
                break
        self.residual = norm / scale
        self.products = (*made, Gdx)
        return dx, dy, dzt
