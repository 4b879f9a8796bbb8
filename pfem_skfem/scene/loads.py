"""Surface loads of a PFEM scene: a traction prescribed on the free surface in a zone.

A :class:`SurfaceLoad` presses on the boundary edges of each step's mesh whose midpoints
lie in its zone (a :class:`~pfem_skfem.scene.outlets.HalfPlane` or
:class:`~pfem_skfem.scene.outlets.PolygonZone`, its edge included): the PFEM's boundary
changes from step to step, so the edges are found again on every mesh. The load is a force
per unit length of the edge in plane strain, per unit area of the surface of revolution in
axisymmetry (the 2 pi r weight of (7.26); the axis r = 0 is no surface and takes none).

Either a fixed ``traction`` (tx, ty), the same direction whatever the surface does, or a
``pressure`` p along the edge's inward normal, -p n (a follower load: the normal of the
step's mesh, at t_n). ``ramp`` (Python only, a function of t) scales either; the load of a
step is that of the theta method, theta1 F(t_{n+1}) + (1 - theta1) F(t_n) on its mesh
(:meth:`~pfem_skfem.discretisation.theta.ThetaMethod.load`).

The vector is int N_u^T t dS on the P2 boundary (scikit-fem's FacetBasis): a uniform
traction on a straight edge gives its end and midside nodes 1/6, 4/6, 1/6 of the edge's
force, the consistent load. It is added to the step's external force beside gravity's.
"""
from dataclasses import dataclass

import numpy as np
from skfem import FacetBasis, LinearForm

from ..discretisation.static import boundary_facets
from ..pfem.surface import axis_vertices
from .bodies import MOTION_CHECK_STEPS, step_count

#: how far (in units of the smallest spacing h) a midpoint may lie outside a zone and count
ZONE_TOL = 1e-6


@dataclass(frozen=True)
class SurfaceLoad:
    """A traction on the free surface in ``zone`` (module docstring).

    Parameters
    ----------
    zone : HalfPlane or PolygonZone; the boundary edges whose midpoints it holds (its edge
        included) are loaded.
    traction : (tx, ty), a force per unit length (per unit area in axisymmetry), fixed in
        direction;  or
    pressure : p, along the edge's inward normal (p > 0 presses on the material).
    ramp : None (constant) or a function of time t -> factor of the traction or pressure;
        a Python function has no TOML form.
    name : the load's name in messages and in the step records (``loads``).
    """

    zone: object
    traction: tuple = None
    pressure: float = None
    ramp: object = None
    name: str = "load"

    def __post_init__(self):
        if not hasattr(self.zone, "contains"):
            raise ValueError(f"load {self.name!r}: zone must be a HalfPlane or PolygonZone, "
                             f"got {self.zone!r}")
        if (self.traction is None) == (self.pressure is None):
            raise ValueError(f"load {self.name!r}: give one of traction (tx, ty) or "
                             f"pressure p")
        if self.traction is not None:
            t = np.asarray(self.traction, dtype=float)
            if t.shape != (2,) or not np.all(np.isfinite(t)):
                raise ValueError(f"load {self.name!r}: traction must be a finite (tx, ty), "
                                 f"got {self.traction!r}")
            object.__setattr__(self, "traction", tuple(map(float, t)))
        else:
            if isinstance(self.pressure, bool) or not np.isfinite(float(self.pressure)):
                raise ValueError(f"load {self.name!r}: pressure must be finite, got "
                                 f"{self.pressure!r}")
            object.__setattr__(self, "pressure", float(self.pressure))
        if self.ramp is not None and not callable(self.ramp):
            raise ValueError(f"load {self.name!r}: ramp must be None or a function of t, "
                             f"got {self.ramp!r}")

    def factor(self, t):
        """The ramp's factor at time t (1 without a ramp); ValueError naming the load if it
        fails or is not finite."""
        if self.ramp is None:
            return 1.0
        try:
            with np.errstate(all="ignore"):
                value = float(self.ramp(t))
        except Exception as err:                     # noqa: BLE001 - reported with the load
            raise ValueError(f"load {self.name!r}: ramp(t) failed at t = {t:g} ({err})") \
                from err
        if not np.isfinite(value):
            raise ValueError(f"load {self.name!r}: ramp(t) must be finite at every step time, "
                             f"got {value!r} at t = {t:g}")
        return value

    def facets(self, disc, tol):
        """The boundary facets of ``disc``'s mesh whose midpoints lie in the zone (within
        ``tol``), less those on the axis in axisymmetry."""
        facets = boundary_facets(disc, lambda mid: self.zone.contains(mid.T, tol=tol))
        on_axis = np.all(axis_vertices(disc)[disc.mesh.facets[:, facets]], axis=0)
        return facets[~on_axis]

    def vector(self, disc, tol):
        """int N_u^T t dS over :meth:`facets` at factor 1 (zeros if none is loaded)."""
        facets = self.facets(disc, tol)
        if facets.size == 0:
            return np.zeros(disc.n_u)
        geometry = disc.geometry
        fb = FacetBasis(disc.mesh, disc.basis_u.elem, facets=facets,
                        intorder=geometry.intorder(4))
        traction, pressure = self.traction, self.pressure

        @LinearForm
        def load(v, w):
            tt = (-pressure * w.n) if traction is None else np.asarray(traction)
            return (tt[0] * v[0] + tt[1] * v[1]) * geometry.weight(w.x)

        return load.assemble(fb)


def check_loads(loads):
    """The loads as a tuple of SurfaceLoads with unique names, or ValueError."""
    if isinstance(loads, SurfaceLoad) or isinstance(loads, str) or not hasattr(loads, "__iter__"):
        raise ValueError(f"loads must be a list or tuple, got {loads!r}")
    loads = tuple(loads)
    for load in loads:
        if not isinstance(load, SurfaceLoad):
            raise ValueError(f"loads must be SurfaceLoad objects, got {load!r}")
    names = [load.name for load in loads]
    if len(set(names)) != len(names):
        raise ValueError(f"load names must be unique, got {names}")
    return loads


def outline_points(regions, axisymmetric):
    """Points on the surface of the regions' material at t = 0: the midpoints of each
    polygon's and hole's edges cut into pieces of at most h, less those inside another
    region (an edge two regions share) and, in axisymmetry, those on the axis."""
    points = []
    for region in regions:
        for ring in (region.polygon, *region.holes):
            v = np.asarray(ring, dtype=float)
            for a, b in zip(v, np.roll(v, -1, axis=0)):
                n = max(int(np.ceil(np.linalg.norm(b - a) / region.h - 1e-9)), 1)
                s = (np.arange(n) + 0.5) / n
                points.append(a + s[:, None] * (b - a))
    x = np.vstack(points)
    eps = 1e-3 * min(r.h for r in regions)
    count = np.zeros(len(x), dtype=int)            # offsets in the material, of 4
    for d in ((eps, 0.0), (-eps, 0.0), (0.0, eps), (0.0, -eps)):
        here = np.zeros(len(x), dtype=bool)
        for r in regions:
            here |= r.contains(x + np.array(d))
        count += here
    surface = count < 4        # an edge two regions share has material on every side
    if axisymmetric:
        surface &= x[:, 0] > eps
    return x[surface]


def check_on_surface(scene):
    """Refuse (ValueError naming it) a load whose zone holds no surface edge of the
    material at t = 0 (:func:`outline_points`), and a ramp that fails or is not finite at
    a step time (to t_end, else the first ``MOTION_CHECK_STEPS``)."""
    if not scene.loads:
        return
    x = outline_points(scene.regions, scene.axisymmetric)
    h = min(r.h for r in scene.regions)
    for load in scene.loads:
        if not load.zone.contains(x, tol=ZONE_TOL * h).any():
            raise ValueError(f"load {load.name!r}: its zone holds no surface edge of the "
                             f"material at t = 0 (it would load nothing); give a zone over "
                             f"the body's free surface")
        check_ramp_over(load, scene.config.dt, scene.t_end)


def check_ramp_over(load, dt, t_end=None, *, start=0.0, steps=None,
                    default_steps=MOTION_CHECK_STEPS):
    """Refuse a ramp that fails or is not finite at t = start + k dt, k = 0..steps (None:
    :func:`~.bodies.step_count`, to t_end, else ``default_steps``)."""
    if load.ramp is None:
        return
    if steps is None:
        steps = step_count(dt, t_end, default_steps)
    for k in range(int(steps) + 1):
        load.factor(start + k * dt)


def load_acceleration(scene):
    """The acceleration the largest load gives a layer of the scene's density and length,
    max |t| / (rho L) (0 without loads): a scale of the step
    (:func:`~pfem_skfem.pfem.assemble.step_scales`), a ramp's factor not counted."""
    if not scene.loads:
        return 0.0
    size = max(float(np.hypot(*load.traction)) if load.pressure is None else abs(load.pressure)
               for load in scene.loads)
    return size / (scene.rho * scene.length)


def surface_loads(scene, disc, t_n, theta):
    """The step's surface load vector, theta1 F(t_{n+1}) + (1 - theta1) F(t_n) summed over
    the scene's loads on ``disc``'s mesh, and each load's resultant (Fx, Fy) of the step
    (a ring force's r-component in axisymmetry) by name."""
    h = min(r.h for r in scene.regions)
    total = np.zeros(disc.n_u)
    resultants = {}
    x_dofs = np.concatenate([disc.basis_u.nodal_dofs[0], disc.basis_u.facet_dofs[0]])
    y_dofs = np.concatenate([disc.basis_u.nodal_dofs[1], disc.basis_u.facet_dofs[1]])
    for load in scene.loads:
        factor = theta.load(load.factor(t_n), load.factor(t_n + theta.dt))
        f = factor * load.vector(disc, ZONE_TOL * h)
        if not np.all(np.isfinite(f)):
            raise ValueError(f"load {load.name!r}: its load vector is not finite at "
                             f"t = {t_n:g}")
        total += f
        resultants[load.name] = [float(f[x_dofs].sum()), float(f[y_dofs].sum())]
    return total, resultants
