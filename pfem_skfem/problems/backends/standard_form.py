"""The standard form the direct assembly writes the step in, with its variables named.

    minimise  1/2 x^T P x + c^T x   subject to  A x + s = b,  s in K

(Clarabel's; QOCO and the dual form read the same data). A :class:`Layout` names the
blocks of x (``sigma``, ``r`` and each term's: ``p``, ``q``, ``rate_stress``, ...) in the
order they are declared; a :class:`StandardForm` collects the blocks of P, c, the columns of
the internal forces K x (B^T sigma + A^T r' + each term's) and the cone rows, which it
states in :data:`SECTIONS` order: equilibrium (the zero cone on the free dofs), the terms'
equalities, the terms' rows before the yield cones, the yield cones, the terms' rows after
them. The equalities (equilibrium and the terms') are one zero cone.

Also here: the rows of the yield cones (:func:`yield_block`, read off the criterion's
``cone_vector``) and the cleaning of the data (:func:`drop_roundoff`).
"""
import clarabel
import numpy as np
import scipy.sparse as sp

from ...materials.criteria import zero_radius

#: the order of the rows (a term names the section of each of its row blocks)
SECTIONS = ("equilibrium", "equality", "before_yield", "yield", "after_yield")

#: An entry of P below this fraction of sqrt(|P_ii P_jj|) is round-off of the assembly
#: (the real couplings are >= 0.1 of it). Relative, so a scaling of the data (the density
#: of a c = 0 run) drops the same entries.
P_ROUNDOFF = 1e-12


class Layout:
    """The named blocks of x in the order declared: ``layout["p"]`` is a slice of x."""

    def __init__(self):
        self._blocks, self.size = {}, 0

    def add(self, name, size):
        if name in self._blocks:
            raise ValueError(f"the layout already has a block {name!r}")
        self._blocks[name] = slice(self.size, self.size + int(size))
        self.size += int(size)
        return self._blocks[name]

    def __getitem__(self, name):
        return self._blocks[name]

    def __contains__(self, name):
        return name in self._blocks

    def __iter__(self):
        return iter(self._blocks)


def _cones(kind, rows):
    """Clarabel's cones of a row block: 'zero', 'nonneg', ('soc', m, count), ('exp', 3,
    count), or a list of Clarabel cones as they are."""
    if kind == "zero":
        return [clarabel.ZeroConeT(rows)]
    if kind == "nonneg":
        return [clarabel.NonnegativeConeT(rows)]
    if isinstance(kind, tuple) and kind[0] == "soc":
        return [clarabel.SecondOrderConeT(kind[1])] * kind[2]
    if isinstance(kind, tuple) and kind[0] == "exp":
        return [clarabel.ExponentialConeT()] * kind[2]
    return list(kind)


class StandardForm:
    """The direct assembly of one scaled step: its layout, P's blocks, c, K's columns and
    the cone rows by section (:data:`SECTIONS`); :meth:`assemble` states them."""

    def __init__(self, step, terms):
        self.step = step
        self.layout = Layout()
        self.layout.add("sigma", 4 * step.n)           # sigma / stress, point-major
        self.layout.add("r", step.n_r)                 # r' / r_ref, element-major
        for term in terms:
            term.declare(self)
        self.n_x = self.layout.size
        self.c = np.zeros(self.n_x)
        self._P, self._coupled, self._columns, self._K = {}, {}, [], None
        self._rows = {section: [] for section in SECTIONS}
        self.row_slices = {}

    def quadratic(self, name, block):
        """The block of P on the layout block ``name``, added to what it holds."""
        self._P[name] = self._P[name] + block if name in self._P else block

    def coupling(self, name, other, block):
        """The block of P on the rows of ``name`` and the columns of ``other`` (and its
        transpose): P is block-diagonal without one (the compliance of an elastic step with
        a rate stress couples the two)."""
        self._coupled[(name, other)] = block

    def columns(self, block):
        """The next columns of K (n_u, ...): the internal forces of the next variables."""
        self._columns.append(block)
        self._K = None

    def internal(self):
        """K (n_u, n_x): x's internal forces, B^T sigma + A^T r' + the terms'."""
        if self._K is None:
            self._K = sp.hstack(self._columns, format="csr")
        return self._K

    def rows(self, section, A, b, kind):
        """Rows A x + s = b, s in the cones ``kind`` (see :func:`_cones`), in ``section``."""
        self._rows[section].append((A, np.asarray(b, dtype=float), _cones(kind, A.shape[0])))

    def assemble(self):
        """(P (upper triangle, CSC), c, A (CSC), b, cones): the rows in section order, the
        terms' equalities joined to equilibrium's zero cone; ``row_slices`` then holds each
        section's rows."""
        names = list(self.layout)
        blocks = [self._P.get(name, sp.csr_matrix((s.stop - s.start,) * 2))
                  for name, s in ((n, self.layout[n]) for n in names)]
        if self._coupled:
            grid = [[b if i == j else None for j in range(len(names))]
                    for i, b in enumerate(blocks)]
            for (name, other), block in self._coupled.items():
                i, j = names.index(name), names.index(other)
                grid[i][j], grid[j][i] = block, block.T
            P = sp.triu(sp.bmat(grid, format="csc"), format="csc")
        else:
            P = sp.triu(sp.block_diag(blocks, format="csc"), format="csc")
        As, bs, cones, start = [], [], [], 0
        for section in SECTIONS:
            for A, b, kinds in self._rows[section]:
                As.append(A)
                bs.append(b)
                for cone in kinds:
                    if (section == "equality" and type(cone).__name__ == "ZeroConeT"
                            and cones and type(cones[-1]).__name__ == "ZeroConeT"):
                        cones[-1] = clarabel.ZeroConeT(cones[-1].dim + cone.dim)
                    else:
                        cones.append(cone)
            stop = start + sum(A.shape[0] for A, _, _ in self._rows[section])
            self.row_slices[section] = slice(start, stop)
            start = stop
        return P, self.c, sp.vstack(As, format="csc"), np.concatenate(bs), cones


def drop_roundoff(P, rel=P_ROUNDOFF):
    """P (CSC) without its stored zeros and its off-diagonal entries below ``rel``
    sqrt(|P_ii P_jj|); the diagonal is kept. A positive semidefinite P has no nonzero
    off-diagonal entry in a row whose diagonal is zero, so none is dropped there that
    is not round-off."""
    P = sp.coo_matrix(P)
    d = np.abs(P.diagonal())
    keep = (P.data != 0) & ((P.row == P.col)
                            | (np.abs(P.data) >= rel * np.sqrt(d[P.row] * d[P.col])))
    return sp.csc_matrix((P.data[keep], (P.row[keep], P.col[keep])), shape=P.shape)


def cone_matrices(criterion, n):
    """The affine cone map of a yield criterion at n points: D (K n, m, 4), d (K n, m).

    rho_j = D_j sigma_j + d_j with rho_1 >= ||rho_2..m|| (the criterion's
    ``cone_vector``, evaluated at zero and at the four unit stresses); K is the
    criterion's ``n_cones`` (1 for the plane-strain cones), cone j acting on the
    stresses of point j mod n.
    """
    zero = np.zeros(n)
    size = n * getattr(criterion, "n_cones", 1)    # cones per point (declared where not 1)

    def rho(*s):
        t, X = criterion.cone_vector(*s)
        return np.stack([np.broadcast_to(np.asarray(v, dtype=float), (size,))
                         for v in [t, *X]], axis=1)

    d = rho(zero, zero, zero, zero)
    columns = []
    for k in range(4):
        unit = [zero] * 4
        unit[k] = np.ones(n)
        columns.append(rho(*unit) - d)
    return np.stack(columns, axis=2), d


def yield_block(criterion, n):
    """Rows of A (over the 4n stresses) and b for the yield cones, their Clarabel cones and a
    function reading each point's multiplier off their duals.

    One SOC(m) per cone (point-major x); where a radius is zero (a fluid's point:
    :func:`~pfem_skfem.materials.criteria.zero_radius`) the cone has no interior and is
    stated as the zero cone of its rows PRESSURE_ROWS sigma_j = 0 (after the SOCs), the
    multiplier the norm of their duals (as the cvxpy statement,
    :func:`~pfem_skfem.materials.criteria.yield_constraints`).
    """
    zero = zero_radius(criterion)
    live = np.arange(n) if zero is None else np.flatnonzero(~zero)
    if live.size:
        A, b, m = _cone_rows(criterion if zero is None else criterion.at(live), live, n)
    else:                                     # water alone: no cone has an interior
        A, b, m = sp.csr_matrix((0, 4 * n)), np.zeros(0), 1
    n_cones = A.shape[0] // m
    cones = [clarabel.SecondOrderConeT(m)] * n_cones
    if zero is None:
        return A, b, cones, lambda z: z[:n_cones * m:m]
    dead = np.flatnonzero(zero)
    R = criterion.PRESSURE_ROWS
    k = len(R)
    rows = (np.arange(dead.size)[:, None, None] * k + np.arange(k)[None, :, None]).repeat(4, 2)
    cols = (dead[:, None, None] * 4 + np.arange(4)[None, None, :]).repeat(k, axis=1)
    vals = np.broadcast_to(R, (dead.size, k, 4))
    A0 = sp.csr_matrix((vals.ravel(), (rows.ravel(), cols.ravel())), shape=(dead.size * k, 4 * n))
    cones.append(clarabel.ZeroConeT(dead.size * k))

    def multipliers(z):
        out = np.zeros(n)
        out[live] = z[:n_cones * m:m]
        out[dead] = np.linalg.norm(z[n_cones * m:n_cones * m + dead.size * k].reshape(-1, k),
                                   axis=1)
        return out
    return sp.vstack([A, A0], format="csr"), np.concatenate([b, np.zeros(dead.size * k)]), \
        cones, multipliers


def _cone_rows(criterion, points, n):
    """Rows of A and b of one SOC(m) per cone of ``criterion`` at the stress points
    ``points`` (of n), and m."""
    D, d = cone_matrices(criterion, points.size)
    n_cones, m = D.shape[0], D.shape[1]
    point = points[np.arange(n_cones) % points.size]
    rows = (np.arange(n_cones)[:, None, None] * m
            + np.arange(m)[None, :, None]).repeat(4, axis=2)
    cols = (point[:, None, None] * 4 + np.arange(4)[None, None, :]).repeat(m, axis=1)
    A = sp.csr_matrix((-D.ravel(), (rows.ravel(), cols.ravel())),
                      shape=(n_cones * m, 4 * n))
    return A, d.ravel(), m
