"""The pore-pressure field of a saturated soil: continuous P1 on the displacement's mesh.

Beyond the thesis (issue 54). Next to the P2 displacements and the Gauss-point stresses of
:mod:`.static`, the pore pressure p is continuous and linear on each triangle (scikit-fem's
``ElementTriP1``: one dof per vertex). With P2 displacements this is the Taylor-Hood pair,
stable (inf-sup) in the undrained limit where p becomes the multiplier of div du = 0; equal
order (P1 u, P1 p) would need a stabilisation.

The operators the consolidation step needs (:mod:`pfem_skfem.problems.consolidation`):

* ``to_points``: p at the stress points. The stress basis spans the linear fields of each
  element, so ``B^T kron(to_points, m) p`` is int alpha p div(v) dV exactly (m = (1, 1, 1, 0)):
  the total stress sigma' - alpha p I enters equilibrium through the stress rows of B;
* ``gradient`` and ``cell_volume``: grad p (constant on each triangle) and the element's
  volume, so that the Darcy dissipation ``int k/gamma_w |grad p - rho_w g|^2 dV`` is a sum of
  squares, element by element, exactly;
* ``storage``: the P1 mass int N_p^T N_p dV (the storage term (p - p_n)^2 / 2M);
* :func:`inflow_vector`: int q N_p dS over the facets of a prescribed inflow;
* :func:`drained_dofs`: the vertices of drained faces (p = p_bar there), refused unless
  every facet given lies on the boundary.

In axisymmetry (x the radius) every integral carries 2 pi r: the element volume is
2 pi r_c A (r_c the centroid's radius, exact for the constant grad p), the mass and the
facet integrals are raised by one quadrature order.
"""
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from skfem import Basis, BilinearForm, ElementTriP1, FacetBasis, LinearForm

from .fields import barycentric_at_points
from .geometry import PLANE_STRAIN, Geometry

#: the identity in the stored stress order (sx, sy, sz, sxy) (or (rr, zz, tt, rz))
IDENTITY = np.array([1.0, 1.0, 1.0, 0.0])


@dataclass
class PressureField:
    """The P1 pore-pressure basis of a :class:`~.static.Discretisation` and its operators.

    basis : skfem Basis (P1, one dof per vertex);
    to_points : (n_points, n_p) sparse, p at the stress points;
    gradient : (2 n_elements, n_p) sparse, grad p of each element, rows (element, x/y);
    cell_volume : (n_elements,) int dV over each element (area, or 2 pi r_c area); zero on
        a free-draining element (:func:`pressure_field`'s ``wet``);
    storage : (n_p, n_p) sparse, int N_p^T N_p dV (over the saturated elements);
    geometry : plane strain or axisymmetry (the weight of every integral).
    """

    basis: Basis
    to_points: sp.csr_matrix
    gradient: sp.csr_matrix
    cell_volume: np.ndarray
    storage: sp.csr_matrix
    geometry: Geometry = PLANE_STRAIN
    wet: np.ndarray = None          # the saturated elements (pressure_field's); None: all

    def drainable(self):
        """The vertices a drained condition may hold: the mesh's boundary vertices and
        those of free-draining elements (the saturated part's boundary with them)."""
        mesh = self.basis.mesh
        boundary = np.unique(mesh.facets[:, mesh.boundary_facets()])
        if self.wet is None:
            return boundary
        return np.union1d(boundary, mesh.t[:3, ~self.wet].ravel())

    @property
    def n_p(self):
        """Number of pore-pressure dofs (the mesh's vertices)."""
        return self.basis.N

    def total_stress_map(self):
        """(4 n_points, n_p) sparse: p -> p I at the stress points, point-major as sigma."""
        return sp.kron(self.to_points, IDENTITY[:, None], format="csr")


def pressure_field(disc, wet=None):
    """The P1 pore-pressure field on the mesh of ``disc`` (a Discretisation); ``wet`` (a
    boolean per element, or None: all) the saturated elements, the only ones its Darcy and
    storage integrals cover (``cell_volume`` zero and no storage elsewhere: a free-draining
    region's, whose p the caller holds). ``to_points`` covers every element: the total
    stress is the effective one less p everywhere."""
    mesh, geometry = disc.mesh, disc.geometry
    basis = Basis(mesh, ElementTriP1(), intorder=geometry.intorder(2))
    lam, e = barycentric_at_points(disc)
    vertices = mesh.t[:3].T[e]                                  # (n_points, 3)
    rows = np.repeat(np.arange(disc.n_points), 3)
    to_points = sp.csr_matrix((lam.ravel(), (rows, vertices.ravel())),
                              shape=(disc.n_points, basis.N))
    gradient, area = _element_gradients(mesh.p, mesh.t[:3], basis.N)
    centroid = mesh.p[:, mesh.t[:3]].mean(axis=1)
    cell_volume = area * geometry.weight(centroid)
    if wet is not None and np.all(wet):
        wet = None
    if wet is not None:                             # Darcy and storage on the wet only
        wet = np.asarray(wet, dtype=bool)
        cell_volume = np.where(wet, cell_volume, 0.0)
        basis_wet = Basis(mesh, ElementTriP1(), intorder=geometry.intorder(2),
                          elements=np.flatnonzero(wet))
        storage = _mass(geometry).assemble(basis_wet).tocsr()
    else:
        storage = _mass(geometry).assemble(basis).tocsr()
    return PressureField(basis, to_points, gradient, cell_volume, storage, geometry, wet)


def _element_gradients(p, t, n_p):
    """Gradients of the P1 hat functions on each triangle, (2 n_el, n_p), and the areas."""
    x, y = p[0, t], p[1, t]                                      # (3, n_el)
    twice_area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0])
    # grad lambda_i = (y_j - y_k, x_k - x_j) / 2A, (i, j, k) cyclic
    gx = np.stack([y[1] - y[2], y[2] - y[0], y[0] - y[1]]) / twice_area
    gy = np.stack([x[2] - x[1], x[0] - x[2], x[1] - x[0]]) / twice_area
    n_el = t.shape[1]
    rows = np.concatenate([np.tile(2 * np.arange(n_el), 3), np.tile(2 * np.arange(n_el) + 1, 3)])
    cols = np.concatenate([t.ravel(), t.ravel()])
    vals = np.concatenate([gx.ravel(), gy.ravel()])
    return sp.csr_matrix((vals, (rows, cols)), shape=(2 * n_el, n_p)), 0.5 * np.abs(twice_area)


def _mass(geometry):
    @BilinearForm
    def mass(u, v, w):
        return u * v * geometry.weight(w.x)
    return mass


def _facets_on_boundary(mesh, facets, what):
    facets = np.unique(np.asarray(facets, dtype=int).ravel())
    if facets.size == 0:
        raise ValueError(f"{what}: no facet given")
    if facets.min() < 0 or facets.max() >= mesh.facets.shape[1]:
        raise ValueError(f"{what}: facet index out of range [0, {mesh.facets.shape[1]})")
    inside = np.setdiff1d(facets, mesh.boundary_facets())
    if inside.size:
        raise ValueError(f"{what}: {inside.size} facet(s) are not on the boundary (e.g. "
                         f"facet {int(inside[0])}); a drained or inflow face must be")
    return facets


def drained_dofs(pressure, facets):
    """Pore-pressure dofs (vertices) of the drained faces ``facets``; ValueError unless every
    facet is a boundary facet of the mesh."""
    facets = _facets_on_boundary(pressure.basis.mesh, facets, "drained face")
    return np.unique(pressure.basis.get_dofs(facets).all())


def inflow_vector(pressure, facets, q):
    """int q N_p dS over the boundary ``facets``: the prescribed inflow (volume of water per
    unit area and time entering the soil; outflow negative), q constant or a callable of the
    coordinates x (2, ...). In axisymmetry dS = 2 pi r ds."""
    mesh = pressure.basis.mesh
    facets = _facets_on_boundary(mesh, facets, "inflow face")
    geometry = pressure.geometry
    fb = FacetBasis(mesh, pressure.basis.elem, facets=facets, intorder=4)

    @LinearForm
    def flux(v, w):
        qq = q(w.x) if callable(q) else float(q)
        return qq * v * geometry.weight(w.x)

    return flux.assemble(fb)


def element_flux(pressure, p, k_over_gamma_w, water_weight):
    """Darcy's flux q = - k/gamma_w (grad p - rho_w g) of each element, (n_elements, 2)."""
    grad = (pressure.gradient @ np.asarray(p, dtype=float)).reshape(-1, 2)
    return -k_over_gamma_w * (grad - np.asarray(water_weight, dtype=float)[None, :])
