"""SCS as an engine of the direct assembly (MIT, PyPI): a first-order (ADMM) conic solver
for zero, non-negative, second-order and exponential cones.

SCS's form is Clarabel's, min 1/2 x^T P x + c^T x, A x + s = b, s in K, with the rows in its
cone order zero | non-negative | second-order | exponential (:func:`row_order`); its dual y
has Clarabel's sign (P x + c + A^T y = 0), put back in Clarabel's row order. First order:
its answer is as accurate as its tolerances, :data:`DEFAULTS` (1e-9, against its own 1e-4),
and it takes hundreds to thousands of iterations where Clarabel takes tens.
"""
from types import SimpleNamespace

import numpy as np
import scipy.sparse as sp

from ..conic import _absolute_measures
from .clarabel import check_finite

#: SCS's settings for the step (over its defaults): tolerances near Clarabel's
DEFAULTS = dict(eps_abs=1e-9, eps_rel=1e-9, max_iters=200_000, verbose=False)

#: SCS's status names read as Clarabel's
STATUS = {"solved": "Solved", "solved_inaccurate": "AlmostSolved",
          "solved (inaccurate - reached max_iters)": "AlmostSolved",
          "infeasible": "PrimalInfeasible", "unbounded": "DualInfeasible",
          "infeasible_inaccurate": "AlmostPrimalInfeasible",
          "unbounded_inaccurate": "AlmostDualInfeasible"}

#: the Clarabel cones SCS takes, in its order
KINDS = ("ZeroConeT", "NonnegativeConeT", "SecondOrderConeT", "ExponentialConeT")


def row_order(cones):
    """(perm, SCS's cone dict): the rows of ``cones`` (Clarabel's) in SCS's order."""
    groups, soc, start = {kind: [] for kind in KINDS}, [], 0
    for cone in cones:
        kind = type(cone).__name__
        if kind not in groups:
            raise ValueError(f"SCS here takes {', '.join(KINDS)}, not {kind}")
        dim = 3 if kind == "ExponentialConeT" else int(cone.dim)
        groups[kind].append(np.arange(start, start + dim))
        soc += [dim] if kind == "SecondOrderConeT" else []
        start += dim
    parts = [np.concatenate(g) if g else np.zeros(0, dtype=int) for g in groups.values()]
    return np.concatenate(parts), dict(z=parts[0].size, l=parts[1].size, q=soc,
                                       ep=parts[3].size // 3)


class SCSEngine:
    """SCS on Clarabel's data, rows reordered (module docstring)."""

    name = "scs"
    cones = frozenset({"zero", "nonneg", "soc", "exp"})
    defaults = DEFAULTS
    retries = ()

    def settings(self, changes):
        return {**self.defaults, **changes}

    def solve(self, P, c, A, b, cones, settings):
        import scs
        check_finite(P, c, A, b)
        perm, cone = row_order(cones)
        data = dict(P=sp.triu(P, format="csc"), A=sp.csc_matrix(sp.csr_matrix(A)[perm]),
                    b=np.asarray(b, dtype=float)[perm], c=np.asarray(c, dtype=float))
        sol = scs.SCS(data, cone, **settings).solve()
        info = sol["info"]
        z, s = np.empty(perm.size), np.empty(perm.size)
        z[perm], s[perm] = sol["y"], sol["s"]
        return SimpleNamespace(
            x=np.asarray(sol["x"]), z=z, s=s, status=STATUS.get(info["status"], info["status"]),
            iterations=int(info["iter"]), obj_val=float(info["pobj"]),
            measures=_absolute_measures("SCS", info["status"], info["res_pri"],
                                        info["res_dual"], info["gap"], info["pobj"]))
