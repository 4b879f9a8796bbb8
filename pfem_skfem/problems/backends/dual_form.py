"""The dual (displacement) form of the direct assembly: the Lagrangian dual of the standard
form, handed to the same engine.

With x = (x_r, x_0), x_r the columns where P is nonzero (r', the stresses of an elastic
step, a Bingham rate stress) and x_0 the rest (the stresses of a rigid-plastic step, the
contact forces), x_r eliminated by P_r x_r + c_r + A_r^T z = 0:

    minimise  1/2 z^T A_r P_r^-1 A_r^T z + (A_r P_r^-1 c_r + b)^T z
    subject to  A_0^T z = -c_0,  z_K in K  (z free on the zero-cone rows),

the displacement form of the step: its variables are the displacement increment (z on the
equilibrium rows, -du_F in the scale of u) and the multipliers of the cones; P_r^-1 is
block-diagonal (each element's inverse-mass block inverted, the compliance blocks, the
viscous diagonal). The step's x, z and s are recovered from the dual's solution
(tests/test_clarabel_direct.py). Exponential cones are not self-dual: a step with them is
stated in the primal form.
"""
import time
from types import SimpleNamespace

import clarabel
import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from .clarabel import ClarabelEngine

#: State the dual's objective with its constant 1/2 c_r^T P_r^-1 c_r (a variable t with
#: cost 1 and the row t = constant), so that the engine's relative gap is measured on the
#: primal's objective value: without it the dual's objective lacks that constant (the
#: inertia term's, or the work of the prescribed increments), which can exceed the step's
#: objective by orders of magnitude, and the relative stop is that much looser. The
#: constant goes in b, not in c, where it upsets Clarabel's scaling of the cost (book,
#: performance appendix, "The dual form").
DUAL_CONSTANT = True

#: A block of P whose least eigenvalue is below this fraction of its largest is singular
#: for :func:`solve_dual` (which then refuses the problem).
BLOCK_RCOND = 1e-12

#: a status of the dual read as the primal's: an infeasible dual is an unbounded primal
_DUAL_STATUS = {"PrimalInfeasible": "DualInfeasible", "DualInfeasible": "PrimalInfeasible",
                "AlmostPrimalInfeasible": "AlmostDualInfeasible",
                "AlmostDualInfeasible": "AlmostPrimalInfeasible"}
_SELF_DUAL = ("ZeroConeT", "NonnegativeConeT", "SecondOrderConeT")


def inverse_blocks(P, rcond=BLOCK_RCOND):
    """(r, P_r^-1, P): the columns r where the symmetric P (upper triangle or full, CSC) has
    an entry and the inverse of P[r, r] (CSC, in the order of r), which must be
    block-diagonal with positive-definite blocks.

    The blocks are the connected components of P's pattern (a 12 x 12 inverse-mass block
    per element, a compliance block per stress point, one entry per viscous variable; a
    point's stresses and viscous stress one 6 x 6 block where the compliance couples them),
    inverted together per block size (P: the full symmetric matrix, stored zeros dropped);
    a block whose least eigenvalue is below ``rcond`` times its largest raises ValueError.
    """
    U = sp.triu(P, format="csc")
    U.eliminate_zeros()
    full = (U + sp.triu(U, 1).T).tocsr()
    r = np.flatnonzero(np.diff(full.indptr))
    Pr = full[r][:, r].tocoo()
    _, label = connected_components(Pr, directed=False)
    size = np.bincount(label)
    order = np.argsort(label, kind="stable")                # the columns block by block
    local = np.empty(r.size, dtype=int)                     # each column's place in its block
    local[order] = np.arange(r.size) - np.repeat(np.cumsum(size) - size, size)
    rows, cols, vals = [], [], []
    for k in np.unique(size):
        blocks_k = np.flatnonzero(size == k)
        slot = np.full(size.size, -1)
        slot[blocks_k] = np.arange(blocks_k.size)
        dense = np.zeros((blocks_k.size, k, k))
        mine = slot[label[Pr.row]] >= 0
        dense[slot[label[Pr.row[mine]]], local[Pr.row[mine]], local[Pr.col[mine]]] = \
            Pr.data[mine]
        eig = np.linalg.eigvalsh(dense)
        if not np.all(eig[:, 0] > rcond * np.abs(eig).max(axis=1)):
            raise ValueError("solve_dual: a block of P is singular or indefinite")
        inv = np.linalg.inv(dense)
        inv = 0.5 * (inv + inv.transpose(0, 2, 1))
        index = np.empty((blocks_k.size, k), dtype=int)     # columns (in r) of each block
        members = np.isin(label[order], blocks_k)
        index[:] = order[members].reshape(blocks_k.size, k)
        rows.append(np.repeat(index, k, axis=1).ravel())
        cols.append(np.tile(index, (1, k)).ravel())
        vals.append(inv.ravel())
    Pr_inv = sp.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                           shape=(r.size, r.size))
    return r, Pr_inv, full


def solve_dual(P, c, A, b, cones, settings, engine=None):
    """Solve  min 1/2 x^T P x + c^T x  s.t.  A x + s = b, s in K  through its Lagrangian dual.

    With x = (x_r, x_0), x_r the columns where P is nonzero (P_r block-diagonal, positive
    definite: :func:`inverse_blocks`), the optimality condition P_r x_r + c_r + A_r^T z = 0
    eliminates x_r and Clarabel solves the dual in its own form (variable z, minimised)

    .. math::
        \\min_z\\; \\tfrac12 z^T A_r P_r^{-1} A_r^T z + (A_r P_r^{-1} c_r + b)^T z
        \\quad\\text{s.t.}\\quad A_0^T z = -c_0, \\quad z_K \\in K^* = K,

    z free on the rows of the primal's zero cones (its rows: the zero cone A_0^T z + c_0
    = 0, then -z_K + s_d = 0, s_d in K, cone by cone; with :data:`DUAL_CONSTANT` the
    constant 1/2 c_r^T P_r^-1 c_r as + t with a row t = that constant in the zero cone).
    The primal's solution is recovered from the dual's (x, z): z = x_dual; x_0 = -z_dual
    on its equality rows; s = z_dual on the cone rows (0 on the zero-cone rows);
    x_r = -P_r^-1 (c_r + A_r^T z).

    Parameters
    ----------
    P : (n, n) CSC, the upper triangle (as Clarabel takes it). c : (n,).
    A : (m, n) sparse. b : (m,). cones : Clarabel cones of the rows of A, zero,
        nonnegative and second-order cones only (self-dual); an exponential or power
        cone raises ValueError, as does a singular block of P.
    settings : the engine's settings (Clarabel's: clarabel.DefaultSettings), used for the
        dual as given.
    engine : the engine (:data:`~pfem_skfem.problems.backends.ENGINES`; Clarabel by default).

    Returns
    -------
    SimpleNamespace with the primal's x, z, s, status (Clarabel's name; the dual's
    PrimalInfeasible is the primal's DualInfeasible and vice versa), iterations, obj_val
    (1/2 x^T P x + c^T x of the recovered x), setup_time (seconds stating the dual) and
    measures (the solver's, of the dual).
    """
    t0 = time.perf_counter()
    kinds = [type(cone).__name__ for cone in cones]
    if any(kind not in _SELF_DUAL for kind in kinds):
        raise ValueError(f"solve_dual: cones {sorted(set(kinds) - set(_SELF_DUAL))} are not "
                         "self-dual; state the primal")
    dims = np.array([cone.dim for cone in cones], dtype=int)
    zero = np.repeat([kind == "ZeroConeT" for kind in kinds], dims)
    A = sp.csc_matrix(A)
    c, b = np.asarray(c, dtype=float), np.asarray(b, dtype=float)
    m, n = A.shape
    r, Pr_inv, P_full = inverse_blocks(sp.csc_matrix(P))
    x0 = np.setdiff1d(np.arange(n), r)
    Ar, A0 = A[:, r], A[:, x0]
    cone_rows = np.flatnonzero(~zero)
    m_K = cone_rows.size
    P_d = sp.triu(Ar @ Pr_inv @ Ar.T, format="csc")                  # the dual's quadratic
    c_d = Ar @ (Pr_inv @ c[r]) + b
    select = sp.csr_matrix((-np.ones(m_K), (np.arange(m_K), cone_rows)), shape=(m_K, m))
    A_d = sp.vstack([A0.T, select], format="csc")        # A_0^T z = -c_0; -z_K + s_d = 0
    b_d = np.concatenate([-c[x0], np.zeros(m_K)])
    n_eq = x0.size
    if DUAL_CONSTANT:              # + t, t = 1/2 c_r^T P_r^-1 c_r: the objective's constant
        P_d = sp.block_diag([P_d, sp.csc_matrix((1, 1))], format="csc")
        c_d = np.append(c_d, 1.0)
        A_d = sp.bmat([[A_d[:n_eq], None], [None, sp.csc_matrix(np.ones((1, 1)))],
                       [A_d[n_eq:], None]], format="csc")
        b_d = np.concatenate([b_d[:n_eq], [0.5 * c[r] @ (Pr_inv @ c[r])], b_d[n_eq:]])
        n_eq += 1
    cones_d = ([clarabel.ZeroConeT(n_eq)] if n_eq else []) + \
        [cone for cone, kind in zip(cones, kinds) if kind != "ZeroConeT"]
    setup = time.perf_counter() - t0
    sol = (engine or ClarabelEngine()).solve(P_d, c_d, A_d, b_d, cones_d, settings)
    y, w = sol.x[:m], sol.z
    x = np.empty(n)
    x[x0] = -w[:x0.size]
    x[r] = -(Pr_inv @ (c[r] + Ar.T @ y))
    s = np.zeros(m)
    s[cone_rows] = w[n_eq:]
    return SimpleNamespace(x=x, z=y, s=s, status=_DUAL_STATUS.get(sol.status, sol.status),
                           iterations=sol.iterations,
                           obj_val=float(0.5 * x @ (P_full @ x) + c @ x),
                           setup_time=setup, measures=sol.measures)


