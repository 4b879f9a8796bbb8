"""The dynamic problem: theta-method in time (4.3)-(4.11) and the SOCP (4.23).

Each time step solves

.. math::
    \\max_{\\sigma, r}\\; -\\tfrac12 \\Delta\\sigma^T C \\Delta\\sigma
        - \\tfrac12 \\Delta t^2\\, r^T D r
    \\quad\\text{s.t.}\\quad B^T\\sigma + A^T r = f,\\quad F(\\sigma_j) \\le 0

(4.23), with rho~ = rho/(theta1 theta2) in D, and f the discrete form of
b~ and t~ (4.6), (4.10) (the inertia of the state at t_n included).

KKT conditions (4.25), re-derived (the printed first row has a sign error, see
MAP.md). With the Lagrangian

    L = -1/2 ds^T C ds - 1/2 dt^2 r^T D r + du^T (B^T sigma + A^T r - f)

stationarity gives  B du = C ds + dlambda grad F  (flow rule, (4.11)),
dt^2 D r = A du  (r = rho~ du/dt^2, the dynamic force), and eliminating r,
B^T sigma + (A^T D^-1 A) du / dt^2 = f with A^T D^-1 A = int rho~ N_u^T N_u
(4.26)-(4.27). So the multiplier of the equality is +du; cvxpy's dual of an
equality in a maximisation is its negative (tests: free fall, standard-FE agreement).

Scaling. As stated, f carries the inertia rho~ v_n/dt, which dwarfs gravity and
the tractions when dt is small, and Clarabel's tolerances are absolute. We
therefore write r = rho~ v_n / dt + r' (exact: v_n restricted to an element is in
the discontinuous P2 space of r). Then A^T (rho~ v_n/dt) = M~ v_n/dt cancels the
inertia in f, D (rho~ v_n/dt) = A v_n/dt, and the problem becomes

    max  -1/2 ds^T C ds - 1/2 dt^2 r'^T D r' - dt v_n^T A^T r'
    s.t. B^T sigma + A^T r' = f'     (f' = f - M~ v_n/dt: loads and sigma_n only)

with the same multiplier du. In the code r' is ``r``. Stresses, r' and du are measured in
scales (:class:`~pfem_skfem.problems.step_scaling.DynamicScales`) taken from an elastic
predictor of the step or, when stepping, from the previous step's solution, so that the
data are near order one (:func:`~pfem_skfem.problems.step_scaling.scale_step`, which also
maps the answer back). A body in free fall falls g dt^2 (N(N-1)/2 + N theta2) in N steps
to round-off with either material model (tests/test_dynamics.py).

The step is assembled from parts: inertia, equilibrium and the yield cones, and the terms
of :mod:`~pfem_skfem.problems.step_terms` (the compliance, contacts, a rate stress, the
work of prescribed increments); a backend of :mod:`~pfem_skfem.problems.backends` states
and solves it (the cvxpy statement, the reference, or the direct assembly).
"""
import numpy as np

from .backends import step_solver
from .step_scaling import scale_step
from .step_terms import Compliance, PrescribedWork


def dynamic_increment(ops, f_n, f_next, sigma_n, v_n, criterion=None, *, fixed=(),
                      prescribed=((), ()), terms=(), scaling=None, solver="cvxpy", **settings):
    """Solve one time step of the dynamic problem (4.23).

    .. math::
        &\\max_{\\sigma, r'}\\; -\\tfrac12 \\Delta t^2 r'^T D r' - \\Delta t\\, v_n^T A^T r'
          + \\text{terms} \\\\
        &\\text{s.t.}\\quad B_F^T\\sigma + A_F^T r' + \\text{terms' forces} = f'_F,
        \\quad F(\\sigma_j) \\le 0

    which is (4.23) with r = rho~ v_n/dt + r' (see the module docstring), F the free dofs,
    and the terms in this order: the compliance - 1/2 ds^T C ds when ``ops`` carry C
    (:class:`~pfem_skfem.problems.step_terms.Compliance`), the caller's ``terms`` (contacts
    (5.12), a Bingham or mu(I) rate stress: :func:`~pfem_skfem.problems.step_terms.step_terms`),
    and the work of the reactions on the prescribed dofs P,
    du_P^T (B_P^T sigma + A_P^T r' - f'_P) (:class:`~pfem_skfem.problems.step_terms.PrescribedWork`).
    ``C = None`` in ``ops`` means rigid-plastic; ``criterion = None`` elastic (no yield cone).

    Parameters
    ----------
    ops : :class:`~pfem_skfem.discretisation.dynamic.DynamicOperators`.
    f_n, f_next : (n_u,) external forces (3.42) at t_n and t_{n+1}.
    sigma_n : (n_points, 4) stresses at t_n.  v_n : (n_u,) velocities at t_n.
    criterion : yield criterion or None (elastic).
    fixed : dofs held at zero increment.
    prescribed : (dofs, increments): dofs with prescribed increments and their values.
    terms : the step's terms (:mod:`~pfem_skfem.problems.step_terms`), stated in this order.
    scaling : :class:`~pfem_skfem.problems.step_scaling.DynamicScales` (stress, displacement,
        r'); by default from an elastic predictor. Pass the previous step's ``scales`` when
        stepping.
    solver : the step's solver (:data:`~pfem_skfem.problems.backends.STEP_SOLVERS`):
        'cvxpy' (the statement above, the reference; the default here), 'clarabel' (the same
        scaled problem assembled directly, a PFEM run's default), 'clarabel-dual', 'qoco',
        ... A solver lacking a term's cones (QOCO and mu(I)'s exponential cones) is refused
        before any work.
    settings : the solver's settings; ``d_form`` ('quad_form', 'cone': r'^T D r' as one
        rotated second-order cone per element through D = G^T G, App A) for the cvxpy
        statement; ``accept_inaccurate``.

    Returns
    -------
    :class:`~pfem_skfem.problems.step_scaling.DynamicIncrement`
    """
    if ops.C is None and criterion is None:
        raise ValueError("a rigid-plastic material (C = None) needs a yield criterion")
    terms = ((Compliance(),) if ops.C is not None else ()) + tuple(terms)
    dofs, du_prescribed = prescribed
    if np.size(dofs):
        terms += (PrescribedWork(),)
    for term in terms:                                          # refused before any work
        term.check(ops, criterion)
    backend = step_solver(solver, criterion, terms, settings)
    f = ops.theta.equilibrium_rhs(f_n, f_next, ops.B,
                                  np.asarray(sigma_n, dtype=float).reshape(-1, 4))   # f'
    step, inverse = scale_step(ops, f, sigma_n, v_n, criterion,
                               (fixed, dofs, du_prescribed), scaling)
    solution = backend.solve(step, criterion, terms, **settings)
    inverse.terms = terms
    return inverse.invert(solution)
