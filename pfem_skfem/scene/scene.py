"""The scene: the one description every PFEM problem is given as.

A :class:`Scene` holds the material regions (polygons filled with particles, each with
its material, density and initial stress), the rigid bodies and their motions, the
outlets, the phases (time intervals with their own boundary conditions), gravity, the
alpha-shape parameter (adapted to keep the mass, Ch 8, as an option), the end time
and the numerical configuration of the loop
(:class:`~pfem_skfem.scene.config.PFEMConfig`). Everything is checked when the
scene is made, before any step runs. Its own scales, a characteristic length L and
the stress rho g L, are the units of every tolerance the engine uses.
"""
from dataclasses import dataclass, field, fields, is_dataclass
import hashlib
import json
import os

import numpy as np

from ..discretisation.geometry import as_geometry
from ..pfem.state import initial_state
from .bodies import MOTION_CHECK_STEPS, Body, check_motion_over, reach_into
from .config import PFEMConfig, check_passes, legacy_keys
from .crossing import check_no_crossing
from .enclosure import check_room
from .loads import check_loads, check_on_surface
from .outlets import Outlet
from .regions import Geostatic, Region, geostatic_stress, shapes_overlap, volume_shares
from .water import Water

HOLDS = (None, "boundary", "free_surface")
#: The most particles a scene may place (estimated from each region's area / h^2 before
#: any is placed): about 30 times the largest study so far; a million took over 3.6 GB and
#: died. Raise it with ``Scene(max_particles=...)`` or the environment variable below.
MAX_PARTICLES = 200_000
MAX_PARTICLES_ENV = "PFEM_SKFEM_MAX_PARTICLES"
#: The largest share of the particles an outlet's zone may hold at t = 0 (its edge
#: included). An outlet takes what has flowed into it after each step, so what it holds at
#: t = 0 leaves in step 1 without moving: the silo example's orifice holds the 3 of its 409
#: particles that lie on its plane, while a zone over the material (all but the top row:
#: 396 of 409) would discharge the body instead of letting it flow. More than half the material
#: leaving unmoved is a zone drawn over the body, not an orifice beside it.
MAX_OUTLET_SHARE = 0.5


@dataclass(frozen=True)
class Phase:
    """A time interval [previous phase's end, ``until``) with its own boundary conditions.

    hold : None; 'boundary' (every boundary node of the mesh held still: zero
        displacement increments); or 'free_surface' (the boundary nodes not within the
        contact search of a rigid body), as the thesis holds the surface of the
        Yangbaodi slide for its first 10 s to build the initial stresses (Ch 8).
    """

    until: float
    hold: str = None
    name: str = "phase"

    def __post_init__(self):
        if not (self.until > 0):
            raise ValueError(f"phase {self.name!r}: until must be positive, got {self.until!r}")
        if self.hold not in HOLDS:
            raise ValueError(f"phase {self.name!r}: hold must be one of {HOLDS}, got {self.hold!r}")


@dataclass(frozen=True)
class Output:
    """What a run writes: a VTU every ``every`` steps (0: none), a checkpoint every
    ``checkpoint_every`` steps (0: none), into ``directory``."""

    directory: str = "pfem_run"
    every: int = 10
    checkpoint_every: int = 0

    def __post_init__(self):
        for key in ("every", "checkpoint_every"):
            if int(getattr(self, key)) < 0:
                raise ValueError(f"output.{key} must be >= 0, got {getattr(self, key)!r}")


@dataclass(frozen=True)
class Scene:
    """A PFEM problem: what is where, what moves how, and for how long.

    Parameters
    ----------
    regions : one or more :class:`~pfem_skfem.scene.regions.Region`.
    bodies : :class:`~pfem_skfem.scene.bodies.Body` objects (walls, bases, cylinders).
    outlets : :class:`~pfem_skfem.scene.outlets.Outlet` objects.
    phases : :class:`Phase` objects in increasing ``until`` (after the last: no hold).
    gravity : (gx, gy) acceleration.
    alpha : alpha-shape parameter alpha_0;  adaptive_alpha : alpha_n = m0 alpha_0 / m_n
        (thesis Ch 8), clipped to [0.8, 1.5] alpha_0.
    t_end : end time of a run (None: the caller says how many steps).
    length : the characteristic length L (default: the height of the regions'
        bounding box); the stress scale is rho g L (rho the largest density), or the
        largest cohesion without gravity.
    config : :class:`~pfem_skfem.scene.config.PFEMConfig` (time step, passes,
        contact rule, remesher, mappings, backend).
    output : :class:`Output`.
    max_particles : the most particles the regions may hold (None: the environment
        variable ``PFEM_SKFEM_MAX_PARTICLES``, else :data:`MAX_PARTICLES`); not part of the
        scene's identity (:func:`scene_digest`) nor of its TOML form.
    geometry : 'plane' (plane strain, the default) or 'axisymmetric' (thesis Ch 7): x is
        the radius r >= 0 and y the axis z; every mesh of the loop is discretised with the
        2 pi r weight, particles on the axis r = 0 stay on it (u_r = 0), the axis is no
        free surface, volumes and masses are those of the body of revolution and forces
        are ring forces (their r-component has no resultant; the z-component is the
        whole body's).
    water : None (a dry or single-phase scene) or :class:`~pfem_skfem.scene.water.Water`:
        every region is a saturated soil, the pore pressure a particle variable added to
        each step (:mod:`pfem_skfem.scene.water`).
    loads : :class:`~pfem_skfem.scene.loads.SurfaceLoad` objects: tractions or pressures
        on the free surface in their zones, found on each step's mesh
        (:mod:`pfem_skfem.scene.loads`).
    """

    regions: tuple
    bodies: tuple = ()
    outlets: tuple = ()
    phases: tuple = ()
    gravity: tuple = (0.0, -9.8)
    alpha: float = 1.6
    adaptive_alpha: bool = False
    t_end: float = None
    length: float = None
    config: PFEMConfig = field(default_factory=PFEMConfig)
    output: Output = field(default_factory=Output)
    geometry: str = "plane"
    water: Water = None
    loads: tuple = ()
    max_particles: int = field(default=None, compare=False, repr=False)

    def __post_init__(self):
        regions = tuple(self.regions) if isinstance(self.regions, (list, tuple)) else (self.regions,)
        if not regions:
            raise ValueError("a scene needs at least one material region")
        for r in regions:
            if not isinstance(r, Region):
                raise ValueError(f"regions must be Region objects, got {r!r}")
        object.__setattr__(self, "regions", regions)
        for key in ("bodies", "outlets", "phases"):
            value = getattr(self, key)
            if isinstance(value, (Body, Outlet, Phase, str)) or not hasattr(value, "__iter__"):
                raise ValueError(f"{key} must be a list or tuple, got {value!r}")
        object.__setattr__(self, "bodies", tuple(self.bodies))
        object.__setattr__(self, "outlets", tuple(self.outlets))
        object.__setattr__(self, "phases", tuple(self.phases))
        object.__setattr__(self, "loads", check_loads(self.loads))
        self._check_names()
        for b in self.bodies:
            if not isinstance(b, Body):
                raise ValueError(f"bodies must be Body objects, got {b!r}")
        for o in self.outlets:
            if not isinstance(o, Outlet):
                raise ValueError(f"outlets must be Outlet objects, got {o!r}")
        ends = [p.until for p in self.phases]
        if any(not isinstance(p, Phase) for p in self.phases) or np.any(np.diff(ends) <= 0):
            raise ValueError("phases must be Phase objects in increasing 'until'")
        g = np.asarray(self.gravity, dtype=float)
        if g.shape != (2,) or not np.all(np.isfinite(g)):
            raise ValueError(f"gravity must be a finite (gx, gy), got {self.gravity!r}")
        object.__setattr__(self, "gravity", tuple(map(float, g)))
        if not (np.isfinite(self.alpha) and self.alpha > 0):
            raise ValueError(f"alpha must be positive, got {self.alpha!r}")
        if self.t_end is not None and not (self.t_end > 0 and np.isfinite(self.t_end)):
            raise ValueError(f"t_end must be positive and finite, got {self.t_end!r}")
        for b in self.bodies:          # a prescribed motion finite at every step time
            check_motion_over(b, self.config.dt, self.t_end)
        if self.length is None:
            lo, hi = self._bounding_box()
            object.__setattr__(self, "length", float(hi[1] - lo[1]) or float(np.ptp([lo, hi])))
        if not (np.isfinite(self.length) and self.length > 0):
            raise ValueError(f"length must be positive, got {self.length!r}")
        geometry = as_geometry(self.geometry)          # ValueError for an unknown name
        if not isinstance(self.geometry, str):
            object.__setattr__(self, "geometry", "axisymmetric" if geometry.axisymmetric
                               else "plane")
        if geometry.axisymmetric:
            lo, _ = self._bounding_box()
            if lo[0] < 0:
                raise ValueError(f"geometry 'axisymmetric': x is the radius, every region must "
                                 f"lie in x >= 0 (a region reaches x = {lo[0]:g})")
        elastic = {repr(r.material.elastic) for r in regions}
        if len(elastic) > 1:
            raise ValueError("every region must have the same elasticity (or none)")
        if self.config.keep_area and self.elastic is not None:
            raise ValueError("config.keep_area=True keeps the domain's area, which an elastic "
                             "material changes with its stresses: use it with rigid-plastic "
                             "and fluid regions only")
        if not self.stress_scale > 0:
            raise ValueError("the scene has no stress scale: give gravity or a cohesive material")
        self._check_passes()
        self._check_materials(geometry)
        if self.water is not None:
            if not isinstance(self.water, Water):
                raise ValueError(f"water must be None or a Water, got {self.water!r}")
            self.water.check(self.gravity, self.config.theta.theta1)
            names = [r.name for r in regions]
            for name in self.water.regions or ():
                if name not in names:
                    raise ValueError(f"water.regions: no region is named {name!r} (the "
                                     f"regions: {', '.join(map(repr, names))})")
            for r in regions:             # the water fills a soil's pores, not a fluid
                if getattr(r.material, "needs_container", False):
                    raise ValueError(f"water: every region of a saturated scene is a soil "
                                     f"skeleton, region {r.name!r} is a fluid "
                                     f"({type(r.material).__name__})")
        for r in regions:        # a fluid flows under any load that is not a pressure
            if getattr(r.material, "needs_container", False) and not self.bodies:
                raise ValueError(f"region {r.name!r} is a fluid ({type(r.material).__name__}) "
                                 f"and the scene has no rigid bodies to hold it: give bodies "
                                 f"(a floor, walls)")
        self._check_size()
        self._check_overlaps()
        self._check_particles()
        check_on_surface(self)                # each load's zone on the surface at t = 0
        check_no_crossing(self.bodies, self.config.dt, self.t_end,
                          0.5 * min(r.h for r in regions), MOTION_CHECK_STEPS)

    # -- checks ---------------------------------------------------------------------------
    def _check_passes(self):
        # the regions' part of the rule (check_passes): a lagged material with a lagged
        # contact rule needs three passes, a rate-dependent one a tolerance of 0
        lagged = [r.name for r in self.regions if r.material.lagged]
        rate = [r.name for r in self.regions if r.material.rate_dependent]
        check_passes(self.config.passes, self.config.pass_tolerance, self.config.contact,
                     lagged=f"region {lagged[0]!r}" if lagged else None,
                     rate=f"region {rate[0]!r}" if rate else None)

    def _check_materials(self, geometry):
        # a plane cone in axisymmetry leaves the hoop stress unbounded (a column that
        # never moves), an axisymmetric one in plane strain reads s_z as a hoop stress
        name = "axisymmetric" if geometry.axisymmetric else "plane"
        for r in self.regions:
            allowed = r.material.geometries
            if name not in allowed:
                raise ValueError(f"region {r.name!r}: its material "
                                 f"{type(r.material).__name__} is for geometry "
                                 f"{allowed[0]!r}, the scene's is {name!r}: use "
                                 f"{r.material.counterpart}")
        soft = [r for r in self.regions if r.material.softening]
        if soft and len({repr(r.material) for r in self.regions}) > 1:
            raise ValueError(f"region {soft[0].name!r}: a softening material "
                             f"({type(soft[0].material).__name__}) cannot share a scene "
                             f"with other materials yet (its gamma^p is bound to every "
                             f"stress point of the step)")

    def _check_size(self):
        # before any particle is placed: a lattice of spacing h holds about area / h^2
        # (square) or area / (h^2 sqrt(3) / 2) (triangular) particles, and the edges more
        limit = self.max_particles
        source = "Scene(max_particles=...)"
        if limit is None:
            text = os.environ.get(MAX_PARTICLES_ENV)
            limit, source = MAX_PARTICLES, "pfem_skfem.scene.scene.MAX_PARTICLES"
            if text is not None:
                try:
                    limit, source = int(text), f"the environment variable {MAX_PARTICLES_ENV}"
                except ValueError:
                    raise ValueError(f"{MAX_PARTICLES_ENV} must be an integer, got "
                                     f"{text!r}") from None
        total = 0
        for r in self.regions:
            cell = r.h ** 2 * (1.0 if r.lattice == "square" else np.sqrt(3) / 2)
            if r.area < r.h ** 2:
                raise ValueError(f"region {r.name!r}: its area {r.area:.3g} is less than one "
                                 f"particle cell h^2 = {r.h ** 2:.3g} (h = {r.h:g}): too few "
                                 f"particles to form a body; make h smaller or the polygon larger")
            rings = [r.polygon, *r.holes]
            edges = sum(float(np.linalg.norm(np.diff(np.vstack([v, v[:1]]), axis=0),
                                             axis=1).sum()) for v in map(np.asarray, rings))
            total += r.area / cell + edges / r.h
        if total > limit:
            raise ValueError(f"the regions would hold about {total:,.0f} particles (area / h^2), "
                             f"more than the limit of {limit:,} ({source}); make h larger, or "
                             f"raise the limit with max_particles (Scene(max_particles=...), a "
                             f"scene file's top-level key) or the environment variable "
                             f"{MAX_PARTICLES_ENV}")

    def _check_overlaps(self):
        # each region's mass is rho times its own area: overlapping regions count the
        # common part twice; regions that only share edges are fine (particles())
        lo, hi = self._bounding_box()
        tol = 1e-9 * float(np.max(hi - lo))
        shapes = [[np.asarray(r.polygon)] + [np.asarray(h) for h in r.holes]
                  for r in self.regions]
        for k in range(len(shapes)):
            for j in range(k):
                if shapes_overlap(shapes[j], shapes[k], tol):
                    raise ValueError(f"regions {self.regions[j].name!r} and "
                                     f"{self.regions[k].name!r} overlap: regions may share "
                                     f"edges, not area (each carries its own area's mass)")

    def _check_names(self):
        for kind, items in (("region", self.regions), ("body", self.bodies),
                            ("outlet", self.outlets)):
            names = [item.name for item in items]
            if len(set(names)) != len(names):
                raise ValueError(f"{kind} names must be unique, got {names}")

    def _bounding_box(self):
        pts = np.vstack([np.asarray(r.polygon) for r in self.regions])
        return pts.min(axis=0), pts.max(axis=0)

    def _check_particles(self):
        x, _, region = self.particles()
        h = min(r.h for r in self.regions)
        counts = np.bincount(region, minlength=len(self.regions))
        for k, r in enumerate(self.regions):
            others = region != k          # what the vertex test misses (equal polygons)
            inside = r.contains(x[others], tol=-1e-6 * r.h)
            if inside.any():
                j = int(region[others][np.argmax(inside)])
                raise ValueError(f"regions {self.regions[min(j, k)].name!r} and "
                                 f"{self.regions[max(j, k)].name!r} overlap: regions may "
                                 f"share edges, not area (each carries its own area's mass)")
        for k, r in enumerate(self.regions):
            if counts[k] < 3:
                raise ValueError(f"region {r.name!r}: only {counts[k]} particle(s) at h = "
                                 f"{r.h:g}: too few to form a body; make h smaller")
        for body in self.bodies:
            if body.present(0.0):
                g0, _ = body.shape.gap(x)
                inside = g0 < -1e-6 * h
                if inside.any():
                    raise ValueError(f"body {body.name!r}: {int(inside.sum())} particle(s) lie "
                                     f"inside it at t = 0 (deepest {-g0.min():.3g})")
                self._check_not_buried(body)
        if self.water is not None:    # a drained face that drains nothing is a mistake
            for i, face in enumerate(self.water.drained):
                if face.zone is not None and not face.zone.contains(x, tol=1e-6 * h).any():
                    raise ValueError(f"water.drained[{i}]: its zone holds no particle at "
                                     f"t = 0 (it would drain nothing); give a zone on the "
                                     f"body's boundary")
        check_room(self, x, MOTION_CHECK_STEPS)      # bodies closing in on the material
        for outlet in self.outlets:
            # particles on the zone's edge count as in it: a silo's bottom row lies on the
            # orifice's plane, and a reversed normal would discharge all the others
            held = outlet.zone.contains(x, tol=1e-6 * h)
            if held.all():
                raise ValueError(f"outlet {outlet.name!r} contains every particle at t = 0 "
                                 f"(those on its edge included): they would all leave in "
                                 f"step 1; a half-plane's normal points out of the body, "
                                 f"into the discharge side (is it reversed?)")
            if held.sum() > MAX_OUTLET_SHARE * len(x):
                raise ValueError(f"outlet {outlet.name!r} holds {int(held.sum())} of the "
                                 f"{len(x)} particles at t = 0 (those on its edge included), "
                                 f"more than {MAX_OUTLET_SHARE:.0%}: they would leave in step "
                                 f"1 without flowing to it. An outlet is where the material "
                                 f"leaves, beyond the body: move its zone out of the material "
                                 f"(a half-plane's normal points out of the body)")

    def _check_not_buried(self, body):
        # a body in the material with no particle inside it (a pebble between the lattice
        # points) is not felt: the contacts are searched from the mesh's boundary, which
        # does not pass near it, and the run is bit for bit the one without it
        for r in self.regions:
            where = reach_into(body.shape, r, 1e-6 * r.h)
            if where is not None:
                raise ValueError(f"body {body.name!r} reaches into the material of region "
                                 f"{r.name!r} at t = 0 ({where}), with no particle inside "
                                 f"it: the material would not feel it (the run would be the "
                                 f"one without it). Cut a hole around it in the region "
                                 f"(holes = [...], a polygon just outside the body, h small "
                                 f"enough to follow it), or move it out of the material")

    # -- scales ---------------------------------------------------------------------------
    @property
    def rho(self):
        """The largest density of the regions."""
        return max(r.rho for r in self.regions)

    @property
    def g(self):
        """|gravity|."""
        return float(np.hypot(*self.gravity))

    @property
    def stress_scale(self):
        """rho g L, or without gravity the largest cohesion: the unit of stresses."""
        s = self.rho * self.g * self.length
        if s > 0:
            return s
        return max(r.material.c for r in self.regions)

    @property
    def mass(self):
        """Total mass of the regions: rho times the area (plane strain, per unit length)
        or the volume of revolution (axisymmetry); a state of the scene holds it, with
        what it has discharged."""
        axisymmetric = self.axisymmetric
        return float(sum(r.rho * (r.volume if axisymmetric else r.area) for r in self.regions))

    @property
    def axisymmetric(self):
        """True in axisymmetry (x = r, y = z), False in plane strain."""
        return as_geometry(self.geometry).axisymmetric

    @property
    def elastic(self):
        return self.regions[0].material.elastic

    # -- particles ------------------------------------------------------------------------
    def particles(self):
        """Particles of every region: positions (n, 2), spacings (n,), region indices (n,).

        Regions that touch share their common edge: a region's particle closer than half
        a spacing to one of an earlier region is left out (the edge keeps the earlier
        region's particles), so a refined region can be set beside a coarse one.
        """
        from scipy.spatial import cKDTree
        xs, hs, rs = [], [], []
        for k, region in enumerate(self.regions):
            x = region.particles()
            if xs:
                d, i = cKDTree(np.vstack(xs)).query(x)
                x = x[d >= 0.5 * np.minimum(region.h, np.concatenate(hs)[i])]
            xs.append(x)
            hs.append(np.full(len(x), region.h))
            rs.append(np.full(len(x), k))
        return np.vstack(xs), np.concatenate(hs), np.concatenate(rs)

    def initial_state(self):
        """The state at t = 0: the particles at rest, each region's mass shared equally by
        its particles (in axisymmetry: by their shares of the region's volume of revolution,
        :func:`~pfem_skfem.scene.regions.volume_shares`), the lagged mean stress and
        (elastoplastic) the stresses from each region's initial stress.

        In a saturated scene the stresses are effective: a Geostatic region's are those of
        its (saturated) density less the hydrostatic pore pressure of the water table,
        which is the initial p (:mod:`pfem_skfem.scene.water`; above the table a negative
        p, the soil saturated by capillarity).

        The lagged mean stress is what the region's material lags (its
        ``mean_stress(sigma)``: (sx + sy)/2, or e.g. I1/3 for the axisymmetric cones); in
        axisymmetry the geostatic hoop stress equals the radial one, s_tt = s_rr = K0 s_zz.
        """
        x, h, region = self.particles()
        mass = np.zeros(len(x))
        sigma = np.zeros((len(x), 4))
        sigma_m = np.zeros(len(x))
        axisymmetric = self.axisymmetric
        for k, r in enumerate(self.regions):
            mine = region == k
            if axisymmetric:
                mass[mine] = r.rho * volume_shares(r, x[mine])
            else:
                mass[mine] = r.rho * r.area / mine.sum()
            if isinstance(r.stress, Geostatic):
                phi = r.material.phi
                k0 = 1 - np.sin(np.radians(phi)) if r.stress.k0 is None else r.stress.k0
                top = max(p[1] for p in r.polygon) if r.stress.top is None else r.stress.top
                nu = 0.0 if self.elastic is None else self.elastic.nu
                pore = (None if self.water is None       # effective, under the table
                        else self._initial_pore(k, x[mine]))
                sigma[mine] = geostatic_stress(x[mine], top, r.rho, self.g, k0, nu, pore)
                if axisymmetric:
                    sigma[mine, 2] = sigma[mine, 0]
            sigma_m[mine] = r.material.mean_stress(sigma[mine])
        stress = sigma if self.elastic is not None else None
        h_arg = h[0] if np.all(h == h[0]) else h
        state = initial_state(x, h_arg, sigma_m, stress, region=region, mass=mass)
        if self.water is not None:                   # at rest: the hydrostatic pressure
            state.pore_pressure = np.zeros(len(x))
            for k in range(len(self.regions)):
                state.pore_pressure[region == k] = self._initial_pore(k, x[region == k])
        return state

    def _initial_pore(self, k, x):
        """The pore pressure at rest of region ``k``'s points x: hydrostatic where it is
        saturated, free-draining where it is not (:class:`~pfem_skfem.scene.water.Water`)."""
        if self.water.saturated(self.regions)[k]:
            return self.water.hydrostatic(x)
        return self.water.free_draining(x)

    # -- per step -------------------------------------------------------------------------
    def phase_at(self, t):
        """The phase a step starting at time t is in (None after the last)."""
        for phase in self.phases:
            if t < phase.until:
                return phase
        return None

    def bodies_at(self, t_n, dt):
        """The bodies present in the step t_n -> t_n + dt: (index, shape at t_n, translation
        over the step)."""
        out = []
        for k, body in enumerate(self.bodies):
            if body.present(t_n):
                d_n = body.motion(t_n)
                out.append((k, body.shape.translated(d_n), body.motion(t_n + dt) - d_n))
        return out


# -- identity ------------------------------------------------------------------------------
_NOT_IDENTITY = ("t_end", "output", "max_particles")
_UNSET = object()


#: fields added after digests were first stored, left out at their default value so that
#: a run checkpointed before a field existed is still known as the same scene
_LATER_FIELDS = {("PFEMConfig", "solver"): "clarabel", ("PFEMConfig", "form"): None,
                 ("PFEMConfig", "keep_area"): False, ("AlphaMesh", "thin"): 0.0,
                 ("PFEMConfig", "spread_mass"): False,
                 ("PFEMConfig", "refine_interior"): 0.0,
                 ("AlphaMesh", "keep_surface"): False,
                 ("PFEMConfig", "keep_area_step"): 0.0, ("Water", "regions"): None,
                 ("RigidPolyline", "sharp_ends"): False}


#: fields whose one value replaced several earlier ones: the identity is written in the
#: earlier keys (a function of the value), so that the digests of earlier runs stay theirs
_RENAMED = {("PFEMConfig", "solver"): legacy_keys}


def _identity(value):
    """Plain JSON values of a scene's parts: dataclasses by type and fields, functions by
    qualified name (a repr would hold a memory address), floats exactly (repr)."""
    if is_dataclass(value) and not isinstance(value, type):
        kind = type(value).__name__
        items = {}
        for f in fields(value):
            if not f.compare:
                continue
            earlier = _RENAMED.get((kind, f.name))
            keys = earlier(getattr(value, f.name)) if earlier else {f.name: getattr(value, f.name)}
            items.update({key: _identity(v) for key, v in keys.items()
                          if _LATER_FIELDS.get((kind, key), _UNSET) != v})
        return {"type": kind, **items}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [_identity(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float):
        return repr(value)
    if value is None or isinstance(value, (bool, int, str)):
        return value
    if callable(value):
        return f"{getattr(value, '__module__', '')}.{getattr(value, '__qualname__', '')}"
    return repr(value)


def scene_digest(scene):
    """A stable hex digest (SHA-256) of what defines a scene's states: its regions
    (polygons, holes, materials, densities, spacings, initial stresses), bodies and their
    motions, outlets, phases, gravity, alpha, length, geometry, numerical config, water and
    surface loads (the last two only where the scene has them).
    Not ``t_end`` (a run may be extended), ``output`` nor ``max_particles``. The same scene
    gives the same digest in every process (a checkpoint can store it and refuse another
    scene's); a FunctionMotion is known by its function's qualified name only."""
    parts = {f.name: _identity(getattr(scene, f.name)) for f in fields(scene)
             if f.name not in _NOT_IDENTITY
             and not (f.name == "water" and scene.water is None)    # the digests before it
             and not (f.name == "loads" and not scene.loads)}
    text = json.dumps(parts, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()
