"""The dynamic step (4.23) with contact (5.12) handed to Clarabel directly.

:func:`~pfem_skfem.problems.dynamic.dynamic_increment` states the step in cvxpy,
the readable reference. cvxpy then spends a noticeable part of a PFEM step
compiling it (measured in ``benchmarks/pfem_step.py``), so this module writes the
same scaled problem in Clarabel's standard form

    minimise  1/2 x^T P x + c^T x   subject to  A x + s = b,  s in K

with x = (sigma / stress, r' / r_ref, p, q) and K = {0}^(free dofs [+ smooth
contacts]) x R+^(contacts) x SOC(m)^(stress points) x R+^(2 x rough contacts):

* P = blockdiag(kappa_C C^, kappa D^, 0, 0) and c the linear terms of the objective
  (the sign flipped: Clarabel minimises);
* the zero cone is equilibrium B_F^T sigma + A_F^T r' - G_F (p, q) = f'_F;
* each yield cone rho_j = D_j sigma_j + d_j (the criterion's ``cone_vector``, affine,
  read off numerically) is s = b - A x with A = -D_j, b = d_j; a criterion with
  ``n_cones`` cones per point (cone-major) gives n_cones x n_points cones; a point of
  radius zero (a fluid's: the cone has no interior) is the zero cone of its criterion's
  ``PRESSURE_ROWS``, after the SOCs;
* |q_j| <= mu_j p_j is the pair mu_j p_j - q_j >= 0, mu_j p_j + q_j >= 0 (a friction
  bound k_j: k_j -+ q_j >= 0), as cvxpy writes an absolute value.
* a rate stress (``viscous`` of ``dynamic_increment``) appends (a_j, b_j) per point to x
  (with ``hoop``, (a_j, b_j, c_j)), sigma_j + E_j (a_j, b_j[, c_j]) in equilibrium
  (:func:`viscous_stress_map`), and either a diagonal block of P (the Bingham term) or
  s_j, t_j per point with one SOC(3) (SOC(4)) and one exponential cone each (the mu(I)
  dissipation), after all other rows.

Clarabel's dual z of the equality rows has the sign of cvxpy's dual of the same
equality, so the displacement increment is du_F = -z_eq x displacement scale (checked
against the cvxpy statement, tests/test_clarabel_direct.py). The yield multipliers are
the first component of each cone's dual.

With ``FORM = "dual"`` (or ``form="dual"``) Clarabel is handed the Lagrangian dual of
that statement of (4.23)+(5.12) instead (:func:`solve_dual`): x split into x_r (the
columns where P is nonzero: r', the stresses of an elastic step, a Bingham rate stress)
and x_0 (the rest: the stresses of a rigid-plastic step, the contact forces), x_r
eliminated by
P_r x_r + c_r + A_r^T z = 0,

    minimise  1/2 z^T A_r P_r^-1 A_r^T z + (A_r P_r^-1 c_r + b)^T z
    subject to  A_0^T z = -c_0,  z_K in K  (z free on the zero-cone rows),

the displacement form of the step: its variables are the displacement increment (z on
the equilibrium rows, -du_F in the scale of u) and the multipliers of the cones; P_r^-1
is block-diagonal (each element's inverse-mass block inverted, the compliance blocks,
the viscous diagonal), and the objective carries its constant 1/2 c_r^T P_r^-1 c_r (a
variable fixed at it) so that Clarabel's relative gap is that of the step's objective. The
step's x, z and s are recovered from the dual's solution and read as above
(tests/test_clarabel_direct.py). The exponential cones of the mu(I) rate term are not
self-dual: a step with them is stated in the primal form whatever ``FORM`` says.
"""
import time
from types import SimpleNamespace

import clarabel
import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from ..materials.criteria import zero_radius
from .conic import SolveInfo, check_status
from .direct_engines import ENGINES

#: Clarabel settings of the direct assembly (over Clarabel's defaults; a caller's
#: ``settings`` override them): the package's (qdldl). Iterative refinement, the
#: regularisations and the step fraction stay Clarabel's: none makes the solve faster
#: without moving the figures (benchmarks/iteration_cost.py, book/performance.md).
#: Another engine (QOCO) takes its own defaults and the caller's ``settings`` only.
SETTINGS = dict(ENGINES["clarabel"].defaults)

#: Clean the data before the call: drop A's stored zeros (the yield block's zero entries
#: of D, ~15 % of A) and P's round-off (:func:`drop_roundoff`); the same problem, a
#: factor with 0.91x the entries. Measured (issue 19; benchmarks/iteration_cost.py,
#: book/performance.md): at 2,048 elements 27.5 iterations instead of 30.5, every solve 'Solved'
#: (1 of 4 before), 0.83x the solve time; the quick a = 1 column's figures move within
#: the round-off spread of six density-scaled reruns (benchmarks/solver_tolerances.py).
#: Turning off Clarabel's iterative refinement as well (0.60x) moves the height at rest
#: beyond that spread: refinement stays on (Clarabel's default).
CLEAN_DATA = True

#: After a 'NumericalError' or an 'InsufficientProgress' of the primal form (the statuses
#: of :data:`RETRY_ON`), the step is solved once more with these settings: Clarabel's
#: equilibration off. Measured: the clay-block-and-water scene's step 6 (two free water
#: particles at a 30-degree wedge tip) ends 'NumericalError' as shipped and solves in 20
#: iterations without equilibration (as in the dual form, or with the data uncleaned);
#: without equilibration du is also the more accurate (issue 40,
#: benchmarks/equilibration.py). The block into the tank at the quick size with dt = 0.015
#: s stopped at its step 251 on 'InsufficientProgress' after 11 iterations (residuals
#: 1.4e-7, 2.5e-7, relative gap 3.6e-4); without equilibration it ends 'Solved' in 19
#: (gap 5e-9), as did its four 'NumericalError' steps before it (16 to 20 iterations). A
#: step that ends otherwise ('AlmostSolved' included: :func:`~.conic.check_status`'s rule)
#: is not touched.
RETRY = dict(equilibrate_enable=False)
RETRY_ON = ("NumericalError", "InsufficientProgress")

#: The form handed to Clarabel: "primal" (the statement of the module docstring) or
#: "dual" (its Lagrangian dual, the displacement form, :func:`solve_dual`); a step with
#: exponential cones (the implicit mu(I) term) is stated in the primal form either way.
#: ``solve_dynamic_step(form=...)`` overrides it.
FORM = "primal"
FORMS = ("primal", "dual")

#: State the dual's objective with its constant 1/2 c_r^T P_r^-1 c_r (a variable t with
#: cost 1 and the row t = constant), so that Clarabel's relative gap is measured on the
#: primal's objective value. Without it the dual's objective lacks that constant (the
#: inertia term's, or the work of the prescribed increments), which can exceed the step's
#: objective by 600x (the axisymmetric extension of tests/test_mu_i_axisymmetric.py):
#: Clarabel's relative stop was that much looser (sqrt(J2) 1.1e-5 from cvxpy's instead of
#: 1e-6). The constant goes in b, not in c: as a cost (t = 1, cost the constant) it
#: upsets Clarabel's scaling of the cost (measured 26.2 iterations per solve against
#: 21.3 on the a = 1 column's steps 2-7 at 512 elements; 20.6 without the constant, 21.0
#: in the primal form). On those steps the dual's du is 5e-5 and its r' 1.3e-4 from a
#: primal solve at 1e-11 whatever the placement and tolerance (1e-8 to 1e-10), the
#: primal's 5.5e-6 and 1.1e-5 (book/performance.md).
DUAL_CONSTANT = True

#: A block of P whose least eigenvalue is below this fraction of its largest is singular
#: for :func:`solve_dual` (which then refuses the problem).
BLOCK_RCOND = 1e-12

#: An entry of P below this fraction of sqrt(|P_ii P_jj|) is round-off of the assembly
#: (measured ~1e-15 on the column's inverse-mass blocks; the real couplings are >= 0.1).
#: Relative, so a scaling of the data (the density of a c = 0 run) drops the same entries.
P_ROUNDOFF = 1e-12


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


_STATUS = {"Solved": "optimal", "AlmostSolved": "optimal_inaccurate",
           "PrimalInfeasible": "infeasible", "AlmostPrimalInfeasible": "infeasible_inaccurate",
           "DualInfeasible": "unbounded", "AlmostDualInfeasible": "unbounded_inaccurate"}

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
    per element, a compliance block per stress point, one entry per viscous variable),
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
    engine : the solver (:mod:`~pfem_skfem.problems.direct_engines`; Clarabel by default).

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
    sol = (engine or ENGINES["clarabel"]).solve(P_d, c_d, A_d, b_d, cones_d, settings)
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


def cone_matrices(criterion, n):
    """The affine cone map of a yield criterion at n points: D (K n, m, 4), d (K n, m).

    rho_j = D_j sigma_j + d_j with rho_1 >= ||rho_2..m|| (the criterion's
    ``cone_vector``, evaluated at zero and at the four unit stresses); K is the
    criterion's ``n_cones`` (1 for the plane-strain cones), cone j acting on the
    stresses of point j mod n.
    """
    zero = np.zeros(n)
    size = n * getattr(criterion, "n_cones", 1)

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


def viscous_stress_map(n, hoop=False):
    """E (4n, 2n): the viscous stress (a, -a, 0, b) of each point from its (a, b); with
    ``hoop`` E (4n, 3n): (a, -a, 0, b) + c (1, 1, -2, 0) / sqrt3 from (a, b, c), the
    deviators of axisymmetry (rr, zz, tt, rz). Either way sqrt(J2) = ||(a, b[, c])||."""
    j = np.arange(n)
    rows = np.concatenate([4 * j, 4 * j + 1, 4 * j + 3])
    if not hoop:
        cols = np.concatenate([2 * j, 2 * j, 2 * j + 1])
        vals = np.concatenate([np.ones(n), -np.ones(n), np.ones(n)])
        return sp.csr_matrix((vals, (rows, cols)), shape=(4 * n, 2 * n))
    rows = np.concatenate([rows, 4 * j, 4 * j + 1, 4 * j + 2])
    cols = np.concatenate([3 * j, 3 * j, 3 * j + 1, 3 * j + 2, 3 * j + 2, 3 * j + 2])
    c = np.full(n, 1 / np.sqrt(3.0))
    vals = np.concatenate([np.ones(n), -np.ones(n), np.ones(n), c, c, -2 * c])
    return sp.csr_matrix((vals, (rows, cols)), shape=(4 * n, 3 * n))


def _yield_block(criterion, n):
    """Rows of A and b for the yield cones, their Clarabel cones and a function reading each
    point's multiplier off their duals.

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


def solve_dynamic_step(*, Bh, Ah, Dh, Ch, kappa, kappa_C, s_n, v_h, f_h, free, P, u_P,
                       criterion, contact=None, viscous=None, rate_log=None, hoop=False,
                       what="dynamic step (4.23)", form=None, engine="clarabel",
                       accept_inaccurate=False, **settings):
    """Solve the scaled step of :func:`~pfem_skfem.problems.dynamic.dynamic_increment`.

    Arguments are the scaled data of that function (Bh (4n, n_u), Ah (n_r, n_u), Dh, Ch
    or None, the weights kappa, kappa_C, s_n, v_h, f_h, the free and prescribed dofs and
    u_P); ``criterion`` is already scaled; ``contact`` is None or a dict with G (n_u, 2 nc),
    gap (nc,) scaled, mu (nc,), bound (nc,) scaled friction bound or None, slip (nc,)
    scaled tangential motion of the body or None; ``viscous`` is None or the weights
    kv (n,) of a viscous stress (a, -a, 0, b) per point added to sigma, with the term
    -1/2 sum_j kv_j (a_j^2 + b_j^2) in the objective (:func:`viscous_stress_map`);
    ``rate_log`` is None or dict(kw, tau_max) (n,) of the mu(I) rate stress (a, -a, 0, b)
    with the term - sum_j kw_j (t_j - s_j), ||(a_j, b_j)|| <= tau_max_j s_j and
    (-t_j, 1, 1 - s_j) in the exponential cone (t_j >= -ln(1 - s_j)); with either, "s" is
    the total stress; ``hoop``: the rate stress has the third (hoop) component c_j of
    axisymmetry, (a_j, b_j) reading (a_j, b_j, c_j) throughout; ``form``: "primal" or
    "dual" (:data:`FORM` by default; with ``rate_log``, whose exponential cones are not
    self-dual, the primal form is stated either way); ``engine``: the solver handed the
    data, a name of :data:`~pfem_skfem.problems.direct_engines.ENGINES` ('clarabel',
    'qoco'); ``settings`` are the engine's (Clarabel's over :data:`SETTINGS`).

    Returns dict(s, q, p, qc, dual_equilibrium, dual_yield, info): the scaled solution and
    the duals of equilibrium (on the free dofs; du_F = -dual x displacement scale, the
    sign of cvxpy's dual) and of the first component of each yield cone.
    """
    t0 = time.perf_counter()
    form = FORM if form is None else form
    if form not in FORMS:
        raise ValueError(f"form must be one of {FORMS}, got {form!r}")
    if engine not in ENGINES:
        raise ValueError(f"engine must be one of {tuple(ENGINES)}, got {engine!r}")
    solver_engine = ENGINES[engine]
    n = Bh.shape[0] // 4
    n_r = Ah.shape[0]
    nc = 0 if contact is None else contact["G"].shape[1] // 2
    if viscous is not None and rate_log is not None:
        raise ValueError("viscous and rate_log exclude each other")
    m_v = 3 if hoop else 2                            # components of a rate deviator
    n_v = 0 if viscous is None and rate_log is None else m_v * n
    n_l = 0 if rate_log is None else 2 * n            # s_j, t_j of the log term
    n_x = 4 * n + n_r + 2 * nc + n_v + n_l
    sl_s, sl_q = slice(0, 4 * n), slice(4 * n, 4 * n + n_r)
    end_c = 4 * n + n_r + 2 * nc
    sl_p, sl_c = slice(4 * n + n_r, 4 * n + n_r + nc), slice(4 * n + n_r + nc, end_c)
    sl_v = slice(end_c, end_c + n_v)
    sl_sv = slice(end_c + n_v, end_c + n_v + n_l // 2)
    sl_tv = slice(end_c + n_v + n_l // 2, n_x)

    # objective: -J = 1/2 kappa q^T D q + (A v)^T q [+ kappa_C (1/2 s^T C s - (C s_n)^T s)]
    #               + g0^T p - u_P^T (internal_P - f_P)
    blocks = [kappa_C * Ch if Ch is not None else sp.csr_matrix((4 * n, 4 * n)),
              kappa * Dh, sp.csr_matrix((2 * nc, 2 * nc))]
    if viscous is not None:                   # + 1/2 sum kv_j (a_j^2 + b_j^2)
        blocks.append(sp.diags(np.repeat(np.asarray(viscous, dtype=float), m_v)))
    elif n_v:
        blocks.append(sp.csr_matrix((n_v + n_l, n_v + n_l)))
    Pmat = sp.triu(sp.block_diag(blocks, format="csc"), format="csc")
    c = np.zeros(n_x)
    c[sl_q] = Ah @ v_h
    if Ch is not None:
        c[sl_s] -= kappa_C * (Ch @ s_n)
    # internal forces: K x with K = [B^T, A^T, -G]
    parts = [Bh.T, Ah.T]
    if nc:
        parts.append(-contact["G"])
        c[sl_p] = contact["gap"]
        if contact.get("slip") is not None:               # - (n^ . d) q: a moving body
            c[sl_c] = -contact["slip"]
    if n_v:                                   # B^T (sigma + E v)
        parts.append(Bh.T @ viscous_stress_map(n, hoop))
    if n_l:                                   # + sum kw_j (t_j - s_j)
        parts.append(sp.csr_matrix((Bh.shape[1], n_l)))
        c[sl_tv] = rate_log["kw"]
        c[sl_sv] = -np.asarray(rate_log["kw"])
    K = sp.hstack(parts, format="csr")
    if P.size:
        c -= K[P].T @ u_P

    rows_A, rows_b, cones = [K[free]], [f_h[free]], [clarabel.ZeroConeT(free.size)]
    if nc:
        mu, bound = contact["mu"], contact["bound"]
        tangential = sp.csr_matrix((np.ones(nc), (np.arange(nc), 4 * n + n_r + nc
                                                   + np.arange(nc))), shape=(nc, n_x))
        normal = sp.csr_matrix((np.ones(nc), (np.arange(nc), 4 * n + n_r + np.arange(nc))),
                               shape=(nc, n_x))
        k = mu if bound is None else bound
        smooth = np.flatnonzero(k <= 0)
        rough = np.flatnonzero(k > 0)
        if smooth.size:                                    # q_j = 0
            rows_A.append(tangential[smooth])
            rows_b.append(np.zeros(smooth.size))
            cones[0] = clarabel.ZeroConeT(free.size + smooth.size)
        rows_A.append(-normal)                             # p_j >= 0
        rows_b.append(np.zeros(nc))
        cones.append(clarabel.NonnegativeConeT(nc))
    A_yield, b_yield, yield_cones, yield_multipliers = _yield_block(criterion, n)
    rows_A.append(sp.hstack([A_yield, sp.csr_matrix((A_yield.shape[0], n_x - 4 * n))]))
    rows_b.append(b_yield)
    cones += yield_cones
    if nc and rough.size:              # mu_j p_j -+ q_j >= 0  (or k_j -+ q_j >= 0)
        i = np.arange(rough.size)
        r = np.concatenate([i, rough.size + i])
        col = np.concatenate([sl_c.start + rough, sl_c.start + rough])
        val = np.concatenate([np.ones(rough.size), -np.ones(rough.size)])
        b_pairs = np.zeros(2 * rough.size)
        if bound is None:
            r = np.concatenate([r, i, rough.size + i])
            col = np.concatenate([col, sl_p.start + rough, sl_p.start + rough])
            val = np.concatenate([val, -mu[rough], -mu[rough]])
        else:
            b_pairs[:] = np.tile(bound[rough], 2)
        rows_A.append(sp.csr_matrix((val, (r, col)), shape=(2 * rough.size, n_x)))
        rows_b.append(b_pairs)
        cones.append(clarabel.NonnegativeConeT(2 * rough.size))
    if n_l:                            # ||(a_j, b_j)|| <= tau_max_j s_j;  t_j >= -ln(1 - s_j)
        j = np.arange(n)
        tm = np.asarray(rate_log["tau_max"], dtype=float)
        w = m_v + 1                                        # SOC(w): (tau_max s, a, b[, c])
        r = np.concatenate([w * j] + [w * j + 1 + k for k in range(m_v)])
        col = np.concatenate([sl_sv.start + j] + [sl_v.start + m_v * j + k for k in range(m_v)])
        val = np.concatenate([-tm] + [-np.ones(n)] * m_v)
        rows_A.append(sp.csr_matrix((val, (r, col)), shape=(w * n, n_x)))
        rows_b.append(np.zeros(w * n))
        cones += [clarabel.SecondOrderConeT(w)] * n
        r = np.concatenate([3 * j, 3 * j + 2])             # (-t_j, 1, 1 - s_j) in K_exp
        col = np.concatenate([sl_tv.start + j, sl_sv.start + j])
        rows_A.append(sp.csr_matrix((np.ones(2 * n), (r, col)), shape=(3 * n, n_x)))
        rows_b.append(np.tile([0.0, 1.0, 1.0], n))
        cones += [clarabel.ExponentialConeT()] * n
    Amat = sp.vstack(rows_A, format="csc")
    b = np.concatenate(rows_b)
    if CLEAN_DATA:                 # the same problem, fewer entries (benchmarks/iteration_cost.py)
        Amat.eliminate_zeros()
        Pmat = drop_roundoff(Pmat)

    changes = {**SETTINGS, **settings} if engine == "clarabel" else dict(settings)
    opts = solver_engine.settings(changes)
    t1 = time.perf_counter()
    build = t1 - t0                          # our assembly (cvxpy's 'compile' counterpart)
    retried, first_iterations = False, 0
    if form == "dual" and not n_l:           # the displacement form (exponential cones: primal)
        sol = solve_dual(Pmat, c, Amat, b, cones, opts, solver_engine)
        build += sol.setup_time              # stating the dual is our assembly
        wall = time.perf_counter() - t1 - sol.setup_time
    else:
        sol = solver_engine.solve(Pmat, c, Amat, b, cones, opts)
        retried = (engine == "clarabel" and sol.status in RETRY_ON
                   and opts.equilibrate_enable)
        if retried:                          # once more without equilibration (RETRY),
            first_iterations = sol.iterations           # the first attempt's counted
            opts = solver_engine.settings({**changes, **RETRY})
            sol = solver_engine.solve(Pmat, c, Amat, b, cones, opts)
        wall = time.perf_counter() - t1      # the solver's setup and iterations
    status = _STATUS.get(sol.status, sol.status)
    check_status(status, what, accept_inaccurate, sol.measures)
    x, z = sol.x, sol.z
    start = free.size + (smooth.size if nc else 0) + nc
    info = SolveInfo(status=status, iterations=int(sol.iterations) + first_iterations,
                     compile_time=build, solve_time=wall, objective=-float(sol.obj_val))
    if engine != "clarabel":
        info.extra["engine"] = engine
    if form == "dual" and not n_l:
        info.extra["form"] = "dual"
    elif retried:
        info.extra["retried"] = dict(RETRY)
    s_total = x[sl_s] if not n_v else x[sl_s] + viscous_stress_map(n, hoop) @ x[sl_v]
    return {"s": s_total, "q": x[sl_q], "p": x[sl_p], "qc": x[sl_c],
            "dual_equilibrium": z[:free.size], "dual_yield": yield_multipliers(z[start:]),
            "info": info}
