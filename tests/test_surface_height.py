"""The height profile of a mesh's top (pfem.measure.surface_height)."""
from types import SimpleNamespace

import numpy as np

from pfem_skfem.pfem.measure import surface_height


def test_the_top_of_a_meshed_trapezoid_is_its_sloping_side():
    # a trapezoid (0,0) (2,0) (2,1) (0,2), cut into triangles with an inner vertex
    p = np.array([[0, 0], [2, 0], [2, 1], [0, 2], [1, 0.7]], dtype=float)
    t = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    x = np.array([0.0, 0.5, 1.0, 1.7, 2.0, 2.5])
    h = surface_height(SimpleNamespace(mesh_p=p, mesh_t=t), x)
    np.testing.assert_allclose(h[:5], 2 - x[:5] / 2, atol=1e-15)
    assert h[5] == -np.inf                    # beyond the body
