"""Effective-stress limit analysis: a given pore-pressure field in the strict bounds.

The soil's strength is a criterion on the effective stress sigma' (tension positive);
equilibrium is of the total stress sigma = sigma' - p I, with p the pore pressure
(compression positive), given as a field p(x) (Terzaghi's principle, as in
:mod:`pfem_skfem.problems.consolidation`). The bounds of :mod:`pfem_skfem.problems.bounds`
take it as follows, both with the same field p_h: the continuous P1 interpolant of p at
the mesh's vertices (exact for a hydrostatic field in every element that the water table
does not cross), so that the bracket is strict for the problem with p_h.

A free boundary carries the water's pressure equal to the pore pressure there: the traction
-p_h n (no water where p_h = 0: above the water table, on a seepage face). Then:

Lower bound. sigma' linear and p_h linear make sigma linear; p_h is continuous, so the
jump conditions are those of sigma', and on a free edge (sigma' - p_h I) n = t - p_h n
leaves sigma' n = t. Equilibrium div sigma + b = 0 is

.. math::
    \\nabla\\cdot\\sigma' + b - \\nabla p_h = 0 \\quad\\text{in each element},

the pore pressure a body force -grad p_h (buoyancy and seepage force together), constant
in each element. On a punch the force is of the total traction: its power loses
int_punch p_h n . v ds.

Upper bound. The virtual power of the total stress on a mechanism v (v = 0 on supports):
int sigma' : eps(v) - int p_h div v = the power of the loads, the water's on the free
edges, -int_free p_h n . v ds, included. With sigma' : eps <= D(eps),

.. math::
    \\begin{aligned}
    &\\alpha\\, f\\cdot v + f_0\\cdot v + \\Pi_p(v) \\le \\int D(\\varepsilon(v)),\\\\
    &\\Pi_p(v) = \\int_\\Omega p_h \\nabla\\cdot v - \\int_{\\Gamma_{free}} p_h n\\cdot v
             = -\\int_\\Omega \\nabla p_h\\cdot v + \\int_{punch} p_h n\\cdot v,
    \\end{aligned}

the power of the pore pressure on the volumetric strain rate, written as the body force
-grad p_h (integration by parts is exact: p_h and v are continuous; v . n = 0 on a
support). Pi_p is a load vector beside f_0 (a dead pore pressure) or beside f (a live one,
scaled with the multiplier: gravity's, which scales the water's weight too). The sum of
the local gaps stays the gap (the lower bound's sigma' is an effective stress).

Associated flow dilates (Mohr-Coulomb: div v = sin(phi) ``|dev eps|`` >= 0), so Pi_p >= 0 and
grows with p: more pore pressure, a lower collapse load. Tresca (phi = 0) keeps div v = 0:
p enters only through the water's pressure on the boundary (a surcharge on the punch).
"""
from dataclasses import dataclass
from typing import Callable

import numpy as np
from skfem import Basis, ElementTriP1, FacetBasis, LinearForm, condense, solve
from skfem.models.poisson import laplace

from ..discretisation.bounds import element_gradients


@dataclass(frozen=True)
class WaterTable:
    """Hydrostatic pore pressure below a phreatic surface y_w(x):
    p = gamma_w (y_w(x) - y) below it, 0 above (no suction).

    ``level``: y_w, a height (a horizontal table) or a polyline [(x, y), ...] with x
    increasing (a table that follows a slope's face, say), constant beyond its ends.
    Free water stands above the ground where y_w is higher than the ground (a free
    boundary carries the pore pressure as the water's pressure).
    """

    level: object
    gamma_w: float = 9.81

    def __post_init__(self):
        if not (np.isfinite(self.gamma_w) and self.gamma_w > 0):
            raise ValueError(f"gamma_w must be positive and finite, got {self.gamma_w!r}")
        pts = np.asarray(self.level, dtype=float)
        if pts.ndim == 0:
            if not np.isfinite(pts):
                raise ValueError(f"level must be finite, got {self.level!r}")
        elif (pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] < 2
              or not np.all(np.isfinite(pts)) or not np.all(np.diff(pts[:, 0]) > 0)):
            raise ValueError("level must be a height or a polyline [(x, y), ...] of two or "
                             f"more finite points with x increasing, got {self.level!r}")

    def height(self, x):
        """y_w at the abscissae x."""
        pts = np.asarray(self.level, dtype=float)
        if pts.ndim == 0:
            return np.full(np.shape(x), float(pts))
        return np.interp(x, pts[:, 0], pts[:, 1])

    def __call__(self, x):
        return self.gamma_w * np.maximum(self.height(x[0]) - x[1], 0.0)


@dataclass(frozen=True)
class Seepage:
    """The pore pressure of steady confined seepage: p = gamma_w (h - y), the total head h
    harmonic (Darcy's law and continuity, uniform permeability: div grad h = 0), held at
    the given ``heads`` ((where, h), ...: the boundary facets whose midpoints x (2, m)
    satisfy ``where(x)``, at head h, a number or a callable h(x) of their vertices) and
    without flow across the rest of the boundary.

    Made by :meth:`solve` on a triangle mesh (continuous P1, the field of the bounds: at
    the mesh's vertices p is the solve's own); elsewhere h is interpolated.
    """

    mesh: object
    head: np.ndarray
    gamma_w: float

    @classmethod
    def solve(cls, mesh, heads, gamma_w=9.81):
        """The seepage of ``heads`` on ``mesh``; refuses gamma_w <= 0, a head that is not
        finite, a selection of no boundary facet, and no head at all."""
        if not (np.isfinite(gamma_w) and gamma_w > 0):
            raise ValueError(f"gamma_w must be positive and finite, got {gamma_w!r}")
        if not heads:
            raise ValueError("heads: give at least one (where, h): a head somewhere")
        basis = Basis(mesh, ElementTriP1())
        facets = mesh.boundary_facets()
        mid = mesh.p[:, mesh.facets[:, facets]].mean(axis=1)
        h = np.zeros(basis.N)
        held = []
        for where, value in heads:
            on = facets[np.asarray(where(mid), dtype=bool)]
            if on.size == 0:
                raise ValueError(f"heads: the head {value!r} selects no boundary facet")
            dofs = np.unique(mesh.facets[:, on])
            h[dofs] = value(mesh.p[:, dofs]) if callable(value) else value
            if not np.all(np.isfinite(h[dofs])):
                raise ValueError(f"heads: a head must be finite, got {value!r}")
            held.append(dofs)
        K = laplace.assemble(basis)
        h = solve(*condense(K, np.zeros(basis.N), x=h, D=np.unique(np.concatenate(held))))
        return cls(mesh, h, float(gamma_w))

    def __call__(self, x):
        x = np.asarray(x, dtype=float)
        same = x.shape == self.mesh.p.shape and np.array_equal(x, self.mesh.p)
        h = self.head if same else Basis(self.mesh, ElementTriP1()).interpolator(self.head)(x)
        return self.gamma_w * (h - x[1])


@dataclass(frozen=True)
class PorePressure:
    """A pore-pressure field p(x) (x: (2, n) -> (n,)); ``live``: scaled with the load
    multiplier (a pore pressure of the water's weight under gravity as the live load),
    else carried as it is (a dead load). At alpha = 1 both are one problem; for the factor
    of safety give it live: a dead one leaves a trial of small alpha with the water's
    uplift unbalanced, and that bound infeasible."""

    field: Callable
    live: bool = False

    def __post_init__(self):
        if not callable(self.field):
            raise TypeError(f"field must be a callable p(x), got {self.field!r}")

    def nodal(self, mesh):
        """p at the mesh's vertices, refused unless finite and of one value a vertex."""
        p = np.asarray(self.field(mesh.p), dtype=float)
        if p.shape != (mesh.p.shape[1],):
            raise ValueError(f"pore_pressure must return one value per point (shape "
                             f"({mesh.p.shape[1]},)), got shape {p.shape}")
        bad = ~np.isfinite(p)
        if bad.any():
            raise ValueError(f"pore_pressure is not finite at {bad.sum()} vertex(es), "
                             f"e.g. x = {mesh.p[:, np.argmax(bad)]}")
        return p


def as_pore_pressure(value):
    """None, a :class:`PorePressure`, or a callable p(x) (a dead one)."""
    if value is None or isinstance(value, PorePressure):
        return value
    if callable(value):
        return PorePressure(value)
    raise TypeError(f"pore_pressure must be a callable p(x) or a PorePressure, got {value!r}")


def pore_body_force(mesh, p):
    """(n_el, 2) -grad p_h in each element, p_h the P1 interpolant of the nodal p."""
    g, _ = element_gradients(mesh)                          # (n_el, 3, 2)
    return -np.einsum("ej,ejk->ek", p[mesh.t.T], g)


def punch_pore_power(mesh, facets, normal, length, punched, p, v):
    """int over the punch of p_h sum_k n_k v_k ds (k its prescribed components): the part
    of the punch's power that the pore pressure carries. ``punched`` (m, 2) bool per
    facet and component, ``normal`` (m, 2) outward, ``v`` the punch's velocity."""
    mean = 0.5 * (p[mesh.facets[0, facets]] + p[mesh.facets[1, facets]])
    return float(np.sum(length[:, None] * mean[:, None] * normal * v[None, :] * punched))


def pore_load_vector(disc, p, punch_facets=(), v=None):
    """Pi_p as a vector on the P2 velocities (module docstring): -int grad p_h . u over
    the mesh, plus int p_h n_k u_k over ``punch_facets`` = ((facets, k), ...) of the
    punch's components k (``v`` its velocity: used only there)."""
    mesh, basis = disc.mesh, disc.basis_u
    grad = -pore_body_force(mesh, p)                       # (n_el, 2)
    nqp = basis.X.shape[1]
    g = np.repeat(grad.T[:, :, None], nqp, axis=2)          # (2, n_el, n_qp)

    @LinearForm
    def body(u, w):
        return -(w.g[0] * u[0] + w.g[1] * u[1])            # -grad p_h . u (exact: P2 x P0)

    f = body.assemble(basis, g=g)
    for facets, k in punch_facets:
        if len(facets) == 0:
            continue
        fb = FacetBasis(mesh, basis.elem, facets=np.asarray(facets), intorder=4)
        ph = fb.with_element(ElementTriP1()).interpolate(p)

        @LinearForm
        def punch(u, w):
            return w.ph * w.n[k] * u[k]                     # p_h n_k u_k (exact: degree 3)

        f = f + punch.assemble(fb, ph=ph)
    return np.asarray(f, dtype=float)
