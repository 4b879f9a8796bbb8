"""The Newton system (N) of :mod:`.newton` unreduced: the fallback once the reduced
system runs out of digits.

The reduced matrix S = E H^+ E^T is the normal equations of the cones: its condition
number is the square of the scaled system's, and on a degenerate problem (water at rest:
the cones of a block at their apex, s and z both going to zero) it passes what double
precision resolves while the gap is still far above its tolerance (the refinement
stalls). The scaled system itself::

    [ P         E^T   G^T W^-1 ] [dx ]   [bx ]
    [ E         0     0        ] [dy ] = [by ]
    [ W^-1 G    0     -I       ] [dzt]   [bzt],

is quasi-definite once its zero block is regularised (-delta I), its third block row
never squares W, and its condition number is the square root of S's: factorised by a
sparse LU (SuperLU through scipy; no new dependency) and refined on (N) itself, it
carries the iterations to the full tolerances, at 4 to 6 times the cost of an iteration
of the reduced system (its factorisation, predictor and corrector: 4.4x on the a = 1
column's step at 512 elements, 5.7x at 2,048, 5.1x on the water tank of
verification/hydrostatics.py). The solver turns to it only when the reduced solve's
residual is not trusted far from the tolerances.
"""
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from .newton import Newton

#: the regularisation of the zero diagonal blocks, relative to the largest entry of the
#: matrix (a displacement or a variable that nothing reaches); the refinement removes it
REGULARISATION = 1e-12

#: the regularisation once REGULARISATION's solve is not trusted: an LU without pivoting
#: of a matrix whose first block is nothing but the regularisation (a linear objective:
#: the upper bound's kinematic problem) loses its digits at 1e-12; at 1e-10, refined while
#: a step gains, it carries the upper bound to its tolerances (water at rest, whose
#: quadratic fills that block, stays at 1e-12: 1e-10 leaves its walls 3e-6 off)
STRONG = 1e-10

#: the last rung: (N) by an LU with partial pivoting (SuperLU's own column ordering,
#: COLAMD), regularised by this only (a Tresca point's rows leave (N) singular: the
#: velocity's divergence). The regularisations above are relative to the largest entry
#: of the matrix, which W^-1 G's blocks pass 1e6 by as the gap closes: on a linear
#: objective (the first block zero) STRONG then perturbs (N) by 1e-4 against entries of
#: order one, the refinement gains 1 % a step, and every direction keeps 3e-3 of its
#: right-hand side (the slope's upper bound of verification/limit_bounds.py --quick: its
#: primal residual stalled at 5e-7 and its gap at 5.7e-5, 'NumericalError'). Pivoting
#: needs no more than this: the same matrix solved to 3e-10 of its right-hand side after
#: two refinements, at ~10x STRONG's factorisation (0.3 s against 0.03 s for 25,000
#: rows: its ordering is not symmetric, 4.8 million entries in L and U against 0.6);
#: unregularised, the Tresca footing's (N) is singular and its LU answers nothing
PIVOTED = 1e-18

#: the residual of (N), relative to its right-hand side, below which the unreduced
#: system's refinement never goes (the reduced system's floor is ``newton.REFINE_TOL``,
#: 1e-8, where its refinement stalls; an LU's goes on to a few units of round-off): the
#: iteration asks 1e-3 of how far it is from solved. Near the tolerances 1e-8 does not
#: do: (N)'s third block row is scaled by W^-1, and a direction that misses it by e_z
#: misses G dx + ds = -r_z by W e_z. On the quick dam break's last solves
#: (verification/dam_break.py) W reached 1.6e6 on the non-negative rows at a gap of
#: 1.6e-8: a direction refined to 5.4e-9 of its right-hand side left e_z = 1.1e-10, W e_z
#: = 2.4e-6, and the primal residual went from 5.5e-11 to 1.7e-7, then tenfold an
#: iteration (the solve ended 'AlmostSolved' after 60). Refined to the 2e-11 asked
#: (2.0e-12 reached: W e_z = 1.2e-15), one iteration of the unreduced system ends it
#: 'Solved'.
REFINE_TOL = 1e-14


def block_diagonal(blocks):
    """The sparse block-diagonal matrix of a stack (m, d, d)."""
    m, d, _ = blocks.shape
    return sp.bsr_matrix((blocks, np.arange(m), np.arange(m + 1)),
                         shape=(m * d, m * d)).tocsr()


class Augmented(Newton):
    """(N) at one scaling, factorised whole: :meth:`solve`, ``residual`` and ``products``
    as :class:`.newton.Newton`'s (the refinement is the same; only the first solve
    differs)."""

    #: the third row of (N) is not satisfied by construction: the residual includes it
    third_by_construction = False

    #: refined to the accuracy the iteration asks, down to round-off (:data:`REFINE_TOL`)
    refine_tol = REFINE_TOL

    def __init__(self, structure, scalings, regularisation=REGULARISATION):
        st = self.st = structure
        self.W = scalings
        if regularisation > REGULARISATION:     # refined while a step still gains: the
            self.slow = 0.99                    # stronger regularisation slows each gain
        n, nE = st.P.shape[0], st.E.shape[0]
        WiG = {d: block_diagonal(scalings[d].inverse_matrix()) @ G for d, G in st.G.items()}
        rows_z = sum(G.shape[0] for G in WiG.values())
        K = sp.bmat([[st.P, st.ET, *(M.T for M in WiG.values())],
                     [st.E, sp.csr_matrix((nE, nE)), *(None for _ in WiG)],
                     *([M, None, *(-sp.identity(M.shape[0]) if e == d else None
                                   for e in WiG)] for d, M in WiG.items())],
                    format="csc")
        delta = regularisation * max(abs(K).max(), 1e-300)
        K = (K + sp.diags(delta * np.r_[np.ones(n), -np.ones(nE + rows_z)])).tocsc()
        if regularisation == PIVOTED:                       # partial pivoting
            self._lu = sla.splu(K, permc_spec="COLAMD")
        else:
            self._lu = sla.splu(K, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                                options={"SymmetricMode": True})
        self._split = np.cumsum([n, nE, *(G.shape[0] for G in WiG.values())])[:-1]

    def _predict(self, bx, by, bzt):
        """dzt of (N), unrefined (the predictor's)."""
        return self._once(bx, by, bzt)[2]

    def _once(self, bx, by, bzt):
        """(dx, dy, dzt) of the regularised (N), and G dx per group."""
        parts = np.split(self._lu.solve(np.concatenate([bx, by, *(b.ravel() for b in bzt.values())])),
                         self._split)
        dx, dy = parts[0], parts[1]
        dzt = {d: part.reshape(-1, d) for d, part in zip(bzt, parts[2:])}
        Gdx = {d: (G @ dx).reshape(-1, d) for d, G in self.st.G.items()}
        return dx, dy, dzt, (Gdx, None)           # E^T dy: the residual makes it
