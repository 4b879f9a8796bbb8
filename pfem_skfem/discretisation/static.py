"""Discrete operators of the static problem (3.41)-(3.43), assembled by scikit-fem.

Ordering. Displacement dofs are scikit-fem's (``basis_u``). The stress vector is
ordered point-major as in (3.28): entry ``4 p + k`` is component k in
(sx, sy, sz, sxy) at stress point p, so a stress field reshapes to (n_points, 4).

Geometry. A :class:`Discretisation` carries a
:class:`~pfem_skfem.discretisation.geometry.Geometry`: plane strain (the default) or
axisymmetry (thesis (7.24)-(7.28)), where x is the radius r, y the axis z, the
out-of-plane stress the hoop stress s_tt, the strain gains eps_tt = u_r / r and every
integral the weight 2 pi r, with the quadrature raised by one order (see
:mod:`pfem_skfem.discretisation.geometry`). The plane-strain forms are the same code as
before the geometry existed.
"""
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from skfem import Basis, BilinearForm, FacetBasis, LinearForm, MeshTri
from skfem.helpers import dot

from .elements import STRESS_INTORDER, displacement_element, stress_element
from .geometry import PLANE_STRAIN, Geometry, as_geometry, check_axisymmetric_mesh


@dataclass
class Discretisation:
    """A mesh with the P2 displacement basis and the Gauss-point stress basis."""

    mesh: MeshTri
    basis_u: Basis
    basis_s: Basis
    geometry: Geometry = PLANE_STRAIN

    @property
    def n_u(self):
        """Number of displacement dofs."""
        return self.basis_u.N

    @property
    def n_points(self):
        """Number of stress points (3 per element)."""
        return self.basis_s.N

    @property
    def points(self):
        """Coordinates of the stress points, shape (n_points, 2)."""
        return self.basis_s.doflocs.T

    @property
    def weights(self):
        """Integration weight of each stress point (a third of its element's area;
        in axisymmetry times 2 pi r at the point)."""
        return stress_mass(self).diagonal()

    @property
    def point_element(self):
        """Element that owns each stress point."""
        owner = np.empty(self.n_points, dtype=int)
        owner[self.basis_s.element_dofs] = np.arange(self.mesh.nelements)[None, :]
        return owner

    @property
    def area(self):
        """Sum of the stress-point weights: the area, or in axisymmetry the volume."""
        return float(self.weights.sum())


def check_mesh(mesh):
    """Raise ValueError for an empty or degenerate triangle mesh."""
    if mesh.t.shape[1] == 0 or mesh.p.shape[1] < 3:
        raise ValueError("mesh is empty: it needs at least one triangle")
    if not np.all(np.isfinite(mesh.p)):
        raise ValueError("mesh has non-finite node coordinates")
    x, y = mesh.p[0, mesh.t[:3]], mesh.p[1, mesh.t[:3]]
    twice_area = np.abs((x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]))
    # degenerate relative to the triangle's own size, so small elements are fine
    longest2 = np.max([(x[i] - x[j]) ** 2 + (y[i] - y[j]) ** 2
                       for i, j in ((0, 1), (1, 2), (2, 0))], axis=0)
    bad = twice_area <= 1e-10 * longest2
    if np.any(bad):
        raise ValueError(f"mesh is degenerate: {int(bad.sum())} triangle(s) have zero area")


def discretise(mesh, geometry=PLANE_STRAIN):
    """Bases of the thesis element (Fig 3.1, Fig 7.3) on a triangle mesh.

    Parameters
    ----------
    mesh : skfem.MeshTri (straight-sided) or skfem.MeshTri2 (curved, P2 geometry).
    geometry : :data:`~pfem_skfem.discretisation.geometry.PLANE_STRAIN` (default) or
        :data:`~pfem_skfem.discretisation.geometry.AXISYMMETRIC` (or their names 'plane',
        'axisymmetric'); in axisymmetry x is the radius and the mesh must lie in
        x >= 0 without crossing the axis (ValueError otherwise).
    """
    geometry = as_geometry(geometry)
    check_mesh(mesh)
    if geometry.axisymmetric:
        check_axisymmetric_mesh(mesh.p, mesh.t, getattr(mesh, "doflocs", None))
    basis_u = Basis(mesh, displacement_element(), intorder=STRESS_INTORDER)
    basis_s = basis_u.with_element(stress_element())
    return Discretisation(mesh, basis_u, basis_s, geometry)


# -- forms -------------------------------------------------------------------
@BilinearForm
def _mass(u, v, w):
    return u * v


@BilinearForm
def _mass_axi(u, v, w):
    return u * v * (2 * np.pi * w.x[0])


def _strain_row(k, geometry=PLANE_STRAIN):
    """Bilinear form q * eps_k(u) dV.

    Plane strain (3.24): eps = (du_x/dx, du_y/dy, 0, du_x/dy + du_y/dx), dV = dA.
    Axisymmetry (7.6)-(7.8): eps = (du_r/dr, du_z/dz, u_r / r, du_r/dz + du_z/dr),
    dV = 2 pi r dA; the hoop row is written q u_r 2 pi (the r cancels exactly).
    """
    if not geometry.axisymmetric:
        @BilinearForm
        def form(u, q, w):
            g = u.grad
            return q * (g[0][0], g[1][1], 0 * g[0][0], g[0][1] + g[1][0])[k]
        return form

    @BilinearForm
    def form_axi(u, q, w):
        g = u.grad
        two_pi_r = 2 * np.pi * w.x[0]
        return q * (two_pi_r * g[0][0], two_pi_r * g[1][1], 2 * np.pi * u[0],
                    two_pi_r * (g[0][1] + g[1][0]))[k]
    return form_axi


def stress_mass(disc):
    """Mass matrix of the scalar stress basis; diagonal because its nodes are the Gauss points.

    In axisymmetry it is the r-weighted mass integrated by the same 3-point rule:
    diagonal, w_p = (element area / 3) 2 pi r_p, whose row sums are exact
    (w_p = int N_p 2 pi r dA, a quadratic integrand).
    """
    if disc.geometry.axisymmetric:
        return _mass_axi.assemble(disc.basis_s).tocsr()
    return _mass.assemble(disc.basis_s).tocsr()


def assemble_B(disc):
    """B = int N_sigma^T B_u dV (3.41), (7.25), shape (4 n_points, n_u), rows point-major.

    In axisymmetry the integrand (degree 3 with the weight r) is integrated exactly
    at quadrature order 3.
    """
    geometry = disc.geometry
    basis_u, basis_s = disc.basis_u, disc.basis_s
    if geometry.axisymmetric:
        basis_u = Basis(disc.mesh, disc.basis_u.elem,
                        intorder=geometry.intorder(STRESS_INTORDER))
        basis_s = basis_u.with_element(stress_element())
    rows = [_strain_row(k, geometry).assemble(basis_u, basis_s) for k in range(4)]
    n = disc.n_points
    order = (np.arange(4)[None, :] * n + np.arange(n)[:, None]).ravel()  # 4p+k <- k n + p
    return sp.vstack(rows).tocsr()[order]


def assemble_C(disc, elastic):
    """C = int N_sigma^T C N_sigma dV (3.43): one 4x4 block w_p * C per stress point.

    The scalar stress mass is diagonal (its nodes are the quadrature points), so
    C = kron(M_sigma, C_4x4) with only the diagonal of M_sigma kept (its off-diagonal
    entries are rounding noise).
    """
    return sp.kron(sp.diags(stress_mass(disc).diagonal()), elastic.compliance(), format="csr")


def body_force_vector(disc, b):
    """int N_u^T b dV (first term of (3.42), (7.26)) for a constant body force b = (bx, by)."""
    b = np.asarray(b, dtype=float)
    if disc.geometry.axisymmetric:
        @LinearForm
        def load_axi(v, w):
            return (b[0] * v[0] + b[1] * v[1]) * (2 * np.pi * w.x[0])
        return load_axi.assemble(Basis(disc.mesh, disc.basis_u.elem,
                                       intorder=disc.geometry.intorder(STRESS_INTORDER)))

    @LinearForm
    def load(v, w):
        return b[0] * v[0] + b[1] * v[1]

    return load.assemble(disc.basis_u)


def traction_vector(disc, facets, t):
    """int N_u^T t dS (second term of (3.42)) for a traction t on the given facets.

    ``t`` is a constant (tx, ty) or a callable of the coordinates x (2, ...) returning it.
    In axisymmetry dS = 2 pi r ds (second term of (7.26)).
    """
    geometry = disc.geometry
    fb = FacetBasis(disc.mesh, disc.basis_u.elem, facets=np.asarray(facets),
                    intorder=geometry.intorder(4))

    @LinearForm
    def load(v, w):
        tt = t(w.x) if callable(t) else np.asarray(t, dtype=float)
        return tt[0] * v[0] + tt[1] * v[1]

    @LinearForm
    def load_axi(v, w):
        tt = t(w.x) if callable(t) else np.asarray(t, dtype=float)
        return (tt[0] * v[0] + tt[1] * v[1]) * (2 * np.pi * w.x[0])

    return (load_axi if geometry.axisymmetric else load).assemble(fb)


def consistent_mass(disc, rho):
    """Consistent mass matrix int rho N_u^T N_u dV of the P2 displacement basis."""
    _check_rho(rho)
    geometry = disc.geometry

    @BilinearForm
    def mass(u, v, w):
        return rho * dot(u, v)

    @BilinearForm
    def mass_axi(u, v, w):
        return rho * dot(u, v) * (2 * np.pi * w.x[0])

    return (mass_axi if geometry.axisymmetric else mass).assemble(
        Basis(disc.mesh, disc.basis_u.elem, intorder=geometry.intorder(4))).tocsr()


def _check_rho(rho):
    if not np.isfinite(rho) or rho <= 0:
        raise ValueError(f"rho (density) must be positive, got {rho!r}")


def stiffness_matrix(disc, elastic):
    """Standard P2 stiffness; a reference only.

    Plane strain: scikit-fem's linear_elasticity. Axisymmetry: int eps(v)^T E eps(u)
    2 pi r dA with the hoop strain u_r / r (the standard displacement element, not
    B^T C^-1 B: the hoop strain is not linear, so the stress space does not hold it).
    Its entries for u_r dofs on the axis are quadrature values of a divergent integral
    (u_r v_r / r); those dofs must be fixed (:func:`axis_dofs`).
    """
    if disc.geometry.axisymmetric:
        return _axisymmetric_stiffness(elastic).assemble(
            Basis(disc.mesh, disc.basis_u.elem, intorder=6)).tocsr()
    from skfem.models.elasticity import linear_elasticity
    return linear_elasticity(elastic.lame_lambda, elastic.shear_modulus).assemble(
        Basis(disc.mesh, disc.basis_u.elem, intorder=4)).tocsr()


def _axisymmetric_stiffness(elastic):
    """Standard axisymmetric elasticity form (7.6)-(7.8), isotropic, strains (rr, zz, tt, rz)."""
    lam, mu = elastic.lame_lambda, elastic.shear_modulus

    def strain(u, r):
        g = u.grad
        return g[0][0], g[1][1], u[0] / r, g[0][1] + g[1][0]

    @BilinearForm
    def form(u, v, w):
        r = w.x[0]
        eu, ev = strain(u, r), strain(v, r)
        tr_u, tr_v = eu[0] + eu[1] + eu[2], ev[0] + ev[1] + ev[2]
        normal = eu[0] * ev[0] + eu[1] * ev[1] + eu[2] * ev[2]
        return (lam * tr_u * tr_v + 2 * mu * normal + mu * eu[3] * ev[3]) * (2 * np.pi * r)

    return form


# -- boundary dofs ------------------------------------------------------------
def boundary_facets(disc, where):
    """Boundary facets whose midpoints x (2, n) satisfy ``where(x)``."""
    mesh = disc.mesh
    facets = mesh.boundary_facets()
    mid = mesh.p[:, mesh.facets[:, facets]].mean(axis=1)
    return facets[np.asarray(where(mid), dtype=bool)]


def boundary_dofs(disc, where, component):
    """Displacement dofs of one component (0 = x, 1 = y) on the facets selected by ``where``.

    Includes the corner and the midside nodes of those facets.
    """
    if component not in (0, 1):
        raise ValueError(f"component must be 0 (x) or 1 (y), got {component!r}")
    facets = boundary_facets(disc, where)
    return np.unique(disc.basis_u.get_dofs(facets).all(f"u^{component + 1}"))


def dof_coordinates(disc):
    """Coordinates (2, n_u) of every displacement dof."""
    return disc.basis_u.doflocs


def axis_dofs(disc):
    """Radial dofs u_r of every node (corner or midside) on the axis r = 0.

    The weak form of axisymmetry does not forbid u_r != 0 there; a body of
    revolution needs u_r = 0 on its axis, so add these to the fixed dofs. Empty in
    plane strain and for meshes away from the axis.
    """
    if not disc.geometry.axisymmetric:
        return np.zeros(0, dtype=int)
    x = disc.basis_u.doflocs
    scale = float(np.ptp(disc.mesh.p, axis=1).max()) or 1.0
    radial = disc.basis_u.nodal_dofs[0], disc.basis_u.facet_dofs[0]
    dofs = np.concatenate(radial)
    return np.sort(dofs[np.abs(x[0, dofs]) <= 1e-12 * scale])
