"""Steady flow down an incline on a periodic strip: a layer's exact profiles.

A strip one element wide, periodic in x (the two ends' dofs tied,
:mod:`pfem_skfem.discretisation.periodic`), no-slip base, free surface, on a fixed mesh (a
uniform flow needs no remeshing), x along the slope; each step is the dynamic problem
(4.23) of a rigid-plastic PFEM material in
:func:`~pfem_skfem.problems.nonassociated.lagged_step`, run from rest (or from a given
profile). A uniform flow has closed-form steady profiles: mu(I)'s Bagnold profile
(``verification/inclined_plane_flow.py``), a Newtonian film's parabola and a Bingham
layer's plug over a sheared parabola (``verification/fluid_films.py``).
"""
from dataclasses import replace

import numpy as np

from ..discretisation import ThetaMethod, dynamic_operators
from ..discretisation.periodic import periodic_operators, periodic_tie
from ..discretisation.static import body_force_vector, discretise
from ..harness.progress import progress_bar
from ..problems.nonassociated import StepStart, lagged_step
from ..scene.config import PFEMConfig


def layer(h, ny):
    """The strip: width h / ny, ny x 1 squares cut in two; its P2 discretisation."""
    from skfem import MeshTri

    mesh = MeshTri.init_tensor(np.linspace(0.0, h / ny, 2), np.linspace(0.0, h, ny + 1))
    return discretise(mesh)


def profile_weights(z):
    """Trapezoid weights of the sorted heights z (integrals over the depth)."""
    dz = np.diff(z)
    w = np.zeros_like(z)
    w[:-1] += dz / 2
    w[1:] += dz / 2
    return w


def strip_flow(theta, h, material, rho, *, ny, steps, t_end, g, v0=None, verbose=False,
               **config):
    """Run the periodic layer of depth h at slope theta [deg] from rest (or from
    x-velocities ``v0(z)``) for ``steps`` implicit steps (theta1 = theta2 = 1) to t_end.

    ``material`` a rigid-plastic :class:`~pfem_skfem.materials.PFEMMaterial`, ``rho`` the
    layer's density; stresses are scaled by rho g h and the lagged mean stress starts
    geostatic.

    Returns dict(z, u) of the x-velocity on the end x = 0 (all P2 nodes, sorted by z), the
    time series t, surface and mean velocity, the steps' solver iterations and the mesh's
    element count.
    """
    disc = layer(h, ny)
    th = np.radians(theta)
    method = ThetaMethod(t_end / steps, 1.0, 1.0)
    T, kept = periodic_tie(disc, 0.0, h / ny)                 # kept: the dof of each column
    ops = periodic_operators(dynamic_operators(disc, rho, method), T)
    f = T.T @ body_force_vector(disc, (rho * g * np.sin(th), -rho * g * np.cos(th)))
    xy = disc.basis_u.doflocs[:, kept]
    along = np.zeros(disc.n_u, dtype=bool)
    along[np.concatenate([disc.basis_u.nodal_dofs[0], disc.basis_u.facet_dofs[0]])] = True
    along = along[kept]
    base = np.flatnonzero(np.abs(xy[1]) <= 1e-9 * h)
    end = np.flatnonzero(along & (np.abs(xy[0]) <= 1e-9 * h))
    end = end[np.argsort(xy[1, end])]
    top = end[-1]
    config = PFEMConfig(theta=method, **config)      # passes, solver, ...
    stress_scale = rho * g * h
    sigma_m = -rho * g * np.cos(th) * (h - disc.mesh.p[1])    # lagged: geostatic
    sigma = np.zeros((disc.n_points, 4))
    v = np.zeros(T.shape[1])
    if v0 is not None:
        v[along] = v0(xy[1, along])
    scales, t, surface, mean, iterations = None, [0.0], [v[top]], [np.mean(v[end])], []
    weights = profile_weights(xy[1, end])
    bar = progress_bar(range(steps), total=steps, desc=f"theta = {theta:g}, h = {h:.3g}",
                       unit="step", disable=not verbose)
    for n in bar:
        solved = lagged_step(ops, f, None, disc, material, StepStart(v, sigma, sigma_m, scales),
                             config=config, stress_scale=stress_scale, fixed=base)
        inc = solved.increment
        v, sigma, sigma_m = inc.v, inc.sigma, solved.sigma_m
        # the next step's scales, not below a free-fall step's (as pfem.assemble.step_scales):
        # a layer at rest would otherwise shrink the displacement scale without end
        scales = replace(inc.scales, displacement=max(inc.scales.displacement, g * method.dt ** 2),
                         dynamic_force=max(inc.scales.dynamic_force, rho * g))
        t.append((n + 1) * method.dt)
        surface.append(v[top])
        mean.append(weights @ v[end] / h)
        iterations.append(inc.info.iterations)
    return dict(z=xy[1, end], u=v[end], t=np.array(t), surface=np.array(surface),
                mean=np.array(mean), iterations=np.array(iterations), elements=disc.mesh.nelements)
