"""The dynamic step (4.23) with its terms assembled directly in the standard form.

:class:`~pfem_skfem.problems.backends.cvxpy_step.CvxpyStep` states the step in cvxpy, the
readable reference; cvxpy then spends a noticeable part of a PFEM step compiling it
(``benchmarks/pfem_step.py``), so :class:`DirectStep` writes the same scaled problem in
the standard form min 1/2 x^T P x + c^T x, A x + s = b, s in K
(:class:`~pfem_skfem.problems.backends.standard_form.StandardForm`) and hands it to an
engine (Clarabel, QOCO), in its primal form or its dual (displacement) form
(:func:`~pfem_skfem.problems.backends.dual_form.solve_dual`):

* x = (sigma / stress, r' / r_ref, the terms' variables), named by a ``Layout``;
* P = blockdiag(kappa D^ on r', the terms' blocks: kappa_C C^ on sigma, ...), c the linear
  terms of the objective (the sign flipped: the engines minimise);
* the zero cone is equilibrium K_F x = f'_F, K = [B^T, A^T, the terms' columns];
* each yield cone rho_j = D_j sigma_j + d_j (the criterion's ``cone_vector``, affine, read
  off numerically) is s = b - A x with A = -D_j, b = d_j; a point of radius zero (a fluid's)
  is the zero cone of its criterion's ``PRESSURE_ROWS``.

The engines' dual z of the equality rows has the sign of cvxpy's dual of the same equality,
so du_F = -z_eq x displacement scale (checked against the cvxpy statement,
tests/test_clarabel_direct.py); the yield multipliers are the first component of each
cone's dual.
"""
import time

import scipy.sparse as sp

from ..conic import SolveInfo, check_status
from ..step_scaling import ScaledSolution
from .clarabel import SETTINGS
from .dual_form import solve_dual
from .standard_form import StandardForm, drop_roundoff, yield_block

#: Drop A's stored zeros (the yield block's zero entries of D, ~15 % of A) and P's round-off
#: (:func:`~.standard_form.drop_roundoff`) before the solve: the same problem, a factor with
#: fewer entries (book, performance appendix).
CLEAN_DATA = True

#: After a 'NumericalError' or an 'InsufficientProgress' of Clarabel on the primal form (the
#: statuses of :data:`RETRY_ON`) the step is solved once more with these settings: Clarabel's
#: equilibration off, which ends such steps 'Solved' (book, performance appendix, "When a
#: solve fails"). A step that ends otherwise ('AlmostSolved' included:
#: :func:`~pfem_skfem.problems.conic.check_status`'s rule) is not touched.
RETRY = dict(equilibrate_enable=False)
RETRY_ON = ("NumericalError", "InsufficientProgress")

#: the engines' status names read as cvxpy's (the package's vocabulary)
STATUS = {"Solved": "optimal", "AlmostSolved": "optimal_inaccurate",
          "PrimalInfeasible": "infeasible", "AlmostPrimalInfeasible": "infeasible_inaccurate",
          "DualInfeasible": "unbounded", "AlmostDualInfeasible": "unbounded_inaccurate"}

FORMS = ("primal", "dual")


class DirectStep:
    """The step assembled in the standard form and handed to ``engine`` in ``form``.

    Supports: a yield criterion (an elastic step without one is the cvxpy statement's),
    the quadratic inertia (``d_form='quad_form'``), every term whose cones the engine takes;
    a term with cones that are not self-dual (mu(I)'s exponential cones) makes the dual form
    state the primal.
    """

    statement = "direct"

    def __init__(self, engine, form="primal"):
        if form not in FORMS:
            raise ValueError(f"form must be one of {FORMS}, got {form!r}")
        self.engine, self.form = engine, form

    @property
    def cones(self):
        return self.engine.cones

    def unsupported(self, criterion, terms, settings):
        """Why this backend cannot state the step (a sentence), or None."""
        if criterion is None:
            return "the direct assembly needs a yield criterion (an elastic step: solver 'cvxpy')"
        if settings.get("d_form", "quad_form") != "quad_form":
            return "the direct assembly states the inertia as a quadratic (d_form='quad_form')"
        return None

    def assemble(self, step, criterion, terms):
        """(form, (P, c, A, b, cones), the yield multipliers' reader)."""
        form = StandardForm(step, terms)
        layout = form.layout
        # objective: -J = 1/2 kappa r'^T D r' + (A v)^T r' + the terms'
        form.quadratic("r", step.kappa * step.Dh)
        form.c[layout["r"]] = step.Ah @ step.v_h
        form.columns(step.Bh.T)                       # internal forces K x: B^T sigma
        form.columns(step.Ah.T)                       # + A^T r'
        for term in terms:
            term.blocks(form)
        K = form.internal()
        form.rows("equilibrium", K[step.free], step.f_h[step.free], "zero")   # K_F x = f'_F
        A_y, b_y, cones_y, multipliers = yield_block(criterion.scaled(step.stress), step.n)
        zeros = sp.csr_matrix((A_y.shape[0], form.n_x - 4 * step.n))
        form.rows("yield", sp.hstack([A_y, zeros]), b_y, cones_y)    # F(sigma_j) <= 0
        return form, form.assemble(), multipliers

    def solve(self, step, criterion, terms, *, what="dynamic step (4.23)",
              accept_inaccurate=False, **settings):
        """Solve the scaled step; a :class:`~pfem_skfem.problems.step_scaling.ScaledSolution`."""
        t0 = time.perf_counter()
        settings.pop("d_form", None)
        form, (P, c, A, b, cones), multipliers = self.assemble(step, criterion, terms)
        if CLEAN_DATA:                           # the same problem, fewer entries
            A.eliminate_zeros()
            P = drop_roundoff(P)
        engine = self.engine
        changes = {**SETTINGS, **settings} if engine.name == "clarabel" else dict(settings)
        opts = engine.settings(changes)
        t1 = time.perf_counter()
        build = t1 - t0                          # our assembly (cvxpy's 'compile' counterpart)
        retried, first_iterations = False, 0
        dual = self.form == "dual" and all(term.self_dual for term in terms)
        if dual:                                 # the displacement form
            sol = solve_dual(P, c, A, b, cones, opts, engine)
            build += sol.setup_time              # stating the dual is our assembly
            wall = time.perf_counter() - t1 - sol.setup_time
        else:
            sol = engine.solve(P, c, A, b, cones, opts)
            retried = (engine.name == "clarabel" and sol.status in RETRY_ON
                       and opts.equilibrate_enable)
            if retried:                          # once more without equilibration (RETRY),
                first_iterations = sol.iterations           # the first attempt's counted
                opts = engine.settings({**changes, **RETRY})
                sol = engine.solve(P, c, A, b, cones, opts)
            wall = time.perf_counter() - t1      # the solver's setup and iterations
        status = STATUS.get(sol.status, sol.status)
        check_status(status, what, accept_inaccurate, sol.measures)
        info = SolveInfo(status=status, iterations=int(sol.iterations) + first_iterations,
                         compile_time=build, solve_time=wall, objective=-float(sol.obj_val))
        if engine.name != "clarabel":
            info.extra["engine"] = engine.name
        if dual:
            info.extra["form"] = "dual"
        elif retried:
            info.extra["retried"] = dict(RETRY)
        x, z = sol.x, sol.z
        rows = form.row_slices
        solution = ScaledSolution(s=x[form.layout["sigma"]], r=x[form.layout["r"]],
                                  dual_equilibrium=z[rows["equilibrium"]],
                                  dual_yield=multipliers(z[rows["yield"].start:]), info=info)
        for term in terms:                       # the rate stresses, the contact forces
            term.read_direct(form, x, solution)
        return solution
