"""The optional parts of the dynamic step (4.23) as terms added to it.

The step itself is inertia, equilibrium and the yield cones; everything else is a
:class:`StepTerm` added to it, as ``prob.add_convex_term(...)`` adds a term in
dolfinx_optim. A term knows its two statements:

* :meth:`StepTerm.cvxpy`: its part of the cvxpy statement (the reference), written on the
  statement's variables (:class:`~pfem_skfem.problems.backends.cvxpy_step.CvxpyStatement`:
  the stresses ``s``, r' ``r``, the internal forces ``internal``, the objective and the
  constraints), and :meth:`StepTerm.cvxpy_stress` when it adds a stress of its own;
* :meth:`StepTerm.declare` and :meth:`StepTerm.blocks`: its variable blocks, its blocks
  of the quadratic and linear cost, its columns of the internal forces and its cone rows
  in the standard form min 1/2 x^T P x + c^T x, A x + s = b, s in K of the direct
  assembly (:class:`~pfem_skfem.problems.backends.standard_form.StandardForm`);

and :meth:`StepTerm.read` / :meth:`StepTerm.invert` read its part of the answer. The
terms of this module, in the order a step states them (the step adds the compliance first
and the prescribed work last; a caller gives the others, :func:`step_terms` for the usual
ones):

=======================  =============================================================  ========
term                     in (4.23)                                                      cones
=======================  =============================================================  ========
:class:`Compliance`      ``- 1/2 (sigma - sigma_n)^T C (sigma - sigma_n)``              (none)
:class:`Contact`         (5.12): ``- sum g0_j p_j``, ``|q_j| <= mu_j p_j``, G (p, q)    nonneg
:class:`BinghamStress`   ``- sum_j dt w_j tau_j^2 / (2 eta_j)``, sigma += E (a, b)      (none)
:class:`MuIRate`         ``- sum_j dt w_j c_j (-s_j - ln(1 - s_j))``, tau <= tau_max s  soc, exp
:class:`ElasticSupport`  ``- sum_i g_i^2 / (2 k_i)``, + g_i on dof i (springs)          (none)
:class:`PrescribedWork`  ``+ du_P^T (B_P^T sigma + A_P^T r' - f'_P)``                   (none)
=======================  =============================================================  ========

A new term is a subclass with these methods, handed to the step in ``terms=[...]``; the
step knows nothing of its kind. The static increment (3.45) states the terms marked
``static`` (the compliance, the contacts, the springs, the prescribed work) through their
cvxpy form, in the same order (:mod:`~pfem_skfem.problems.static`) (CONTRIBUTING.md, "A new term of the step"). Beyond this
module: :class:`~pfem_skfem.problems.pore_term.PorePressureTerm`, the pore pressure of a
saturated soil (Darcy, storage, Biot's alpha p in equilibrium; zero cones).
"""
import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from ..materials.rate import RateDissipation, ViscousStress
from .contact import contact_matrix, contact_terms


class StepTerm:
    """A part of the dynamic step (4.23) beyond inertia, equilibrium and the yield cones.

    Attributes
    ----------
    name : a short name (in messages).
    cones : the cone kinds its statement needs (:data:`~pfem_skfem.problems.conic.CONE_KINDS`).
    self_dual : whether its cones are self-dual (the direct assembly's dual form needs it).
    static : whether the static increment (3.45) states it too (its cvxpy form, ``read`` and
        ``invert`` on :class:`~pfem_skfem.problems.static.StaticStep`, which has no time step).
    """

    name = ""
    cones = frozenset()
    self_dual = True
    static = False

    def check(self, ops, criterion):
        """Refuse data that do not fit the step's operators and criterion (ValueError),
        before any work."""

    # -- the cvxpy statement -------------------------------------------------------------
    def cvxpy_stress(self, st):
        """A stress of the term's added to sigma (a cvxpy expression (4n,)), or None."""
        return None

    def cvxpy(self, st):
        """Add the term's objective, constraints and internal forces to the statement."""
        raise NotImplementedError

    def read(self, st, solution):
        """Put the term's scaled values into ``solution.parts`` (cvxpy statement)."""

    # -- the direct assembly -------------------------------------------------------------
    def declare(self, form):
        """Add the term's variable blocks to ``form.layout``."""

    def blocks(self, form):
        """Add the term's cost blocks, internal-force columns and cone rows to ``form``."""
        raise NotImplementedError

    def read_direct(self, form, x, solution):
        """Put the term's scaled values into ``solution.parts`` (direct assembly)."""

    # -- back to physical units ----------------------------------------------------------
    def invert(self, solution, increment, step):
        """Write the term's physical values into the increment (and take its forces off
        the reactions)."""


class Compliance(StepTerm):
    """The elastic part of (4.23): - 1/2 (sigma - sigma_n)^T C (sigma - sigma_n), C scaled by
    its median diagonal (the weight kappa_C of the scaled step). Added by the step when its
    operators carry C (an elastoplastic material). sigma is the total stress: with a
    Bingham rate stress (an elastoviscoplastic step) sigma = sigma_p + E (a, b), and the
    compliance couples the two blocks (B du - C dsigma is then the viscoplastic strain)."""

    name = "compliance"
    static = True

    def cvxpy(self, st):
        step = st.step
        Ch = step.Ch                             # - kappa_C (1/2 s^T C s - (C s_n)^T s)
        st.objective += -step.kappa_C * (0.5 * cp.quad_form(st.stress, cp.psd_wrap(Ch))
                                         - (Ch @ step.s_n) @ st.stress)

    def blocks(self, form):
        step = form.step
        form.quadratic("sigma", step.kappa_C * step.Ch)
        form.c[form.layout["sigma"]] -= step.kappa_C * (step.Ch @ step.s_n)
        if "rate_stress" in form.layout:         # sigma = s + E v: the blocks of v
            rate = form.layout["rate_stress"]
            E = viscous_stress_map(step.n, hoop=(rate.stop - rate.start) == 3 * step.n)
            CE = (step.kappa_C * step.Ch @ E).tocsr()
            form.coupling("sigma", "rate_stress", CE)
            form.quadratic("rate_stress", (E.T @ CE).tocsr())
            form.c[rate] -= step.kappa_C * (E.T @ (step.Ch @ step.s_n))


class Contact(StepTerm):
    """Rigid frictional boundaries (5.10)-(5.12): the contact forces (p, q) of the nodes of a
    :class:`~pfem_skfem.problems.contact.ContactSet` join equilibrium (- G (p, q)), - sum g0_j
    p_j (+ sum (n^_j . d) q_j for a moving body) the objective, p_j >= 0 and ``|q_j| <= mu_j p_j``
    (or ``|q_j| <= k_j``, a friction bound) the constraints. A friction bound is a force of the
    momentum balance: theta1 x the variable, hence its scale force x theta1."""

    name = "contact"
    cones = frozenset({"zero", "nonneg"})
    static = True

    def __init__(self, contacts):
        self.contacts = contacts

    def cvxpy(self, st):
        step = st.step
        self.ct = contact_terms(self.contacts, step.n_u, length_scale=step.u_ref,
                                force_scale=step.force * step.theta1)
        st.internal = st.internal - self.ct.force()   # B^T sigma + A^T r - G (p, q)
        st.objective += self.ct.objective             # - sum g0_j p_j
        st.constraints += self.ct.constraints         # |q_j| <= mu_j p_j

    def read(self, st, solution):
        solution.parts.update(p=self.ct.p.value, q=self.ct.q.value)

    def declare(self, form):
        nc = self.contacts.size
        form.layout.add("p", nc)                      # normal forces
        form.layout.add("q", nc)                      # tangential forces

    def blocks(self, form):
        step, cs, layout = form.step, self.contacts, form.layout
        nc = cs.size
        form.columns(-contact_matrix(cs, step.n_u))   # - G (p, q) in equilibrium
        form.c[layout["p"]] = cs.gap / step.u_ref     # + sum g0_j p_j (minimised)
        if cs.slip is not None:                       # - (n^ . d) q: a moving body
            form.c[layout["q"]] = -(cs.slip / step.u_ref)
        bound = (None if cs.friction_bound is None
                 else np.asarray(cs.friction_bound) / (step.force * step.theta1))
        k = cs.mu if bound is None else bound
        smooth, rough = np.flatnonzero(k <= 0), np.flatnonzero(k > 0)
        q0, p0 = layout["q"].start, layout["p"].start
        if smooth.size:                               # q_j = 0
            form.rows("equality", _pick(smooth, q0 + smooth, form.n_x), np.zeros(smooth.size),
                      "zero")
        form.rows("before_yield", -_pick(np.arange(nc), p0 + np.arange(nc), form.n_x),
                  np.zeros(nc), "nonneg")             # p_j >= 0
        if rough.size:                 # mu_j p_j -+ q_j >= 0  (or k_j -+ q_j >= 0)
            i = np.arange(rough.size)
            r = np.concatenate([i, rough.size + i])
            col = np.concatenate([q0 + rough, q0 + rough])
            val = np.concatenate([np.ones(rough.size), -np.ones(rough.size)])
            b_pairs = np.zeros(2 * rough.size)
            if bound is None:
                r = np.concatenate([r, i, rough.size + i])
                col = np.concatenate([col, p0 + rough, p0 + rough])
                val = np.concatenate([val, -cs.mu[rough], -cs.mu[rough]])
            else:
                b_pairs[:] = np.tile(bound[rough], 2)
            form.rows("after_yield", sp.csr_matrix((val, (r, col)),
                                                   shape=(2 * rough.size, form.n_x)),
                      b_pairs, "nonneg")

    def read_direct(self, form, x, solution):
        solution.parts.update(p=x[form.layout["p"]], q=x[form.layout["q"]])

    def invert(self, solution, increment, step):
        p_c = solution.parts["p"] * step.force
        q_c = solution.parts["q"] * step.force
        increment.reactions -= contact_matrix(self.contacts, step.n_u) @ np.concatenate([p_c, q_c])
        increment.p, increment.q = step.theta1 * p_c, step.theta1 * q_c   # of the momentum balance


def viscous_stress_map(n, hoop=False):
    """E (4n, 2n): the viscous stress (a, -a, 0, b) of each point from its (a, b); with
    ``hoop`` E (4n, 3n): (a, -a, 0, b) + c (1, 1, -2, 0) / sqrt3 from (a, b, c), the
    deviators of axisymmetry (rr, zz, tt, rz). Either way sqrt(J2) = ||(a, b[, c])||."""
    j = np.arange(n)
    rows = np.concatenate([4 * j, 4 * j + 1, 4 * j + 3])
    if not hoop:
        cols = np.concatenate([2 * j, 2 * j, 2 * j + 1])
        vals = np.concatenate([np.ones(n), -np.ones(n), np.ones(n)])
        return sp.csr_matrix((vals, (rows, cols)), shape=(4 * n, 2 * n))
    rows = np.concatenate([rows, 4 * j, 4 * j + 1, 4 * j + 2])
    cols = np.concatenate([3 * j, 3 * j, 3 * j + 1, 3 * j + 2, 3 * j + 2, 3 * j + 2])
    c = np.full(n, 1 / np.sqrt(3.0))
    vals = np.concatenate([np.ones(n), -np.ones(n), np.ones(n), c, c, -2 * c])
    return sp.csr_matrix((vals, (rows, cols)), shape=(4 * n, 3 * n))


class _RateStress(StepTerm):
    """A rate deviator sigma_v = E (a, b[, c]) added at each point to the plastic stress
    (rigid-plastic steps only, but for :class:`BinghamStress`): sigma = sigma_p + sigma_v,
    tau_j = ||(a_j, b_j[, c_j])|| = sqrt(J2) (:func:`viscous_stress_map`; ``hoop``: the three
    deviators of axisymmetry)."""

    def __init__(self, data):
        self.data = data
        self.m = 3 if data.hoop else 2           # components of a rate deviator

    def check(self, ops, criterion):
        if ops.C is not None or criterion is None:
            raise ValueError(f"{self.name}: only for a rigid-plastic material with a yield "
                             "criterion")

    def cvxpy_stress(self, st):
        self.V = cp.Variable((st.step.n, self.m))         # (a, b[, c]) per point
        return viscous_stress_map(st.step.n, self.data.hoop) @ cp.vec(self.V, order="C")

    def declare(self, form):
        form.layout.add("rate_stress", self.m * form.step.n)

    def stress_columns(self, form):
        """B^T E: the internal forces of the rate stresses."""
        return form.step.Bh.T @ viscous_stress_map(form.step.n, self.data.hoop)

    def read_direct(self, form, x, solution):
        solution.s = solution.s + viscous_stress_map(form.step.n, self.data.hoop) @ \
            x[form.layout["rate_stress"]]


class BinghamStress(_RateStress):
    """A viscous stress beside the yield cone, ``ViscousStress`` (eta_j, w_j): the term
    - sum_j dt w_j tau_j^2 / (2 eta_j) of the objective (a Bingham dissipation, as Zhang et
    al. 2017 add to (4.23)), so that at a flowing point R(sigma) = R(sigma_p) + eta_j
    gamma_dot_j. In the scaled variables ``- 1/2 sum_j kv_j |(a_j, b_j)|^2``.

    With C (an elastic material: Zhang et al.'s elastoviscoplastic clay) the compliance
    acts on the total stress sigma_p + sigma_v (:class:`Compliance`), and stationarity in
    (a_j, b_j) gives sigma_v = eta_j E^T Delta eps^p_j / dt, Delta eps^p = B du -
    C dsigma: R(sigma) = R(sigma_p) + eta_j gamma_dot^p_j, the overstress carried by the
    viscoplastic shear rate (both terms concave: the step stays convex)."""

    name = "bingham"

    def check(self, ops, criterion):
        if criterion is None:
            raise ValueError(f"{self.name}: only for a material with a yield criterion")

    def weights(self, step):
        """kv (n,): dt stress w_j / (eta_j length u_ref)."""
        d = self.data
        return step.dt * step.stress * d.weights / (d.eta * step.length * step.u_ref)

    def cvxpy(self, st):                          # - 1/2 sum kv_j |(a_j, b_j)|^2
        kv = self.weights(st.step)
        st.objective += -0.5 * cp.sum(cp.multiply(kv, cp.sum(cp.square(self.V), axis=1)))

    def blocks(self, form):
        kv = self.weights(form.step)
        form.quadratic("rate_stress", sp.diags(np.repeat(np.asarray(kv, dtype=float), self.m)))
        form.columns(self.stress_columns(form))


class MuIRate(_RateStress):
    """The rate part of mu(I) at frozen pressure, ``RateDissipation`` (c_j, tau_max_j, w_j):
    the complementary dissipation - sum_j dt w_j c_j (-s_j - ln(1 - s_j)) with tau_j <=
    tau_max_j s_j (one SOC) and t_j >= -ln(1 - s_j) (one exponential cone) per point, so that
    R(sigma) = mu(I_j) p_j. Its exponential cones are not self-dual: the direct assembly
    states the primal form whatever its form says."""

    name = "mu(I) rate"
    cones = frozenset({"soc", "exp"})
    self_dual = False

    def weights(self, step):
        """kw (n,) and tau_max (n,) in the scaled variables."""
        d = self.data
        return step.dt * d.weights * d.c / step.j_ref, d.tau_max / step.stress

    def cvxpy(self, st):                          # - sum kw_j (-s_j - ln(1 - s_j))
        n = st.step.n
        kw, tau_max = self.weights(st.step)
        sv, tv = cp.Variable(n), cp.Variable(n)
        st.objective += -cp.sum(cp.multiply(kw, tv - sv))
        st.constraints += [cp.SOC(cp.multiply(tau_max, sv), self.V, axis=1),  # tau <= tau_max s
                           cp.constraints.ExpCone(-tv, np.ones(n), 1 - sv)]   # t >= -ln(1 - s)

    def declare(self, form):
        super().declare(form)
        form.layout.add("rate_s", form.step.n)
        form.layout.add("rate_t", form.step.n)

    def blocks(self, form):
        n, layout = form.step.n, form.layout
        kw, tm = self.weights(form.step)
        form.columns(self.stress_columns(form))
        form.columns(sp.csr_matrix((form.step.n_u, 2 * n)))
        form.c[layout["rate_t"]] = kw            # + sum kw_j (t_j - s_j)
        form.c[layout["rate_s"]] = -np.asarray(kw)
        j, m, w = np.arange(n), self.m, self.m + 1   # SOC(w): (tau_max s, a, b[, c])
        s0, v0, t0 = layout["rate_s"].start, layout["rate_stress"].start, layout["rate_t"].start
        r = np.concatenate([w * j] + [w * j + 1 + k for k in range(m)])
        col = np.concatenate([s0 + j] + [v0 + m * j + k for k in range(m)])
        val = np.concatenate([-np.asarray(tm, dtype=float)] + [-np.ones(n)] * m)
        form.rows("after_yield", sp.csr_matrix((val, (r, col)), shape=(w * n, form.n_x)),
                  np.zeros(w * n), ("soc", w, n))   # ||(a_j, b_j)|| <= tau_max_j s_j
        r = np.concatenate([3 * j, 3 * j + 2])       # (-t_j, 1, 1 - s_j) in K_exp
        col = np.concatenate([t0 + j, s0 + j])
        form.rows("after_yield", sp.csr_matrix((np.ones(2 * n), (r, col)), shape=(3 * n, form.n_x)),
                  np.tile([0.0, 1.0, 1.0], n), ("exp", 3, n))


class ElasticSupport(StepTerm):
    """Springs on some dofs (an elastic foundation, Winkler's): nodal forces g_i = k_i du_i
    that resist the motion, stated as the springs' complementary energy
    - sum_i g_i^2 / (2 k_i) in the objective and + g_i in the internal forces of dof i, so
    that stationarity in g_i gives g_i = k_i du_i. ``dofs`` (m,), ``stiffness`` (m,) > 0 in
    force per length (per unit thickness in plane strain, per radian in axisymmetry).
    The increment's ``parts["spring_forces"]`` holds g."""

    name = "elastic support"
    static = True

    def __init__(self, dofs, stiffness):
        self.dofs = np.asarray(dofs, dtype=int).ravel()
        self.k = np.broadcast_to(np.asarray(stiffness, dtype=float), self.dofs.shape).copy()
        if np.unique(self.dofs).size != self.dofs.size:
            raise ValueError("ElasticSupport: dofs must not repeat")
        if not np.all(np.isfinite(self.k) & (self.k > 0)):
            raise ValueError("ElasticSupport: stiffness must be positive and finite")

    def check(self, ops, criterion):
        if self.dofs.size and (self.dofs.min() < 0 or self.dofs.max() >= ops.B.shape[1]):
            raise ValueError(f"ElasticSupport: dofs out of range [0, {ops.B.shape[1]})")

    def map(self, n_u):
        """E (n_u, m): the spring forces' nodal forces."""
        m = self.dofs.size
        return sp.csr_matrix((np.ones(m), (self.dofs, np.arange(m))), shape=(n_u, m))

    def weights(self, step):
        """The weight of each g_h^2 / 2 in units of j_ref (g in units of force)."""
        return step.force / (self.k * step.u_ref)

    def cvxpy(self, st):
        self.g = cp.Variable(self.dofs.size)                     # g / force
        st.internal = st.internal + self.map(st.step.n_u) @ self.g   # + E g
        st.objective += -0.5 * cp.sum(cp.multiply(self.weights(st.step), cp.square(self.g)))

    def read(self, st, solution):
        solution.parts["spring_forces"] = self.g.value

    def declare(self, form):
        form.layout.add("spring_forces", self.dofs.size)

    def blocks(self, form):
        form.quadratic("spring_forces", sp.diags(self.weights(form.step)))
        form.columns(self.map(form.step.n_u))

    def read_direct(self, form, x, solution):
        solution.parts["spring_forces"] = x[form.layout["spring_forces"]]

    def invert(self, solution, increment, step):
        g = solution.parts["spring_forces"] * step.force
        increment.reactions -= self.map(step.n_u) @ g
        increment.parts["spring_forces"] = g


class PrescribedWork(StepTerm):
    """The work of the reactions on the dofs with prescribed increments,
    + du_P^T (B_P^T sigma + A_P^T r' + [contact forces]_P - f'_P): it comes last, on the
    internal forces every other term has added to."""

    name = "prescribed work"
    static = True

    def cvxpy(self, st):
        step = st.step
        st.objective += step.u_P @ (st.internal[step.P] - step.f_h[step.P])

    def blocks(self, form):
        step = form.step
        form.c -= form.internal()[step.P].T @ step.u_P


def _pick(rows, cols, n_x):
    """The rows (len(rows), n_x) that pick the columns ``cols`` of x, one a row."""
    return sp.csr_matrix((np.ones(len(rows)), (np.arange(len(rows)), cols)), shape=(len(rows), n_x))


def step_terms(*, contacts=None, viscous=None):
    """The terms a caller adds to a step, in the order they are stated: the contacts (a
    ContactSet or None), then the rate stress (``viscous``: None, a ViscousStress or a
    RateDissipation). The step adds the compliance (its operators' C) before them and the
    work of the prescribed increments after them itself."""
    if viscous is not None and not isinstance(viscous, (ViscousStress, RateDissipation)):
        raise ValueError(f"viscous must be a ViscousStress or RateDissipation, got {viscous!r}")
    terms = []
    if contacts is not None:
        terms.append(Contact(contacts))
    if isinstance(viscous, ViscousStress):
        terms.append(BinghamStress(viscous))
    elif viscous is not None:
        terms.append(MuIRate(viscous))
    return tuple(terms)
