"""The rule that gives each element its region (density and cone), shared by the step's
mesh (`assemble.element_regions`) and the map source's (`transfer.old_regions`)."""
import numpy as np

from pfem_skfem.pfem.remesh import last_declared_region


def test_last_declared_region_ignores_vertices_without_a_particle():
    region = np.array([0, 1, 2, 0])                     # particle -> region
    t = np.array([[0, 1, 3],                            # regions 0, 1, 0: the later, 1
                  [0, 3, -1],                           # a thinned vertex counts for none
                  [2, -1, 0],                           # 2 beats 0 whatever the order
                  [-1, -1, -1]])                        # no particle at all: none (-1)
    assert last_declared_region(region, t).tolist() == [1, 0, 2, -1]
    # the thinned vertex's index must not wrap around to the last particle's region
    assert last_declared_region(np.array([0, 0, 5]), np.array([[0, 1, -1]])).tolist() == [0]
