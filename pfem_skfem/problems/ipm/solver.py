"""A primal-dual interior point for the zero, non-negative and second-order cones, its
Newton system reduced to the displacements (:mod:`.newton`).

Mehrotra's predictor-corrector with the Nesterov-Todd scaling (Vandenberghe 2010, the
CVXOPT cone QP algorithm; Mehrotra 1992), on min 1/2 x^T P x + c^T x, A x + s = b, s in
K (the zero cone's rows E x = b_E, the others G x + s = h), infeasible start:

1. residuals r_x = P x + c + A^T z, r_y = E x - b_E, r_z = G x + s - h and the gap
   mu = s^T z / nu (nu the number of cones); stop when Clarabel's tests hold
   (the measures of ``_Problem``, the tolerances :data:`DEFAULTS`, Clarabel's names
   and values), on the problem it was given (a substituted one, :mod:`.presolve`, with the
   objective's constant it dropped: a relative gap normalised by the given objective, as
   Clarabel's on the same data would be; measured on the plastic vibration's and the
   cylinder's solves, the measures of the given data agree). P x, A x and A^T z are
   carried along the steps by the direction's own products (the Newton solve's residual
   computes them), and computed afresh only for an iterate that is answered;
2. the scaling W at (s, z), lambda = W z = W^-1 s, the Newton system factorised once;
3. the affine (predictor) direction: the linearised conditions with the complementarity
   lambda o (W dz + W^-1 ds) = -lambda o lambda; its largest step a in the cones;
4. the centring sigma = (1 - a)^3 and the combined (corrector) direction: the residuals
   scaled by 1 - sigma, the complementarity -lambda o lambda - (W^-1 ds_a) o (W dz_a)
   + sigma mu e, the same factorisation;
5. the step: 0.99 of the largest in the cones, at most one.

The start is CVXOPT's: the least-squares point of the Newton system with W = I, s and z
shifted into the cones. Infeasibility is read off the iterates (no homogeneous
embedding: the embedding of Clarabel and ECOS costs a second solve an iteration, and a
step or an analysis is infeasible only when its load exceeds the collapse load): a dual
iterate with ||A^T z|| <= tol_infeas_rel (-b^T z) certifies primal infeasibility
('PrimalInfeasible'), a primal one with ||P x||, ||E x||, ||G x + s|| <= tol_infeas_rel
(-c^T x) dual infeasibility ('DualInfeasible').

The reduced Newton system is the normal equations of the cones: its condition number
grows as the gap closes, and near a gap of 1e-8 (1e-9 to 1e-10 in mu) it can pass what
double precision resolves. The solve watches the residual of each Newton solve
(after refinement, which stops early far from the solution: :data:`INEXACT`); once it
exceeds :data:`TRUST` the direction is not taken. The iteration is then solved again,
and the rest of the solve too, with (N) unreduced (:mod:`.augmented`, the square root of
the condition number, refined to the accuracy asked); near the tolerances
(:data:`WHOLE_BEYOND`) only while it finds better iterates (:data:`NEAR_TRIES`) and is
trusted (far from them, in a degenerate problem such as water at rest, to the end).
Where that fails far from them, once more with it regularised more
(:data:`.augmented.STRONG`, as from the start where S is singular: the upper bound's
kinematic problem); and once a direction at STRONG misses the accuracy it asked for
(trusted or not: that regularisation grows with W^-1 and its error stalls the primal
residual), by an LU with partial pivoting (:data:`.augmented.PIVOTED`, ~10x STRONG's
factorisation), to the end.
Where that fails too, the solve ends at its best iterate: 'Solved' when that meets the
full tolerances, 'AlmostSolved' (Clarabel's reduced tolerances) or 'NumericalError'
otherwise. The same best iterate answers an iteration limit ('MaxIterations') or a stall
('InsufficientProgress').
"""
import hashlib
from types import SimpleNamespace

import numpy as np
import scipy.sparse as sp

from . import cones as K
from .augmented import PIVOTED, REGULARISATION, STRONG, Augmented
from .cholesky import Cholesky, CholeskyError
from .newton import REFINE_TOL, Newton
from .presolve import Substitution
from .structure import Structure, component_major, from_component_major

#: the tolerances (Clarabel's names and defaults: full, then reduced for 'AlmostSolved')
DEFAULTS = dict(tol_gap_abs=1e-8, tol_gap_rel=1e-8, tol_feas=1e-8, tol_infeas_rel=1e-8,
                reduced_tol_gap_abs=5e-5, reduced_tol_gap_rel=5e-5, reduced_tol_feas=1e-4,
                max_iter=100, step_fraction=0.99, verbose=False)

#: a Newton solve whose residual (relative to its right-hand side, after refinement) is
#: above this is not trusted: its direction is not taken and the solve ends
TRUST = 1e-6

#: an inexact Newton direction: its residual (relative to its right-hand side) need only be
#: this fraction of how far the iterate is from solved (its relative residuals and gap, at
#: most one); the refinement stops there, never below ``newton.REFINE_TOL``, and such a
#: direction is trusted
INEXACT = 1e-3


#: the reduced system running out of digits hands (N) to the unreduced one
#: (:mod:`.augmented`) for the rest of the solve this far from the full tolerances
#: (``_Problem.merit``: two decades). Nearer, it hands it over too, but only at its weaker
#: regularisation: the best iterate answers once a direction of it is not trusted or
#: :data:`NEAR_TRIES` iterations found no better iterate ('AlmostSolved' where it meets
#: the reduced tolerances). Until 2026-12-08 the solve ended there at once: the unreduced
#: system, refined only to 1e-8 of its right-hand side, gained nothing in three more
#: iterations on the a = 1 column at 512 elements, and stalled or took 82 iterations on
#: the quick plane column; refined to the accuracy asked (:data:`.augmented.REFINE_TOL`),
#: it ends the quick dam break's four such solves 'Solved' in one more iteration each.
WHOLE_BEYOND = 100.0

#: near the tolerances, the unreduced system's iterations allowed in a row without a
#: better iterate (``_Problem.merit``) before the best iterate answers: one (the quick
#: plane column's 18 'AlmostSolved' ends, whose gap stalls at 1e-8 to 3e-7 while mu falls
#: to 1e-14, gain nothing from more, nor from the stronger regularisations: their solves
#: cost 8 % more CPU time with this one try, 22 % with three and the stronger ones)
NEAR_TRIES = 1


class _Identity:
    """W = I for every cone of a group (the starting point's system)."""

    def __init__(self, m, d):
        self.m, self.d = m, d

    def apply(self, u):
        return u

    inverse = apply

    def inverse_matrix(self):
        return np.broadcast_to(np.eye(self.d), (self.m, self.d, self.d)).copy()


def _inf(v):
    return float(np.abs(v).max()) if np.size(v) else 0.0


def _dot(u, v):
    """u . v without BLAS: a threaded BLAS dot of a long vector waits for its threads when
    the cores are busy (7 ms for 12,000 entries on the shared 2-core machine)."""
    return float(np.einsum("i,i->", u, v))


class _Problem:
    """The data, split by cone (:class:`~.structure.Structure`), and the iterate's
    measures. The rows are in the solver's order (``st.order``: the zero cone's, then
    each group's by component, :func:`.structure.by_component`), where a group's part of
    a row-length vector is a Fortran-ordered (m, d) view (:mod:`.cones`)."""

    def __init__(self, P, c, A, b, cones, opts, given=None):
        self.st = st = _structure(P, A, cones)
        self.A, self.AT = st.A, st.AT
        b = b[st.order]
        self.P, self.c, self.b = st.P, c, b
        self.b_E = b[st.zero_at]
        self.h = self.split(b)[1]
        self.nu = max(sum(rows.shape[0] for rows in st.groups.values()), 1)
        self.opts = opts
        self.norm_b, self.norm_c = _inf(b), _inf(c)
        self.offset = 0.0
        if given is not None:   # measured as the given problem (presolve.Substitution.given):
            self.offset = given["offset"]       # its objective; its norms, where smaller
            self.norm_b = min(self.norm_b, given["norm_b"])
            self.norm_c = min(self.norm_c, given["norm_c"])

    def split(self, v):
        """A row-length vector (the solver's order) as (its zero rows, {d: its cone
        groups (m, d), Fortran-ordered views})."""
        st = self.st
        return v[st.zero_at], {d: from_component_major(v[at], d)
                               for d, at in st.group_at.items()}

    def measures(self, x, z, s, products=None):
        """Clarabel's measures of the iterate (x, z, s) (z, s of the row length) and the
        residuals the Newton step reduces; ``products`` (P x, A x, A^T z) where they are
        known (updated along the step: :func:`_moved`), else computed."""
        Px, Ax, ATz = products if products is not None else (
            self.P @ x, self.A @ x, self.AT @ z)
        r_prim = Ax + s - self.b
        rx = Px + self.c + ATz
        xPx = _dot(x, Px)
        cx = _dot(self.c, x)
        bz = _dot(self.b, z)
        pobj = 0.5 * xPx + cx + self.offset
        dobj = -0.5 * xPx - bz + self.offset
        gap_abs = abs(pobj - dobj)
        ry, rz = self.split(r_prim)
        inf_x = _inf(x)
        return dict(
            pobj=pobj, dobj=dobj, gap_abs=gap_abs,
            gap_rel=gap_abs / max(1.0, min(abs(pobj), abs(dobj))),
            res_primal=_inf(r_prim) / max(1.0, self.norm_b + inf_x + _inf(s)),
            res_dual=_inf(rx) / max(1.0, self.norm_c + inf_x + _inf(z)),
            rx=rx, ry=ry, rz=rz, Px=Px, Ax=Ax, ATz=ATz, bz=bz, cx=cx)

    def done(self, m, reduced=False):
        o, pre = self.opts, "reduced_" if reduced else ""
        gap = m["gap_abs"] <= o[pre + "tol_gap_abs"] or m["gap_rel"] <= o[pre + "tol_gap_rel"]
        return gap and max(m["res_primal"], m["res_dual"]) <= o[pre + "tol_feas"]

    def merit(self, m):
        """How far the iterate is from the full tolerances (below one: solved)."""
        o = self.opts
        return max(m["res_primal"] / o["tol_feas"], m["res_dual"] / o["tol_feas"],
                   min(m["gap_abs"] / o["tol_gap_abs"], m["gap_rel"] / o["tol_gap_rel"]))

    def infeasible(self, m, x, s):
        """'PrimalInfeasible' / 'DualInfeasible' when the iterate certifies it, else None."""
        tol = self.opts["tol_infeas_rel"]
        if m["bz"] < 0 and _inf(m["ATz"]) <= tol * -m["bz"]:
            return "PrimalInfeasible"
        if m["cx"] < 0:
            Ax_s = m["Ax"] + s
            Ax_s[self.st.zero_at] = m["Ax"][self.st.zero_at]    # E x (s = 0 there)
            if max(_inf(m["Px"]), _inf(Ax_s)) <= tol * -m["cx"]:
                return "DualInfeasible"
        return None


_LAST = {}


def _structure(P, A, cones):
    """The problem's :class:`~.structure.Structure`, kept for the next solve of the same
    matrices (the fixed-point passes of a PFEM step differ in b and c only): one entry,
    keyed by a digest of P's and A's patterns and values and the cones."""
    P, A = sp.csc_matrix(P), sp.csc_matrix(A)
    digest = hashlib.blake2b(digest_size=16)
    for M in (P, A):
        for part in (M.indptr, M.indices, M.data):
            digest.update(np.ascontiguousarray(part).view(np.uint8))
    digest.update(repr([(type(k).__name__, getattr(k, "dim", None)) for k in cones]).encode())
    key = digest.hexdigest()
    if key not in _LAST:
        _LAST.clear()
        st = Structure(P, A, cones)
        # the solver's order of the rows: the zero cone's, then each group's by component
        st.order = np.concatenate([st.zero, *(rows.T.ravel() for rows in st.groups.values())])
        st.A = A.tocsr()[st.order]
        st.AT = st.A.T.tocsr()
        st.zero_at, start = slice(0, st.zero.size), st.zero.size
        st.group_at = {}
        for d, rows in st.groups.items():
            st.group_at[d], start = slice(start, start + rows.size), start + rows.size
        st.cholesky = Cholesky(st.S_rows, st.S_cols, st.E.shape[0])   # its analysis
        _LAST[key] = st
    return _LAST[key]


def _moved(pb, m, a, products):
    """(P x, A x, A^T z) at the next iterate from the current ones (in ``m``) and the
    direction's ``products`` (:attr:`.newton.Newton.products`), without a product of the
    data: x + a dx, z + a dz are linear. Rounding accumulates along the iterations (a few
    units of 1e-16 an iteration, relative), far below the tolerances' 1e-8; an iterate
    that passes them on these is measured in full before it is answered."""
    Pdx, ATdz, Edx, Gdx = products
    Ax = m["Ax"].copy()
    Ax[pb.st.zero_at] += a * Edx
    for d, at in pb.st.group_at.items():
        Ax[at] += a * component_major(Gdx[d])
    return m["Px"] + a * Pdx, Ax, m["ATz"] + a * ATdz


def _step(lam, ds_t, dz_t):
    """The largest step in every cone for the scaled directions."""
    a = np.inf
    for d in lam:
        for u in (ds_t[d], dz_t[d]):
            if u.size:
                a = min(a, float(K.max_step(lam[d], u).min()))
    return a


def _direction(pb, newton, W, lam, m, scale, comp, refine=True, tol=0.0):
    """The Newton direction for the residuals times ``scale`` and the complementarity
    right-hand sides ``comp``: (dx, dz, ds) of the row length and the scaled (W^-1 ds,
    W dz) per group. From lambda o (W dz + W^-1 ds) = comp: W^-1 ds = q - W dz with
    q = lambda \\ comp, and G dx + ds = -scale r_z, scaled by W^-1, is the third row of
    (N): W^-1 G dx - W dz = -scale W^-1 r_z - q."""
    st = pb.st
    q = {d: K.divide(lam[d], comp[d]) for d in lam}
    bzt = {d: -scale * W[d].inverse(m["rz"][d]) - q[d] for d in lam}
    dx, dy, dz_t = newton.solve(-scale * m["rx"], -scale * m["ry"], bzt, refine, tol)
    ds_t = {d: q[d] - dz_t[d] for d in lam}
    if not refine:                      # the predictor: only the scaled ones are used
        return None, None, None, ds_t, dz_t
    dz, ds = np.zeros(pb.b.size), np.zeros(pb.b.size)
    dz[st.zero_at] = dy
    for d, at in st.group_at.items():
        dz[at] = component_major(W[d].inverse(dz_t[d]))
        ds[at] = component_major(W[d].apply(ds_t[d]))
    return dx, dz, ds, ds_t, dz_t


def _directions(pb, newton, W, lam, m, mu, tol):
    """Mehrotra's predictor and corrector (steps 3 and 4) on one factorised system: the
    corrector's (dx, dz, ds, ds_t, dz_t), the predictor's step a_aff and the centring
    sigma."""
    lam2 = {d: K.product(lam[d], lam[d]) for d in lam}
    *_, ds_a, dz_a = _direction(pb, newton, W, lam, m, 1.0, {d: -lam2[d] for d in lam},
                                refine=False)
    a_aff = min(1.0, _step(lam, ds_a, dz_a))
    sigma = (1.0 - a_aff) ** 3
    comp = {d: -lam2[d] - K.product(ds_a[d], dz_a[d]) for d in lam}
    for d in lam:
        comp[d][:, 0] += sigma * mu                     # + sigma mu e
    return (*_direction(pb, newton, W, lam, m, 1.0 - sigma, comp, tol=tol), a_aff, sigma)


def _attempt(pb, W, lam, m, mu, tol, whole, regularisation=REGULARISATION):
    """(the factorised system, :func:`_directions`'s answer) with (N) reduced
    (:class:`.newton.Newton`) or whole (:class:`.augmented.Augmented`, its
    ``regularisation``); (None, None) when its factorisation fails."""
    try:
        newton = Augmented(pb.st, W, regularisation) if whole \
            else Newton(pb.st, W, pb.st.cholesky)
    except (CholeskyError, RuntimeError):        # SuperLU: "Factor is exactly singular"
        return None, None
    return newton, _directions(pb, newton, W, lam, m, mu, tol)


def _trusted(newton, tol):
    """Whether a direction was solved (its residual within TRUST or the asked ``tol``)."""
    return newton is not None and newton.residual <= max(TRUST, tol)


def _met(newton, tol):
    """Whether a direction was solved to the asked ``tol`` (never below the refinement's
    own :data:`.newton.REFINE_TOL`)."""
    return newton is not None and newton.residual <= max(REFINE_TOL, tol)


def _system(whole, regularisation):
    """The Newton system's name in the verbose lines."""
    if not whole:
        return "reduced"
    return "whole, pivoted" if regularisation == PIVOTED else f"whole, {regularisation:.0e}"


def solve(P, c, A, b, cones, settings=None):
    """Solve min 1/2 x^T P x + c^T x, A x + s = b, s in K (Clarabel's data: P upper
    triangular or full, the cone objects of ``clarabel``); answers in Clarabel's terms:
    SimpleNamespace(x, z, s, status, iterations, obj_val, measures, factorisations).
    A variable defined by one equality is substituted first (:mod:`.presolve`)."""
    sub = Substitution(P, c, A, np.asarray(b, dtype=float), cones)
    if not sub.any:
        return _solve(P, c, A, b, cones, settings)
    sol = _solve(*sub.problem, {**(settings or {}), "given": sub.given})
    sol.x, sol.z, sol.s = sub.recover(sol.x, sol.z, sol.s)
    return sol


def _solve(P, c, A, b, cones, settings=None):
    """:func:`solve` without the substitutions."""
    opts = {**DEFAULTS, **(settings or {})}
    given = opts.pop("given", None)           # a substituted problem's given one (:func:`solve`)
    pb = _Problem(P, np.asarray(c, dtype=float), A, np.asarray(b, dtype=float), cones, opts,
                  given)
    st = pb.st
    n, rows = P.shape[0], A.shape[0]
    if st.dead.size and np.any(pb.c[st.dead] != 0):   # a cost on a variable in nothing
        return _answer(np.zeros(n), np.zeros(rows), np.zeros(rows), "DualInfeasible", 0,
                       None, 0)
    chol = st.cholesky
    counted = chol.factorisations
    # the start: the least-squares point of (N) with W = I (z = G x - h), shifted inside
    identity = {d: _Identity(*r.shape) for d, r in st.groups.items()}
    whole, whole_lu = False, 0        # whether (N) is solved unreduced (:mod:`.augmented`)
    regularisation = REGULARISATION   # the unreduced system's, STRONG once not trusted
    try:
        newton = Newton(st, identity, chol)
    except CholeskyError:             # S singular (a kinematic problem's velocities): its
        whole, whole_lu = True, 1     # first block is the regularisation alone
        regularisation = STRONG
        newton = Augmented(st, identity, regularisation)
    x, y, zt = newton.solve(-pb.c, pb.b_E, pb.h)
    z, s = np.zeros(rows), np.zeros(rows)
    z[st.zero_at] = y
    for d, at in st.group_at.items():
        z[at] = component_major(K.shift_inside(zt[d]))
        s[at] = component_major(K.shift_inside(-zt[d]))
    status, best, stall, it, products = None, None, 0, 0, None
    near, since_best = False, 0       # (N) whole from near the tolerances; its iterations
    for it in range(opts["max_iter"] + 1):
        m = pb.measures(x, z, s, products)
        if products is not None and (pb.done(m) or pb.infeasible(m, x, s) is not None
                                     or it == opts["max_iter"]):
            m = pb.measures(x, z, s)              # an answer is measured in full
        if best is None or pb.merit(m) < best[0]:
            best, since_best = (pb.merit(m), x, z, s, m, it), 0
        else:
            since_best += 1
        if pb.done(m):
            status = "Solved"
            break
        status = pb.infeasible(m, x, s)
        if status is not None or it == opts["max_iter"]:
            break
        if near and since_best >= NEAR_TRIES:
            status = "InsufficientProgress"     # the best iterate answers
            break
        _, zg = pb.split(z)
        _, sg = pb.split(s)
        with np.errstate(invalid="ignore", divide="ignore"):
            W = {d: K.Scaling(sg[d], zg[d]) for d in zg}
        if not all(np.isfinite(w.lam).all() for w in W.values()):
            status = "NumericalError"           # an iterate on a cone's boundary, to
            break                               # round-off: the best iterate answers
        lam = {d: W[d].lam for d in zg}
        mu = sum(float(np.sum(sg[d] * zg[d])) for d in zg) / pb.nu
        tol = INEXACT * min(1.0, max(m["res_primal"], m["res_dual"], m["gap_rel"]))
        newton, found = _attempt(pb, W, lam, m, mu, tol, whole, regularisation)
        if not _trusted(newton, tol) and not whole:
            whole = True          # the reduced system ran out of digits: (N) whole from now
            near = pb.merit(m) <= WHOLE_BEYOND
            newton, found = _attempt(pb, W, lam, m, mu, tol, whole, regularisation)
        if not _trusted(newton, tol) and whole and regularisation == REGULARISATION \
                and not near:           # (near the tolerances the best iterate answers)
            regularisation = STRONG     # its LU ran out of digits: regularised more from now
            whole_lu += 1               # the weaker LU of this iteration, counted
            newton, found = _attempt(pb, W, lam, m, mu, tol, whole, regularisation)
        if whole and regularisation == STRONG and not _met(newton, tol):
            # STRONG is relative to W^-1's largest entry, which grows as the gap closes:
            # once its refinement misses the accuracy asked (trusted or not: a direction
            # kept at 3e-3 of its right-hand side stalls the primal residual, and with it
            # the gap, while mu falls), the LU with pivoting (:data:`.augmented.PIVOTED`)
            # from now; where that fails and STRONG's direction was trusted, that one
            kept = newton, found
            newton, found = _attempt(pb, W, lam, m, mu, tol, whole, PIVOTED)
            whole_lu += 1                       # the other LU of this iteration, counted
            if _trusted(newton, tol) or not _trusted(kept[0], tol):
                regularisation = PIVOTED
            else:
                newton, found = kept
        whole_lu += whole
        if not _trusted(newton, tol):
            if opts["verbose"]:
                print(f"{it:3d} not trusted: Newton residual "
                      f"{np.nan if newton is None else newton.residual:.1e}, tol {tol:.1e}, "
                      f"{_system(whole, regularisation)}")
            status = "NumericalError"
            break
        dx, dz, ds, ds_t, dz_t, a_aff, sigma = found
        a = min(1.0, opts["step_fraction"] * _step(lam, ds_t, dz_t))
        if opts["verbose"]:
            print(f"{it:3d} pobj {m['pobj']:+.6e} dobj {m['dobj']:+.6e} pres "
                  f"{m['res_primal']:.1e} dres {m['res_dual']:.1e} gap {m['gap_rel']:.1e} "
                  f"mu {mu:.1e} a_aff {a_aff:.3f} a {a:.3f} kkt {newton.residual:.1e} (tol "
                  f"{tol:.0e}) {_system(whole, regularisation)}")
        if not a > 1e-10:
            stall += 1
            if stall >= 3:
                status = "InsufficientProgress"
                break
        x, z, s = x + a * dx, z + a * dz, s + a * ds
        products = _moved(pb, m, a, newton.products)
    if status not in ("Solved", "PrimalInfeasible", "DualInfeasible"):
        _, x, z, s, _, it_best = best           # the best iterate answers, measured
        m = pb.measures(x, z, s)                # in full
        if pb.done(m):
            status = "Solved"
        elif pb.done(m, reduced=True):
            status = "AlmostSolved"
        elif status is None:
            status = "MaxIterations"
    return _answer(x, _in_order(st, z), _in_order(st, s), status, it, m,
                   chol.factorisations - counted + whole_lu)


def _in_order(st, v):
    """A row-length vector from the solver's order back to the problem's."""
    out = np.empty_like(v)
    out[st.order] = v
    return out


def _answer(x, z, s, status, iterations, m, factorisations):
    """The answer in Clarabel's terms."""
    measures = None if m is None else {
        "solver": "ipm", "status": status,
        **{k: float(m[k]) for k in ("res_primal", "res_dual", "gap_rel", "gap_abs")},
        "ktratio": np.nan}
    return SimpleNamespace(x=x, z=z, s=s, status=status, iterations=int(iterations),
                           obj_val=np.nan if m is None else m["pobj"], measures=measures,
                           factorisations=factorisations)
