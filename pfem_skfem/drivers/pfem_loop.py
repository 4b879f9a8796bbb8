"""The PFEM loop of thesis Section 2.2 (steps 0-2b) for granular flow.

One step from the cloud C^n to C^{n+1}, each stage a function::

    detect   (1a) alpha-shape of the particles             -> AlphaShape
    remesh   (1b) mesh of the detected domain               -> ParticleMesh
    map      (1c) velocities (L2 projection of the P2 field), stresses (uem_bounded),
                  lagged mean stress (carried by the particles)
    assemble      B, A, D (and C if elastoplastic), gravity, the contact set of the walls
    solve    (2a) (4.23) + (5.12) with the psi = 0 scheme of [80], a few fixed-point passes
    move     (2b) particles x += du, v = v_{n+1}; free particles fly and slide ballistically

Keeping the area. The particles are the vertices of the six-node triangles (Section
2.3.1), and two things then lose area although the psi = 0 flow is isochoric in each
P2 element: moving only the vertices drops the bulge of every curved boundary edge,
and the alpha-shape deletes the boundary triangles that a stretching free surface
makes too large. Measured on the a = 1 column with 10 particles across (100 steps, run
to rest): 15.9 % of the area lost in all. Two remedies, both options of
:class:`PFEMConfig`: a boundary edge stretched beyond ``refine_surface`` h hands its
P2 midside node (position and velocity) to the cloud as a new particle, and the other
boundary vertices are shifted so that the chords keep the area of the curved edges
(:func:`bulge_correction`). Without the first the run loses 11.0 %, without the second
9.2 %, with both (``refine_surface`` = 2) 2.4 %; with 1.4 h, 1.6 %, but the new
surface particles feed a thin flowing film (the run-out at rest grows from 2.33 to
2.60 d0, the kinetic energy at t = 4 sqrt(h0/g) from 5.7 % to 6.9 % of its peak).

Kinetic energy. Interpolating the old P2 velocities at the new nodes adds kinetic
energy at every remeshing of a sheared field (measured on the same run: a third of
the peak kinetic energy in all); the L2 projection (``velocity_mapping``) does not.

Material. Mohr-Coulomb with zero dilation by the scheme the thesis cites as [80]
(Krabbenhoft, Karim, Lyamin & Sloan 2012): each step solves an associated problem on
the flow surface of psi = 0, a Tresca-type cone ``sqrt((sx - sy)^2 + 4 sxy^2) <= k_j``
(:class:`~pfem_skfem.materials.TrescaField`), whose radius is the Mohr-Coulomb
strength at a known mean stress, ``k_j = 2 c cos(phi) - 2 sin(phi) sigma_m`` (tension
positive), held at least ``floor`` where sigma_m is tensile. sigma_m is *lagged*:
carried from the previous step and refined by ``passes`` fixed-point passes within
the step. In rigid zones the stress of a rigid-plastic body is not unique and the
interior-point solution returns erratic mean stresses, so sigma_m is smoothed: the
element means of (sx + sy)/2 are averaged onto the vertices, weighted by element
area, and carried by the particles (so the lagged mean stress needs no stress
mapping at all). Rigid-plastic by default (C = 0 in (4.23)); with ``E`` the material
is elastoplastic, starts from geostatic stresses and the mapped stresses enter the
C term. The plain Davis reduction (an associated Mohr-Coulomb cone with
tan phi* = sin phi, c* = c cos phi, with the same least radius ``floor``) is
available as ``material="davis"`` for the comparison.

Contact. The walls and the base are the associated cones of (5.12) by default, as in
the thesis; ``contact="zero-dilation"`` bounds the friction by mu times the normal
force of a first, smooth pass instead (no lift-off; exact for a sliding rigid slab,
tests/test_pfem_loop.py). Measured on the a = 1 column (100 steps) it keeps the film
moving longest (12 % of the peak kinetic energy left at t = 4 sqrt(h0/g) against 6 %,
at rest at 5.9 against 5.4) and the run-out at rest is longer (2.51 against 2.33 d0):
the lift-off of the associated rule dissipates energy that the film otherwise keeps.
"""
from dataclasses import dataclass, field, fields, replace
import json
import time as _time

import numpy as np
from skfem import Basis, ElementTriP1, MeshTri

from ..materials import Elastic, MohrCoulomb, TrescaField, davis, mohr_coulomb_radius
from ..operators import body_force_vector, discretise
from ..pfem import alpha_shape, alpha_mesh, quality_remesh, thin_cloud, adaptive_alpha
from ..pfem.alpha_shape import triangle_areas
from ..pfem.particles import Particles, check_positions
from ..pfem.mapping import interpolate, locate, map_nodal, map_stress, project_nodal
from ..pfem.remesh import ParticleMesh
from ..problems.contact import boundary_nodes, potential_contacts, with_friction_bound
from ..problems.particle import free_particles_step
from ..problems.dynamic import (BACKENDS, DynamicScales, ThetaMethod, dynamic_increment, dynamic_operators,
                                estimate_scales)

MATERIALS = ("tresca-mc", "davis")
CONTACTS = ("zero-dilation", "coulomb")
VELOCITY_MAPPINGS = ("projection", "interpolation")
REMESHERS = ("alpha", "quality")


@dataclass
class PFEMConfig:
    """Parameters of a PFEM run of a cohesionless or cohesive granular body.

    rho, g : density and gravity (units: t/m3, m/s2 give kPa);  E, nu : Young's modulus
    and Poisson's ratio of an elastoplastic material (E = None: rigid-plastic, C = 0
    in (4.23));  c, phi : Mohr-Coulomb
    strength (phi in degrees), psi = 0;  material : "tresca-mc" (the scheme of [80])
    or "davis";  passes : solves per step (1 = lagged mean stress only);  floor :
    least cone radius k (a stress);  dt, theta1, theta2 : theta-method (4.4);
    alpha : alpha-shape parameter;  adaptive : adapt alpha to hold the area
    (alpha_n = A0 alpha0 / A_n, Ch 8);  remesh : "alpha" (the alpha-shape
    triangulation, particles = vertices) or "quality" (Triangle adds nodes, which
    become particles; crowded particles are thinned);  remesh_interval : remesh
    every this many steps (between, the mesh moves with the particles);  mapping :
    stress mapping "uem_bounded", "uem", "ida" or "spr";  velocity_mapping :
    "projection" (L2, no kinetic energy added) or "interpolation" (:func:`map_state`);  bodies : rigid walls and base (contact, (5.12));
    search : contact search distance in units of h;  contact : "zero-dilation" (the
    first pass of a step is smooth, each later one bounds the friction by mu times the
    previous pass's normal force, :func:`~pfem_skfem.problems.contact.with_friction_bound`;
    needs passes >= 2) or "coulomb" (the associated cones of (5.12), which lift a
    sliding node by mu |slip| per step);  backend : "clarabel" (the step assembled
    directly, :mod:`~pfem_skfem.problems.clarabel_direct`) or "cvxpy" (the reference
    statement of :func:`~pfem_skfem.problems.dynamic.dynamic_increment`);  bulge : place the boundary
    particles so that the straight-sided boundary keeps the area of the curved P2 one
    (:func:`bulge_correction`);  refine_surface : a boundary edge stretched longer than
    this many h gets its P2 midside node as a new particle (0: never).
    """

    rho: float = 2.0
    g: float = 9.8
    E: float = None
    nu: float = 0.3
    c: float = 0.0
    phi: float = 31.0
    material: str = "tresca-mc"
    passes: int = 2
    floor: float = 0.1
    dt: float = 0.01
    theta1: float = 1.0
    theta2: float = 1.0
    alpha: float = 1.6
    adaptive: bool = False
    remesh: str = "alpha"
    remesh_interval: int = 1
    quality_size: float = 1.5
    mapping: str = "uem_bounded"
    velocity_mapping: str = "projection"
    bodies: tuple = ()
    search: float = 1.0
    contact: str = "coulomb"
    backend: str = "clarabel"
    bulge: bool = True
    refine_surface: float = 2.0

    def __post_init__(self):
        if self.material not in MATERIALS:
            raise ValueError(f"material must be one of {MATERIALS}, got {self.material!r}")
        if self.contact not in CONTACTS:
            raise ValueError(f"contact must be one of {CONTACTS}, got {self.contact!r}")
        if self.contact == "zero-dilation" and self.bodies and int(self.passes) < 2:
            raise ValueError("contact='zero-dilation' needs passes >= 2 (the first pass "
                             "finds the normal forces)")
        if self.velocity_mapping not in VELOCITY_MAPPINGS:
            raise ValueError(f"velocity_mapping must be one of {VELOCITY_MAPPINGS}, "
                             f"got {self.velocity_mapping!r}")
        if self.backend not in BACKENDS:
            raise ValueError(f"backend must be one of {BACKENDS}, got {self.backend!r}")
        if self.remesh not in REMESHERS:
            raise ValueError(f"remesh must be one of {REMESHERS}, got {self.remesh!r}")
        for name in ("rho", "g", "dt", "alpha", "floor", "search"):
            value = getattr(self, name)
            if not np.isfinite(value) or value <= 0:
                raise ValueError(f"{name} must be positive, got {value!r}")
        if int(self.passes) < 1:
            raise ValueError(f"passes must be >= 1, got {self.passes!r}")
        if int(self.remesh_interval) < 1:
            raise ValueError(f"remesh_interval must be >= 1, got {self.remesh_interval!r}")
        self.theta = ThetaMethod(self.dt, self.theta1, self.theta2)
        self.elastic = None if self.E is None else Elastic(self.E, self.nu)


@dataclass(kw_only=True)
class PFEMState(Particles):
    """Everything that carries over from one step to the next (and into a checkpoint).

    A :class:`~pfem_skfem.pfem.Particles` cloud (x, h, v, and the tags free_surface:
    on the boundary of the last mesh or flying free, contact: pressed against a rigid
    body in the last step), validated the same way, and:
    step, time;  sigma_m : (n,) lagged, smoothed mean stress (sx + sy)/2 carried by the
    particles;  mesh_p, mesh_t : the current mesh (vertices moved to t_n), mesh_particle :
    particle of each vertex;  v_dofs : (n_u,) P2 velocities on it;  sigma : (n_points, 4)
    stresses at its stress points;  scales : (3,) the previous step's DynamicScales
    (nan before the first step);  area0 : area of the initial domain;  alpha : the
    current alpha;  history : dict of per-step lists;  stress0 : (n, 4) initial
    stresses (sx, sy, sz, sxy) at the particles, interpolated to the stress points of
    the first mesh (None: zero), which an elastoplastic body needs to start in equilibrium.
    """

    step: int
    time: float
    sigma_m: np.ndarray
    mesh_p: np.ndarray = None
    mesh_t: np.ndarray = None
    mesh_particle: np.ndarray = None
    v_dofs: np.ndarray = None
    sigma: np.ndarray = None
    scales: np.ndarray = field(default_factory=lambda: np.full(3, np.nan))
    area0: float = np.nan
    alpha: float = np.nan
    history: dict = field(default_factory=dict)
    stress0: np.ndarray = None

    def __post_init__(self):
        super().__post_init__()
        self.sigma_m = np.asarray(self.sigma_m, dtype=float)
        if self.sigma_m.shape != (self.n,):
            raise ValueError(f"sigma_m must have shape ({self.n},), got {self.sigma_m.shape}")
        if self.stress0 is not None:
            self.stress0 = np.asarray(self.stress0, dtype=float)
            if self.stress0.shape != (self.n, 4):
                raise ValueError(f"stress must have shape ({self.n}, 4), got {self.stress0.shape}")

    def subset(self, keep):
        """The state restricted to the kept particles (boolean mask); the old mesh keeps
        its own vertex data, with -1 for a vertex whose particle was dropped."""
        keep = np.asarray(keep, dtype=bool)
        mesh_particle = self.mesh_particle
        if mesh_particle is not None:
            index = np.full(len(keep), -1)
            index[keep] = np.arange(int(keep.sum()))
            mesh_particle = index[mesh_particle]
        return replace(self, x=self.x[keep], v=self.v[keep], h=self.h[keep],
                       free_surface=self.free_surface[keep], contact=self.contact[keep],
                       sigma_m=self.sigma_m[keep], mesh_particle=mesh_particle,
                       stress0=None if self.stress0 is None else self.stress0[keep])


# -- initial state ------------------------------------------------------------------------
def grid_particles(width, height, nx, ny=None, origin=(0.0, 0.0)):
    """A rectangular block of particles on a square grid: (n, 2) positions and spacing h.

    nx particles across ``width`` (edges included); ny by default so that the grid is square.
    """
    if nx < 2:
        raise ValueError(f"nx must be >= 2, got {nx!r}")
    h = width / (nx - 1)
    ny = ny or int(round(height / h)) + 1
    xs = origin[0] + np.linspace(0, width, nx)
    ys = origin[1] + np.linspace(0, height, ny)
    X, Y = np.meshgrid(xs, ys)
    return np.column_stack([X.ravel(), Y.ravel()]), h


def geostatic_mean_stress(x, top, rho, g, k0):
    """Mean stress (sx + sy)/2 of the geostatic column of :func:`geostatic_stress`."""
    s = geostatic_stress(x, top, rho, g, k0)
    return 0.5 * (s[:, 0] + s[:, 1])


def initial_state(x, h, sigma_m=None, stress=None):
    """The state at t = 0: particles at rest with a lagged mean stress (zero by default)
    and, optionally, initial stresses (n, 4) at the particles (zero by default)."""
    x = check_positions(x)                       # ValueError for an empty or bad cloud
    sm = np.zeros(len(x)) if sigma_m is None else sigma_m
    return PFEMState(step=0, time=0.0, x=x.copy(), h=np.array(h, dtype=float), sigma_m=sm,
                     stress0=stress)


def geostatic_stress(x, top, rho, g, k0, nu=0.0):
    """Geostatic stresses (n, 4) (sx, sy, sz, sxy): sy = -rho g (top - y), sx = k0 sy and
    the plane-strain sz = nu (sx + sy)."""
    sy = -rho * g * np.clip(top - x[:, 1], 0, None)
    sx = k0 * sy
    return np.column_stack([sx, sy, nu * (sx + sy), np.zeros_like(sy)])


# -- stages ------------------------------------------------------------------------------
def detect(x, h, alpha):
    """Step 1a: the domain of the cloud by the alpha-shape (Section 2.3)."""
    return alpha_shape(x, h, alpha)


def _drop_degenerate(pm, h):
    """Remove triangles of (near) zero area from a particle mesh (collapsed slivers)."""
    p, t = pm.mesh.p.T, pm.mesh.t.T
    area = triangle_areas(p, t)
    good = area > 1e-8 * np.min(h) ** 2
    if good.all():
        return pm
    used = np.unique(t[good])
    index = np.full(len(p), -1)
    index[used] = np.arange(len(used))
    mesh = MeshTri(np.ascontiguousarray(p[used].T), np.ascontiguousarray(index[t[good]].T),
                   sort_t=False)
    return ParticleMesh(mesh, pm.particle[used])


def remesh(shape, method="alpha", size=1.5):
    """Step 1b: a mesh of the detected domain whose vertices are the particles (Section 2.4)."""
    pm = alpha_mesh(shape) if method == "alpha" else quality_remesh(shape, size=size)
    return _drop_degenerate(pm, shape.h)


def _barycentric_at_points(disc):
    """Area coordinates (n_points, 3) of each stress point in its element, and the element."""
    e = disc.point_element
    v = disc.mesh.p.T[disc.mesh.t[:3].T[e]]                    # (n, 3, 2)
    jac = np.stack([v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]], axis=2)
    xi = np.linalg.solve(jac, (disc.points - v[:, 0])[..., None])[..., 0]
    return np.column_stack([1 - xi.sum(axis=1), xi]), e


def vertex_to_points(disc, values):
    """A vertex field (linear in each element) at the stress points."""
    lam, e = _barycentric_at_points(disc)
    return np.einsum("nk,nk->n", lam, np.asarray(values)[disc.mesh.t[:3].T[e]])


def smoothed_mean_stress(disc, sigma):
    """Area-weighted vertex averages of the element mean of (sx + sy)/2 (lesson (ii) of issue 7)."""
    sm = 0.5 * (sigma[:, 0] + sigma[:, 1])
    e = disc.point_element
    m = disc.mesh.nelements
    area = np.bincount(e, disc.weights, minlength=m)
    elem = np.bincount(e, disc.weights * sm, minlength=m) / area
    t = disc.mesh.t[:3]
    num = np.bincount(t.ravel(), np.tile(area * elem, 3), minlength=disc.mesh.nvertices)
    den = np.bincount(t.ravel(), np.tile(area, 3), minlength=disc.mesh.nvertices)
    return num / den


def vertex_dofs(disc):
    """(n_vertices, 2) x and y displacement dofs at the mesh vertices."""
    return disc.basis_u.nodal_dofs.T


def _collapsed(p, t):
    """Triangles of zero area relative to their size (as :func:`~pfem_skfem.operators.check_mesh`)."""
    v = p[t]
    e = v[:, [1, 2, 0]] - v
    twice_area = np.abs(e[:, 0, 0] * e[:, 2, 1] - e[:, 0, 1] * e[:, 2, 0])
    return twice_area <= 1e-10 * np.max(np.sum(e ** 2, axis=2), axis=1)


def old_discretisation(state):
    """The last mesh, moved to t_n, with its P2 velocities and stresses: the source of a map.

    A step may collapse a triangle of the moved mesh (zero area); it is left out, its
    values living on in its neighbours (vertex and midside dofs are shared), so that the
    map sees a valid mesh. Returns (Discretisation, v_dofs, sigma).
    """
    p, t = state.mesh_p, state.mesh_t
    bad = _collapsed(p, t)
    if not bad.any():
        disc = discretise(MeshTri(np.ascontiguousarray(p.T), np.ascontiguousarray(t.T),
                                  sort_t=False))
        return disc, state.v_dofs, state.sigma
    full = MeshTri(np.ascontiguousarray(p.T), np.ascontiguousarray(t.T), sort_t=False)
    disc = discretise(MeshTri(np.ascontiguousarray(p.T), np.ascontiguousarray(t[~bad].T),
                              sort_t=False))
    # P2 vector dofs (scikit-fem): vertex v -> 2v + c, facet f -> 2 nv + 2f + c, with
    # nv = mesh.nvertices (the largest vertex index in t, plus one)
    nv, nv_red = full.nvertices, disc.mesh.nvertices
    key = lambda f: f[0] * nv + f[1]                       # noqa: E731 (facets are sorted)
    index = dict(zip(key(full.facets), range(full.facets.shape[1])))
    f_full = np.array([index[k] for k in key(disc.mesh.facets)])
    v = np.zeros(disc.n_u)
    v[disc.basis_u.nodal_dofs] = state.v_dofs[np.arange(2 * nv_red).reshape(nv_red, 2).T]
    v[disc.basis_u.facet_dofs] = state.v_dofs[2 * nv + 2 * f_full + np.arange(2)[:, None]]
    sigma = state.sigma.reshape(-1, 3, 4)[~bad].reshape(-1, 4)
    return disc, v, sigma


def map_state(state, pm, disc, mapping="uem_bounded", velocity="projection"):
    """Step 1c: velocities, stresses and the lagged mean stress on the new mesh.

    Nodal velocities (``velocity``): "projection" (default), the L2 projection of the
    old P2 field (on the moved old mesh) onto the new mesh
    (:func:`~pfem_skfem.pfem.mapping.project_nodal`), which conserves momentum and
    does not add kinetic energy; or "interpolation", the old field at the new nodes
    with the vertices set to their particles' velocities and a midside node outside
    the old mesh given the mean of its edge's two vertices (no extrapolation).
    Interpolation adds kinetic energy at every remeshing of a sheared field (measured
    on the a = 1 column, 100 steps: a third of the peak kinetic energy in all).
    Stresses: ``mapping`` ('uem_bounded', 'uem' (Fig 2.6), 'ida' (2.1)-(2.2), 'spr').
    Mean stress: carried by the particles.
    Returns v_dofs (n_u,), sigma (n_points, 4).
    """
    vd = vertex_dofs(disc)
    if state.mesh_p is None:       # first mesh: the particles' velocities, linear in each element
        v = np.zeros(disc.n_u)
        v[vd] = state.v[pm.particle]
        a, b = disc.mesh.facets
        v[disc.basis_u.facet_dofs] = 0.5 * (v[vd[a]] + v[vd[b]]).T
        sigma = np.zeros((disc.n_points, 4))
        if state.stress0 is not None:
            for k in range(4):
                sigma[:, k] = vertex_to_points(disc, state.stress0[pm.particle, k])
        return v, sigma
    old, v_old, sigma_old = old_discretisation(state)
    sigma = map_stress(old, sigma_old, disc, mapping)
    if velocity == "projection":
        return project_nodal(old.basis_u, v_old, disc.basis_u,
                             vertex_values=state.v[pm.particle]), sigma
    v = map_nodal(old.basis_u, v_old, disc.basis_u)
    v[vd] = state.v[pm.particle]
    # a midside node outside the old mesh would take the old quadratic extrapolated, which
    # can be far off near the free surface (measured: a splashing element thrown at 15 m/s);
    # there the velocity is the mean of the edge's two particles
    ends = disc.mesh.facets
    _, inside, _ = locate(old.mesh, disc.mesh.p[:, ends].mean(axis=1).T)
    out = ~inside
    if out.any():
        fd = disc.basis_u.facet_dofs[:, out]
        v[fd] = 0.5 * (v[vd[ends[0, out]]] + v[vd[ends[1, out]]]).T
    return v, sigma


def _adopt_added_nodes(state, pm):
    """Nodes Triangle added become particles: velocity and mean stress from the old mesh."""
    added = pm.particle < 0
    if not added.any():
        return state, pm
    xa = pm.mesh.p.T[added]
    if state.mesh_p is None:
        va, sa = np.zeros((len(xa), 2)), np.zeros(len(xa))
    else:
        old_disc, v_old, _ = old_discretisation(state)
        va = interpolate(old_disc.basis_u, v_old, xa).T
        p1 = Basis(old_disc.mesh, ElementTriP1())
        mp = state.mesh_particle                  # -1: a particle thinned away since
        vals = state.sigma_m[np.maximum(mp, 0)]
        if (mp < 0).any():
            vals[mp < 0] = vals[mp >= 0].mean()
        sa = interpolate(p1, vals, xa)
    ha = np.full(len(xa), np.median(state.h))
    n = len(state.x)
    particle = pm.particle.copy()
    particle[added] = n + np.arange(len(xa))
    stress0 = state.stress0
    if stress0 is not None:                   # first mesh: nearest particle's initial stress
        from scipy.spatial import cKDTree
        stress0 = np.vstack([stress0, stress0[cKDTree(state.x).query(xa)[1]]])
    no = np.zeros(len(xa), dtype=bool)
    new = replace(state, x=np.vstack([state.x, xa]), v=np.vstack([state.v, va]),
                  h=np.concatenate([state.h, ha]), sigma_m=np.concatenate([state.sigma_m, sa]),
                  free_surface=np.concatenate([state.free_surface, no]),
                  contact=np.concatenate([state.contact, no]), stress0=stress0)
    return new, ParticleMesh(pm.mesh, particle)


def assemble(disc, config, search):
    """Operators of (4.23) for this mesh, the gravity load and the contact set (5.12).

    Only the rigid bodies with a boundary node within ``search`` take part.
    """
    ops = dynamic_operators(disc, config.rho, config.theta, elastic=config.elastic)
    f = body_force_vector(disc, (0.0, -config.rho * config.g))
    contacts = None
    if config.bodies:
        _, xb = boundary_nodes(disc)
        near = [b for b in config.bodies if (b.gap(xb)[0] <= search).any()]
        if near:
            contacts = potential_contacts(disc, near, search)
    return ops, f, contacts


def criterion_for(config, sigma_m_points):
    """The cone of the step: TrescaField with radii from the lagged mean stress, or Davis."""
    if config.material == "davis":
        c_star, phi_star = davis(config.c, config.phi, 0.0)
        # the same least radius as the Tresca scheme: 2 c* cos(phi*) >= floor keeps an interior
        c_floor = config.floor / (2 * np.cos(np.radians(phi_star)))
        return MohrCoulomb(max(c_star, c_floor), phi_star)
    return TrescaField(mohr_coulomb_radius(config.c, config.phi, sigma_m_points, config.floor))


def solve_step(ops, f, contacts, disc, config, v_dofs, sigma_n, sigma_m_vertices, scales):
    """Step 2a: (4.23) with (5.12) on the psi = 0 cone; ``passes`` fixed-point passes.

    Each pass takes the mean stress of the previous one (the first: the lagged one
    carried by the particles); with ``contact="zero-dilation"`` the first pass is
    smooth and each later one bounds the friction by mu p of the previous pass.
    Returns the last DynamicIncrement, the smoothed vertex mean stress of its solution,
    the solver iterations, compile and solve seconds summed over the passes, and the
    number of passes Clarabel ended 'AlmostSolved' (accepted, and counted).
    """
    zero_dilation = contacts is not None and config.contact == "zero-dilation"
    passes = int(config.passes) if config.material != "davis" or zero_dilation else 1
    sm_v = sigma_m_vertices
    if scales is None:           # first step: scales from the Mohr-Coulomb strength at sigma_m
        k = mohr_coulomb_radius(config.c, config.phi, vertex_to_points(disc, sm_v), config.floor)
        f_rhs = config.theta.equilibrium_rhs(f, f, ops.B, sigma_n)
        scales = estimate_scales(ops, f_rhs, v_dofs, sigma_n, np.arange(disc.n_u), TrescaField(k))
    iterations, compile_time, solve_time, inaccurate = 0, 0.0, 0.0, 0
    step_contacts = contacts
    if zero_dilation:                                   # pass 1: smooth, for p
        step_contacts = with_friction_bound(contacts, np.zeros(contacts.size))
    for _ in range(passes):
        crit = criterion_for(config, vertex_to_points(disc, sm_v))
        # Clarabel's 'AlmostSolved' is accepted and counted in the step record
        inc = dynamic_increment(ops, f, f, sigma_n, v_dofs, crit, contacts=step_contacts,
                                scaling=scales, accept_inaccurate=True, backend=config.backend)
        inaccurate += inc.info.status != "optimal"
        iterations += inc.info.iterations
        compile_time += inc.info.compile_time
        solve_time += inc.info.solve_time
        sm_v = smoothed_mean_stress(disc, inc.sigma)
        if zero_dilation:
            step_contacts = with_friction_bound(contacts, np.maximum(inc.p, 0.0))
    return inc, sm_v, iterations, compile_time, solve_time, inaccurate


def plastic_strain_increment(disc, B, du):
    """Equivalent plastic strain increment sqrt((dexx - deyy)^2 + dgxy^2) at each stress point.

    For a rigid-plastic body the whole strain increment is plastic; strains are the
    rows of B du divided by the stress point's weight (B integrates N_sigma B_u).
    """
    e = (B @ du).reshape(-1, 4) / disc.weights[:, None]
    return np.sqrt((e[:, 0] - e[:, 1]) ** 2 + e[:, 3] ** 2)


def _boundary_edges(disc, du):
    """Boundary edges: end vertices a, b, midside dofs, the midside deviation
    delta = du_mid - (du_a + du_b)/2 and the outward unit normal at t_n."""
    mesh = disc.mesh
    f = mesh.boundary_facets()
    a, b = mesh.facets[:, f]
    vd = vertex_dofs(disc)
    fd = disc.basis_u.facet_dofs[:, f]
    delta = du[fd].T - 0.5 * (du[vd[a]] + du[vd[b]])
    p = mesh.p.T
    t = p[b] - p[a]
    n = np.column_stack([t[:, 1], -t[:, 0]]) / np.linalg.norm(t, axis=1)[:, None]
    centroid = p[mesh.t[:, mesh.f2t[0, f]]].mean(axis=0)
    n[np.einsum("id,id->i", n, 0.5 * (p[a] + p[b]) - centroid) < 0] *= -1   # outward
    return a, b, fd, delta, n


def bulge_correction(disc, du, skip=None, regularisation=0.01):
    """Shift of the boundary vertices that keeps the area the P2 displacement gives the body.

    The particles are the vertices only, so moving them drops the bulge of each boundary
    edge, the area (2/3) L (delta . n) between the curved P2 edge and its chord, with
    delta = du_mid - (du_a + du_b)/2 and n the outward unit normal. The flow of the psi = 0
    scheme is exactly isochoric in each P2 element (div du is linear and orthogonal to
    the linear stresses), so the dropped bulge is a loss of area at every step, of first
    order in du and independent of dt.

    Each end of an edge puts back half of its bulge: a shift w_a of vertex a adds
    (L_e / 2) (w_a . n_e) to edge e, so w_a should satisfy w_a . n_e = c_e with
    c_e = (2/3) (delta_e . n_e) for both boundary edges e at a. Solved per vertex in the
    least-squares sense with a small Tikhonov term (``regularisation``), which on a
    straight boundary gives w_a = (c_1 + c_2)/2 n (the two equations coincide) and at a
    corner the shift that leaves the edge without bulge unchanged: the crest of a slope
    below a flat top moves along the top, not up. ``skip`` : (n_boundary_edges,) bool,
    edges left out (those whose midside node becomes a particle).

    Returns (n_vertices, 2) shifts (zero at interior vertices).
    """
    a, b, _, delta, n = _boundary_edges(disc, du)
    c = 2.0 / 3.0 * np.einsum("id,id->i", delta, n)
    if skip is not None:
        c = np.where(skip, 0.0, c)
    nv = disc.mesh.nvertices
    normal_matrix = np.zeros((nv, 2, 2))                  # sum_e n_e n_e^T at each vertex
    rhs = np.zeros((nv, 2))                               # sum_e c_e n_e
    nn = n[:, :, None] * n[:, None, :]
    for end in (a, b):
        np.add.at(normal_matrix, end, nn)
        np.add.at(rhs, end, c[:, None] * n)
    on = np.unique(np.concatenate([a, b]))
    # the Tikhonov term in units of the vertex's own normal matrix (trace = edges at it)
    lam = regularisation * np.trace(normal_matrix[on], axis1=1, axis2=2) / 2
    shift = np.zeros((nv, 2))
    shift[on] = np.linalg.solve(normal_matrix[on] + lam[:, None, None] * np.eye(2),
                                rhs[on][..., None])[..., 0]
    return shift


def move(state, pm, disc, inc, config, sigma_m_vertices):
    """Step 2b: particles of the mesh move by du (vertex dofs) and take v_{n+1}; particles
    in no element fly ballistically (theta-method free fall) and slide with friction on the
    rigid bodies (:func:`~pfem_skfem.problems.particle.free_particles_step`).

    Returns x, v, sigma_m, h of the particles (new ones appended: midside nodes of
    stretched boundary edges) and the number of particles found inside a rigid body by
    more than 1e-3 h (put back on its surface)."""
    vd = vertex_dofs(disc)
    x, v = state.x.copy(), state.v.copy()
    sm = state.sigma_m.copy()
    on_mesh = np.zeros(len(x), dtype=bool)
    on_mesh[pm.particle] = True
    x[pm.particle] += inc.du[vd]
    # stretched boundary edges: their P2 midside node becomes a particle, so the free
    # surface is not torn open by the alpha-shape (its triangles would be deleted)
    a, b, fd, _, _ = _boundary_edges(disc, inc.du)
    pa, pb = pm.particle[a], pm.particle[b]
    h_edge = 0.5 * (state.h[pa] + state.h[pb])
    split = np.zeros(len(a), dtype=bool)
    if config.refine_surface > 0:
        split = np.linalg.norm(x[pa] - x[pb], axis=1) > config.refine_surface * h_edge
    if config.bulge:
        x[pm.particle] += bulge_correction(disc, inc.du, skip=split)
    new_x = disc.basis_u.doflocs[:, fd[0, split]].T + inc.du[fd[:, split]].T
    new_v = inc.v[fd[:, split]].T
    new_h = h_edge[split]
    v[pm.particle] = inc.v[vd]
    sm[pm.particle] = sigma_m_vertices
    free = ~on_mesh
    if free.any():              # gravity and frictional contact with the walls, (5.2)
        x[free], v[free] = free_particles_step(x[free], v[free], (0.0, -config.g), config.dt,
                                               config.theta.theta2, config.bodies)
        sm[free] = 0.0
    h = state.h
    if split.any():
        new_sm = 0.5 * (sm[pa[split]] + sm[pb[split]])
        x, v = np.vstack([x, new_x]), np.vstack([v, new_v])
        sm, h = np.concatenate([sm, new_sm]), np.concatenate([h, new_h])
    # no particle inside a rigid body: a node that was outside the contact search (or a
    # free particle) and crossed a wall is put back on it with its normal velocity removed
    projected = 0
    for body in config.bodies:
        g0, n = body.gap(x)
        inside = g0 < 0
        if inside.any():
            x[inside] -= g0[inside, None] * n[inside]
            vn = np.einsum("id,id->i", v[inside], n[inside])
            v[inside] -= np.minimum(vn, 0)[:, None] * n[inside]
            projected += int(np.sum(g0 < -1e-3 * np.median(state.h)))
    return x, v, sm, h, projected


def particle_tags(disc, pm, contacts, inc, n, weight):
    """The tags of :class:`~pfem_skfem.pfem.Particles` after a step, for n particles.

    free_surface : a vertex of a boundary edge of the step's mesh, or a particle in no
    element (flying free, or new: the midside node of a stretched boundary edge);
    contact : a vertex pressed against a rigid body, normal force p above 1e-6 ``weight``
    (a particle's weight, rho g h^2).
    """
    free_surface = np.ones(n, dtype=bool)
    free_surface[pm.particle] = False
    free_surface[pm.particle[disc.mesh.boundary_nodes()]] = True
    contact = np.zeros(n, dtype=bool)
    if contacts is not None:
        vertex_of = np.full(disc.n_u, -1)
        vertex_of[vertex_dofs(disc)[:, 0]] = np.arange(disc.mesh.nvertices)
        vertex = vertex_of[contacts.dofs[:, 0]]          # -1: a midside node
        pressed = (vertex >= 0) & (inc.p > 1e-6 * weight)
        contact[pm.particle[vertex[pressed]]] = True
    return free_surface, contact


# -- the step ----------------------------------------------------------------------------
def pfem_step(state, config):
    """One PFEM step C^n -> C^{n+1} (Section 2.2); returns (new state, step record)."""
    t0 = _time.perf_counter()
    timing = {}
    search = config.search * float(np.median(state.h))
    remesh_now = state.mesh_p is None or state.step % int(config.remesh_interval) == 0
    alpha = config.alpha if not np.isfinite(state.alpha) else state.alpha
    if remesh_now:
        if config.remesh == "quality":                     # keep the spacing near h
            keep = thin_cloud(state.x, state.h, fraction=0.4)
            if not keep.all():
                state = state.subset(keep)
        shape = detect(state.x, state.h, alpha)
        area = shape.area
        if not np.isfinite(state.area0):
            state.area0 = area
        if config.adaptive:
            alpha = float(np.clip(adaptive_alpha(alpha, state.area0, area), 0.8 * config.alpha,
                                  1.5 * config.alpha))
        t1 = _time.perf_counter()
        timing["detect"] = t1 - t0
        pm = remesh(shape, config.remesh, config.quality_size)
        state, pm = _adopt_added_nodes(state, pm)
        disc = discretise(pm.mesh)
        t2 = _time.perf_counter()
        timing["remesh"] = t2 - t1
        v_dofs, sigma_n = map_state(state, pm, disc, config.mapping, config.velocity_mapping)
        timing["map"] = _time.perf_counter() - t2
    else:
        t1 = _time.perf_counter()
        timing["detect"] = 0.0
        mesh = MeshTri(np.ascontiguousarray(state.x[state.mesh_particle].T),
                       np.ascontiguousarray(state.mesh_t.T), sort_t=False)
        pm = ParticleMesh(mesh, state.mesh_particle)
        disc = discretise(mesh)
        area = disc.area
        timing["remesh"] = _time.perf_counter() - t1
        t2 = _time.perf_counter()
        v_dofs, sigma_n = state.v_dofs, state.sigma
        timing["map"] = 0.0
    t3 = _time.perf_counter()
    ops, f, contacts = assemble(disc, config, search)
    timing["assemble"] = _time.perf_counter() - t3
    scales = None
    if np.all(np.isfinite(state.scales)):
        # the previous step's magnitudes, but not below those of a free-fall step: as a
        # body comes to rest the displacement scale would otherwise shrink step by step,
        # the scaled gaps g0 / u_ref of (5.12) grow as much, and Clarabel reports
        # 'unbounded' (measured: phi = 35, a = 0.5, step 189 of 200)
        stress, u, r = state.scales
        scales = DynamicScales(stress, max(u, config.g * config.dt ** 2),
                               max(r, config.rho * config.g))
    t4 = _time.perf_counter()
    inc, sm_v, iters, t_compile, t_solve, inaccurate = solve_step(
        ops, f, contacts, disc, config, v_dofs, sigma_n, state.sigma_m[pm.particle], scales)
    t5 = _time.perf_counter()
    timing["compile"] = t_compile
    timing["solve"] = t_solve
    timing["other_solve"] = (t5 - t4) - t_compile - t_solve
    x, v, sm, h_new, projected = move(state, pm, disc, inc, config, sm_v)

    # the mesh moved with its vertices (straight sides), for the next map
    mesh_p = x[pm.particle]
    speed = np.linalg.norm(v[pm.particle], axis=1)
    deps = plastic_strain_increment(disc, ops.B, inc.du)
    # the mesh's own area before and after the move: the change is the solve's (straight
    # sides, contact dilation); the rest of the area change is the detection's
    mesh_area = float(triangle_areas(disc.mesh.p.T, disc.mesh.t.T).sum())
    moved_area = float(triangle_areas(mesh_p, disc.mesh.t.T).sum())
    record = {"step": state.step + 1, "time": state.time + config.dt, "area": area,
              "mesh_area": mesh_area, "moved_area": moved_area,
              "area_change": area / state.area0 - 1, "alpha": alpha,
              "iterations": iters, "inaccurate": inaccurate, "elements": int(disc.mesh.nelements),
              "particles": int(len(x)), "free_particles": int(len(x) - len(pm.particle)),
              "projected": projected,
              "max_speed": float(speed.max()),
              "kinetic_energy": float(0.5 * inc.v @ (ops.M @ inc.v)),
              "max_plastic_strain_increment": float(deps.max()),
              "seconds": _time.perf_counter() - t0, **{f"t_{k}": v_ for k, v_ in timing.items()}}
    history = {k: list(vals) for k, vals in state.history.items()}
    for k, val in record.items():
        history.setdefault(k, []).append(val)
    free_surface, contact = particle_tags(
        disc, pm, contacts, inc, len(x), config.rho * config.g * float(np.median(state.h)) ** 2)
    new = PFEMState(step=state.step + 1, time=state.time + config.dt, x=x, v=v, h=h_new,
                    free_surface=free_surface, contact=contact, sigma_m=sm, mesh_p=mesh_p,
                    mesh_t=disc.mesh.t.T.copy(),
                    mesh_particle=pm.particle.copy(), v_dofs=inc.v.copy(),
                    sigma=inc.sigma.copy(),
                    scales=np.array([inc.scales.stress, inc.scales.displacement,
                                     inc.scales.dynamic_force]),
                    area0=state.area0, alpha=alpha, history=history)
    new._last = {"disc": disc, "inc": inc, "deps": deps, "pm": pm}   # for output only
    return new, record


# -- checkpoints -----------------------------------------------------------------------
_ARRAYS = ("x", "v", "h", "free_surface", "contact", "sigma_m", "mesh_p", "mesh_t",
           "mesh_particle", "v_dofs", "sigma", "stress0", "scales")


def save_checkpoint(path, state):
    """Write the state to ``path`` (np.savez): arrays exactly, history as JSON text."""
    data = {k: getattr(state, k) for k in _ARRAYS if getattr(state, k) is not None}
    np.savez(path, step=state.step, time=state.time, area0=state.area0, alpha=state.alpha,
             history=json.dumps(state.history), **data)


def load_checkpoint(path):
    """A state written by :func:`save_checkpoint`."""
    with np.load(path) as z:
        kw = {k: z[k].copy() for k in _ARRAYS if k in z.files}
        return PFEMState(step=int(z["step"]), time=float(z["time"]), area0=float(z["area0"]),
                         alpha=float(z["alpha"]), history=json.loads(str(z["history"])), **kw)


# -- output --------------------------------------------------------------------------------
def step_fields(state):
    """Points, triangles and fields of the last step for VTU output.

    Point data: velocity (3 components, z = 0 for ParaView), lagged mean stress,
    pressure p = -(sx + sy)/2 (smoothed, vertex), the tags free_surface and contact
    (0/1);  cell data: element mean stress (sx, sy, sxy), equivalent plastic strain
    increment.
    """
    last = state._last
    disc, inc, deps, pm = last["disc"], last["inc"], last["deps"], last["pm"]
    points = state.x[pm.particle]
    cells = disc.mesh.t.T
    e, w, m = disc.point_element, disc.weights, disc.mesh.nelements
    area = np.bincount(e, w, minlength=m)
    mean = lambda a: np.bincount(e, w * a, minlength=m) / area     # noqa: E731
    vel = np.zeros((len(points), 3))
    vel[:, :2] = state.v[pm.particle]
    sm = state.sigma_m[pm.particle]
    point_data = {"velocity": vel, "speed": np.linalg.norm(vel, axis=1),
                  "pressure": -sm, "mean_stress": sm,
                  "free_surface": state.free_surface[pm.particle].astype(float),
                  "contact": state.contact[pm.particle].astype(float)}
    cell_data = {"stress": np.column_stack([mean(inc.sigma[:, 0]), mean(inc.sigma[:, 1]),
                                            mean(inc.sigma[:, 3])]),
                 "plastic_strain_increment": mean(deps)}
    return points, cells, point_data, cell_data


def run(state, config, steps, *, checkpoint=None, checkpoint_every=0, series=None,
        save_every=1, on_step=None, verbose=False, snapshots=()):
    """Advance ``state`` by ``steps`` PFEM steps.

    Parameters
    ----------
    state : PFEMState (fresh from :func:`initial_state` or from :func:`load_checkpoint`).
    config : PFEMConfig.
    steps : number of steps to take.
    checkpoint : path of the checkpoint file, written every ``checkpoint_every`` steps.
    series : a :class:`pfem_skfem.io.TimeSeries` to write a VTU every ``save_every`` steps.
    on_step : callable(state, record) after each step.
    verbose : print one progress line per step (step, time, area change, iterations, s).
    snapshots : step numbers whose particle positions, velocities and plastic strain
        increment are kept in the returned dict.

    Returns
    -------
    (state, snaps) with snaps {step: dict(x, v, points, cells, deps)}.
    """
    snaps = {}
    for _ in range(int(steps)):
        state, rec = pfem_step(state, config)
        if verbose:
            print(f"step {rec['step']:5d}  t = {rec['time']:.4f}  dA = {rec['area_change']:+.3%}"
                  f"  it = {rec['iterations']:3d}  elements = {rec['elements']:5d}"
                  f"  |v|max = {rec['max_speed']:.3g}  {rec['seconds']:.2f} s", flush=True)
        if series is not None and save_every and state.step % save_every == 0:
            series.write(state.time, *step_fields(state))
        if state.step in snapshots:
            pts, cells, pd, cd = step_fields(state)
            snaps[state.step] = {"x": state.x.copy(), "points": pts, "cells": cells,
                                 "speed": pd["speed"], "deps": cd["plastic_strain_increment"]}
        if checkpoint is not None and checkpoint_every and state.step % checkpoint_every == 0:
            save_checkpoint(checkpoint, state)
        if on_step is not None:
            on_step(state, rec)
    return state, snaps


def run_to_rest(state, config, speed, max_steps, **options):
    """Advance ``state`` one step at a time until every particle is slower than ``speed``,
    for at most ``max_steps`` steps (``options`` go to :func:`run`).

    Returns (state, at_rest, steps taken).
    """
    at_rest = lambda st: bool(np.max(np.linalg.norm(st.v, axis=1)) < speed)   # noqa: E731
    taken = 0
    while not at_rest(state) and taken < max_steps:
        state, _ = run(state, config, 1, **options)
        taken += 1
    return state, at_rest(state), taken


def config_summary(config):
    """The config as plain JSON-able values (rigid bodies by their repr)."""
    d = {f.name: getattr(config, f.name) for f in fields(PFEMConfig)}
    d["bodies"] = [repr(b) for b in config.bodies]
    return d


# -- the granular column of Section 6.4.3 ---------------------------------------------------
def granular_column(a, nx, *, d0=1.0, rho=2.0, g=9.8, phi=31.0, c=0.0, mu=None,
                    right_wall=False, floor_fraction=0.005, k0=None, **options):
    """Initial state and config of the plane granular column (thesis Fig 6.11).

    A column d0 wide and h0 = a d0 high on particles of a square grid (nx across)
    rests on a rigid base y = 0 against a rigid wall x = 0; the right wall x = d0 is
    removed at t = 0 unless ``right_wall``. Base and walls have friction ``mu``
    (default tan phi). The lagged mean stress starts geostatic with K0 = 1 - sin phi
    (Jaky) unless ``k0`` is given. ``floor_fraction`` * rho g h0 is the least cone radius.
    Other keyword options go to :class:`PFEMConfig` (dt defaults to 0.01 sqrt(h0/g)).
    """
    from ..problems.contact import RigidSegment

    if a <= 0:
        raise ValueError(f"a (aspect ratio h0/d0) must be positive, got {a!r}")
    h0 = a * d0
    mu = np.tan(np.radians(phi)) if mu is None else mu
    x, h = grid_particles(d0, h0, nx)
    top = 20 * h0 + 10 * d0
    bodies = [RigidSegment((-top, 0.0), (top, 0.0), mu),          # base, solid above
              RigidSegment((0.0, top), (0.0, -h), mu)]              # left wall, solid right
    if right_wall:
        bodies.append(RigidSegment((d0, -h), (d0, top), mu))        # right wall, solid left
    options.setdefault("dt", 0.01 * np.sqrt(h0 / g))
    config = PFEMConfig(rho=rho, g=g, c=c, phi=phi, floor=floor_fraction * rho * g * h0,
                        bodies=tuple(bodies), **options)
    k0 = 1 - np.sin(np.radians(phi)) if k0 is None else k0
    stress = None
    if options.get("E") is not None:          # elastoplastic: start in geostatic equilibrium
        stress = geostatic_stress(x, h0, rho, g, k0, options.get("nu", 0.3))
    state = initial_state(x, h, geostatic_mean_stress(x, h0, rho, g, k0), stress)
    return state, config


def deposit_extent(state, alpha):
    """Height and toe (largest x) of the main body: the detected body of largest area.

    Particles splashed off the body (free, or in a small separate body) are left out,
    as an experimentalist measures the deposit, not its outliers.
    Returns (height, toe, main-body particle indices).
    """
    shape = detect(state.x, state.h, alpha)
    main = int(np.argmax(shape.body_area))
    idx = np.unique(shape.triangles[shape.body == main])
    return float(state.x[idx, 1].max()), float(state.x[idx, 0].max()), idx


def wall_height(state, particles, wall_x=0.0):
    """Height of the deposit at the wall x = ``wall_x``: the highest of ``particles`` within
    one spacing h of it (Lube et al. 2005 and Lagree et al. 2011 measure the final height
    there, where the deposit is thickest)."""
    idx = np.asarray(particles)
    near = idx[np.abs(state.x[idx, 0] - wall_x) <= state.h[idx]]
    if near.size == 0:
        raise ValueError(f"no particle of the deposit lies within one spacing of x = {wall_x}")
    return float(state.x[near, 1].max())
