"""pfem_skfem: the Particle Finite Element Method for geomechanics with second-order
cone programming, after X. Zhang, *Particle Finite Element Method in Geomechanics*,
PhD thesis, University of Newcastle, 2014.

One PFEM step, from the scene to the moved particles (thesis Section 2.2; composed by
:func:`pfem_skfem.drivers.pfem_loop.pfem_step`, which times each stage):

1. particles   ``scene.Scene.initial_state``             step 0: the cloud C^0 of the regions
2. domain      ``pfem.alpha_shape.alpha_shape``           step 1a: the alpha-shape of the cloud
3. mesh        ``pfem.remesh.AlphaMesh``                  step 1b: the mesh of the domain
4. map         ``pfem.transfer.map_state``                step 1c: velocities, stresses onto it
5. assemble    ``pfem.assemble.assemble_operators``       (4.20)-(4.21) by ``discretisation``
6. solve       ``problems.nonassociated.lagged_step``     step 2a: (4.23) + (5.12), the SOCP
7. move        ``pfem.surface.move_particles``            step 2b: the particles moved
8. outlets     ``pfem.bookkeeping.discharge``             the particles that left

A 3 x 3 particle block on a rough base, stepped once (the stages' times, in order):

>>> from pfem_skfem.discretisation import ThetaMethod
>>> from pfem_skfem.drivers.pfem_loop import pfem_step
>>> from pfem_skfem.materials import ZeroDilationMohrCoulomb
>>> from pfem_skfem.problems.contact import RigidSegment
>>> from pfem_skfem.scene import Body, Region, Scene
>>> from pfem_skfem.scene.config import PFEMConfig
>>> block = Region(((0, 0), (0.2, 0), (0.2, 0.2), (0, 0.2)),
...                ZeroDilationMohrCoulomb(c=0.0, phi=30.0), rho=2.0, h=0.1)
>>> scene = Scene(regions=(block,), bodies=(Body("base", RigidSegment((-1, 0), (1, 0), 0.3)),),
...               gravity=(0.0, -9.8), length=0.2, config=PFEMConfig(theta=ThetaMethod(0.01)))
>>> state = scene.initial_state()                                         # 1
>>> new, record, result = pfem_step(state, scene)                         # 2-8
>>> state.n, result.disc.mesh.t.shape[1], new.n, new.time
(9, 8, 9, 0.01)
>>> [k for k in record if k.startswith("t_") and k not in ("t_compile", "t_conic")]
['t_detect', 't_remesh', 't_map', 't_assemble', 't_solve', 't_move']

The packages, in the order of the data flow: ``scene`` (the description and its
``config``), ``drivers`` (the loop, load control, time stepping), ``pfem`` (the stages and
their algorithms; ``pfem.measure`` what is measured on a cloud), ``problems`` (one
statement per thesis formulation, solved by Clarabel or through cvxpy), ``materials``
(elasticity, yield cones), ``discretisation`` (scikit-fem assembly in space and time);
beside them ``io`` (VTU/PVD), ``viz`` (figures) and ``report`` (the verification contract).
"""
__version__ = "0.1.0"
