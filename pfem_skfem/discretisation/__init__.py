"""The assembly in space and time, by scikit-fem (thesis Ch 3, 4 and 7).

* :mod:`.elements` - the P2 displacement and Gauss-point stress elements (3.2);
* :mod:`.geometry` - plane strain or axisymmetry: the stress rows and dV (3.1, 7.2);
* :mod:`.static` - B, C, loads, tractions, masses and boundary dofs (3.41)-(3.43);
* :mod:`.dynamic` - the dynamic forces' A, D, M and G (4.16)-(4.21),
  :class:`DynamicOperators` and the block inverses;
* :mod:`.theta` - :class:`ThetaMethod`, the time stepping (4.3)-(4.11);
* :mod:`.fields` - vertex dofs, values at vertices and points, plastic strain;
* :mod:`.pressure` - the P1 pore pressure of a saturated soil and its operators;
* :mod:`.periodic`, :mod:`.meshes` - periodic ties and mesh generators.
"""
from .dynamic import DynamicOperators, dynamic_operators
from .static import Discretisation, axis_dofs, check_mesh, discretise
from .theta import ThetaMethod

__all__ = ["Discretisation", "DynamicOperators", "ThetaMethod", "axis_dofs", "check_mesh",
           "discretise", "dynamic_operators"]
