"""Fields on a P2 / Gauss-point discretisation: vertex dofs, vertex <-> stress point
transfers, element means and the plastic strain increment.

Small array functions the PFEM stages share (:mod:`pfem_skfem.pfem.transfer`,
:mod:`pfem_skfem.pfem.surface`, :mod:`pfem_skfem.problems.nonassociated`, output).
"""
import numpy as np


def vertex_dofs(disc):
    """(n_vertices, 2) x and y displacement dofs at the mesh vertices."""
    return disc.basis_u.nodal_dofs.T


def barycentric_at_points(disc):
    """Area coordinates (n_points, 3) of each stress point in its element, and the element."""
    e = disc.point_element
    v = disc.mesh.p.T[disc.mesh.t[:3].T[e]]                    # (n, 3, 2)
    jac = np.stack([v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]], axis=2)
    xi = np.linalg.solve(jac, (disc.points - v[:, 0])[..., None])[..., 0]
    return np.column_stack([1 - xi.sum(axis=1), xi]), e


def vertex_to_points(disc, values):
    """A vertex field (linear in each element) at the stress points."""
    lam, e = barycentric_at_points(disc)
    return np.einsum("nk,nk->n", lam, np.asarray(values)[disc.mesh.t[:3].T[e]])


def element_mean(disc, values):
    """The weighted mean over each element of a stress-point field (n_points,) or (n_points, k)."""
    values = np.asarray(values, dtype=float)
    e, w, m = disc.point_element, disc.weights, disc.mesh.nelements
    area = np.bincount(e, w, minlength=m)
    flat = values.reshape(len(values), -1)
    mean = np.stack([np.bincount(e, w * flat[:, j], minlength=m) for j in range(flat.shape[1])],
                    axis=1) / area[:, None]
    return mean.reshape((m,) + values.shape[1:])


def smoothed_mean_stress(disc, sigma, mean=None):
    """sigma_m = (sx + sy)/2 smoothed onto the vertices: the element means averaged at each
    vertex, weighted by element area (a rigid zone's stresses are not unique, their mean is).

    ``mean`` : callable(sigma (n, 4)) -> (n,), the mean stress a material lags instead
    (e.g. I1/3, :func:`~pfem_skfem.materials.axisymmetric.mean_stress`); None: (sx + sy)/2.
    """
    sm = 0.5 * (sigma[:, 0] + sigma[:, 1]) if mean is None else mean(sigma)
    e = disc.point_element
    m = disc.mesh.nelements
    area = np.bincount(e, disc.weights, minlength=m)
    elem = np.bincount(e, disc.weights * sm, minlength=m) / area
    t = disc.mesh.t[:3]
    num = np.bincount(t.ravel(), np.tile(area * elem, 3), minlength=disc.mesh.nvertices)
    den = np.bincount(t.ravel(), np.tile(area, 3), minlength=disc.mesh.nvertices)
    return num / den


def collapsed(p, t):
    """Triangles of zero area relative to their size (as
    :func:`~pfem_skfem.discretisation.static.check_mesh`)."""
    v = p[t]
    e = v[:, [1, 2, 0]] - v
    twice_area = np.abs(e[:, 0, 0] * e[:, 2, 1] - e[:, 0, 1] * e[:, 2, 0])
    return twice_area <= 1e-10 * np.max(np.sum(e ** 2, axis=2), axis=1)


def plastic_strain_increment(disc, B, du, hoop=False):
    """Equivalent plastic strain increment sqrt((dexx - deyy)^2 + dgxy^2) at each stress point.

    With ``hoop`` (axisymmetry, strains (rr, zz, tt, rz)) the hoop strain counts: the
    shear strain sqrt(2 de':de') of the deviator de',

    .. math::
        \\sqrt{\\tfrac23\\bigl((e_{rr}-e_{zz})^2 + (e_{zz}-e_{tt})^2 + (e_{tt}-e_{rr})^2\\bigr)
        + \\gamma_{rz}^2}

    which is the in-plane one for an isochoric flow with e_tt = 0. For a rigid-plastic
    body the whole strain increment is plastic; strains are the rows of B du divided by
    the stress point's weight (B integrates N_sigma B_u).
    """
    e = (B @ du).reshape(-1, 4) / disc.weights[:, None]
    if not hoop:
        return np.sqrt((e[:, 0] - e[:, 1]) ** 2 + e[:, 3] ** 2)
    normal = (e[:, 0] - e[:, 1]) ** 2 + (e[:, 1] - e[:, 2]) ** 2 + (e[:, 2] - e[:, 0]) ** 2
    return np.sqrt(2.0 / 3.0 * normal + e[:, 3] ** 2)
