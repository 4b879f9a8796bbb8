"""Rigid bodies that close in on an incompressible material (issue 56 item 9, R11).

A rigid-plastic or fluid material keeps its area (its volume in axisymmetry). When the
rigid bodies close it in (a box with a lid) and their motions make the room they leave
smaller than the material, no step can satisfy both the flow rule and the contacts: the
closed box of squeeze.py with a 0.1 m gap, its right wall moving in at 0.5 m/s, reached
248 m/s in step 11, when the wall passed the block's side, and lost 6 % of the area before
the solver gave up in step 17. This module finds such a scene before any step.

The room is measured on a grid over the regions' bounding box widened by its size on every
side: the bodies' shapes at a time block the cells they pass through, the free cells that
hold particles are filled (side-neighbours only, which a blocked chain of corner-touching
cells stops), and the room is their area, plus half of the blocked cells along it. A fill
that reaches the grid's edge is open (not closed in, or in a container larger than the
grid): nothing is said of it.
"""
import numpy as np

from ..problems.contact import RigidCircle
from .bodies import Fixed

#: The room may fall to this fraction of the material's area (volume) before a scene is
#: refused: the grid's area is good to about 1 %, and a material that keeps its area
#: cannot be squeezed into less room at all.
MIN_ROOM = 0.95
#: cells along the grid's widest side (the box is three times the regions' extent)
CELLS = 300
#: the times of the run the room is measured at (and the motions' own breakpoints)
TIMES = 24


def _blocked(grid, body, d):
    """Mark in ``grid`` (lo, cell, mask) the cells that ``body``'s shape, translated by
    ``d``, passes through (a disc: its inside too)."""
    lo, cell, mask = grid
    shape = body.shape
    if isinstance(shape, RigidCircle):
        c = np.asarray(shape.center) + d
        ix, iy = np.indices(mask.shape)
        centres = lo + (np.stack([ix, iy], axis=-1) + 0.5) * cell
        mask |= np.linalg.norm(centres - c, axis=-1) <= shape.radius
        a = np.linspace(0, 2 * np.pi, max(int(6 * np.pi * shape.radius / cell), 16))
        pts = c + shape.radius * np.column_stack([np.cos(a), np.sin(a)])
    else:
        p = np.asarray(shape.points, dtype=float) + d
        pts = [p[:1]]
        for a, b in zip(p[:-1], p[1:]):                 # a third of a cell apart
            m = max(int(np.ceil(3 * np.linalg.norm(b - a) / cell)), 1)
            pts.append(a + (np.arange(1, m + 1) / m)[:, None] * (b - a))
        pts = np.vstack(pts)
    ij = np.floor((pts - lo) / cell).astype(int)
    ij = ij[np.all((ij >= 0) & (ij < mask.shape), axis=1)]
    mask[ij[:, 0], ij[:, 1]] = True


def room(bodies, displacements, particles, box, weight=None):
    """The room the bodies (each translated by its displacement) leave around the
    particles on their material side: the area (``weight`` per cell: the volume) of the
    free cells those particles are in, plus half of the blocked cells beside them; None
    when open (the fill reaches the grid's edge)."""
    from scipy import ndimage
    lo, cell, shape = box
    mask = np.zeros(shape, dtype=bool)
    for body, d in zip(bodies, displacements):
        _blocked((lo, cell, mask), body, d)
    labels, _ = ndimage.label(~mask)                   # side-neighbours
    for body, d in zip(bodies, displacements):         # the particles a body has passed
        particles = particles[body.shape.translated(d).gap(particles)[0] > 0]
    ij = np.floor((particles - lo) / cell).astype(int)
    ij = ij[np.all((ij >= 0) & (ij < shape), axis=1)]
    mine = np.setdiff1d(np.unique(labels[ij[:, 0], ij[:, 1]]), [0])
    if not len(mine):
        return None
    inside = np.isin(labels, mine)
    if inside[[0, -1], :].any() or inside[:, [0, -1]].any():
        return None
    beside = np.zeros_like(inside)                      # the blocked cells along it
    beside[1:] |= inside[:-1]
    beside[:-1] |= inside[1:]
    beside[:, 1:] |= inside[:, :-1]
    beside[:, :-1] |= inside[:, 1:]
    if weight is None:
        return float(cell * cell * (inside.sum() + 0.5 * (beside & mask).sum()))
    return float(weight[inside].sum() + 0.5 * weight[beside & mask].sum())


def check_room(scene, particles, steps=1000):
    """ValueError when the bodies of ``scene`` close in its material (rigid-plastic or
    fluid: no elasticity, no water, no outlet for it to leave by) and leave it less than :data:`MIN_ROOM` of its area
    (volume) before t_end (no t_end: the first ``steps`` steps), naming the moving bodies
    and the time the room falls below the material."""
    bodies = [b for b in scene.bodies if b.present(0.0)]
    if (scene.elastic is not None or scene.water is not None or scene.outlets
            or all(type(b.motion) is Fixed for b in bodies)):
        return
    dt = scene.config.dt
    horizon = min([scene.t_end if scene.t_end is not None else steps * dt]
                  + [b.removed_at for b in bodies])
    if not horizon > 0:
        return
    pts = np.vstack([np.asarray(r.polygon) for r in scene.regions])
    size = float(np.ptp(pts, axis=0).max())
    lo = pts.min(axis=0) - size
    cell = 3 * size / CELLS
    shape = tuple(np.ceil((pts.max(axis=0) + size - lo) / cell).astype(int))
    weight = None
    if scene.axisymmetric:                            # 2 pi r per cell
        r = lo[0] + (np.arange(shape[0]) + 0.5) * cell
        weight = np.repeat((2 * np.pi * np.abs(r) * cell * cell)[:, None], shape[1], axis=1)
    material = sum(r.volume if scene.axisymmetric else r.area for r in scene.regions)
    times = [0.0, *np.linspace(0, horizon, TIMES + 1)[1:]]
    for b in bodies:
        times += [t for t in getattr(b.motion, "times", ()) if 0 < t < horizon]
    first = None
    for t in sorted(set(times)):
        now = [b for b in bodies if b.present(t)]
        have = room(now, [b.motion(t) for b in now], particles, (lo, cell, shape), weight)
        if have is None:
            if t == 0:
                return                                  # not closed in at the start
            continue
        if t == 0:
            scale = max(1.0, material / have)           # the grid's error at the start
        have *= scale
        if have < material and first is None:
            first = t
        if have < MIN_ROOM * material:
            moving = [repr(b.name) for b in now if type(b.motion) is not Fixed]
            what = "volume" if scene.axisymmetric else "area"
            until = (f"t_end = {scene.t_end:g} s" if scene.t_end is not None
                     else f"step {steps}")
            raise ValueError(
                f"the bodies close the material in, and as {' and '.join(moving)} "
                f"move{'s' * (len(moving) == 1)} the room they leave falls below its {what} "
                f"{material:.4g} from t = {first:.4g} s (to {have / material:.1%} of it at "
                f"t = {t:.4g} s, before {until}): a material without elasticity keeps its "
                f"{what}, and no step can keep it inside the bodies. End the run before "
                f"(t_end), or give the material room")
