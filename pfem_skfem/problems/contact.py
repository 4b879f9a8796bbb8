"""Rigid frictional boundaries as cone constraints (thesis Ch 5, (5.10)-(5.12)).

Each boundary node of the mesh near a rigid body is a *potential contact*: a
weightless particle with the gap g0 to the body at t_n, the body's unit normal n
there (pointing from the body towards the deformable solid) and the tangent
n^ = (-n2, n1). Its contact force on the solid is ``n p + n^ q`` with::

    |q| <= mu p                                  (Coulomb cone; p >= 0 when mu = 0)

and the problem gains the objective term ``- sum_j g0_j p_j`` (5.10), (5.12). The
KKT conditions then give (5.11): the gap at t_{n+1}, g0 + n . du, equals
mu * lambda >= 0 (no penetration; the associated sliding rule dilates by
mu * lambda), and the slip n^ . du opposes q.

Zero dilation. The associated rule lifts a sliding node off the body by mu ``|slip|``
per step. The contact counterpart of the psi = 0 scheme of [80] removes it: with a
known normal force p~_j (lagged, e.g. from a first pass of the step), the cone
``|q_j| <= mu_j p_j`` becomes the bound ``|q_j| <= mu_j p~_j`` (Tresca-type friction).
The KKT conditions then give g0 + n . du >= 0 with complementarity to p_j (no
opening while in contact) and a slip opposing q_j, at the friction force mu p~_j
(:func:`with_friction_bound`). At a fixed point p = p~ it is Coulomb's law
without the dilation.

Conventions: the thesis writes the forces through rho_j = -(n_j p_j + n^_j q_j)
and the index matrix E (5.12); here ``contact_matrix`` is the matrix G = -E^T
[n, n^] that maps (p, q) to nodal forces on the solid.
"""
from dataclasses import dataclass, field, replace

import cvxpy as cp
import numpy as np
import scipy.sparse as sp


def _check_mu(mu):
    if not np.isfinite(mu) or mu < 0:
        raise ValueError(f"mu (friction coefficient) must be >= 0, got {mu!r}")


@dataclass(frozen=True)
class RigidPolyline:
    """A rigid polyline through ``points`` (k >= 2, 2); the solid lies on its left.

    Walking from points[0] to points[-1], the normal n points to the left.
    ``mu`` is the friction coefficient (0: smooth).

    ``sharp_ends``: False (the default, the thesis' walls): a point beyond the first or the
    last point is measured along the end segment's normal, as if the segment went on (a wall
    drawn to its ends behaves as a half-plane there). True: the body ends at them (a strip
    footing's edge): the gap of a point beyond an end is its distance to the end point and
    its normal the direction from it, so the surface beside a footing is no contact (without
    it the surface within the search distance of the footing's line is pushed down with it).
    """

    points: tuple
    mu: float = 0.0
    sharp_ends: bool = False

    def __post_init__(self):
        pts = np.asarray(self.points, dtype=float)
        if pts.ndim != 2 or pts.shape[0] < 2 or pts.shape[1] != 2:
            raise ValueError("a rigid polyline needs at least two 2D points")
        if np.any(np.linalg.norm(np.diff(pts, axis=0), axis=1) <= 0):
            raise ValueError("a rigid polyline has a zero-length segment")
        _check_mu(self.mu)
        if not isinstance(self.sharp_ends, (bool, np.bool_)):
            raise ValueError(f"sharp_ends must be True or False, got {self.sharp_ends!r}")
        object.__setattr__(self, "points", tuple(map(tuple, pts)))

    def gap(self, x):
        """Signed distance g0 (positive on the solid's side) and normal n at the closest point.

        x : (m, 2) points. Returns g0 (m,), n (m, 2).
        """
        x = np.atleast_2d(np.asarray(x, dtype=float))
        pts = np.asarray(self.points)
        a, b = pts[:-1], pts[1:]
        t = b - a
        length2 = np.sum(t ** 2, axis=1)
        along = np.einsum("mkd,kd->mk", x[:, None, :] - a[None], t) / length2
        s = np.clip(along, 0, 1)
        closest = a[None] + s[..., None] * t[None]
        dist = np.linalg.norm(x[:, None, :] - closest, axis=2)
        k = np.argmin(dist, axis=1)
        tk = t[k] / np.sqrt(length2[k])[:, None]
        n = np.stack([-tk[:, 1], tk[:, 0]], axis=1)             # left normal
        rows = np.arange(len(x))
        d = x - closest[rows, k]
        g0 = np.einsum("md,md->m", d, n)
        if self.sharp_ends:                   # beyond an end: the distance to the end point
            last = len(a) - 1
            r = np.linalg.norm(d, axis=1)
            beyond = ((((k == 0) & (along[rows, 0] < 0))
                       | ((k == last) & (along[rows, last] > 1)))
                      & (r > 1e-9 * np.sqrt(length2[k])))
            n[beyond] = d[beyond] / r[beyond, None]
            g0[beyond] = r[beyond]
        return g0, n

    def translated(self, d):
        return replace(self, points=tuple(map(tuple, np.asarray(self.points) + np.asarray(d))))


def RigidSegment(a, b, mu=0.0, sharp_ends=False):
    """A rigid straight segment from a to b; the solid lies on its left (``sharp_ends``:
    :class:`RigidPolyline`)."""
    return RigidPolyline((tuple(a), tuple(b)), mu, sharp_ends)


@dataclass(frozen=True)
class RigidCircle:
    """A rigid disc (pipe, cylinder) of ``radius`` about ``center``; the solid lies outside."""

    center: tuple
    radius: float
    mu: float = 0.0

    def __post_init__(self):
        if not np.isfinite(self.radius) or self.radius <= 0:
            raise ValueError(f"radius of a rigid circle must be positive, got {self.radius!r}")
        _check_mu(self.mu)
        object.__setattr__(self, "center", tuple(float(c) for c in self.center))

    def gap(self, x):
        x = np.atleast_2d(np.asarray(x, dtype=float))
        d = x - np.asarray(self.center)
        r = np.linalg.norm(d, axis=1)
        n = d / np.where(r > 0, r, 1.0)[:, None]
        return r - self.radius, n

    def translated(self, d):
        return replace(self, center=tuple(np.asarray(self.center) + np.asarray(d)))


@dataclass
class ContactSet:
    """Potential contacts: one row per (boundary node, rigid body) pair.

    dofs : (nc, 2) x and y displacement dofs of the node;  x : (nc, 2) its position;
    gap : (nc,) g0 at t_n (reduced by the body's prescribed motion over the step);
    normal : (nc, 2) n;  mu : (nc,) friction;  body : (nc,) index of the rigid body;
    slip : (nc,) n^ . d, the body's own tangential motion d over the step (the slip of
        the node relative to the body is n^ . (du - d)); None: zero;
    friction_bound : None (Coulomb, ``|q_j| <= mu_j p_j``) or (nc,) known friction forces
        mu_j p~_j (zero dilation, ``|q_j| <= mu_j p~_j``; see :func:`with_friction_bound`).
    """

    dofs: np.ndarray
    x: np.ndarray
    gap: np.ndarray
    normal: np.ndarray
    mu: np.ndarray
    body: np.ndarray
    n_bodies: int = 1
    motion: list = field(default_factory=list)
    friction_bound: np.ndarray = None
    slip: np.ndarray = None

    @property
    def size(self):
        return len(self.gap)

    @property
    def tangent(self):
        return np.stack([-self.normal[:, 1], self.normal[:, 0]], axis=1)


def boundary_nodes(disc):
    """(x, y) dofs and coordinates of every boundary node of the P2 mesh (corners and midsides)."""
    facets = disc.mesh.boundary_facets()
    dofs = disc.basis_u.get_dofs(facets)
    ux = np.concatenate([dofs.nodal["u^1"], dofs.facet["u^1"]])
    uy = np.concatenate([dofs.nodal["u^2"], dofs.facet["u^2"]])
    return np.stack([ux, uy], axis=1), disc.basis_u.doflocs[:, ux].T


def potential_contacts(disc, bodies, search_distance, *, motions=None, displacement=None):
    """Boundary nodes within ``search_distance`` of each rigid body, with g0 and n at t_n.

    Parameters
    ----------
    disc : Discretisation of the solid at t_n.
    bodies : sequence of rigid bodies (RigidPolyline, RigidSegment, RigidCircle).
    search_distance : nodes with g0 <= search_distance are potential contacts.
    motions : optional (n_bodies, 2) prescribed translation d of each body over the step;
        the gap seen by the solid shrinks by n . d, and the slip is measured relative to
        the body (``slip`` = n^ . d).
    displacement : optional (n_u,) displacements of the solid since its mesh was
        made; the nodes are taken at their displaced positions (time stepping on a
        fixed mesh).

    Raises ValueError if a body has no potential contact node (contact requested
    where none can occur is almost always a set-up error).
    """
    if not np.isfinite(search_distance) or search_distance <= 0:
        raise ValueError(f"search_distance must be positive, got {search_distance!r}")
    bodies = list(bodies)
    motions = np.zeros((len(bodies), 2)) if motions is None else np.asarray(motions, float)
    dofs, x = boundary_nodes(disc)
    if displacement is not None:
        x = x + np.asarray(displacement, dtype=float)[dofs]
    rows = []
    for k, body in enumerate(bodies):
        g0, n = body.gap(x)
        near = g0 <= search_distance
        if not near.any():
            raise ValueError(f"rigid body {k} ({type(body).__name__}) has no boundary node "
                             f"within the search distance {search_distance:g}")
        g = g0[near] - n[near] @ motions[k]
        t = np.stack([-n[near, 1], n[near, 0]], axis=1)
        rows.append((dofs[near], x[near], g, n[near], np.full(near.sum(), body.mu),
                     np.full(near.sum(), k), t @ motions[k]))
    cat = [np.concatenate([r[i] for r in rows]) for i in range(7)]
    slip = cat.pop()
    return ContactSet(*cat, n_bodies=len(bodies), motion=list(motions),
                      slip=slip if np.any(slip != 0) else None)


def without_nodes(contacts, dofs):
    """The contacts whose node has none of ``dofs`` (a held node is a support, not a contact);
    None if no contact is left."""
    keep = ~np.isin(contacts.dofs[:, 0], np.asarray(dofs, dtype=int))
    if keep.all():
        return contacts
    if not keep.any():
        return None
    pick = lambda a: None if a is None else np.asarray(a)[keep]          # noqa: E731
    return replace(contacts, dofs=contacts.dofs[keep], x=contacts.x[keep],
                   gap=contacts.gap[keep], normal=contacts.normal[keep], mu=contacts.mu[keep],
                   body=contacts.body[keep], friction_bound=pick(contacts.friction_bound),
                   slip=pick(contacts.slip))


def with_friction_bound(contacts, normal_force):
    """The same contacts with zero dilation: ``|q_j| <= mu_j p~_j`` for a known normal force p~.

    ``normal_force`` : (nc,) p~_j >= 0, typically the p of a first, associated pass of
    the same step (in the units of the problem's forces, as returned in ``p``).
    """
    p = np.asarray(normal_force, dtype=float)
    if p.shape != (contacts.size,):
        raise ValueError(f"normal_force must have one value per contact ({contacts.size}), "
                         f"got shape {p.shape}")
    if not np.all(np.isfinite(p)) or np.any(p < 0):
        raise ValueError("normal_force must be finite and non-negative")
    return replace(contacts, friction_bound=contacts.mu * p)


@dataclass(frozen=True)
class CoulombCones:
    """Contact rule: the associated Coulomb cones ``|q_j| <= mu_j p_j`` of (5.12), as in the
    thesis (a sliding node lifts off by mu ``|slip|`` per step, which vanishes as dt -> 0)."""

    passes_needed = 1

    def start(self, contacts):
        """The contacts of a step's first pass."""
        return contacts

    def update(self, contacts, normal_force):
        """The contacts of the next pass, given the last pass's normal forces."""
        return contacts


@dataclass(frozen=True)
class LaggedFriction:
    """Contact rule without dilation: the first pass of a step is smooth, each later one
    bounds the friction by mu times the previous pass's normal force,
    ``|q_j| <= mu_j p~_j`` (:func:`with_friction_bound`; needs two passes or more)."""

    passes_needed = 2

    def start(self, contacts):
        return with_friction_bound(contacts, np.zeros(contacts.size))

    def update(self, contacts, normal_force):
        return with_friction_bound(contacts, np.maximum(normal_force, 0.0))


def contact_matrix(contacts, n_u):
    """G (n_u, 2 nc): nodal forces on the solid from (p, q), i.e. n_j p_j + n^_j q_j at node j."""
    nc = contacts.size
    j = np.arange(nc)
    t = contacts.tangent
    rows = np.concatenate([contacts.dofs[:, 0], contacts.dofs[:, 1],
                           contacts.dofs[:, 0], contacts.dofs[:, 1]])
    cols = np.concatenate([j, j, nc + j, nc + j])
    vals = np.concatenate([contacts.normal[:, 0], contacts.normal[:, 1], t[:, 0], t[:, 1]])
    return sp.csr_matrix((vals, (rows, cols)), shape=(n_u, 2 * nc))


@dataclass
class ContactTerms:
    """cvxpy pieces of the contact problem, in scaled units (force / force_scale)."""

    p: cp.Variable
    q: cp.Variable
    G: sp.csr_matrix
    objective: object          # - sum g0_j p_j (scaled)
    constraints: list          # |q_j| <= mu_j p_j

    def force(self):
        """cvxpy expression of the nodal contact forces on the solid, G (p, q)."""
        return self.G @ cp.hstack([self.p, self.q])


def contact_terms(contacts, n_u, *, length_scale, force_scale=1.0):
    """The contact part of (5.12): variables p, q, the objective term and the cones.

    ``length_scale`` divides the gaps (the objective is measured in
    force_scale x length_scale, like the rest of the scaled problem);
    ``force_scale`` divides a friction bound (the force one unit of p, q stands for).
    """
    nc = contacts.size
    p, q = cp.Variable(nc), cp.Variable(nc)
    mu = contacts.mu
    cons = [p >= 0]                                  # normal force compressive (5.5)
    if contacts.friction_bound is None:              # Coulomb: |q_j| <= mu_j p_j
        rough = mu > 0
        limit = lambda idx: cp.multiply(mu[idx], p[idx])               # noqa: E731
    else:                                            # zero dilation: |q_j| <= mu_j p~_j
        k = np.asarray(contacts.friction_bound, dtype=float) / force_scale
        rough = k > 0
        limit = lambda idx: k[idx]                                      # noqa: E731
    if rough.any():
        idx = np.flatnonzero(rough)
        cons.append(cp.abs(q[idx]) <= limit(idx))    # |q_j| - limit_j <= 0
    if (~rough).any():                               # smooth (or no normal force): q_j = 0
        cons.append(q[np.flatnonzero(~rough)] == 0)
    objective = -(contacts.gap / length_scale) @ p   # - sum g0_j p_j  (5.10)
    if contacts.slip is not None:                    # + sum (n^_j . d) q_j: a moving body
        objective = objective + (contacts.slip / length_scale) @ q
    return ContactTerms(p, q, contact_matrix(contacts, n_u), objective, cons)


def resultants(contacts, p, q):
    """Contact force resultant on each rigid body (the reaction of the solid on it), (n_bodies, 2)."""
    force_on_solid = contacts.normal * p[:, None] + contacts.tangent * q[:, None]
    out = np.zeros((contacts.n_bodies, 2))
    np.add.at(out, contacts.body, -force_on_solid)
    return out
