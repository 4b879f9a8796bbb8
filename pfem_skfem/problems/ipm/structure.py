"""The structure of a conic problem that the reduced Newton system (:mod:`.newton`) uses,
found once per problem (a PFEM step's pattern does not change between its iterations).

* the rows by cone: the zero cone's (E, the equilibrium) and each group of cones of one
  dimension (G_d, the yield and contact cones; a non-negative row is a cone of dimension
  one);
* the variables by **block**: the connected sets of variables that the quadratic P or a
  common cone joins (a stress point's stresses, a contact's two forces, an element's
  r'), each small; a variable in no cone and without a quadratic but in an equality is a
  block of its own (a fluid point's pressure), unless it is in many equalities (a load
  factor's dense column: kept **free**); a variable in nothing is **dead** (zero);
* each block's **null space**: the directions that neither P nor any cone sees (the mean
  stress of a zero-dilation or Tresca point without compliance, a pressure). H is
  singular there: they are the "pressures", penalised and eliminated by
  :mod:`.newton` (their constant E_N E_N^T kept here);
* the constant dense pieces (P's blocks and square roots, each cone's rows on its block,
  E's rows on each block, E_N = E N on the null directions) and the scatter of the
  blocks' E_b H_b^+ E_b^T into the lower triangle of S, the displacements' matrix.
"""
import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

try:                                     # y += A x in place (scipy's own kernel)
    from scipy.sparse._sparsetools import csr_matvec as _csr_matvec
except ImportError:                      # pragma: no cover - a scipy without it
    _csr_matvec = None

#: a block's direction is null (no cone, no quadratic) when its eigenvalue of
#: P_b^2 + G_b^T G_b is below this, relative to the block's largest
NULL_TOL = 1e-12

#: the largest block (variables) the batched inversion takes; a problem whose cones or
#: quadratic join more variables is not of the step's structure (refused: NotStructured)
MAX_BLOCK = 48

#: a variable outside the blocks in more equalities than this is a dense column (free)
DENSE_COLUMN = 64

#: the most free variables kept beside the reduced matrix (each costs one solve a
#: factorisation and a row of a dense Schur complement)
MAX_FREE = 200


class NotStructured(ValueError):
    """The problem does not have the block structure the reduced Newton system needs."""


def cone_rows(cones):
    """(zero rows, {dim: (m, dim) rows of its cones}) of Clarabel cone objects (a
    non-negative cone of n rows is n cones of dimension one)."""
    zero, groups, start = [], {}, 0
    for cone in cones:
        kind = type(cone).__name__
        if kind not in ("ZeroConeT", "NonnegativeConeT", "SecondOrderConeT"):
            raise ValueError(f"the interior point takes zero, non-negative and second-order "
                             f"cones, not {kind}")
        dim = int(cone.dim)
        rows = np.arange(start, start + dim)
        if kind == "ZeroConeT":
            zero.append(rows)
        elif kind == "NonnegativeConeT":
            groups.setdefault(1, []).append(rows[:, None])
        else:
            groups.setdefault(dim, []).append(rows[None, :])
        start += dim
    zero = np.concatenate(zero) if zero else np.zeros(0, dtype=int)
    return zero, {d: np.concatenate(r) for d, r in sorted(groups.items())}


def by_component(m, d):
    """The rows of m cones of dimension d (cone k's at k d .. k d + d - 1) ordered by
    component: the first of every cone, then the second, ..."""
    return (np.arange(m)[None, :] * d + np.arange(d)[:, None]).ravel()


def component_major(u):
    """A group's (m, d) vector flattened by component (u.T.ravel(): a view of a Fortran-
    ordered array)."""
    return u.T.ravel()


def from_component_major(v, d):
    """The (m, d) group vector of a vector ordered by component (a Fortran-ordered view)."""
    return v.reshape(d, -1).T


def full_symmetric(P):
    """P with both triangles (CSR), given Clarabel's upper triangle or both."""
    P = sp.csr_matrix(P)
    return (P + sp.triu(P, 1).T).tocsr() if sp.tril(P, -1).nnz == 0 else P


def _membership(m, d):
    """The (m, m d) matrix summing each cone's d rows."""
    return sp.csr_matrix((np.ones(m * d), (np.repeat(np.arange(m), d), np.arange(m * d))),
                         shape=(m, m * d))


class Structure:
    """What the Newton system of one problem needs, computed once (module docstring)."""


    def __init__(self, P, A, cones):
        n = A.shape[1]
        A = sp.csr_matrix(A)
        self.zero, self.groups = cone_rows(cones)
        self.E = A[self.zero].tocsr()
        self.ET = self.E.T.tocsr()
        self.G = {d: A[rows.ravel()].tocsr() for d, rows in self.groups.items()}
        # G^T and N (below) are tall with few entries: CSC (the CSR's transpose, no copy)
        # skips their empty rows in a product (G_1^T: 0.17 to 0.04 ms at 8,192 elements)
        self.GT = {d: G.T for d, G in self.G.items()}
        # the same rows ordered by component (every cone's first row, then every second,
        # ...): the solver's order, where a group's vectors are Fortran-ordered (m, d)
        # arrays (:mod:`.cones`), and G_c dx reshaped to (d, m) is one without a copy
        self.Gc = {d: G[by_component(G.shape[0] // d, d)].tocsr() for d, G in self.G.items()}
        self.GcT = {d: G.T for d, G in self.Gc.items()}
        self.P = full_symmetric(P)
        links, self._incidence = abs(self.P), {}
        for d, rows in self.groups.items():               # variables in a common cone
            inc = (_membership(rows.shape[0], d) @ abs(self.G[d])).tocsr()
            inc.data[:] = 1.0
            self._incidence[d] = inc
            links = links + inc.T @ inc
        in_h = np.asarray(abs(links).sum(axis=0)).ravel() != 0
        rows_of = np.diff(self.E.tocsc().indptr)
        dense = ~in_h & (rows_of > DENSE_COLUMN)
        self.free = np.flatnonzero(dense)
        self.dead = np.flatnonzero(~in_h & (rows_of == 0))
        if self.free.size > MAX_FREE:
            raise NotStructured(f"{self.free.size} variables are in no cone, have no "
                                f"quadratic and each is in over {DENSE_COLUMN} equalities "
                                f"(at most {MAX_FREE})")
        _, label = connected_components(links.tocsr(), directed=False)
        label = np.where(in_h | ((rows_of > 0) & ~dense), label, -1)
        self._blocks(label, n)
        self._pieces()
        self._null_spaces()
        self._rotated()
        self._pattern()
        self._operators()

    def _blocks(self, label, n):
        """self.blocks {size: (m, size) variables}; self.where[j] = (size, block, local)."""
        order = np.argsort(label, kind="stable")
        order = order[label[order] >= 0]
        starts = np.flatnonzero(np.r_[True, np.diff(label[order]) != 0]) if order.size \
            else np.zeros(0, dtype=int)
        sizes = np.diff(np.r_[starts, order.size])
        if sizes.size and sizes.max() > MAX_BLOCK:
            raise NotStructured(f"a block of {sizes.max()} variables joined by the "
                                f"quadratic or a cone (at most {MAX_BLOCK})")
        self.blocks = {}
        self.where = np.full((n, 3), -1)
        for size in np.unique(sizes):
            first = starts[sizes == size]
            vars_ = order[first[:, None] + np.arange(size)]
            self.blocks[int(size)] = vars_
            self.where[vars_.ravel()] = np.c_[np.full(vars_.size, size),
                                              np.repeat(np.arange(len(first)), size),
                                              np.tile(np.arange(size), len(first))]

    def _pieces(self):
        """P's blocks and their square roots L (P_b = L^T L, no rows where every block of the
        size has P_b = 0); each cone's rows on its block
        (per cone dimension and block size: cones, blocks, dense rows, and the rows'
        place in the block's stacked M = [L; W^-1 G_b])."""
        self.P_blocks, self.P_roots, count = {}, {}, {}
        Pc = self.P.tocoo()
        size_r = self.where[Pc.row, 0]
        for size, vars_ in self.blocks.items():
            pb = np.zeros((vars_.shape[0], size, size))
            on = size_r == size
            np.add.at(pb, (self.where[Pc.row[on], 1], self.where[Pc.row[on], 2],
                           self.where[Pc.col[on], 2]), Pc.data[on])
            lam, U = np.linalg.eigh(pb)
            self.P_blocks[size] = pb
            root = np.sqrt(np.clip(lam, 0, None))[:, :, None] * np.swapaxes(U, 1, 2)
            # M's first rows are L; none where no block of the size has a quadratic
            # (a rigid-plastic stress point): M is then the cone rows alone
            self.P_roots[size] = root if root.any() else root[:, :0]
            count[size] = np.full(vars_.shape[0], self.P_roots[size].shape[1])
        self.cone_parts = []
        for d, rows in self.groups.items():
            inc = self._incidence[d]
            nonempty = np.diff(inc.indptr) > 0
            first_var = np.zeros(rows.shape[0], dtype=int)
            first_var[nonempty] = inc.indices[inc.indptr[:-1][nonempty]]
            size_k = np.where(nonempty, self.where[first_var, 0], -1)
            for size in self.blocks:
                cones_k = np.flatnonzero(size_k == size)
                if cones_k.size == 0:
                    continue
                blk = self.where[first_var[cones_k], 1]
                sub = self.G[d][(cones_k[:, None] * d + np.arange(d)).ravel()].tocoo()
                dense = np.zeros((cones_k.size, d, size))
                np.add.at(dense, (sub.row // d, sub.row % d, self.where[sub.col, 2]),
                          sub.data)
                order = np.argsort(blk, kind="stable")       # the k-th cone of its block
                sb = blk[order]
                first = np.r_[True, sb[1:] != sb[:-1]]
                rank = np.arange(sb.size) - np.maximum.accumulate(
                    np.where(first, np.arange(sb.size), 0))
                offset = np.empty(blk.size, dtype=int)
                offset[order] = count[size][sb] + rank * d
                np.add.at(count[size], blk, d)
                self.cone_parts.append((d, cones_k, size, blk, dense, offset))
        # at least square (zero rows below: R is then square for a block of fewer rows)
        self.M_rows = {size: max(int(c.max()), size) for size, c in count.items()}
        self.coned = {size for _, _, size, _, _, _ in self.cone_parts}

    def _null_spaces(self):
        """Each block's range and null directions (constant: W^-2 is positive definite),
        from the eigenvectors of P_b^2 + G_b^T G_b; the pressures' numbers."""
        gram = {size: np.einsum("mij,mjk->mik", p, p) for size, p in self.P_blocks.items()}
        for d, cones_k, size, blk, dense, offset in self.cone_parts:
            np.add.at(gram[size], blk, np.einsum("mri,mrj->mij", dense, dense))
        self.range_, self.null, self.pressure = {}, {}, {}
        n_p = 0
        for size, g in gram.items():
            lam, V = np.linalg.eigh(g)
            null = lam <= NULL_TOL * np.maximum(lam[:, -1:], 1e-300)
            null[lam[:, -1] <= 0] = True                  # nothing at all: all null
            self.range_[size] = V * ~null[:, None, :]
            self.null[size] = (V * null[:, None, :], null)
            index = np.full(null.shape, -1)
            index[null] = n_p + np.arange(int(null.sum()))
            n_p += int(null.sum())
            self.pressure[size] = index
        self.n_p = n_p

    def _rotated(self):
        """M V_r's constant parts, V_r the range's directions, null ones last (eigh sorts
        them first): ``MV_fixed`` {size: (m, rows, size)} with L V_r on top, and each cone
        part's G_b V_r (``cone_parts_V``: (d, cones, size, blocks, G_b V_r, offset, whole),
        whole when its cones are the group's and fill the same rows of every block, in
        order: a slice, not a gather). The iteration adds W^-1 G_b V_r.
        The null columns that every block of a size has (a rigid-plastic stress point's
        mean stress: one of its three) are left out of V_r: they are zero, and M V_r, its
        R and U = V_r R^-1 are then narrower (U: (m, size, rank), H^+ = U U^T the same)."""
        self.Vr, self.null_last = {}, {}
        for size in self.coned:
            null = self.null[size][1][:, ::-1]
            rank = max(size - int(null.sum(axis=1).min()), 1)    # the columns kept
            self.Vr[size] = np.ascontiguousarray(self.range_[size][:, :, ::-1][:, :, :rank])
            self.null_last[size] = np.ascontiguousarray(null[:, :rank])
        self.MV_fixed = {}
        for size in self.coned:
            MV = np.zeros((len(self.P_blocks[size]), self.M_rows[size],
                           self.Vr[size].shape[2]))
            roots = self.P_roots[size]
            MV[:, :roots.shape[1]] = roots @ self.Vr[size]
            self.MV_fixed[size] = MV
        self.cone_parts_V = []
        for d, cones_k, size, blk, dense, offset in self.cone_parts:
            m = len(self.P_blocks[size])
            whole = (cones_k.size == self.groups[d].shape[0] == m
                     and np.array_equal(cones_k, np.arange(m))
                     and np.array_equal(blk, np.arange(m)) and np.all(offset == offset[0]))
            self.cone_parts_V.append((d, cones_k, size, blk, dense @ self.Vr[size][blk],
                                      offset, whole))

    def _dense_rows(self, size):
        """E on each block of ``size``: dense (m, r, size) and its rows (m, r), -1 padded."""
        vars_ = self.blocks[size]
        m, nE = vars_.shape[0], self.E.shape[0]
        Ec = self.E.tocsc()[:, vars_.ravel()].tocoo()
        blk, local = np.divmod(Ec.col, size)
        key = blk.astype(np.int64) * nE + Ec.row
        uniq, slot = np.unique(key, return_inverse=True)
        ublk = uniq // nE
        first = np.searchsorted(ublk, np.arange(m))
        r = max(int(np.bincount(ublk, minlength=m).max()) if uniq.size else 0, 1)
        pos = np.arange(uniq.size) - first[ublk]
        rows = np.full((m, r), -1)
        rows[ublk, pos] = uniq % nE
        dense = np.zeros((m, r, size))
        np.add.at(dense, (blk, pos[slot], local), Ec.data)
        return dense, rows

    def _pattern(self):
        """The lower triangle of S, the slots of each block's E_b H_b^+ E_b^T in it, E_N
        (E on the null directions: displacements x pressures) and S's constant part
        (E_N E_N^T / delta, and the blocks that no cone touches: an element's r', a
        pressure alone, whose H^+ is constant)."""
        nE = self.E.shape[0]
        self.E_parts, keys, masks, self.S_groups = {}, [], {}, {}
        self.E_grouped = {}
        en = [], [], []
        for size in self.blocks:
            dense, rows = self._dense_rows(size)
            self.E_parts[size] = (dense, rows)
            self.S_groups[size] = _same_rows(rows)
            on = rows                                 # the rows of each scattered matrix
            if self.S_groups[size] is not None:       # one E_g H_g^+ E_g^T per group
                order, group = self.S_groups[size]
                on = rows[order[::group]]
                m, r, s = dense.shape                 # E_g = [E_1 .. E_k], side by side
                self.E_grouped[size] = np.ascontiguousarray(
                    dense[order].reshape(m // group, group, r, s).transpose(0, 2, 1, 3)
                    .reshape(m // group, r, group * s))
            i, k = on[:, :, None], on[:, None, :]
            ok = np.broadcast_to((i >= 0) & (k >= 0) & (i >= k),
                                 (on.shape[0], on.shape[1], on.shape[1]))
            masks[size] = ok
            # keyed by (column, row): S's lower triangle in compressed-column order,
            # the order CHOLMOD takes its values in
            keys.append(np.broadcast_to(k, ok.shape)[ok].astype(np.int64) * nE
                        + np.broadcast_to(i, ok.shape)[ok])
            Vn, null = self.null[size]
            if null.any():
                EN = dense @ Vn
                p = self.pressure[size]
                ok_n = (rows[:, :, None] >= 0) & (p[:, None, :] >= 0)
                en[0].append(np.broadcast_to(rows[:, :, None], ok_n.shape)[ok_n])
                en[1].append(np.broadcast_to(p[:, None, :], ok_n.shape)[ok_n])
                en[2].append(EN[ok_n])
        en_rows, en_cols = (np.concatenate(v) if v else np.zeros(0, int) for v in en[:2])
        en_vals = np.concatenate(en[2]) if en[2] else np.zeros(0)
        self.EN = sp.csr_matrix((en_vals, (en_rows, en_cols)), shape=(nE, self.n_p))
        diag = np.arange(nE, dtype=np.int64) * (nE + 1)
        uniq, inverse = np.unique(np.concatenate(keys + [diag]), return_inverse=True)
        self.S_rows, self.S_cols, self.S_nnz = uniq % nE, uniq // nE, uniq.size
        # each block matrix's lower-triangle entries summed into S's values: one sparse
        # matrix a size (S's slots x the dense entries), applied by one matvec
        start, self.S_sum = 0, {}
        for size, key in zip(self.blocks, keys):
            mask = masks[size]
            self.S_sum[size] = sp.csr_matrix(
                (np.ones(key.size), (inverse[start:start + key.size], np.flatnonzero(mask))),
                shape=(uniq.size, mask.size))
            start += key.size
        self.diag_slots = inverse[-nE:]
        self.S_fixed, self.S_pressures = np.zeros(self.S_nnz), np.zeros(self.S_nnz)
        self.penalised = None        # (1 / delta, S_fixed + S_pressures / delta): Newton's
        if self.n_p:                     # the pressures' E_N E_N^T (times 1 / delta)
            C = sp.tril(self.EN @ self.EN.T).tocoo()
            key = C.col.astype(np.int64) * nE + C.row
            slot = np.searchsorted(uniq, key)    # within the blocks' pattern: each
            np.add.at(self.S_pressures, slot, C.data)   # pressure's rows are its block's
        self.Hinv_fixed = {}
        for size, p in self.P_blocks.items():
            if size in self.coned:
                continue
            lam, U = np.linalg.eigh(p)
            keep = lam > NULL_TOL * np.maximum(lam[:, -1:], 1e-300)
            root = U * np.where(keep, 1.0 / np.sqrt(np.where(keep, lam, 1.0)), 0.0)[:, None, :]
            self.Hinv_fixed[size] = root @ np.swapaxes(root, 1, 2)
            self.scatter(size, root, self.S_fixed)

    def _operators(self):
        """N^T as a sparse matrix (pressures x variables), the order that lays the
        blocks' dense H^+ into one block-diagonal CSR matrix (one matvec an application),
        and for each coned size its variables (block by block), E^T's rows and each G_c's
        columns on them (``coned_parts``: the predictor's dx, :meth:`.newton.Newton._predict`)."""
        self.coned_parts = {}
        for size in self.coned:
            flat = self.blocks[size].ravel()
            self.coned_parts[size] = (flat, self.ET[flat], {d: G[:, flat].tocsr()
                                                            for d, G in self.Gc.items()})
        rows_, cols_, vals_ = [], [], []
        for size, vars_ in self.blocks.items():
            Vn, null = self.null[size]
            p = self.pressure[size]
            b, j = np.nonzero(p >= 0)
            rows_.append(np.repeat(p[b, j], size))
            cols_.append(vars_[b].ravel())
            vals_.append(Vn[b, :, j].ravel())
        n = self.where.shape[0]
        self.NT = sp.csr_matrix((np.concatenate(vals_) if vals_ else np.zeros(0),
                                 (np.concatenate(rows_) if rows_ else np.zeros(0, int),
                                  np.concatenate(cols_) if cols_ else np.zeros(0, int))),
                                shape=(self.n_p, n))
        self.N = self.NT.T
        self.blocked = np.ones(n, bool)             # the variables of the blocks
        self.blocked[self.free] = False
        self.blocked[self.dead] = False
        r_, c_, order, start = [], [], [], 0
        for size, vars_ in self.blocks.items():
            m = vars_.shape[0]
            r_.append(np.repeat(vars_, size, axis=1).ravel())        # row var, each col
            c_.append(np.tile(vars_, (1, size)).ravel())
            order.append(start + np.arange(m * size * size))
            start += m * size * size
        r_ = np.concatenate(r_) if r_ else np.zeros(0, int)
        c_ = np.concatenate(c_) if c_ else np.zeros(0, int)
        perm = np.lexsort((c_, r_))                 # CSR order: by row, then column
        self.H_indices = c_[perm].astype(np.int32)
        self.H_indptr = np.r_[0, np.cumsum(np.bincount(r_, minlength=n))].astype(np.int32)
        place = np.empty_like(perm)                 # each block entry's place in CSR order
        place[perm] = np.arange(perm.size)
        self.H_places, self.H_fixed = {}, np.zeros(perm.size)
        for size, first in zip(self.blocks, order):
            self.H_places[size] = place[first]
            if size in self.Hinv_fixed:             # the blocks no cone touches: constant
                self.H_fixed[self.H_places[size]] = self.Hinv_fixed[size].ravel()


    def scatter(self, size, U, out):
        """Add the blocks' E_b H_b^+ E_b^T of ``size`` into S's values ``out``, H_b^+ =
        U_b U_b^T; blocks on the same rows of E (an element's stress points) summed first,
        as [F_1 .. F_k] [F_1 .. F_k]^T: a third of the entries to scatter. F and F F^T are
        written into buffers kept for the next iteration (a fresh 10 MB array an
        iteration costs its page faults), and the sum goes into ``out`` in place."""
        if self.S_groups[size] is None:
            F = np.matmul(self.E_parts[size][0], U, out=self._buffer(("F", size), (
                U.shape[0], self.E_parts[size][0].shape[1], U.shape[2])))
        else:                                 # F_g = [E_1 U_1 .. E_k U_k], side by side
            order, k = self.S_groups[size]
            Eg = self.E_grouped[size]
            m, s, r = U.shape                 # r: U's columns (the rank kept)
            Uo = U[order].reshape(m // k, k, s, r)
            F = self._buffer(("F", size), (m // k, Eg.shape[1], k * r))
            for j in range(k):
                np.matmul(Eg[:, :, j * s:(j + 1) * s], Uo[:, j], out=F[:, :, j * r:(j + 1) * r])
        FF = np.matmul(F, np.swapaxes(F, 1, 2),
                       out=self._buffer(("FF", size), (F.shape[0], F.shape[1], F.shape[1])))
        accumulate(self.S_sum[size], FF.ravel(), out)

    def _buffer(self, key, shape):
        """A work array of ``shape`` kept under ``key`` (its values are not kept)."""
        buffers = self.__dict__.setdefault("_buffers", {})
        if key not in buffers or buffers[key].shape != shape:
            buffers[key] = np.empty(shape)
        return buffers[key]

    def block_matrix(self, mats):
        """The block-diagonal sparse matrix of H^+: the constant blocks
        (:attr:`Hinv_fixed`) and the coned blocks' dense ``mats`` {size: (m, s, s)}. Its
        values are one array kept here, the constant blocks written once: the matrix of
        the previous call is overwritten (one Newton system is in use at a time)."""
        data = self.__dict__.get("_H_data")
        if data is None:
            data = self._H_data = self.H_fixed.copy()
        for size, mat in mats.items():
            data[self.H_places[size]] = mat.ravel()
        n = self.where.shape[0]
        return sp.csr_matrix((data, self.H_indices, self.H_indptr), shape=(n, n))


def accumulate(A, x, y):
    """y += A x for a CSR matrix A, in place (scipy's kernel, which its ``A @ x`` calls
    on a fresh zero vector); ``A @ x`` added where that kernel is not there."""
    if _csr_matvec is not None and A.format == "csr" and y.dtype == np.float64 \
            and x.dtype == np.float64 and y.flags.c_contiguous:
        _csr_matvec(A.shape[0], A.shape[1], A.indptr, A.indices, A.data, x, y)
    else:
        y += A @ x


def _same_rows(rows):
    """(order, k) where the blocks fall into groups of k > 1 on the same rows of E (the
    stress points of one element), ``order`` listing each group's blocks side by side;
    None where they do not (groups of different sizes, or every block alone)."""
    m = rows.shape[0]
    if m < 2:
        return None
    order = np.lexsort(rows.T[::-1])
    ordered = rows[order]
    new = np.r_[True, np.any(ordered[1:] != ordered[:-1], axis=1)]
    counts = np.diff(np.r_[np.flatnonzero(new), m])
    k = int(counts[0])
    if k < 2 or np.any(counts != k):
        return None
    return order, k
