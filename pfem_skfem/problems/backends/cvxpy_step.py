"""The dynamic step (4.23) stated in cvxpy, the reference: the statement reads as printed.

In the scaled variables of :mod:`~pfem_skfem.problems.step_scaling` (stresses s, r' r, all
near order one):

.. math::
    \\max_{s, r}\\; -\\tfrac12 \\kappa\\, r^T \\hat D r - (\\hat A v)^T r + \\text{terms}
    \\quad\\text{s.t.}\\quad \\hat B_F^T s + \\hat A_F^T r + \\text{terms' forces} = \\hat f_F,
    \\quad F(s_j) \\le 0

and each :class:`~pfem_skfem.problems.step_terms.StepTerm` adds its part to the
:class:`CvxpyStatement` (its objective, its constraints, its stresses and forces).
"""
import cvxpy as cp
import numpy as np

from ...materials.criteria import yield_constraints
from ..conic import SOLVERS, solve
from ..step_scaling import ScaledSolution

D_FORMS = ("quad_form", "cone")

#: why a script whose checks hold energy to 1e-6 refuses ``--d-form cone`` (issue 56; book,
#: studies, "Options away from their defaults"): the cone form's objective kappa sum t_e is
#: flat to first order at its optimum, so the interior point's stopping gap g leaves r' and du
#: wrong by about sqrt(g), not g (one step of plastic_vibration: du 2.4e-5 off at Clarabel's
#: gap 9.1e-9, 7.7e-6 at its floor 3.6e-10); the quadratic form is solved to round-off
D_FORM_CONE_REFUSED = ("--d-form cone is refused here: the cone form's answer is only as "
                       "accurate as the square root of the solver's duality gap (du about "
                       "2e-5 off per step at Clarabel's default tolerances, 8e-6 at its "
                       "floor), and this script's energy checks ask 1e-6 to 1e-5; the "
                       "library keeps d_form='cone' for study (book, studies, the option "
                       "audit)")


class CvxpyStatement:
    """What the terms write on: the scaled step ``step``, the stresses ``S`` (n, 4) and
    ``s`` (their vector, point-major), r' ``r``, the total stress ``stress`` (s plus the terms'
    rate stresses), the objective, the constraints, and ``internal``: the internal forces
    B^T stress + A^T r' (made from ``stress`` when first read) that a term may add to."""

    def __init__(self, step):
        self.step = step
        self.S = cp.Variable((step.n, 4))            # sigma_{n+1} / stress, one row per point
        self.s = cp.vec(self.S, order="C")           # point-major as (3.28)
        self.r = cp.Variable(step.n_r)               # r' / r_ref, element-major (12 per element)
        self.stress = self.s
        self.objective = 0
        self.constraints = []
        self._internal = None

    @property
    def internal(self):
        if self._internal is None:                   # B^T sigma + A^T r
            self._internal = self.step.Bh.T @ self.stress + self.step.Ah.T @ self.r
        return self._internal

    @internal.setter
    def internal(self, value):
        self._internal = value


class CvxpyStep:
    """The cvxpy statement, solved by a solver of :data:`~pfem_skfem.problems.conic.SOLVERS`.

    Supports every term, an elastic step without a yield criterion and both forms of the
    inertia (``d_form``: 'quad_form', r'^T D r' as a quadratic objective, or 'cone', one
    rotated second-order cone per element through D = G^T G, App A); the cones are the
    solver's (checked before any work by :func:`~pfem_skfem.problems.conic.solver_backend`).
    """

    statement = "cvxpy"

    def __init__(self, solver="clarabel"):
        self.solver = solver

    @property
    def cones(self):
        return SOLVERS[self.solver].cones

    def unsupported(self, criterion, terms, settings):
        d_form = settings.get("d_form", "quad_form")
        if d_form not in D_FORMS:
            return f"d_form must be one of {D_FORMS}, got {d_form!r}"
        return None

    def state(self, step, criterion, terms, d_form="quad_form"):
        """(problem, the statement, equilibrium, the yield multipliers' reader) of the step."""
        st = CvxpyStatement(step)
        for term in terms:                           # sigma = sigma_p + the rate stresses
            extra = term.cvxpy_stress(st)
            if extra is not None:
                st.stress = st.stress + extra
        # -1/2 dt^2 r'^T D r' - dt v_n^T A^T r'   (in units of j_ref)
        if d_form == "quad_form":
            inertia = 0.5 * step.kappa * cp.quad_form(st.r, cp.psd_wrap(step.Dh))
        else:                                        # sum_e |G_e r_e|^2 <= 2 sum_e t_e (A.4)-(A.8)
            n_e = step.n_r // 12
            W = cp.reshape((step.ops.G / np.sqrt(step.d_ref)) @ st.r, (n_e, 12), order="C")
            t = cp.Variable(n_e)
            rest = cp.reshape(2 * t - 1, (-1, 1), order="C")
            st.constraints.append(cp.SOC(2 * t + 1, cp.hstack([2 * W, rest]), axis=1))
            inertia = step.kappa * cp.sum(t)
        st.objective = -inertia - (step.Ah @ step.v_h) @ st.r
        for term in terms:                           # compliance, contacts, rates, supports
            term.cvxpy(st)
        equilibrium = st.internal[step.free] == step.f_h[step.free]   # B^T sigma + A^T r = f
        st.constraints.insert(0, equilibrium)
        multipliers = None
        if criterion is not None:           # F(sigma_j) <= 0 (a fluid's point: rho_2..m = 0)
            cones, multipliers = yield_constraints(criterion.scaled(step.stress), st.S)
            st.constraints += cones
        return cp.Problem(cp.Maximize(st.objective), st.constraints), st, equilibrium, multipliers

    def solve(self, step, criterion, terms, *, what="dynamic step (4.23)", d_form="quad_form",
              **settings):
        """Solve the scaled step; a :class:`~pfem_skfem.problems.step_scaling.ScaledSolution`
        (cvxpy's dual of an equality in a maximisation is minus its multiplier)."""
        problem, st, equilibrium, multipliers = self.state(step, criterion, terms, d_form)
        info = solve(problem, what=what, solver=self.solver, **settings)
        s = st.S.value.ravel() if st.stress is st.s else st.stress.value
        solution = ScaledSolution(s=s, r=st.r.value, dual_equilibrium=equilibrium.dual_value,
                                  dual_yield=None if multipliers is None else multipliers(),
                                  info=info)
        for term in terms:                           # contact forces
            term.read(st, solution)
        return solution
