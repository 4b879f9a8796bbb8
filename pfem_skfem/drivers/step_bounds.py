"""The collapse load of a PFEM step's own geometry: the step's mesh as a
:class:`~pfem_skfem.problems.bounds.LimitProblem`, a rigid body's loaded contacts as its
punch, bracketed by the lower and upper bounds.

A large-deformation run changes the geometry its load acts on: a footing pushed into the
ground sinks and heaves the surface beside it, so its resistance drifts away from the
flat ground's collapse load. The bounds on the step's own mesh (the particles at t_n of
the step), with the footing touching where the step's contact forces say it touches, are
that geometry's collapse load, bracketed as strictly as the flat one
(``verification/penetration_rate.py --engine pfem``).
"""
import numpy as np
from skfem import MeshTri

from ..problems.bounds import LimitProblem, Punch, lower_bound, upper_bound

__all__ = ["on_segments", "loaded_facets", "step_limit_problem", "step_bracket"]


def on_segments(segments, tol):
    """``where(x)`` for a :class:`~pfem_skfem.problems.bounds.Support` or
    :class:`~pfem_skfem.problems.bounds.Punch`: the facet midpoints x (2, m) within ``tol``
    of one of ``segments`` (k, 2, 2), each a pair of end points. A selection by segments,
    not by points, holds on the facets of a refined mesh too."""
    a, b = np.asarray(segments, dtype=float)[:, 0], np.asarray(segments, dtype=float)[:, 1]
    d = b - a

    def where(x):
        p = np.asarray(x, dtype=float).T[:, None, :]                     # (m, 1, 2)
        t = np.clip(((p - a) * d).sum(-1) / (d * d).sum(-1), 0.0, 1.0)  # nearest point's
        return np.linalg.norm(p - (a + t[..., None] * d), axis=-1).min(axis=1) < tol
    return where


def loaded_facets(result, body, rel=1e-6):
    """(k, 2, 2) the boundary facets of the step's mesh that rigid body ``body`` (its index
    in the scene) pushed on in the step: those whose midside node carries a normal contact
    force above ``rel`` of the step's largest. ValueError when there is none."""
    contacts, p = result.contacts, result.increment.p
    if contacts is None or contacts.size == 0:
        raise ValueError("the step has no contact: no body loads its mesh")
    mesh = result.disc.mesh
    facets = mesh.boundary_facets()
    ends = mesh.p[:, mesh.facets[:, facets]]                      # (2, 2, nf)
    mid = ends.mean(axis=1).T                                     # (nf, 2)
    pushed = contacts.x[(contacts.body == body) & (p > rel * np.abs(p).max(initial=0.0))]
    if pushed.size == 0:
        raise ValueError(f"body {body} pushed on no boundary node in the step")
    scale = np.ptp(mesh.p, axis=1).max()
    near = np.linalg.norm(mid[:, None, :] - pushed[None, :, :], axis=-1).min(axis=1)
    on = near < 1e-9 * scale                                      # a midside node loaded
    if not on.any():
        raise ValueError(f"body {body} loaded no facet's midside node in the step")
    return np.transpose(ends[:, :, on], (2, 1, 0))


def step_limit_problem(result, body, criterion, supports=(), velocity=(0.0, -1.0),
                       components="y"):
    """The limit problem of the step's mesh: ``criterion`` everywhere, ``supports`` as
    given, and body ``body`` a rigid punch moving at ``velocity`` on the facets it loaded
    (:func:`loaded_facets`; ``components`` 'y' for a smooth footing)."""
    mesh = result.disc.mesh
    segments = loaded_facets(result, body)
    tol = 1e-9 * np.ptp(mesh.p, axis=1).max()
    return LimitProblem(MeshTri(mesh.p, mesh.t), criterion, supports=tuple(supports),
                        punch=Punch(on_segments(segments, tol), velocity, components))


def step_bracket(result, body, lower, upper=None, supports=(), levels=0, **settings):
    """The step's collapse load bracketed: the lower bound of criterion ``lower`` and the
    upper bound of ``upper`` (``lower`` if None; two criteria bracket a non-associated
    soil, Radenkovic's theorems), on the step's mesh refined uniformly ``levels`` times
    (the geometry unchanged: straight facets). (lower, upper, elements): the punch's force
    per unit speed of its velocity, per unit thickness."""
    same = upper is None
    low = step_limit_problem(result, body, lower, supports)
    up = low if same else step_limit_problem(result, body, upper, supports)
    for _ in range(levels):
        low = low.refined()
        up = low if same else up.refined()
    return (lower_bound(low, **settings).load, upper_bound(up, **settings).load,
            low.mesh.t.shape[1])
