"""Operators of the dynamic problem (4.16)-(4.21), assembled by scikit-fem.

The dynamic forces r (4.16)-(4.19) use the displacement shape functions
(quadratic, six nodes) but are discontinuous between elements:
``ElementVector(ElementDG(ElementTriP2()))``. Their dofs are element-major, 12
per element (scikit-fem's ``element_dofs`` are contiguous), so

* A = int N_r^T N_u dV, shape (n_r, n_u), couples r to the displacements (4.21);
* D = int N_r^T rho~^-1 N_r dV (4.21, with N_r on both sides: the thesis text
  prints N_sigma, an extraction error) is block-diagonal, one 12 x 12 block per
  element, which is what makes the cone form of its quadratic term (App A) cheap.

With rho~ constant in each element, A^T D^-1 A = int rho~ N_u^T N_u dV, the
consistent mass matrix (4.26)-(4.27), because the discontinuous P2 space contains
the continuous one.

In axisymmetry ((7.27)-(7.28), ``disc.geometry``) every integral carries 2 pi r and
the quadrature rises by one order (degree 5); the identity holds unchanged, the
weight being part of the measure dV.
"""
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp
from skfem import Basis, BilinearForm, ElementDG, ElementTriP2, ElementVector, LinearForm
from skfem.helpers import dot

from .static import assemble_B, assemble_C
from .theta import ThetaMethod

#: quadrature order exact for the product of two quadratics (A, D, mass)
MASS_INTORDER = 4


def r_element():
    """Quadratic vector element, discontinuous between elements, for r (4.18)-(4.19)."""
    return ElementVector(ElementDG(ElementTriP2()))


def r_basis(disc):
    """scikit-fem basis of the dynamic forces r on the mesh of ``disc``."""
    return Basis(disc.mesh, r_element(), intorder=_mass_intorder(disc))


def _mass_intorder(disc):
    """MASS_INTORDER, raised by one in axisymmetry (the weight r)."""
    return disc.geometry.intorder(MASS_INTORDER)


def _volume_weight(basis, disc):
    """The weight of dV at the quadrature points of ``basis``: 1 or 2 pi r."""
    return disc.geometry.weight(np.array(basis.global_coordinates()))


def element_density(disc, rho):
    """Density per element, shape (n_elements,), from a number or an array; checked > 0."""
    rho = np.broadcast_to(np.asarray(rho, dtype=float), (disc.mesh.nelements,))
    if not np.all(np.isfinite(rho)) or np.any(rho <= 0):
        raise ValueError(f"rho (density) must be positive in every element, got min "
                         f"{float(np.min(rho))!r}")
    return np.array(rho)


def _per_element(basis, values):
    """A field constant per element, sampled at the quadrature points of ``basis``."""
    return np.repeat(values[:, None], basis.X.shape[1], axis=1)


def assemble_A(disc, basis_r=None):
    """A = int N_r^T N_u dV (4.21), shape (n_r, n_u): r^T A du = int r . du dV."""
    basis_r = basis_r or r_basis(disc)
    basis_u = basis_r.with_element(disc.basis_u.elem)
    if disc.geometry.axisymmetric:                  # (7.28)
        @BilinearForm
        def coupling_axi(u, r, w):
            return dot(u, r) * (2 * np.pi * w.x[0])
        return coupling_axi.assemble(basis_u, basis_r).tocsr()

    @BilinearForm
    def coupling(u, r, w):
        return dot(u, r)

    return coupling.assemble(basis_u, basis_r).tocsr()


def assemble_D(disc, rho_tilde, basis_r=None):
    """D = int N_r^T rho~^-1 N_r dV (4.21), block-diagonal (one 12 x 12 block per element).

    Parameters
    ----------
    rho_tilde : number or (n_elements,) array, rho / (theta1 theta2) (4.6).
    """
    basis_r = basis_r or r_basis(disc)
    inv_rho = 1.0 / element_density(disc, rho_tilde)

    @BilinearForm
    def weighted_mass(r, q, w):
        return w.inv_rho * dot(r, q)

    if disc.geometry.axisymmetric:                  # (7.27), N_r on both sides
        inv_rho_q = _per_element(basis_r, inv_rho) * _volume_weight(basis_r, disc)
        return weighted_mass.assemble(basis_r, inv_rho=inv_rho_q).tocsr()
    return weighted_mass.assemble(basis_r, inv_rho=_per_element(basis_r, inv_rho)).tocsr()


def element_blocks(D, basis_r):
    """The diagonal blocks of a block-diagonal D as an (n_elements, 12, 12) array."""
    dofs = basis_r.element_dofs                       # (12, n_elements)
    n_loc, n_el = dofs.shape
    element = np.empty(D.shape[0], dtype=int)
    local = np.empty(D.shape[0], dtype=int)
    element[dofs] = np.arange(n_el)[None, :]
    local[dofs] = np.arange(n_loc)[:, None]
    coo = D.tocoo()
    if np.any(element[coo.row] != element[coo.col]):
        raise ValueError("D couples different elements: it is not block-diagonal")
    blocks = np.zeros((n_el, n_loc, n_loc))
    np.add.at(blocks, (element[coo.row], local[coo.row], local[coo.col]), coo.data)
    return blocks


def block_cholesky(D, basis_r):
    """Sparse G with D = G^T G, G block upper-triangular per element (App A, (A.4)-(A.8)).

    Rows of G are element-major like the r dofs, so ``(G @ r).reshape(-1, 12)``
    gives one row per element and the quadratic term r^T D r = sum_e |G_e r_e|^2.
    """
    blocks = element_blocks(D, basis_r)
    upper = np.transpose(np.linalg.cholesky(blocks), (0, 2, 1))
    dofs = basis_r.element_dofs.T                     # (n_elements, 12)
    n_el, n_loc = dofs.shape
    rows = np.repeat(np.arange(n_el * n_loc).reshape(n_el, n_loc)[:, :, None], n_loc, axis=2)
    cols = np.repeat(dofs[:, None, :], n_loc, axis=1)
    return sp.csr_matrix((upper.ravel(), (rows.ravel(), cols.ravel())), shape=D.shape)


def mass_matrix(disc, rho):
    """Consistent mass int rho N_u^T N_u dV with rho a number or one value per element."""
    rho_e = element_density(disc, rho)
    basis = Basis(disc.mesh, disc.basis_u.elem, intorder=_mass_intorder(disc))

    @BilinearForm
    def mass(u, v, w):
        return w.rho * dot(u, v)

    if disc.geometry.axisymmetric:
        rho_q = _per_element(basis, rho_e) * _volume_weight(basis, disc)
        return mass.assemble(basis, rho=rho_q).tocsr()
    return mass.assemble(basis, rho=_per_element(basis, rho_e)).tocsr()


def gravity_vector(disc, rho, g, direction=(0.0, -1.0)):
    """Self-weight int N_u^T rho g e dV with rho a number or one value per element."""
    rho_e = element_density(disc, rho)
    if not np.isfinite(g) or g < 0:
        raise ValueError(f"g (gravitational acceleration) must be >= 0, got {g!r}")
    e = np.asarray(direction, dtype=float)
    basis = Basis(disc.mesh, disc.basis_u.elem, intorder=_mass_intorder(disc))

    @LinearForm
    def weight(v, w):
        return w.rho * g * (e[0] * v[0] + e[1] * v[1])

    if disc.geometry.axisymmetric:
        rho_q = _per_element(basis, rho_e) * _volume_weight(basis, disc)
        return weight.assemble(basis, rho=rho_q)
    return weight.assemble(basis, rho=_per_element(basis, rho_e))


def kinetic_energy(M, v):
    """1/2 v^T M v."""
    return 0.5 * float(v @ (M @ v))


def elastic_energy(C, sigma):
    """Complementary (= stored, for linear elasticity) energy 1/2 sigma^T C sigma."""
    s = np.asarray(sigma, dtype=float).ravel()
    return 0.5 * float(s @ (C @ s))


@dataclass
class DynamicOperators:
    """Matrices of (4.20)-(4.21) for one mesh, density and theta-method.

    B (3.41), C (3.43; None for a rigid-plastic material), A and D (4.21),
    M the consistent mass int rho N_u^T N_u (for energies and the velocity term),
    basis_r the basis of r; derived on first use: G with D = G^T G (block
    upper-triangular, for the cone form of the r^T D r term), K = B^T C^-1 B (the
    elastic stiffness), C_inverse, D_inverse (for the elastic predictor).
    """

    B: object
    C: object
    A: object
    D: object
    M: object
    theta: ThetaMethod
    basis_r: object = None

    @cached_property
    def G(self):
        return block_cholesky(self.D, self.basis_r)

    @cached_property
    def D_inverse(self):
        return block_inverse_elements(self.D)

    @cached_property
    def C_inverse(self):
        return None if self.C is None else block_inverse(self.C, 4)

    @cached_property
    def K(self):
        return None if self.C is None else (self.B.T @ self.C_inverse @ self.B).tocsr()

    @property
    def M_tilde(self):
        """A^T D^-1 A = M / (theta1 theta2) (4.26)-(4.27)."""
        return self.M / (self.theta.theta1 * self.theta.theta2)


def dynamic_operators(disc, rho, theta, elastic=None):
    """Assemble B, C, A, D and M for (4.23) (G, K and the inverses follow on first use).

    Parameters
    ----------
    disc : :class:`~pfem_skfem.discretisation.static.Discretisation`.
    rho : density, a number or one value per element.
    theta : :class:`ThetaMethod`.
    elastic : :class:`~pfem_skfem.materials.Elastic`, or None for rigid-plastic.
    """
    rho_e = element_density(disc, rho)
    basis_r = r_basis(disc)
    D = assemble_D(disc, theta.rho_tilde(rho_e), basis_r)
    return DynamicOperators(B=assemble_B(disc),
                            C=None if elastic is None else assemble_C(disc, elastic),
                            A=assemble_A(disc, basis_r), D=D,
                            M=mass_matrix(disc, rho_e), theta=theta, basis_r=basis_r)


def block_inverse_elements(D):
    """Inverse of D (4.21), block-diagonal with one 12 x 12 block per element."""
    return block_inverse(D, 12)


def block_inverse(M, size):
    """Inverse of a block-diagonal sparse matrix with consecutive square blocks of ``size``."""
    n = M.shape[0] // size
    coo = M.tocoo()
    keep = np.abs(coo.data) > 1e-12 * np.abs(coo.data).max()    # quadrature round-off
    coo = sp.coo_matrix((coo.data[keep], (coo.row[keep], coo.col[keep])), shape=M.shape)
    if np.any(coo.row // size != coo.col // size):
        raise ValueError("matrix is not block-diagonal")
    blocks = np.zeros((n, size, size))
    np.add.at(blocks, (coo.row // size, coo.row % size, coo.col % size), coo.data)
    inv = np.linalg.inv(blocks)
    rows = np.arange(n * size).reshape(n, size)
    return sp.csr_matrix((inv.ravel(), (np.repeat(rows[:, :, None], size, axis=2).ravel(),
                                        np.repeat(rows[:, None, :], size, axis=1).ravel())),
                         shape=M.shape)
