"""The numerical choices of a PFEM run, beside the scene that holds them.

:class:`PFEMConfig` is the ``config`` of a :class:`~pfem_skfem.scene.Scene`: the time
step, the fixed-point passes, the contact rule, the remesher, the mappings, the step's
solver. The rule for the passes is written once, :func:`check_passes` (beside
:func:`~pfem_skfem.problems.nonassociated.least_passes`, where the step that runs the
passes can use it too): the config checks what it alone knows, the scene what its
regions add (a lagged or rate-dependent material).
"""
from dataclasses import dataclass, field

import numpy as np

from ..discretisation.theta import ThetaMethod
from ..pfem.remesh import AlphaMesh, QualityRemesh
from ..pfem.transfer import Interpolation, L2Projection
from ..problems.contact import CoulombCones, LaggedFriction
from ..problems.backends import STEP_SOLVERS
from ..problems.nonassociated import MAX_PASSES, check_passes, least_passes  # noqa: F401

__all__ = ["PFEMConfig", "STRESS_MAPPINGS", "MAX_PASSES", "check_passes", "least_passes",
           "legacy_solver", "legacy_keys"]

STRESS_MAPPINGS = ("uem_bounded", "uem", "ida", "spr")


@dataclass(frozen=True)
class PFEMConfig:
    """The numerical choices of a PFEM run (the physics is the scene's).

    Attributes
    ----------
    theta : :class:`~pfem_skfem.discretisation.theta.ThetaMethod` (dt, theta1, theta2), held once.
    passes : solves per step when the material or the contact rule is lagged (1: the
        lagged values only); with ``pass_tolerance`` the most.
    pass_tolerance : end a step's passes once a pass changes the smoothed mean stress by
        less than this many stress scales (rho g L; and a lagged contact rule's normal
        forces by less than this fraction of the largest), after the least passes the
        scene needs (:func:`~pfem_skfem.problems.nonassociated.least_passes`); 0: always
        ``passes``.
    contact : contact rule, :class:`~pfem_skfem.problems.contact.CoulombCones` (the
        associated cones of (5.12), the thesis') or
        :class:`~pfem_skfem.problems.contact.LaggedFriction` (no dilation; passes >= 2, and
        >= 3 with a lagged material: the scene checks, :func:`check_passes`).
    remesher : :class:`~pfem_skfem.pfem.remesh.AlphaMesh` (the alpha-shape's triangles;
        ``AlphaMesh(thin=0.4)`` first thins particles crowded closer than 0.4 h) or
        :class:`~pfem_skfem.pfem.remesh.QualityRemesh` (Triangle; added nodes become
        particles, the cloud thinned first).
    remesh_interval : remesh every this many steps (between, the mesh moves with the particles).
    stress_mapping : 'uem_bounded', 'uem' (Fig 2.6), 'ida' (2.1)-(2.2) or 'spr'.
    velocity : :class:`~pfem_skfem.pfem.transfer.L2Projection` (no kinetic energy added)
        or :class:`~pfem_skfem.pfem.transfer.Interpolation`.
    search : contact search distance in units of h.
    solver : who states and solves every step, one name of
        :data:`~pfem_skfem.problems.backends.STEP_SOLVERS`: 'clarabel' (the default: the
        step assembled directly, primal form, Clarabel), 'clarabel-dual' (its dual, the
        displacement form), 'qoco', 'qoco-dual', 'scs', 'scs-dual', 'cvxpy' (the
        reference statement, Clarabel), 'cvxpy-qoco', 'cvxpy-scs', 'mosek'. QOCO on the
        dual form is faster but does not keep every family's figures (the dam break's at
        rest): an option, not the default (book/performance.md, "The default by the
        rule"). (Scene files written before one name held the choice say it with
        ``backend``, ``solver`` and ``form``: they are read into this name,
        :func:`legacy_solver`.)
    bulge : place the boundary particles so that the straight-sided boundary keeps the
        area of the curved P2 one (:func:`~pfem_skfem.pfem.surface.bulge_correction`).
    refine_surface : a boundary edge stretched longer than this many h gets its P2
        midside node as a new particle (0: never).
    refine_interior : the same for an interior edge (0, the default: never): the
        remesher's thinning merges particles that come closer than a fraction of h and
        nothing else adds any inside, so over a long run the cloud thins out (the clay
        block into the tank, book/water_and_mud.md).
    volume_correction : shift the moved particles so that every vertex patch keeps the
        volume their linearised motion states (one linear solve a step;
        :mod:`~pfem_skfem.pfem.volume_projection`); off by default.
    keep_area : with ``volume_correction``, every patch's target volume also grows by the
        one factor that takes the step's domain back to its first detected area (times the
        fraction of the mass still in the scene): the area the alpha shape adds at each
        remeshing, where it closes the gaps of a broken free surface, is given back at
        the next step (:func:`~pfem_skfem.pfem.volume_projection.area_growth`). For rigid-
        plastic and fluid scenes (the engine's materials flow at zero dilation); an
        elastic material's volume change is not a gain, and the scene refuses it. Off by
        default.
    keep_area_step : with ``keep_area``, the most of its volume a step's domain is asked
        to grow or shrink by (0, the default: all at once); a larger change is given back
        over several steps. Why: a remeshing that closes or opens a splash's gaps changes
        the area by 1-2 % at once, and the shift that gives it back in one step is
        larger than the step's motion, so the projection is refused. A limit trades
        those refusals for a larger energy gain of the particles (the clay block into
        the tank, book/water_and_mud.md, "The refused projections").
    spread_mass : at each remeshing, spread each region's mass over its particles on the mesh
        in proportion to their lumped areas
        (:func:`~pfem_skfem.pfem.bookkeeping.spread_mass`): the particles' masses then
        follow the material the step weighs, where thinning and the particles added at
        the surface would otherwise pile them on a few. The step does not read the
        particles' masses; what does: their energy and centre of mass, the mass an outlet
        discharges, ``keep_area``'s drops. Off by default.
    alpha_advected : keep a Delaunay triangle that fails the alpha test while its centroid
        lies in the previous step's mesh moved with the particles and its circumradius
        is at most this many h (:func:`~pfem_skfem.pfem.alpha_shape.alpha_shape`): a
        thinning layer is not cut off the body until stretched that far; and no triangle
        fills a notch of that mesh's surface. 0 (default): off, the plain alpha-shape of
        the thesis.
    """

    theta: ThetaMethod = field(default_factory=lambda: ThetaMethod(0.01, 1.0, 1.0))
    passes: int = 2
    pass_tolerance: float = 0.0
    contact: object = field(default_factory=CoulombCones)
    remesher: object = field(default_factory=AlphaMesh)
    remesh_interval: int = 1
    stress_mapping: str = "uem_bounded"
    velocity: object = field(default_factory=L2Projection)
    search: float = 1.0
    solver: str = "clarabel"
    bulge: bool = True
    refine_surface: float = 2.0
    refine_interior: float = 0.0
    volume_correction: bool = False
    keep_area: bool = False
    keep_area_step: float = 0.0
    spread_mass: bool = False
    alpha_advected: float = 0.0

    def __post_init__(self):
        if not isinstance(self.theta, ThetaMethod):
            raise ValueError(f"theta must be a ThetaMethod(dt, theta1, theta2), got {self.theta!r}")
        if not isinstance(self.contact, (CoulombCones, LaggedFriction)):
            raise ValueError(f"contact must be CoulombCones() or LaggedFriction(), got "
                             f"{self.contact!r}")
        check_passes(self.passes, self.pass_tolerance, self.contact)
        if not isinstance(self.remesher, (AlphaMesh, QualityRemesh)):
            raise ValueError(f"remesher must be AlphaMesh() or QualityRemesh(size), got "
                             f"{self.remesher!r}")
        if int(self.remesh_interval) < 1:
            raise ValueError(f"remesh_interval must be >= 1, got {self.remesh_interval!r}")
        if self.stress_mapping not in STRESS_MAPPINGS:
            raise ValueError(f"stress_mapping must be one of {STRESS_MAPPINGS}, got "
                             f"{self.stress_mapping!r}")
        if not isinstance(self.velocity, (L2Projection, Interpolation)):
            raise ValueError(f"velocity must be L2Projection() or Interpolation(), got "
                             f"{self.velocity!r}")
        if self.solver not in STEP_SOLVERS:
            raise ValueError(f"solver must be one of {tuple(STEP_SOLVERS)}, got "
                             f"{self.solver!r}")
        if not (np.isfinite(self.search) and self.search > 0):
            raise ValueError(f"search must be positive, got {self.search!r}")
        if not (np.isfinite(self.alpha_advected) and self.alpha_advected >= 0):
            raise ValueError(f"alpha_advected must be >= 0 (0: off), got "
                             f"{self.alpha_advected!r}")
        if self.keep_area and not self.volume_correction:
            raise ValueError("keep_area=True needs volume_correction=True (the area is given "
                             "back through the volume projection's targets)")
        if not (np.isfinite(self.keep_area_step) and self.keep_area_step >= 0):
            raise ValueError(f"keep_area_step must be >= 0 (0: all at once), got "
                             f"{self.keep_area_step!r}")
        if self.keep_area_step > 0 and not self.keep_area:
            raise ValueError("keep_area_step > 0 needs keep_area=True (it limits the area "
                             "keep_area gives back in one step)")
        if not (self.refine_surface >= 0):
            raise ValueError(f"refine_surface must be >= 0, got {self.refine_surface!r}")
        if not (np.isfinite(self.refine_interior) and self.refine_interior >= 0):
            raise ValueError(f"refine_interior must be >= 0 (0: never), got "
                             f"{self.refine_interior!r}")

    @property
    def dt(self):
        return self.theta.dt


#: the solvers that had an engine of the direct assembly when three keys chose the solver
_DIRECT = ("clarabel", "qoco")

#: the keys (backend, solver, form) of the step solvers that three keys could choose
_EARLIER = {"clarabel": ("clarabel", "clarabel", None),
            "clarabel-dual": ("clarabel", "clarabel", "dual"),
            "qoco": ("clarabel", "qoco", None), "qoco-dual": ("clarabel", "qoco", "dual"),
            "cvxpy": ("cvxpy", "clarabel", None), "cvxpy-qoco": ("cvxpy", "qoco", None),
            "cvxpy-scs": ("clarabel", "scs", None), "mosek": ("clarabel", "mosek", None)}


def legacy_solver(backend="clarabel", solver="clarabel", form=None):
    """The step's solver (a name of ``STEP_SOLVERS``) that the three keys of earlier scene
    files chose: ``backend`` 'clarabel' (the direct assembly, where ``solver`` had an
    engine: Clarabel, QOCO; the others' cvxpy statement) or 'cvxpy'; ``form`` 'primal',
    'dual' or None (primal)."""
    for key, value, allowed in (("backend", backend, ("clarabel", "cvxpy")),
                                ("form", form, (None, "primal", "dual"))):
        if value not in allowed:
            raise ValueError(f"{key} must be one of {allowed}, got {value!r}")
    if solver not in ("clarabel", "qoco", "mosek", "scs"):
        raise ValueError(f"solver must be one of ('clarabel', 'qoco', 'mosek', 'scs'), got "
                         f"{solver!r}")
    if solver == "mosek":
        return "mosek"
    if backend == "cvxpy" or solver not in _DIRECT:
        return "cvxpy" if solver == "clarabel" else f"cvxpy-{solver}"
    return solver + ("-dual" if form == "dual" else "")


def legacy_keys(name):
    """The keys (backend, solver, form) that :func:`legacy_solver` reads as ``name``, in which
    a scene's identity is written so that the digests of earlier runs stay theirs; a solver
    added since is written with backend 'direct', which no earlier file had."""
    backend, solver, form = _EARLIER.get(name, ("direct", name, None))
    return dict(backend=backend, solver=solver, form=form)
