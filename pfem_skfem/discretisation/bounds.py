"""Operators of the two bounding elements of limit analysis (plane strain).

Both elements keep one stress (or one strain-rate cone) per element vertex: point
``3 e + j`` of a field is vertex ``mesh.t[j, e]`` of element ``e``, the ordering of
scikit-fem's discontinuous P1 element, so the two elements' fields line up.

* Upper bound (Makrodimopoulos & Martin 2007, IJNAMG 31): the thesis' P2 velocities,
  whose strain rate is linear in each element, with the flow rule imposed at the
  three vertices instead of the thesis' points (1/6, 4/6, 1/6). :func:`vertex_discretise`
  gives the thesis' bases with the vertex rule (weights A/3), so that ``assemble_B``
  returns rows w_j eps(u)(x_j) at the vertices.
* Lower bound (Sloan 1988; Makrodimopoulos & Martin 2006, IJNME 66): a linear stress
  in each element, discontinuous between elements. :class:`LowerBoundOperators` holds
  the linear maps of its constraints: equilibrium inside each element (two rows), the
  traction sigma n at each end of each edge (two rows), the edge lengths and normals.
"""
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from skfem import Basis, ElementDG, ElementTriP1, MeshTri

from .elements import displacement_element
from .static import Discretisation, check_mesh

#: the vertex rule on the reference triangle: exact for linear integrands, weights A / 3
VERTEX_RULE = (np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]), np.full(3, 1.0 / 6.0))


def vertex_discretise(mesh):
    """The thesis' P2 velocities with one stress point at each element vertex (weight A/3).

    ``assemble_B`` of the result is the upper-bound element's B: row block j of element e
    is (A_e / 3) eps(u) at vertex ``mesh.t[j, e]``; ``weights`` are A_e / 3.
    """
    if type(mesh) is not MeshTri:
        raise TypeError("the bounding elements need a straight-sided skfem.MeshTri, got "
                        f"{type(mesh).__name__}")
    check_mesh(mesh)
    basis_u = Basis(mesh, displacement_element(), quadrature=VERTEX_RULE)
    return Discretisation(mesh, basis_u, basis_u.with_element(ElementDG(ElementTriP1())))


def element_gradients(mesh):
    """Gradients of the barycentric coordinates: (n_el, 3, 2), and the element areas."""
    p = mesh.p[:, mesh.t]                                   # (2, 3, n_el)
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    det = e1[0] * e2[1] - e1[1] * e2[0]                     # +-2 A (either orientation)
    # grad lambda_1 = (e2_y, -e2_x) / det, grad lambda_2 = (-e1_y, e1_x) / det
    g1 = np.stack([e2[1], -e2[0]]) / det
    g2 = np.stack([-e1[1], e1[0]]) / det
    g = np.stack([-g1 - g2, g1, g2], axis=1)                # (2, 3, n_el)
    return g.transpose(2, 1, 0), 0.5 * np.abs(det)


@dataclass
class LowerBoundOperators:
    """The linear maps of the lower-bound element on ``mesh``.

    Stress unknowns are (sx, sy, sz, sxy) at the 3 n_el element vertices, point-major
    (entry 4 p + k), as the other stress fields of the project.

    equilibrium : (2 n_el, 4 n_p) div sigma per element, rows (x, y) element-major;
    area : (n_el,) element areas.
    """

    mesh: MeshTri
    equilibrium: sp.csr_matrix
    area: np.ndarray

    @classmethod
    def build(cls, mesh):
        g, area = element_gradients(mesh)
        n_el = mesh.t.shape[1]
        e = np.repeat(np.arange(n_el), 3)                   # element of each point
        pts = np.arange(3 * n_el)
        gx, gy = g[:, :, 0].ravel(), g[:, :, 1].ravel()
        # d sx/dx + d sxy/dy (row 2e) and d sxy/dx + d sy/dy (row 2e + 1)
        rows = np.concatenate([2 * e, 2 * e, 2 * e + 1, 2 * e + 1])
        cols = np.concatenate([4 * pts, 4 * pts + 3, 4 * pts + 3, 4 * pts + 1])
        vals = np.concatenate([gx, gy, gx, gy])
        Q = sp.csr_matrix((vals, (rows, cols)), shape=(2 * n_el, 12 * n_el))
        return cls(mesh, Q, area)

    @property
    def n_points(self):
        return 3 * self.mesh.t.shape[1]

    def point(self, element, vertex):
        """Stress point of ``element`` at mesh node ``vertex`` (arrays of equal length)."""
        element, vertex = np.asarray(element), np.asarray(vertex)
        local = np.argmax(self.mesh.t[:, element] == vertex[None, :], axis=0)
        if not np.all(self.mesh.t[local, element] == vertex):
            raise ValueError("a vertex is not a node of its element")
        return 3 * element + local

    def traction(self, points, normals):
        """(2 m, 4 n_p) sigma n at the given points for unit normals (m, 2), rows (x, y)
        per point: t_x = sx n_x + sxy n_y, t_y = sxy n_x + sy n_y."""
        points, normals = np.asarray(points), np.asarray(normals, dtype=float)
        m = points.size
        r = np.arange(m)
        rows = np.concatenate([2 * r, 2 * r, 2 * r + 1, 2 * r + 1])
        cols = np.concatenate([4 * points, 4 * points + 3, 4 * points + 3, 4 * points + 1])
        vals = np.concatenate([normals[:, 0], normals[:, 1], normals[:, 0], normals[:, 1]])
        return sp.csr_matrix((vals, (rows, cols)), shape=(2 * m, 4 * self.n_points))

    def facet_geometry(self, facets):
        """Lengths (m,) and unit normals (m, 2) of facets, the normal pointing out of the
        facet's first element ``mesh.f2t[0]``."""
        mesh = self.mesh
        a, b = mesh.p[:, mesh.facets[0, facets]], mesh.p[:, mesh.facets[1, facets]]
        d = b - a
        length = np.hypot(*d)
        n = np.stack([d[1], -d[0]]) / length
        centre = mesh.p[:, mesh.t[:, mesh.f2t[0, facets]]].mean(axis=1)
        mid = 0.5 * (a + b)
        flip = np.einsum("ij,ij->j", n, mid - centre) < 0   # point away from the element
        n[:, flip] *= -1
        return length, n.T

    def interior_continuity(self):
        """(4 n_f, 4 n_p): the jump of sigma n at both ends of every interior facet (the
        statically admissible discontinuity: normal and shear tractions continuous)."""
        mesh = self.mesh
        facets = np.flatnonzero(mesh.f2t[1] >= 0)
        _, n = self.facet_geometry(facets)
        blocks = []
        for end in (0, 1):
            v = mesh.facets[end, facets]
            left = self.traction(self.point(mesh.f2t[0, facets], v), n)
            right = self.traction(self.point(mesh.f2t[1, facets], v), n)
            blocks.append(left - right)
        return sp.vstack(blocks).tocsr()

    def point_coordinates(self):
        """(n_p, 2) coordinates of the stress points (the element vertices)."""
        return self.mesh.p[:, self.mesh.t.T.ravel()].T
