"""Rigid bodies of a PFEM scene and their prescribed motions.

A body is a rigid shape of :mod:`pfem_skfem.problems.contact` (segment, polyline,
circle; the material on the side its normal points to) with a friction coefficient,
a prescribed translation d(t) (a function of time, d(0) = 0) and the time it is
removed (a gate opened, a wall taken away). Over a step t_n -> t_n+1 the body
translates by d(t_n+1) - d(t_n); the contact cones (5.12) see the relative motion.
"""
from dataclasses import dataclass

import numpy as np

from ..problems.contact import RigidCircle, RigidPolyline
from .regions import _edges


class Motion:
    """A prescribed translation d(t) of a rigid body, (2,) at time t, d(0) = 0."""

    def __call__(self, t):  # pragma: no cover - abstract
        raise NotImplementedError


@dataclass(frozen=True)
class Fixed(Motion):
    """No motion."""

    def __call__(self, t):
        return np.zeros(2)


@dataclass(frozen=True)
class ConstantVelocity(Motion):
    """d(t) = velocity t."""

    velocity: tuple

    def __post_init__(self):
        v = np.asarray(self.velocity, dtype=float)
        if v.shape != (2,) or not np.all(np.isfinite(v)):
            raise ValueError(f"velocity must be a finite (vx, vy), got {self.velocity!r}")
        object.__setattr__(self, "velocity", tuple(map(float, v)))

    def __call__(self, t):
        return np.asarray(self.velocity) * float(t)


@dataclass(frozen=True)
class PiecewiseLinear(Motion):
    """d(t) interpolated linearly between (times[i], displacements[i]), held after the last;
    times increasing from 0, displacements[0] = (0, 0). The cylinder of 6.4.1:
    ``PiecewiseLinear((0, 80, 280), ((0, 0), (0, -0.8), (2, -0.8)))``."""

    times: tuple
    displacements: tuple

    def __post_init__(self):
        t = np.asarray(self.times, dtype=float)
        d = np.asarray(self.displacements, dtype=float)
        if t.ndim != 1 or len(t) < 2 or d.shape != (len(t), 2):
            raise ValueError("a piecewise-linear motion needs k >= 2 times and k (dx, dy) "
                             f"displacements, got {t.shape} and {d.shape}")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(d))):
            raise ValueError("times and displacements must be finite")
        if t[0] != 0 or np.any(np.diff(t) <= 0):
            raise ValueError(f"times must start at 0 and increase, got {self.times!r}")
        if np.any(d[0] != 0):
            raise ValueError(f"the displacement at t = 0 must be (0, 0), got {tuple(d[0])}")
        object.__setattr__(self, "times", tuple(map(float, t)))
        object.__setattr__(self, "displacements", tuple(map(tuple, d.tolist())))

    def __call__(self, t):
        d = np.asarray(self.displacements)
        return np.array([np.interp(float(t), self.times, d[:, k]) for k in (0, 1)])


@dataclass(frozen=True)
class FunctionMotion(Motion):
    """Any function of time returning (dx, dy), with d(0) = 0."""

    function: object

    def __call__(self, t):
        return np.asarray(self.function(float(t)), dtype=float)


def as_motion(motion, name):
    """``motion`` as a :class:`Motion` (a callable of t is wrapped), checked at t = 0 and
    t = 1: ValueError naming the body if it is not a function of time giving (dx, dy)."""
    if motion is None:
        return Fixed()
    if not callable(motion):
        raise ValueError(f"body {name!r}: motion must be a function of time t -> (dx, dy), "
                         f"got {motion!r}")
    wrapped = motion if isinstance(motion, Motion) else FunctionMotion(motion)
    for t in (0.0, 1.0):
        try:
            d = np.asarray(wrapped(t), dtype=float)
        except Exception as err:                     # noqa: BLE001 - reported with the body
            raise ValueError(f"body {name!r}: motion(t) failed at t = {t:g} ({err})") from err
        if d.shape != (2,) or not np.all(np.isfinite(d)):
            raise ValueError(f"body {name!r}: motion(t) must return a finite (dx, dy), got "
                             f"{d!r} at t = {t:g}")
    if np.any(np.asarray(wrapped(0.0)) != 0):
        raise ValueError(f"body {name!r}: motion(0) must be (0, 0)")
    return wrapped


#: the step times a prescribed motion is checked at when the scene has no t_end
MOTION_CHECK_STEPS = 1000


def step_count(dt, t_end=None, default=MOTION_CHECK_STEPS):
    """The steps of dt a run from t = 0 takes to t_end (``default`` without one), at most
    100000: how far a check of what a scene prescribes in time looks ahead."""
    return min(default if t_end is None else int(np.ceil(t_end / dt * (1 - 1e-9))), 100_000)


def check_motion_over(body, dt, t_end=None, *, start=0.0, first=0, steps=None):
    """Refuse (ValueError naming the body and the time) a motion of ``body`` that fails or
    is not a finite (dx, dy) at a step time of a run while the body is present.

    The step times are start + k dt, k = 1..``steps``, numbered ``first`` + k (a run from a
    state: its time and step); ``steps`` None: those of a run from t = 0 to t_end, else
    the first :data:`MOTION_CHECK_STEPS` (at most 100000).
    :func:`as_motion` checks t = 0 and 1 only; a function finite there can blow up in
    between (1 / (0.02 - t)) and the run would go on with RuntimeWarnings. The motions of
    the package (Fixed, ConstantVelocity, PiecewiseLinear) are finite by construction and
    not evaluated."""
    motion = body.motion
    if type(motion) in (Fixed, ConstantVelocity, PiecewiseLinear):
        return
    if steps is None:
        steps = step_count(dt, t_end)
    for k in range(1, steps + 1):
        t = start + k * dt
        if t >= body.removed_at:
            break
        try:
            with np.errstate(all="ignore"):
                d = np.asarray(motion(t), dtype=float)
        except Exception as err:                     # noqa: BLE001 - reported with the body
            raise ValueError(f"body {body.name!r}: motion(t) failed at t = {t:g} (step "
                             f"{first + k}: {err})") from err
        if d.shape != (2,) or not np.all(np.isfinite(d)):
            raise ValueError(f"body {body.name!r}: motion(t) must return a finite (dx, dy) "
                             f"at every step time, got {d!r} at t = {t:g} (step {first + k} "
                             f"of dt = {dt:g})")


def _distance_to_edges(point, loops):
    """The distance from ``point`` (2,) to the nearest edge of the closed ``loops``."""
    e = np.vstack([_edges(np.asarray(loop, dtype=float)) for loop in loops])
    a, t = e[:, 0], e[:, 1] - e[:, 0]
    s = np.clip(np.einsum("kd,kd->k", point - a, t) / np.maximum(np.sum(t * t, axis=1),
                                                                 1e-300), 0, 1)
    return float(np.min(np.linalg.norm(point - a - s[:, None] * t, axis=1)))


def reach_into(shape, region, tol):
    """Where a body's ``shape`` at t = 0 lies in ``region``'s material (inside its polygon
    and outside its holes) by more than ``tol``: a text naming the point, or None.

    A disc reaches in when its centre is in the material or an edge passes nearer its
    centre than its radius; a polyline when a point of it (its vertices and points a
    quarter of the region's h apart) is in the material. Touching (a cylinder resting on
    the surface, a wall along an edge) is not reaching in.
    """
    loops = [region.polygon, *region.holes]
    if isinstance(shape, RigidCircle):
        c = np.asarray(shape.center)
        if region.contains(c[None], tol=-tol)[0]:
            return f"its centre {tuple(map(float, c))} lies in the material"
        gap = _distance_to_edges(c, loops)
        if gap < shape.radius - tol:
            return (f"its disc (centre {tuple(map(float, c))}, radius {shape.radius:g}) "
                    f"reaches {shape.radius - gap:.3g} into the material")
        return None
    pts = np.asarray(shape.points, dtype=float)
    samples = [pts[:1]]
    for a, b in zip(pts[:-1], pts[1:]):
        m = max(int(np.ceil(np.linalg.norm(b - a) / (region.h / 4))), 1)
        samples.append(a + (np.arange(1, m + 1) / m)[:, None] * (b - a))
    x = np.vstack(samples)
    inside = region.contains(x, tol=-tol)
    if inside.any():
        p = x[np.argmax(inside)]
        return (f"its point {tuple(round(float(v), 12) for v in p)} lies "
                f"{_distance_to_edges(p, loops):.3g} inside the material")
    return None


@dataclass(frozen=True)
class Body:
    """A rigid body of the scene.

    Parameters
    ----------
    name : label in the records (force on it, its position).
    shape : RigidPolyline / RigidSegment / RigidCircle at t = 0 (its ``mu`` is the friction).
    motion : a :class:`Motion` or a function t -> (dx, dy) (default :class:`Fixed`).
    removed_at : the body takes no part from this time on (default never; 0: never there).
    reference : point about which the moment is reported, at t = 0 (default: a circle's
        centre, a polyline's first point); it moves with the body.
    """

    name: str
    shape: object
    motion: object = None
    removed_at: float = np.inf
    reference: tuple = None

    def __post_init__(self):
        if not isinstance(self.shape, (RigidPolyline, RigidCircle)):
            raise ValueError(f"body {self.name!r}: shape must be a RigidPolyline, RigidSegment "
                             f"or RigidCircle, got {type(self.shape).__name__}")
        object.__setattr__(self, "motion", as_motion(self.motion, self.name))
        if not (self.removed_at >= 0):
            raise ValueError(f"body {self.name!r}: removed_at must be >= 0, got {self.removed_at!r}")
        ref = self.reference
        if ref is None:
            ref = (self.shape.center if isinstance(self.shape, RigidCircle)
                   else self.shape.points[0])
        ref = np.asarray(ref, dtype=float)
        if ref.shape != (2,) or not np.all(np.isfinite(ref)):
            raise ValueError(f"body {self.name!r}: reference must be a finite (x, y)")
        object.__setattr__(self, "reference", tuple(map(float, ref)))

    def present(self, t):
        """Whether the body takes part in a step starting at time t."""
        return t < self.removed_at

    def at(self, t):
        """The rigid shape at time t (translated by d(t))."""
        return self.shape.translated(self.motion(t))

    def reference_at(self, t):
        return np.asarray(self.reference) + self.motion(t)
