"""A rectangular column of material on a floor against a wall, released: the scene of the
granular column collapse (thesis 6.4.3), the dam break and the slump benchmarks.
"""
from dataclasses import dataclass, field, fields

from ..discretisation.theta import ThetaMethod
from ..problems.contact import RigidSegment
from .bodies import Body
from .config import PFEMConfig
from .regions import Region
from .scene import Scene

__all__ = ["Column", "column_scene"]


@dataclass(frozen=True)
class Column:
    """A column ``width`` x ``height`` of ``material`` (particles ``spacing`` apart on a
    square lattice) standing on the floor y = 0 against the wall x = 0: the parameters of
    the scene, which :meth:`scene` builds.

    Attributes
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
    config : the rest of the :class:`~pfem_skfem.scene.config.PFEMConfig` (passes, contact,
        solver, volume_correction, ...), a dict.
    """

    material: object
    width: float
    height: float
    spacing: float
    rho: float
    g: float
    dt: float
    name: str = "column"
    stress: object = None
    floor_friction: float = 0.0
    wall_friction: float = 0.0
    gate_removed_at: float = None
    far: float = None
    body_names: tuple = ("floor", "wall", "gate")
    alpha: float = 1.6
    t_end: float = None
    theta1: float = 1.0
    theta2: float = 1.0
    config: dict = field(default_factory=dict)

    def scene(self):
        """The :class:`~pfem_skfem.scene.Scene` of the column, its floor, wall and gate."""
        far = 50 * max(self.width, self.height) if self.far is None else self.far
        w, h, s = self.width, self.height, self.spacing
        floor, wall, gate = self.body_names
        column = Region(((0.0, 0.0), (w, 0.0), (w, h), (0.0, h)), self.material, self.rho, s,
                        stress=self.stress, name=self.name)
        bodies = (Body(floor, RigidSegment((-far, 0.0), (far, 0.0), self.floor_friction)),
                  Body(wall, RigidSegment((0.0, far), (0.0, -s), self.wall_friction)))
        if self.gate_removed_at is not None:   # the solid: above the floor, right of the wall
            bodies += (Body(gate, RigidSegment((w, -s), (w, far), self.wall_friction),  # left
                            removed_at=self.gate_removed_at),)
        numerics = PFEMConfig(theta=ThetaMethod(self.dt, self.theta1, self.theta2), **self.config)
        return Scene(regions=(column,), bodies=bodies, gravity=(0.0, -self.g), alpha=self.alpha,
                     t_end=self.t_end, length=h, config=numerics)


_FIELDS = {f.name for f in fields(Column)} - {"config"}


def column_scene(material, width, height, spacing, **parameters):
    """(state, scene) of a :class:`Column` of ``material``; ``parameters`` are its other
    attributes (``rho``, ``g``, ``dt`` needed) and the rest of its PFEMConfig (passes, contact,
    solver, volume_correction, ...)."""
    config = {k: v for k, v in parameters.items() if k not in _FIELDS}
    column = Column(material, width, height, spacing, config=config,
                    **{k: v for k, v in parameters.items() if k in _FIELDS})
    scene = column.scene()
    return scene.initial_state(), scene
