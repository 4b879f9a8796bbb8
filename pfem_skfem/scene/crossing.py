"""Rigid bodies that pass through each other during a run (issue 56 item 9, R10).

Two rigid bodies cannot pass through each other: the material between them is crushed to
no area, and what a run computes from then on has no physical meaning. The open vice
(two walls driven towards each other, crossing at t = 0.25 s) lost 37 % of the area in
five steps and ran on with every particle free; a run only warns of its steps' size,
which blames dt. This module finds such a crossing from the scene alone, before any step.

A crossing is a point of one body's shape that moves (relative to the other body) from
the other's material side, through its shape, to its back, at a place where there was
room for material: the point crossed is on the first body's material side before the
crossing. A wall sliding along a base it reaches below (a bulldozer, the accretionary
wedge's backstop) crosses the base's line behind the material only, and a gate lifted
out through the base crosses it from behind: neither is a crossing.
"""
import numpy as np

from ..problems.contact import RigidCircle
from .bodies import ConstantVelocity, Fixed, PiecewiseLinear

#: the most points of a body's shape tested, and of times of a motion given as a function
MAX_POINTS = 1000
MAX_TIMES = 200


def _times(body, dt, horizon):
    """Times in [0, horizon] between which the body's d(t) is linear (a function motion:
    the step times, at most :data:`MAX_TIMES` of them)."""
    motion = body.motion
    if type(motion) in (Fixed, ConstantVelocity):
        return np.array([0.0, horizon])
    if type(motion) is PiecewiseLinear:
        inner = [t for t in motion.times if 0 < t < horizon]
        return np.array([0.0, *inner, horizon])
    steps = max(int(np.ceil(horizon / dt * (1 - 1e-9))), 1)
    return np.unique(np.r_[np.linspace(0, steps, min(steps, MAX_TIMES) + 1).round() * dt,
                           horizon].clip(0, horizon))


def _samples(shape, spacing):
    """Points of a body's shape (polyline: its vertices and points between; circle: its
    rim), about ``spacing`` apart, at most :data:`MAX_POINTS`."""
    if isinstance(shape, RigidCircle):
        n = int(np.clip(np.ceil(2 * np.pi * shape.radius / spacing), 16, MAX_POINTS))
        a = 2 * np.pi * np.arange(n) / n
        return np.asarray(shape.center) + shape.radius * np.column_stack([np.cos(a),
                                                                          np.sin(a)])
    pts = np.asarray(shape.points, dtype=float)
    length = float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum())
    spacing = max(spacing, length / MAX_POINTS)
    out = [pts[:1]]
    for a, b in zip(pts[:-1], pts[1:]):
        m = max(int(np.ceil(np.linalg.norm(b - a) / spacing)), 1)
        out.append(a + (np.arange(1, m + 1) / m)[:, None] * (b - a))
    return np.vstack(out)


def _entries(paths, shape, tol):
    """Where the straight paths (n, 2, 2) pass from ``shape``'s material side through it:
    (path index, fraction along it, point of the shape crossed) for each."""
    if isinstance(shape, RigidCircle):
        c, r = np.asarray(shape.center), shape.radius
        a, d = paths[:, 0], paths[:, 1] - paths[:, 0]
        s = np.clip(np.einsum("nd,nd->n", c - a, d) / np.maximum(np.sum(d * d, axis=1),
                                                                 1e-300), 0, 1)
        near = a + s[:, None] * d
        dist = np.linalg.norm(near - c, axis=1)
        hit = (np.linalg.norm(a - c, axis=1) > r + tol) & (dist < r - tol)
        away = (near - c) / np.maximum(dist, 1e-300)[:, None]
        return [(i, s[i], c + r * away[i]) for i in np.flatnonzero(hit)]
    pts = np.asarray(shape.points, dtype=float)
    p, q = paths[:, 0], paths[:, 1]
    lo, hi = np.minimum(p, q), np.maximum(p, q)
    found = []
    for a, b in zip(pts[:-1], pts[1:]):                # each edge against every path
        near = np.flatnonzero(np.all(lo <= np.maximum(a, b), axis=1)
                              & np.all(hi >= np.minimum(a, b), axis=1))
        t = b - a
        sp = t[0] * (p[near, 1] - a[1]) - t[1] * (p[near, 0] - a[0])   # > 0: material side
        sq = t[0] * (q[near, 1] - a[1]) - t[1] * (q[near, 0] - a[0])
        d = q[near] - p[near]
        sa = d[:, 0] * (a[1] - p[near, 1]) - d[:, 1] * (a[0] - p[near, 0])
        sb = d[:, 0] * (b[1] - p[near, 1]) - d[:, 1] * (b[0] - p[near, 0])
        # from the material side to the back, through the edge (not past its ends)
        hit = (sp > 0) & (sq < 0) & (sa * sb < 0)
        for i, f in zip(near[hit], sp[hit] / (sp[hit] - sq[hit])):
            found.append((i, f, p[i] + f * (q[i] - p[i])))
    return found


def first_crossing(first, second, dt, horizon, spacing, tol):
    """The first time (and the point) at which a point of ``first`` passes through
    ``second`` where there was room for material (see the module), or None. Both bodies
    are present until ``horizon``."""
    times = np.union1d(_times(first, dt, horizon), _times(second, dt, horizon))
    rel = np.array([first.motion(t) - second.motion(t) for t in times])  # in second's frame
    pts = _samples(first.shape, spacing)
    moves = np.flatnonzero(np.any(rel[1:] != rel[:-1], axis=1))     # pieces that move
    if not len(moves):
        return None
    paths = np.stack([(pts[:, None, :] + rel[None, moves]).reshape(-1, 2),
                      (pts[:, None, :] + rel[None, moves + 1]).reshape(-1, 2)], axis=1)
    best = None
    for i, f, crossed in _entries(paths, second.shape, tol):
        j = moves[i % len(moves)]
        t = times[j] + f * (times[j + 1] - times[j])
        # room for material there: the point crossed is on first's material side before
        gap, _ = first.shape.gap((crossed - rel[j])[None])
        if gap[0] > tol and (best is None or t < best[0]):
            best = (t, pts[i // len(moves)])
    return best


def check_no_crossing(bodies, dt, t_end, spacing, steps=1000):
    """ValueError naming both bodies and the time when two bodies of a scene pass through
    each other before t_end (no t_end: in the first ``steps`` steps) while both are
    present; ``spacing`` (about half the smallest particle spacing) is how finely their
    shapes are sampled."""
    horizon = t_end if t_end is not None else steps * dt
    tol = 1e-6 * spacing
    found = None
    for a, one in enumerate(bodies):
        for other in bodies[a + 1:]:
            if type(one.motion) is Fixed and type(other.motion) is Fixed:
                continue                               # no relative motion
            until = min(horizon, one.removed_at, other.removed_at)
            if not until > 0:
                continue
            for first, second in ((one, other), (other, one)):
                hit = first_crossing(first, second, dt, until, spacing, tol)
                if hit is not None and (found is None or hit[0] < found[0]):
                    found = (hit[0], hit[1], first.name, second.name)
    if found is not None:
        t, p, name, other = found
        until = f"t_end = {t_end:g} s" if t_end is not None else f"step {steps}"
        raise ValueError(
            f"bodies {name!r} and {other!r} pass through each other from t = {t:.6g} s "
            f"(before {until}; dt = {dt:g} s): the point "
            f"{tuple(round(float(v), 9) for v in p)} of {name!r} crosses {other!r} from its "
            f"material side, and the material between them would be crushed to no area. "
            f"End the run before they meet (t_end), remove one (removed_at) or change their "
            f"motions")
