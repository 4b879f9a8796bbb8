"""pfem_skfem: the Particle Finite Element Method for geomechanics with second-order
cone programming, after X. Zhang, *Particle Finite Element Method in Geomechanics*,
PhD thesis, University of Newcastle, 2014.

Stages (each a module, arrays in and out):
``elements`` / ``operators`` (discretisation, scikit-fem), ``materials`` (elasticity,
yield cones), ``problems`` (one cvxpy problem per thesis formulation, solved by
Clarabel), ``pfem`` (alpha-shape detection, remeshing, mapping), ``drivers``
(load control, time stepping), ``report`` (verification contract), ``viz``/``io``.
"""
__version__ = "0.1.0"
