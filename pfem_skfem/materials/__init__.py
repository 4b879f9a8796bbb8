"""Materials: the physics of the package (numpy and cvxpy; no other module of it).

* :mod:`~pfem_skfem.materials.elastic`: isotropic elasticity (3.9)-(3.10);
* :mod:`~pfem_skfem.materials.criteria`: the yield criteria of App A as second-order cones;
* :mod:`~pfem_skfem.materials.axisymmetric`: the cones of axisymmetry (Ch 7);
* :mod:`~pfem_skfem.materials.pfem`: :class:`PFEMMaterial`, what the PFEM engine asks of
  a material, and the materials of the PFEM runs ([80]; :class:`RegionCones` for regions
  of different materials);
* :mod:`~pfem_skfem.materials.rate`: mu(I) and the rate terms of the dynamic step;
* :mod:`~pfem_skfem.materials.fluids`: water and mud (Newtonian and Bingham fluids);
* :mod:`~pfem_skfem.materials.softening`: strain softening (Tresca, Mohr-Coulomb);
  :mod:`~pfem_skfem.materials.softening_axisymmetric`: the same in axisymmetry.

Stresses are tension positive and ordered (sx, sy, sz, sxy) as in (3.23).
"""
from .checks import _check_angle, _check_positive, _is_real, check_cohesion
from .elastic import Elastic
from .criteria import (DruckerPrager, MohrCoulomb, Tresca, TrescaField, YieldCriterion, davis,
                       mohr_coulomb_radius)
from .axisymmetric import (DP_MATCHES, MohrCoulombAxisymmetric, TrescaAxisymmetric,
                           TrescaField3, VonMisesField, drucker_prager_match,
                           drucker_prager_radius, mohr_coulomb_pair_radii, zero_dilation_cone)
from .pfem import (CohesiveTresca, DavisMohrCoulomb, PFEMMaterial, RegionCones,
                   ZeroDilationDruckerPrager, ZeroDilationMohrCoulomb,
                   ZeroDilationMohrCoulombAxisymmetric)
from .rate import MuIRheology, MuIRheologyAxisymmetric, RateDissipation, ViscousStress
from .softening import (ExponentialSoftening, FractureEnergy, LinearSoftening,
                        NonlocalAverage, SofteningMohrCoulomb, SofteningStep, SofteningTresca)
from .softening_axisymmetric import (SofteningMohrCoulombAxisymmetric,
                                     SofteningTrescaAxisymmetric)
from .fluids import (BinghamFluid, BinghamFluidAxisymmetric, NewtonianFluid,
                     NewtonianFluidAxisymmetric)

__all__ = ["Elastic", "check_cohesion",
           "YieldCriterion", "MohrCoulomb", "Tresca", "DruckerPrager", "TrescaField",
           "mohr_coulomb_radius", "davis",
           "DP_MATCHES", "MohrCoulombAxisymmetric", "TrescaAxisymmetric", "TrescaField3",
           "VonMisesField", "drucker_prager_match", "drucker_prager_radius",
           "mohr_coulomb_pair_radii", "zero_dilation_cone",
           "PFEMMaterial", "ZeroDilationMohrCoulomb", "DavisMohrCoulomb", "CohesiveTresca",
           "ZeroDilationDruckerPrager", "ZeroDilationMohrCoulombAxisymmetric", "RegionCones",
           "MuIRheology", "MuIRheologyAxisymmetric", "ViscousStress", "RateDissipation",
           "NewtonianFluid", "BinghamFluid", "NewtonianFluidAxisymmetric",
           "BinghamFluidAxisymmetric", "LinearSoftening", "ExponentialSoftening",
           "FractureEnergy", "NonlocalAverage", "SofteningTresca", "SofteningMohrCoulomb", "SofteningStep",
           "SofteningTrescaAxisymmetric", "SofteningMohrCoulombAxisymmetric"]
