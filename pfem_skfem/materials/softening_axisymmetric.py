"""Strain softening in axisymmetry: the softening Tresca and Mohr-Coulomb of
:mod:`pfem_skfem.materials.softening` on the three principal pairs (issue 55).

Beyond the thesis. The stresses are (s_rr, s_zz, s_tt, s_rz) (the hoop stress s_tt principal,
:mod:`pfem_skfem.materials.axisymmetric`); the cone of a step is that of the perfectly plastic
axisymmetric Tresca, :class:`~pfem_skfem.materials.axisymmetric.TrescaField3` with the same
radius k_j = 2 c(gamma^p_j) for its three pairs, max over principal pairs |s_i - s_j| <= 2 c
(Mohr-Coulomb with zero dilation: k_j = max(2 c cos(phi) - 2 p_j sin(phi), k_min) at the lagged
p = I1/3, as :class:`~pfem_skfem.materials.ZeroDilationMohrCoulombAxisymmetric`). The strength
is data of each step, the step convex, as in plane strain.

The plastic strain increment keeps its hoop row: Delta eps^p = eps(du) - C^-1 (sigma_{n+1} -
sigma_n), (rr, zz, tt, 2rz) (:func:`~pfem_skfem.materials.softening.plastic_strain_increment`,
unchanged: B's hoop row integrates u_r / r). Its measure (:func:`axisymmetric_shear_invariant`)
is the Tresca dissipation per unit strength. With the principal increments m +- R in the
(r, z) plane (m = (de_rr + de_zz) / 2, 2R = sqrt((de_rr - de_zz)^2 + dg_rz^2)) and de_tt,

.. math::
    D(\\Delta\\varepsilon^p) = \\sup_{|s_i - s_j| \\le 2c}
        \\textstyle\\sum_i s_i\\,\\Delta\\varepsilon_i
    = c \\sum_i |\\Delta\\varepsilon_i| \\quad (\\textstyle\\sum_i \\Delta\\varepsilon_i = 0)

and for an isochoric increment (de_tt = -2m: Tresca's flow, and zero dilation's)
sum |de_i| = 2 max(|m|, R) + 2 |m|, that is

.. math::
    \\Delta\\gamma^p = \\max\\bigl(\\Delta\\gamma_{rz},\\,
                      |\\Delta\\varepsilon^p_{\\theta\\theta}|\\bigr)
                      + |\\Delta\\varepsilon^p_{\\theta\\theta}|, \\qquad
    \\Delta\\gamma_{rz} = \\sqrt{(\\Delta\\varepsilon^p_{rr} - \\Delta\\varepsilon^p_{zz})^2
                               + (\\Delta\\gamma^p_{rz})^2}

Delta gamma_rz is the plane invariant (:func:`~pfem_skfem.materials.softening.shear_invariant`):
without a hoop increment the measure is the plane one exactly (whatever the in-plane strain);
in simple shear (dg_rz alone) it is the engineering shear strain; and c Delta gamma^p =
sigma . Delta eps^p on the cone, the plastic work, as in plane strain, so that a fracture
energy G_f = ell x int (c - c_r) dgamma^p keeps its meaning. Under uniaxial flow (axial -e,
radial and hoop e / 2) it is 2 e. (The deviator's norm sqrt(2 de' : de'), the shear rate of
mu(I) in axisymmetry, is also the plane one for an isochoric in-plane flow, but it is the von
Mises dissipation, sqrt(3) e under uniaxial flow: not Tresca's.)

A Bingham viscosity (eta > 0, :meth:`SofteningTrescaAxisymmetric.viscous`) is the viscous
stress of the axisymmetric Bingham fluid beside the cone: eta times the deviatoric rate with
its hoop component, sqrt(J2) = eta sqrt(2 D':D'), the von Mises norm. In simple shear (and
any isochoric flow without a hoop rate) it is the plane one, tau = c(gamma^p) + eta
gamma_dot^p; under uniaxial flow of axial plastic rate e_p, (s_rr - s_zz) / 2 = c + (3/2)
eta e_p = c + (3/4) eta gamma_dot^p, gamma^p being Tresca's measure (2 e_p) and the viscous
norm von Mises' (sqrt(3) e_p) (tests/test_softening_viscous.py, each step against its
recurrence).

Not built (refused by name): a Tresca residual strength c_r = 0 (the three cones need
positive radii).
"""
from dataclasses import dataclass

import numpy as np

from .axisymmetric import TrescaField3, mean_stress
from .rate import ViscousStress
from .softening import SofteningMohrCoulomb, SofteningTresca, point_sizes


def axisymmetric_shear_invariant(deps):
    """max(sqrt((de_rr - de_zz)^2 + dg_rz^2), abs(de_tt)) + abs(de_tt) of strains (n, 4)
    (rr, zz, tt, 2rz): the sum of the principal increments' magnitudes for an isochoric
    increment (the Tresca dissipation per unit strength; the module's docstring), the plane
    invariant where de_tt = 0."""
    deps = np.asarray(deps, dtype=float)
    hoop = np.abs(deps[:, 2])
    return np.maximum(np.hypot(deps[:, 0] - deps[:, 1], deps[:, 3]), hoop) + hoop


def axisymmetric_point_sizes(weights, points):
    """Element size sqrt(2 A) at each stress point, A = 3 w / (2 pi r) the area of its
    element (the weight w = (A / 3) 2 pi r of a point at radius r)."""
    r = np.asarray(points, dtype=float)[:, 0]
    return point_sizes(np.asarray(weights, dtype=float) / (2 * np.pi * r))


class _Axisymmetric:
    """The axisymmetric part of a softening material: the three Tresca pairs of its radii,
    the lagged mean stress I1/3, the hoop strain in gamma^p, the element size of the area."""

    geometries = ("axisymmetric",)

    def viscous(self, sigma_m, stress_scale, shear_rate, weights):
        """The step's viscous stress: :class:`~pfem_skfem.materials.rate.ViscousStress` of
        viscosity eta at every point, its deviator with the hoop component (``hoop``, as the
        axisymmetric Bingham fluid's); None for eta = 0."""
        if self.eta == 0:
            return None
        return ViscousStress(np.full(len(weights), float(self.eta)), weights, hoop=True)

    def criterion(self, gamma_p, size, sigma_m=None, stress_scale=1.0):
        """:class:`TrescaField3` of the plane material's radii k_j for each of the three
        principal pairs."""
        k = super().criterion(gamma_p, size, sigma_m, stress_scale).k
        return TrescaField3(np.vstack([k, k, k]))

    @staticmethod
    def mean_stress(sigma):
        """The lagged quantity: I1/3 (:func:`~pfem_skfem.materials.axisymmetric.mean_stress`)."""
        return mean_stress(sigma)

    def shear_strain(self, deps):
        """Delta gamma^p of plastic strain increments (n, 4):
        :func:`axisymmetric_shear_invariant`."""
        return axisymmetric_shear_invariant(deps)

    def sizes(self, weights, points):
        """Element size at each stress point: :func:`axisymmetric_point_sizes`."""
        return axisymmetric_point_sizes(weights, points)


@dataclass(frozen=True)
class SofteningTrescaAxisymmetric(_Axisymmetric, SofteningTresca):
    """:class:`~pfem_skfem.materials.softening.SofteningTresca` in axisymmetry: the exact
    Tresca of the three principal stresses (the hoop stress principal) at the step's strength,

    .. math::
        \\max_{i,j} |s_i - s_j| \\le 2\\,c(\\gamma^p_j)

    (:class:`~pfem_skfem.materials.axisymmetric.TrescaField3`, k = 2c for each pair), gamma^p
    accumulating :func:`axisymmetric_shear_invariant`. Parameters as the plane material;
    c_r > 0 (refused otherwise: not built); eta > 0 adds the viscous stress of
    :meth:`viscous`, its deviator with the hoop component.
    """

    name = "Tresca (axisymmetric, 3 cones), strain softening"
    counterpart = "SofteningTresca"

    def __post_init__(self):
        super().__post_init__()
        if self.law.c_r <= 0:
            raise ValueError(f"c_r (residual strength) = {self.law.c_r!r}: an axisymmetric "
                             f"Tresca of zero residual strength is not built (its three cones "
                             f"need positive radii); give c_r > 0")


@dataclass(frozen=True)
class SofteningMohrCoulombAxisymmetric(_Axisymmetric, SofteningMohrCoulomb):
    """:class:`~pfem_skfem.materials.softening.SofteningMohrCoulomb` in axisymmetry: the
    three pairs of :class:`~pfem_skfem.materials.ZeroDilationMohrCoulombAxisymmetric` with
    the softened cohesion,

    .. math::
        s_i - s_j \\le \\max\\bigl(2c(\\gamma^p_j)\\cos\\phi - 2\\sin\\phi\\,p_j,\\; k_{min}\\bigr)
        \\quad \\text{for every principal pair } (i, j)

    at the lagged mean stress p = I1/3; the flow isochoric (zero dilation), gamma^p
    accumulating :func:`axisymmetric_shear_invariant`; eta > 0 adds the viscous stress of
    :meth:`viscous`, as the Tresca's.
    """

    name = "Mohr-Coulomb (axisymmetric, 3 cones), zero dilation, cohesion softening"
    counterpart = "SofteningMohrCoulomb"
