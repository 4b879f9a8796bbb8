"""The plastic shear strain gamma^p of a softening material through a PFEM step (issue 55).

Beyond the thesis (the model of Zhang, Sheng, Sloan & Bleyer, IJNME 112, 2017). gamma^p
lives where the stresses live, at the stress points of the mesh moved to t_n
(``PFEMState.gamma_p`` beside ``PFEMState.sigma``), and goes through a step in three
stages, each a function here:

* map (1c): at a remeshing the old points' values are mapped to the new points by the
  stresses' own scheme (``PFEMConfig.stress_mapping``: the bounded UEM by default, whose
  values lie within the range of the old ones around each old element, so gamma^p stays
  >= 0 and no larger than it was; another scheme's value is clipped at 0)
  (:func:`carried_strain`);
* solve (2a): the step's cone is the material's at the carried gamma^p, data of the step,
  so that the step stays convex (:func:`step_material`, the material's ``at_strain``);
* after the step: Delta eps^p = eps(du) - C^-1 (sigma_{n+1} - sigma_n) at each point, its
  shear invariant added to gamma^p (:func:`strain_update`): gamma^p never decreases at a
  point between remeshings. The update lags one step; the step control is a cap on the
  strength drop of a step (:func:`~pfem_skfem.materials.softening.strength_drop`, in the
  step record as ``softening_drop``), which the time-step policy
  :class:`~pfem_skfem.drivers.time_step.SofteningTimeStep` holds by halving dt.

A run without a softening material carries nothing (``gamma_p`` None): its steps are those
of the engine without this module, bit for bit.
"""
import numpy as np

from ..discretisation.fields import collapsed
from ..materials.softening import (NonlocalAverage, nonlocal_average,
                                   plastic_strain_increment, strength_drop)
from .mapping import map_stress
from .transfer import stress_options


def carried_strain(state, disc, source, stress_mapping):
    """gamma^p at the stress points of the step's mesh ``disc``.

    Parameters
    ----------
    state : the PFEMState at t_n (its ``gamma_p`` on its mesh moved to t_n, None: zero).
    disc : the step's Discretisation.
    source : the map source of a remeshing (:func:`~pfem_skfem.pfem.transfer.
        old_discretisation`), None on the first mesh; False: the step keeps the mesh.
    stress_mapping : the stresses' scheme (:func:`~pfem_skfem.pfem.mapping.map_stress`).

    Returns (n_points,) values >= 0.
    """
    if state.gamma_p is None or source is None:
        return np.zeros(disc.n_points)
    if source is False:
        return state.gamma_p
    old = source[0]
    values = state.gamma_p
    if len(values) != old.n_points:             # collapsed triangles left out of the source
        values = values.reshape(-1, 3)[~collapsed(state.mesh_p, state.mesh_t)].ravel()
    return np.maximum(map_stress(old, values, disc, stress_mapping,
                                 **stress_options(state, stress_mapping)), 0.0)


def step_material(material, gamma_p, disc):
    """The step's material: a softening one at the carried ``gamma_p`` (its element sizes
    those of ``disc``), any other as it is."""
    if not material.softening:
        return material
    return material.at_strain(gamma_p, material.sizes(disc.weights, disc.points))


def strain_update(material, ops, increment, sigma_n, disc, gamma_n):
    """gamma^p after the step and the step's strength drop (a fraction of c_p - c_r).

    Delta gamma^p is the shear invariant of eps(du) - C^-1 (sigma_{n+1} - sigma_n) at each
    stress point (:func:`~pfem_skfem.materials.softening.plastic_strain_increment`, with the
    step's B and C), averaged over the step's points with a
    :class:`~pfem_skfem.materials.softening.NonlocalAverage` regularisation; ``material`` the
    region's softening material.
    """
    deps = plastic_strain_increment(ops.B, increment.du, ops.C, increment.sigma, sigma_n,
                                    disc.weights)
    dgamma = material.shear_strain(deps)
    if isinstance(material.regularisation, NonlocalAverage):
        dgamma = nonlocal_average(disc.points, disc.weights,
                                  material.regularisation.length) @ dgamma
    gamma = gamma_n + dgamma
    return gamma, strength_drop(material, gamma_n, gamma,
                                material.sizes(disc.weights, disc.points))
