"""Bounds that meet: adaptive refinement on the local bound gap, and the factor of
safety by strength reduction, each bracketed by the strict lower and upper bounds of
:mod:`pfem_skfem.problems.bounds`.

Adaptive loop: solve both bounds on the mesh, split the gap alpha_U - alpha_L into its
element shares eta_e (:func:`~pfem_skfem.problems.bounds.local_gap`; eta_e >= 0, they
sum to the gap), refine the fewest elements holding a fraction ``theta`` of it (Doerfler
marking; scikit-fem's red-green-blue refinement keeps the mesh conforming), repeat.

Factor of safety (strength reduction): c / F and tan(phi) / F. The load multiplier of
gravity alpha(F) falls as F grows, and alpha_L(F) <= alpha(F) <= alpha_U(F), so the
roots F_L of alpha_L = 1 and F_U of alpha_U = 1 bracket the F of alpha = 1:
F_L <= F <= F_U.
"""
import time
from dataclasses import dataclass, field, replace

import numpy as np

from ..materials.criteria import MohrCoulomb
from ..problems.bounds import local_gap, lower_bound, upper_bound
from ..problems.conic import SolverError


@dataclass
class Round:
    """One round of :func:`adapt`: the mesh's bounds and their gap."""

    elements: int
    lower: float
    upper: float
    seconds: float
    solvers: tuple = ()             # the solvers that gave (lower, upper)

    @property
    def gap(self):
        """(upper - lower) / (upper + lower) * 2: the relative width of the bracket."""
        return 2 * (self.upper - self.lower) / (self.upper + self.lower)

    def as_json(self, scale=1.0):
        """The round for a report: elements, the bounds times ``scale``, gap, seconds."""
        return dict(elements=self.elements, lower=self.lower * scale,
                    upper=self.upper * scale, gap=self.gap, seconds=self.seconds)


def bracket(problem, **solver_settings):
    """Both bounds of ``problem`` on its mesh as a :class:`Round` (no refinement)."""
    t0 = time.perf_counter()
    lower = lower_bound(problem, **solver_settings).load
    upper = upper_bound(problem, **solver_settings).load
    return Round(problem.mesh.t.shape[1], lower, upper, time.perf_counter() - t0)


def refine_uniformly(problem, levels, *, progress=None, **solver_settings):
    """:func:`bracket` of ``problem`` and of each of ``levels`` uniform refinements of its
    mesh, in turn: the rounds an adaptive refinement (:func:`adapt`) of the same first mesh
    is measured against. ``progress(round)`` is called after each."""
    rounds = []
    for level in range(levels + 1):
        if level:
            problem = problem.refined()
        rounds.append(bracket(problem, **solver_settings))
        if progress is not None:
            progress(rounds[-1])
    return rounds


def bounds_at(problem, F, **solver_settings):
    """``problem`` with its strength reduced by ``F`` (:func:`reduced`), and its lower and
    upper bounds there: the fields of a slope at (a bracket of) its factor of safety."""
    at = replace(problem, criterion=reduced(problem.criterion, F))
    return at, lower_bound(at, **solver_settings), upper_bound(at, **solver_settings)


@dataclass
class Adapted:
    """The result of :func:`adapt`: its rounds, the last problem and its two bounds."""

    rounds: list
    problem: object
    lower: object
    upper: object
    eta: np.ndarray = field(default=None, repr=False)


def doerfler(eta, theta):
    """The fewest elements whose shares of ``eta`` sum to at least ``theta`` of it."""
    order = np.argsort(eta)[::-1]
    total = np.cumsum(eta[order])
    n = int(np.searchsorted(total, theta * total[-1])) + 1
    return np.sort(order[:n])


def adapt(problem, *, rounds=5, target_gap=0.005, max_elements=5000, theta=0.5,
          progress=None, fallback=(), **solver_settings):
    """Refine ``problem`` where the bound gap lies until the relative gap is below
    ``target_gap``, ``rounds`` rounds were made, or the next mesh would pass
    ``max_elements``. ``progress(round)`` is called after each round. ``fallback``: solver
    names tried in turn, each with its own settings, for a bound the chosen solver
    (``solver_settings``) cannot certify; a bound is strict whichever solver certified it
    (each round records which, :attr:`Round.solvers`), and the chosen solver's error is
    raised when every one fails.

    Returns :class:`Adapted` (the last round's bounds are of its problem's mesh)."""
    for name, value in (("rounds", rounds), ("max_elements", max_elements)):
        if int(value) != value or value < 1:
            raise ValueError(f"{name} must be a positive integer, got {value!r}")
    if not 0 < theta <= 1:
        raise ValueError(f"theta must be in (0, 1], got {theta!r}")
    if not target_gap > 0:
        raise ValueError(f"target_gap must be positive, got {target_gap!r}")
    history = []
    while True:
        t0 = time.perf_counter()
        lo, lo_by = _certified(lower_bound, problem, fallback, solver_settings)
        up, up_by = _certified(upper_bound, problem, fallback, solver_settings)
        history.append(Round(problem.mesh.t.shape[1], lo.load, up.load,
                             time.perf_counter() - t0, (lo_by, up_by)))
        if progress is not None:
            progress(history[-1])
        eta = np.maximum(local_gap(problem, lo, up), 0.0)
        marked = doerfler(eta, theta)
        # red-green-blue refinement about quadruples a marked element and splits a
        # neighbour or two: 4 x marked is a fair guess of the growth
        done = (history[-1].gap <= target_gap or len(history) >= rounds
                or problem.mesh.t.shape[1] + 4 * marked.size > max_elements)
        if done:
            return Adapted(history, problem, lo, up, eta)
        problem = problem.refined(marked)


def _certified(bound, problem, fallback, solver_settings):
    """(``bound(problem)``, the name of the solver that certified it): the chosen solver's
    answer, else the first of ``fallback`` to give one; the chosen solver's error if none."""
    try:
        return bound(problem, **solver_settings), solver_settings.get("solver", "clarabel")
    except SolverError as error:
        for name in fallback:
            try:
                return bound(problem, solver=name), name
            except SolverError:
                continue
        raise error


def reduced(criterion, F):
    """The Mohr-Coulomb (or Tresca) criterion with c / F and tan(phi) / F."""
    if not isinstance(criterion, MohrCoulomb):
        raise TypeError("strength reduction needs a MohrCoulomb (or Tresca) criterion, got "
                        f"{criterion!r}")
    if not (np.isfinite(F) and F > 0):
        raise ValueError(f"F must be positive, got {F!r}")
    phi = np.degrees(np.arctan(np.tan(np.radians(criterion.phi)) / F))
    return MohrCoulomb(c=criterion.c / F, phi=phi)


@dataclass
class SafetyFactor:
    """F of one bound: alpha(F) = 1, with the trials (F, alpha) the search made."""

    kind: str
    F: float
    trials: list


def factor_of_safety(problem, kind, *, tol=1e-4, start=1.0, max_solves=40,
                     **solver_settings):
    """F with alpha(F) = 1 for the ``kind`` ('lower' or 'upper') bound, alpha the
    multiplier of the problem's live load (gravity), by bracketing and the Illinois
    method on ln alpha(ln F) to a relative width ``tol`` of the bracket.

    A lower-bound F is safe (the true F is at least it), an upper-bound F unsafe."""
    solver = {"lower": lower_bound, "upper": upper_bound}.get(kind)
    if solver is None:
        raise ValueError(f"kind must be 'lower' or 'upper', got {kind!r}")
    if problem.punch is not None:
        raise ValueError("the factor of safety needs a live load (gravity), not a punch")
    trials = []

    def g(x):                              # ln alpha at F = exp(x); decreasing in x
        F = float(np.exp(x))
        alpha = solver(replace(problem, criterion=reduced(problem.criterion, F)),
                       **solver_settings).load
        trials.append((F, alpha))
        if not alpha > 0:
            raise ValueError(f"the {kind} bound of the gravity multiplier is {alpha!r} "
                             f"at F = {F:.6g}: no positive multiplier to bracket")
        return float(np.log(alpha))

    x0, g0 = np.log(start), None
    g0 = g(x0)
    # a first step from alpha ~ 1 / F (exact for a weightless cohesive soil)
    x1 = x0 + g0
    g1 = g(x1)
    while g0 * g1 > 0:                     # step on until the sign changes
        if len(trials) >= max_solves:
            raise RuntimeError(f"no bracket of alpha = 1 after {len(trials)} solves")
        step = 2 * (x1 - x0) if x1 != x0 else 0.5
        x0, g0, x1 = x1, g1, x1 + step
        g1 = g(x1)
    a, ga, b, gb = x0, g0, x1, g1
    while abs(b - a) > tol and gb != 0 and len(trials) < max_solves:
        x = b - gb * (b - a) / (gb - ga)   # regula falsi
        gx = g(x)
        if gx * gb < 0:
            a, ga = b, gb
        else:
            ga /= 2                        # Illinois: the end kept twice counts half
        b, gb = x, gx
    # the end on the safe side of its own bound: alpha_L >= 1, alpha_U <= 1
    safe = (b if gb >= 0 else a) if kind == "lower" else (b if gb <= 0 else a)
    return SafetyFactor(kind, float(np.exp(safe)), trials)


@dataclass
class SafetyRound:
    """One round of :func:`bracket_safety`: the mesh's F_L <= F <= F_U."""

    elements: int
    lower: float
    upper: float
    solves: int
    seconds: float

    @property
    def gap(self):
        """(F_U - F_L) / (F_U + F_L) * 2: the relative width of the bracket."""
        return 2 * (self.upper - self.lower) / (self.upper + self.lower)


def bracket_safety(problem, *, rounds=4, target_gap=0.03, max_elements=5000, theta=0.5,
                   tol=1e-3, progress=None, **solver_settings):
    """F_L <= F <= F_U on meshes refined where the bounds of the gravity multiplier
    differ at F = (F_L + F_U) / 2 (:func:`adapt`'s marking), until the bracket is
    narrower than ``target_gap``, after ``rounds`` rounds or at ``max_elements``.

    Returns (rounds: a list of :class:`SafetyRound`, the last mesh's problem)."""
    history, start = [], 1.0
    while True:
        t0 = time.perf_counter()
        lo = factor_of_safety(problem, "lower", tol=tol, start=start, **solver_settings)
        up = factor_of_safety(problem, "upper", tol=tol, start=lo.F, **solver_settings)
        history.append(SafetyRound(problem.mesh.t.shape[1], lo.F, up.F,
                                   len(lo.trials) + len(up.trials), time.perf_counter() - t0))
        if progress is not None:
            progress(history[-1])
        if (history[-1].gap <= target_gap or len(history) >= rounds):
            return history, problem
        start = 0.5 * (lo.F + up.F)
        at, lower, upper = bounds_at(problem, start, **solver_settings)
        marked = doerfler(np.maximum(local_gap(at, lower, upper), 0.0), theta)
        if problem.mesh.t.shape[1] + 4 * marked.size > max_elements:
            return history, problem
        problem = problem.refined(marked)
