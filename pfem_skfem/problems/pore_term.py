"""The pore pressure as a term of the dynamic step (4.23) (issue 54).

The terms of the consolidation step (C.1) (:mod:`pfem_skfem.problems.consolidation`) added
to (4.23) as one :class:`~pfem_skfem.problems.step_terms.StepTerm`: the pore pressure p
(continuous P1) joins the variables, - alpha B^T (p I) the internal forces (the total
stress sigma' - alpha p I in equilibrium), and the objective gains

    ``- (dt/2) int k/gamma_w |grad p - rho_w g|^2 dV - int (p - p_n)^2 / 2M dV``
    ``+ dt int q_bar p dS``,

with p = p_bar on the drained dofs. The multiplier of equilibrium is du in (4.23) as in
(3.45), so stationarity in p is again the discrete mass balance of backward Euler; the
term therefore asks theta1 = 1 (with theta1 < 1 the step's equilibrium is weighted between
t_n and t_{n+1}, the mass balance is not: refused). Scaled as the step is
(:class:`~pfem_skfem.problems.step_scaling.ScaledStep`): p in units of ``step.stress``, its
forces in ``step.force``, the objective in ``step.j_ref``.
"""
import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from .consolidation import Hydraulic, check_hydraulic
from .step_terms import StepTerm


class PorePressureTerm(StepTerm):
    """The pore pressure of a saturated soil in (4.23) (module docstring).

    Parameters
    ----------
    soil : :class:`~pfem_skfem.problems.consolidation.SaturatedSoil` (its skeleton's cone is
        the step's criterion: give the same one to the step).
    pressure : the P1 field (:func:`~pfem_skfem.discretisation.pressure.pressure_field`).
    p_n : (n_p,) the pore pressures at t_n.
    hydraulic : :class:`~pfem_skfem.problems.consolidation.Hydraulic` or None (impermeable).

    The increment's ``parts["pore_pressure"]`` holds p at t_{n+1}; its reactions are those of
    the total stress.
    """

    name = "pore pressure"
    cones = frozenset({"zero"})
    # its block of P (Darcy's D^T D, singular without storage: p is fixed only by the
    # drained rows) is not invertible, which the dual form needs: that form states the primal
    self_dual = False

    def __init__(self, soil, pressure, p_n, hydraulic=None):
        self.soil, self.pressure = soil, pressure
        self.p_n = np.asarray(p_n, dtype=float)
        if self.p_n.shape != (pressure.n_p,) or not np.all(np.isfinite(self.p_n)):
            raise ValueError(f"PorePressureTerm: p_n must be a finite vector ({pressure.n_p},)")
        self.hydraulic = hydraulic or Hydraulic()
        self.drained, self.p_bar = check_hydraulic(self.hydraulic, pressure)

    def check(self, ops, criterion):
        if ops.theta.theta1 != 1.0:
            raise ValueError(f"PorePressureTerm: the pore pressure is backward Euler: it needs "
                             f"theta1 = 1, got {ops.theta.theta1!r}")
        if self.pressure.to_points.shape[0] != ops.B.shape[0] // 4:
            raise ValueError("PorePressureTerm: the pressure field is not on the step's mesh")

    def coupling(self, step):
        """- alpha B^T (p I) in the scaled units: (n_u, n_p), force per unit of p / stress."""
        return -self.soil.alpha * (step.Bh.T @ self.pressure.total_stress_map()).tocsr()

    def weights(self, step):
        """(D, d, S, w): the Darcy term ``1/2 |D p - d|^2``, the storage 1/2 (p - p_n)^T S (p - p_n)
        and the inflow w^T p, p in units of the stress, the objective in j_ref."""
        soil, field, dt = self.soil, self.pressure, step.dt
        per_stress = step.stress ** 2 / step.j_ref
        root = np.repeat(np.sqrt(dt * soil.k_over_gamma_w * field.cell_volume * per_stress), 2)
        D = sp.diags(root) @ field.gradient
        d = root * np.tile(np.asarray(soil.water_weight, dtype=float) / step.stress,
                           field.cell_volume.size)
        S = field.storage * (per_stress / soil.M)
        inflow = self.hydraulic.inflow
        w = (np.zeros(field.n_p) if inflow is None
             else dt * np.asarray(inflow) * step.stress / step.j_ref)
        return D.tocsr(), d, S.tocsr(), w

    # -- the cvxpy statement -------------------------------------------------------------
    def cvxpy(self, st):
        step = st.step
        D, d, S, w = self.weights(step)
        self.p = cp.Variable(self.pressure.n_p)                 # p_{n+1} / stress
        p_n = self.p_n / step.stress
        st.internal = st.internal + self.coupling(step) @ self.p     # - alpha B^T (p I)
        st.objective += (-0.5 * cp.sum_squares(D @ self.p - d)          # Darcy's dissipation
                         - 0.5 * cp.quad_form(self.p - p_n, cp.psd_wrap(S))   # storage
                         + w @ self.p)                                   # dt q_bar p
        if self.drained.size:
            st.constraints.append(self.p[self.drained] == self.p_bar / step.stress)  # p = p_bar

    def read(self, st, solution):
        solution.parts["pore_pressure"] = self.p.value

    # -- the direct assembly -------------------------------------------------------------
    def declare(self, form):
        form.layout.add("pore_pressure", self.pressure.n_p)

    def blocks(self, form):
        step, block = form.step, form.layout["pore_pressure"]
        D, d, S, w = self.weights(step)
        p_n = self.p_n / step.stress
        form.quadratic("pore_pressure", (D.T @ D + S).tocsr())     # Darcy + storage
        form.c[block] += -(D.T @ d) - S @ p_n - w
        form.columns(self.coupling(step))
        m = self.drained.size
        if m:
            pick = sp.csr_matrix((np.ones(m), (np.arange(m), block.start + self.drained)),
                                 shape=(m, form.n_x))
            form.rows("equality", pick, self.p_bar / step.stress, "zero")   # p = p_bar

    def read_direct(self, form, x, solution):
        solution.parts["pore_pressure"] = x[form.layout["pore_pressure"]]

    # -- back to physical units ----------------------------------------------------------
    def invert(self, solution, increment, step):
        p = solution.parts["pore_pressure"] * step.stress
        increment.parts["pore_pressure"] = p
        # the supports carry the total stress: - alpha B^T (p I) joins the reactions
        increment.reactions -= self.soil.alpha * (
            step.ops.B.T @ (self.pressure.total_stress_map() @ p))
