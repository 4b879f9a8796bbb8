"""The sparse Cholesky factorisation of the reduced Newton matrix: CHOLMOD's supernodal
LL^T (Chen, Davis, Hager & Rajamanickam, ACM TOMS 35, 2008) through the ``cvxopt`` wheel,
which ships it (``pip install`` only; book, "How a step is solved", for the choice).

The pattern is fixed for a problem: the ordering and the symbolic analysis (supernodes)
are done once (:class:`Cholesky`), the numeric factorisation once an interior-point
iteration (:meth:`Cholesky.factor`), and each solve reuses it.
"""
import numpy as np


class CholeskyError(ArithmeticError):
    """The matrix is not numerically positive definite."""


class Cholesky:
    """LL^T of a symmetric positive definite matrix of a fixed pattern given by its lower
    triangle's (rows, cols), n x n (supernodal: CHOLMOD's choice, by the pattern)."""

    def __init__(self, rows, cols, n):
        from cvxopt import cholmod, matrix, spmatrix
        self._cholmod, self._matrix, self._spmatrix = cholmod, matrix, spmatrix
        self.n = n
        self.factorisations = 0
        if n == 0:                                   # no equality: nothing to factorise
            return
        self._I = matrix(np.asarray(rows, dtype=np.int32).astype(int))
        self._J = matrix(np.asarray(cols, dtype=int))
        cholmod.options["supernodal"] = 2            # CHOLMOD's default: automatic
        self._A = spmatrix(1.0, self._I, self._J, (n, n))
        self._F = cholmod.symbolic(self._A, uplo="L")
        # the values are handed over in place, in the matrix's compressed-column order
        # (by column, then row), not rebuilt from triplets (a sort) each iteration
        self._order = np.lexsort((np.asarray(rows), np.asarray(cols)))
        if np.array_equal(self._order, np.arange(self._order.size)):
            self._order = None                       # given in that order already

    def factor(self, values):
        """The numeric factorisation with the lower triangle's ``values`` (in the order of
        the pattern's (rows, cols))."""
        self.factorisations += 1
        if self.n == 0:
            return
        values = np.asarray(values, dtype=float)
        self._A.V = self._matrix(values if self._order is None else values[self._order])
        try:
            self._cholmod.numeric(self._A, self._F)
        except ArithmeticError as error:
            raise CholeskyError(f"the reduced Newton matrix is not positive definite "
                                f"({error})") from None

    def solve(self, b):
        """x with L L^T x = b (b a vector or an (n, k) array)."""
        if self.n == 0:
            return np.zeros(np.shape(b))
        B = self._matrix(np.array(b, dtype=float, order="F").reshape(self.n, -1))
        self._cholmod.solve(self._F, B)
        out = np.array(B)
        return out.ravel() if np.ndim(b) == 1 else out
