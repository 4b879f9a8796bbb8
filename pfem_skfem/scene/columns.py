"""A rectangular column of material on a floor against a wall, released: the scene of the
granular column collapse (thesis 6.4.3), the dam break and the slump benchmarks.
"""
from ..discretisation.theta import ThetaMethod
from ..problems.contact import RigidSegment
from .bodies import Body
from .config import PFEMConfig
from .regions import Region
from .scene import Scene

__all__ = ["column_scene"]


def column_scene(material, width, height, spacing, *, rho, g, dt, name="column", stress=None,
                 floor_friction=0.0, wall_friction=0.0, gate_removed_at=None, far=None,
                 body_names=("floor", "wall", "gate"), alpha=1.6, t_end=None, theta1=1.0,
                 theta2=1.0, **config):
    """A column ``width`` x ``height`` of ``material`` (particles ``spacing`` apart on a
    square lattice) standing on the floor y = 0 against the wall x = 0, and its initial
    state.

    Parameters
    ----------
    material, rho, name, stress : the column's :class:`~pfem_skfem.scene.Region` (``stress``
        None: unstressed, or :class:`~pfem_skfem.scene.Geostatic`).
    g, dt : gravity (downwards) and the time step.
    floor_friction : friction coefficient of the floor.
    wall_friction : friction coefficient of the wall x = 0 and of the gate x = ``width``.
    gate_removed_at : None: no gate (the column released from the start); else the time at
        which the gate holding the column's other side goes (``np.inf``: it stays; 0: gone
        before the first step).
    far : how far the floor and the walls reach (default: 50 times the column's size).
    body_names : the names of the floor, the wall and the gate in the records.
    alpha, t_end : the :class:`~pfem_skfem.scene.Scene`'s; its length is ``height``.
    theta1, theta2 : the :class:`~pfem_skfem.discretisation.theta.ThetaMethod`'s.
    **config : the rest of the :class:`~pfem_skfem.scene.config.PFEMConfig` (passes, contact,
        solver, volume_correction, ...).

    Returns
    -------
    (state, scene)
    """
    far = 50 * max(width, height) if far is None else far
    floor, wall, gate = body_names
    column = Region(((0.0, 0.0), (width, 0.0), (width, height), (0.0, height)), material,
                    rho, spacing, stress=stress, name=name)
    bodies = (Body(floor, RigidSegment((-far, 0.0), (far, 0.0), floor_friction)),  # solid above
              Body(wall, RigidSegment((0.0, far), (0.0, -spacing), wall_friction)))  # solid right
    if gate_removed_at is not None:                                                 # solid left
        bodies += (Body(gate, RigidSegment((width, -spacing), (width, far), wall_friction),
                        removed_at=gate_removed_at),)
    numerics = PFEMConfig(theta=ThetaMethod(dt, theta1, theta2), **config)
    scene = Scene(regions=(column,), bodies=bodies, gravity=(0.0, -g), alpha=alpha,
                  t_end=t_end, length=height, config=numerics)
    return scene.initial_state(), scene
