"""The theta-method in time (4.3)-(4.11): weights, rho~, the load and velocity updates."""
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class ThetaMethod:
    """The theta-method of (4.4): theta1 weights the stresses (and loads), theta2 the velocities.

    theta1 = theta2 = 1/2 is Newmark's average acceleration scheme (no numerical
    damping); theta1 = 1 damps. Only the implicit, unconditionally stable range
    1/2 <= theta <= 1 is accepted.
    """

    dt: float
    theta1: float = 1.0
    theta2: float = 1.0

    def __post_init__(self):
        if not np.isfinite(self.dt) or self.dt <= 0:
            raise ValueError(f"dt (time step) must be positive, got {self.dt!r}")
        for name in ("theta1", "theta2"):
            value = getattr(self, name)
            if not np.isfinite(value) or not 0.5 <= value <= 1.0:
                raise ValueError(f"{name} must lie in [1/2, 1] (implicit, unconditionally "
                                 f"stable theta-method), got {value!r}")

    def rho_tilde(self, rho):
        """rho~ = rho / (theta1 theta2) (4.6)."""
        return np.asarray(rho, dtype=float) / (self.theta1 * self.theta2)

    def load(self, f_n, f_next):
        """External load of the step, theta1 f_{n+1} + (1 - theta1) f_n.

        The thesis weights the stresses in (4.4) and (4.8) by theta1; the loads are
        weighted alike (for a load linear in time this is its value at t_n + theta1 dt),
        which keeps theta1 = theta2 = 1/2 the energy-conserving trapezoidal rule.
        """
        return self.theta1 * np.asarray(f_next, dtype=float) + \
            (1 - self.theta1) * np.asarray(f_n, dtype=float)

    def equilibrium_rhs(self, f_n, f_next, B, sigma_n):
        """f' = f_theta / theta1 - (1 - theta1)/theta1 B^T sigma_n: the b~, t~ of (4.6), (4.10)
        in discrete form, without the inertia term rho~ v_n / dt (carried by r = rho~ v_n/dt + r')."""
        s_n = np.asarray(sigma_n, dtype=float).ravel()
        return (self.load(f_n, f_next) - (1 - self.theta1) * (B.T @ s_n)) / self.theta1

    def velocity(self, du, v_n):
        """v_{n+1} = (du/dt - (1 - theta2) v_n) / theta2 (4.7)."""
        return (np.asarray(du) / self.dt - (1 - self.theta2) * np.asarray(v_n)) / self.theta2
