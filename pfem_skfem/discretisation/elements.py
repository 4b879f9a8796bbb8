"""Finite elements of the thesis (Fig 3.1) as scikit-fem elements.

* displacements: quadratic, continuous (scikit-fem's ``ElementTriP2``, vector);
* stresses: linear, discontinuous between elements, with their three nodes at the
  stress points of area coordinates (1/6, 4/6, 1/6) (3.26)-(3.29), which are the
  points of the 3-point Gauss rule (``intorder=2``).

Because the stress nodes are the quadrature points, the stress mass matrix is
diagonal and the compliance matrix C (3.43) is block-diagonal, one 4x4 block per
stress point.
"""
import numpy as np
from skfem import ElementTriP2, ElementVector
from skfem.element.element_h1 import ElementH1
from skfem.refdom import RefTri

#: area coordinates of the thesis' stress points: point j has lambda_j = 4/6
STRESS_POINT_AREA_COORDS = np.array([[4 / 6, 1 / 6, 1 / 6],
                                     [1 / 6, 4 / 6, 1 / 6],
                                     [1 / 6, 1 / 6, 4 / 6]])

#: integration order whose rule is exactly the stress points (3-point Gauss)
STRESS_INTORDER = 2


class ElementTriStress(ElementH1):
    """Linear, element-wise discontinuous element with nodes at the Gauss points.

    Shape functions (3.29): N_j = 2 lambda_j - 1/3, so N_j = 1 at the point where
    lambda_j = 4/6 and 0 at the other two points. The reference triangle has
    lambda_0 = 1 - x - y, lambda_1 = x, lambda_2 = y; the nodes are ordered like
    scikit-fem's 3-point rule: (1/6, 1/6), (2/3, 1/6), (1/6, 2/3).
    """

    nodal_dofs = 0
    interior_dofs = 3
    maxdeg = 1
    dofnames = ["s", "s", "s"]
    doflocs = np.array([[1 / 6, 1 / 6],
                        [2 / 3, 1 / 6],
                        [1 / 6, 2 / 3]])
    refdom = RefTri

    def lbasis(self, X, i):
        x, y = X
        if i == 0:
            return 2 * (1 - x - y) - 1 / 3, np.array([-2 + 0 * x, -2 + 0 * x])
        if i == 1:
            return 2 * x - 1 / 3, np.array([2 + 0 * x, 0 * x])
        if i == 2:
            return 2 * y - 1 / 3, np.array([0 * x, 2 + 0 * x])
        self._index_error()


def displacement_element():
    """Quadratic vector element for the displacements (3.30)-(3.33)."""
    return ElementVector(ElementTriP2())


def stress_element():
    """Scalar linear discontinuous stress element (3.26)-(3.29); one per component."""
    return ElementTriStress()
