"""The bar (truss) element of thesis Appendix B and its incremental SOCP (B.12).

A bar e joins nodes i and j. With the direction cosines (B.2) of the current
configuration, the axial strain of a linear axial displacement (B.4)-(B.6) is

.. math::
    \\varepsilon_e = B_e \\hat u_e, \\qquad
    B_e = \\tfrac{1}{L_e}\\,[-\\cos\\phi, -\\sin\\phi, \\cos\\phi, \\sin\\phi]   \\qquad (B.7)-(B.9)

(the transverse displacement does not stretch the bar, (B.1)). Node-major
displacements: dofs ``2 i`` (x) and ``2 i + 1`` (y) of node i.

The incremental elastoplastic problem of a truss (B.10)-(B.12), integrated over
each bar's volume V_e = A_e L_e, reads

.. math::
    \\max_{\\sigma}\\; -\\tfrac12 \\sum_e \\frac{V_e}{E_e}\\Delta\\sigma_e^2
        + \\Delta\\bar u_P^T (B_P^T V \\sigma - f_P)
    \\quad\\text{s.t.}\\quad B_F^T V \\sigma = f_F, \\quad |\\sigma_e| \\le \\sigma_s

with Delta sigma = sigma - sigma_n. (B.10) prints sigma_{n+1} in the quadratic
term; for a sequence of increments it is the increment, as in (3.45). The last
objective term is the work of the reactions on prescribed displacements
(displacement control, as in the thesis' examples). Its optimality conditions are
Delta sigma_e = E_e B_e Delta u (elastic bars), the equilibrium of the bar forces
N_e = A_e sigma_e, and plastic flow in yielding bars.

Sign convention, settled by the KKT conditions and ``tests/test_bar.py``: the
cvxpy dual of the equality ``B_F^T V sigma == f_F`` in this maximisation is -du,
as for (3.45) in :mod:`pfem_skfem.problems.static`.

Large deformation by small increments (thesis 6.2-6.3) updates the nodes, the
lengths and, for incompressible bars, the areas A_e = V_e / l_e after each
increment: :func:`truss_displacement_control`.
"""
from dataclasses import dataclass, field
import sys

import cvxpy as cp
import numpy as np
from tqdm import tqdm
import scipy.sparse as sp

from .conic import SolveInfo, prescribed_values, solve, split_dofs


# -- geometry and the bar element (B.1)-(B.9) --------------------------------------------

def _check_truss(x, bars):
    x = np.asarray(x, dtype=float)
    bars = np.asarray(bars, dtype=int)
    if x.ndim != 2 or x.shape[1] != 2:
        raise ValueError(f"x (node coordinates) must have shape (n_nodes, 2), got {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValueError("x (node coordinates) must be finite")
    if bars.ndim != 2 or bars.shape[1] != 2 or bars.shape[0] == 0:
        raise ValueError(f"bars must have shape (n_bars, 2) with n_bars >= 1, got {bars.shape}")
    if bars.min() < 0 or bars.max() >= x.shape[0]:
        raise ValueError("bars refer to a node that does not exist")
    return x, bars


def bar_geometry(x, bars):
    """Lengths and unit directions (cos phi, sin phi) of the bars (B.2).

    Parameters
    ----------
    x : (n_nodes, 2) node coordinates.  bars : (n_bars, 2) node pairs (i, j).

    Returns
    -------
    length : (n_bars,);  direction : (n_bars, 2) unit vectors from node i to node j.
    """
    x, bars = _check_truss(x, bars)
    d = x[bars[:, 1]] - x[bars[:, 0]]
    length = np.hypot(d[:, 0], d[:, 1])
    if np.any(length <= 0):
        raise ValueError(f"bars {np.flatnonzero(length <= 0).tolist()} have zero length")
    return length, d / length[:, None]


def bar_dofs(bars):
    """(n_bars, 4) global dofs (u_ix, u_iy, u_jx, u_jy) of each bar (B.8)."""
    bars = np.asarray(bars, dtype=int)
    return np.column_stack([2 * bars[:, 0], 2 * bars[:, 0] + 1,
                            2 * bars[:, 1], 2 * bars[:, 1] + 1])


def assemble_bar_B(x, bars):
    """The strain-displacement matrix of all bars, one row per bar (B.9).

    Row e holds (1/L_e) [-cos phi, -sin phi, cos phi, sin phi] on the dofs of
    bar e, so that ``B @ du`` is the vector of (small) axial strains.

    Returns
    -------
    scipy.sparse.csr_matrix of shape (n_bars, 2 n_nodes).
    """
    x, bars = _check_truss(x, bars)
    length, n = bar_geometry(x, bars)
    rows = np.repeat(np.arange(len(bars)), 4)
    vals = np.column_stack([-n, n]) / length[:, None]
    return sp.csr_matrix((vals.ravel(), (rows, bar_dofs(bars).ravel())),
                         shape=(len(bars), 2 * x.shape[0]))


def internal_forces(x, bars, force):
    """Nodal forces B^T V sigma = sum_e N_e [-n_e, n_e] of bar forces N_e = A_e sigma_e."""
    length, _ = bar_geometry(x, bars)
    return assemble_bar_B(x, bars).T @ (np.asarray(force, dtype=float) * length)


def stiffness_matrix(x, bars, area, E):
    """Small-deformation stiffness K = B^T diag(E V) B of the truss (reference only)."""
    length, _ = bar_geometry(x, bars)
    B = assemble_bar_B(x, bars)
    return (B.T @ sp.diags(np.broadcast_to(E * area * length, length.shape)) @ B).tocsr()


# -- the incremental problem (B.12) --------------------------------------------------------

@dataclass
class TrussIncrement:
    """Solution of one increment of (B.12).

    sigma : (n_bars,) axial stresses at t_{n+1};  force : (n_bars,) bar forces A sigma;
    du : (n_dof,) displacement increments (prescribed values on prescribed dofs);
    reactions : (n_dof,) B^T V sigma - f on fixed and prescribed dofs (zero on free dofs);
    plastic_strain : (n_bars,) plastic strain increments (zero in elastic bars);
    info : solver report.
    """

    sigma: np.ndarray
    force: np.ndarray
    du: np.ndarray
    reactions: np.ndarray
    plastic_strain: np.ndarray
    info: SolveInfo


def _per_bar(name, value, n, allow_none=False):
    if value is None and allow_none:
        return None
    v = np.broadcast_to(np.asarray(value, dtype=float), (n,)).copy()
    if not np.all(np.isfinite(v)) or np.any(v <= 0):
        raise ValueError(f"{name} must be positive and finite (one value or one per bar)")
    return v


def truss_increment(x, bars, area, E, sigma_n, *, fixed, prescribed=((), ()),
                    f=None, sigma_s=None, solver="clarabel", **solver_settings):
    """Solve one increment of the elastoplastic truss problem (B.12).

    .. math::
        \\max_{\\sigma}\\; -\\tfrac12 \\sum_e \\frac{V_e}{E_e}(\\sigma_e - \\sigma_{n,e})^2
          + \\Delta\\bar u_P^T (B_P^T V \\sigma - f_P)
        \\quad \\text{s.t.}\\quad B_F^T V \\sigma = f_F,\\quad |\\sigma_e| \\le \\sigma_{s,e}

    on the configuration ``x`` (B and V = A L of the current nodes). F are the free
    dofs, P the dofs with a prescribed increment; without ``sigma_s`` the bars are
    elastic. The problem is scaled (stresses by sigma_s or the elastic stress of the
    prescribed motion, lengths and areas by their medians) before Clarabel sees it.

    Parameters
    ----------
    x : (n_nodes, 2) current node coordinates.  bars : (n_bars, 2) node pairs.
    area : current cross-sectional areas (scalar or (n_bars,)).  E : Young's modulus.
    sigma_n : (n_bars,) axial stresses at t_n (tension positive).
    fixed : dofs with zero increment.  prescribed : (dofs, increments): the dofs with a
        prescribed increment and its values.
    f : (n_dof,) external nodal forces at t_{n+1} (default zero).
    sigma_s : yield stress (scalar or per bar), or None for elastic bars.
    solver : the conic solver (:data:`~pfem_skfem.problems.conic.SOLVERS`; 'clarabel').

    Returns
    -------
    TrussIncrement
    """
    x, bars = _check_truss(x, bars)
    n_b, n_dof = len(bars), 2 * x.shape[0]
    length, _ = bar_geometry(x, bars)
    area = _per_bar("area", area, n_b)
    E = _per_bar("E (Young's modulus)", E, n_b)
    sigma_s = _per_bar("sigma_s (yield stress)", sigma_s, n_b, allow_none=True)
    sigma_n = np.asarray(sigma_n, dtype=float).ravel()
    if sigma_n.shape != (n_b,):
        raise ValueError(f"sigma_n must have one stress per bar ({n_b}), got {sigma_n.shape}")
    if sigma_s is not None and np.any(np.abs(sigma_n) > sigma_s * (1 + 1e-6)):
        raise ValueError("sigma_n violates the yield condition |sigma| <= sigma_s")
    f = np.zeros(n_dof) if f is None else np.asarray(f, dtype=float)
    if f.shape != (n_dof,):
        raise ValueError(f"f must have one entry per dof ({n_dof}), got {f.shape}")
    free, P = split_dofs(n_dof, fixed, prescribed[0])
    du_P = prescribed_values(P, np.ravel(prescribed[1]))
    if free.size == 0 and P.size == 0:
        raise ValueError("every dof is fixed: nothing to solve")

    # reference magnitudes: length, area, stress; then displacement = stress * length / E
    ell, a = float(np.median(length)), float(np.median(area))
    E_ref = float(np.median(E))
    if sigma_s is not None:
        s_ref = float(np.median(sigma_s))
    else:
        candidates = [E_ref * np.abs(du_P).max() / ell if P.size else 0.0,
                      np.abs(f).max() / a, np.abs(sigma_n).max()]
        s_ref = max(candidates) or 1e-3 * E_ref
    u_ref = s_ref * ell / E_ref

    Bh = (assemble_bar_B(x, bars) * ell).tocsc()          # dimensionless strain operator
    Vh = area * length / (a * ell)                         # scaled bar volumes
    BV = (Bh.T @ sp.diags(Vh)).tocsr()                     # B^T V, scaled
    f_h = f / (s_ref * a)
    u_P = du_P / u_ref
    s_n = sigma_n / s_ref
    compliance = Vh * E_ref / E                            # V_e / E_e, scaled

    sig = cp.Variable(n_b)                                 # sigma_{n+1} / s_ref
    work_P = u_P @ (BV[P, :] @ sig - f_h[P]) if P.size else 0
    objective = cp.Maximize(-0.5 * cp.sum(cp.multiply(compliance, cp.square(sig - s_n)))
                            + work_P)                      # -1/2 dsig^T C dsig + work
    constraints = []
    if free.size:
        equilibrium = BV[free, :] @ sig == f_h[free]       # B_F^T V sigma_{n+1} = f_F
        constraints.append(equilibrium)
    if sigma_s is not None:
        yield_bound = cp.abs(sig) <= sigma_s / s_ref       # F(sigma_e) = |sigma_e| - sigma_s <= 0
        constraints.append(yield_bound)
    problem = cp.Problem(objective, constraints)
    info = solve(problem, what="truss increment (B.12)", solver=solver, **solver_settings)

    sigma = np.asarray(sig.value).ravel() * s_ref
    du = np.zeros(n_dof)
    if free.size:
        du[free] = -np.asarray(equilibrium.dual_value).ravel() * u_ref
    du[P] = du_P
    reactions = internal_forces(x, bars, sigma * area) - f
    reactions[free] = 0.0
    # plastic strain increment = total - elastic (B.4): B du - dsigma / E
    plastic = assemble_bar_B(x, bars) @ du - (sigma - sigma_n) / E
    if sigma_s is None:
        plastic[:] = 0.0
    return TrussIncrement(sigma, sigma * area, du, reactions, plastic, info)


# -- large deformation by small increments (thesis 6.3) -----------------------------------

@dataclass
class TrussHistory:
    """States of a truss after each increment (index 0 is the initial state).

    x : (n+1, n_nodes, 2) node coordinates (all initial with update_geometry=False);
    sigma : (n+1, n_bars) axial stresses;
    area : (n+1, n_bars) areas;  reactions : (n+1, n_dof) reactions as solved (bar
    forces on the configuration at the start of the increment);
    reactions_updated : (n+1, n_dof) the same bar forces A sigma on the updated
    configuration (B^T V sigma at x_{n+1} with the updated areas);
    iterations, solve_times : solver reports per increment.
    """

    x: np.ndarray
    sigma: np.ndarray
    area: np.ndarray
    reactions: np.ndarray
    reactions_updated: np.ndarray
    iterations: list = field(default_factory=list)
    solve_times: list = field(default_factory=list)

    @property
    def u(self):
        """(n+1, n_nodes, 2) total displacements."""
        return self.x - self.x[0]


#: how the truss's geometry follows an increment (:func:`truss_displacement_control`)
GEOMETRIES = ("updated", "incompressible", "initial")


def truss_displacement_control(x0, bars, area0, E, *, fixed, prescribed, n_increments,
                               sigma_s=None, geometry="updated", f=None, progress=False,
                               **solver_settings):
    """Large deformation by a sequence of small-deformation increments (B.12).

    Each increment solves :func:`truss_increment` on the current configuration,
    then moves the nodes by the displacement increments, recomputes the bar
    lengths and, for incompressible bars, the areas A = V / l (V = A0 L0); the
    stresses carry over. This is the thesis' scheme of Chapter 6.3 (no
    remeshing or mapping is needed for a truss).

    Parameters
    ----------
    x0 : (n_nodes, 2) initial nodes.  bars : (n_bars, 2).  area0 : initial areas.
    E : Young's modulus.  fixed : dofs with zero displacement.
    prescribed : (dofs, motion): the dofs with a prescribed displacement and either their
        (n_P,) total displacement, imposed in equal increments, or a callable
        ``path(k) -> (n_P,)``, the total displacement after increment k (``path(0)`` is
        zero), for non-proportional motions such as a rigid rotation.
    n_increments : number of increments.
    sigma_s : yield stress or None (elastic).
    geometry : 'updated' (the nodes move with each increment), 'incompressible' (and the
        areas follow A = V / l) or 'initial' (the initial configuration kept: pure small
        deformation).
    f : constant external nodal forces.
    progress : False, or a progress bar (tqdm) on stderr; a string labels it.
    solver_settings : ``solver``, the conic solver of every increment, and its settings
        (:func:`truss_increment`).

    Returns
    -------
    TrussHistory
    """
    if int(n_increments) != n_increments or n_increments < 1:
        raise ValueError(f"n_increments must be a positive integer, got {n_increments!r}")
    n_increments = int(n_increments)
    if geometry not in GEOMETRIES:
        raise ValueError(f"geometry must be one of {GEOMETRIES}, got {geometry!r}")
    if not (isinstance(prescribed, tuple) and len(prescribed) == 2):
        raise ValueError("prescribed must be (dofs, motion): the motion their total "
                         "displacement or a path(k)")
    prescribed, path = prescribed
    if not callable(path):
        total = np.asarray(path, dtype=float).ravel()
        path = lambda k: total * k / n_increments  # noqa: E731
    x, bars = _check_truss(x0, bars)
    x = x.copy()
    length0, _ = bar_geometry(x, bars)
    area = _per_bar("area0", area0, len(bars))
    volume = area * length0
    sigma = np.zeros(len(bars))
    n_dof = 2 * x.shape[0]
    free, _ = split_dofs(n_dof, fixed, prescribed)
    xs, sigmas, areas = [x.copy()], [sigma.copy()], [area.copy()]
    reactions, updated = [np.zeros(n_dof)], [np.zeros(n_dof)]
    iterations, times = [], []
    previous = np.asarray(path(0), dtype=float).ravel()
    label = progress if isinstance(progress, str) else None
    bar = tqdm(total=n_increments, desc=label or None, unit="increment", file=sys.stderr,
               disable=not progress, dynamic_ncols=True)
    for k in range(1, n_increments + 1):
        target = np.asarray(path(k), dtype=float).ravel()
        res = truss_increment(x, bars, area, E, sigma, fixed=fixed,
                              prescribed=(prescribed, target - previous), f=f, sigma_s=sigma_s,
                              **solver_settings)
        previous, sigma = target, res.sigma
        if geometry != "initial":
            x = x + res.du.reshape(-1, 2)
            if geometry == "incompressible":
                area = volume / bar_geometry(x, bars)[0]
        r_upd = internal_forces(x, bars, sigma * area) - (0 if f is None else f)
        r_upd[free] = 0.0
        xs.append(x.copy()), sigmas.append(sigma.copy()), areas.append(area.copy())
        reactions.append(res.reactions), updated.append(r_upd)
        iterations.append(res.info.iterations), times.append(res.info.solve_time)
        bar.set_postfix_str(f"iterations {res.info.iterations}", refresh=False)
        bar.update(1)
    bar.close()
    return TrussHistory(np.array(xs), np.array(sigmas), np.array(areas), np.array(reactions),
                        np.array(updated), iterations, times)
