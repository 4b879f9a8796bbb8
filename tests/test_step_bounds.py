"""The collapse load of a PFEM step's own geometry (pfem_skfem.drivers.step_bounds): the
footing's loaded facets as a punch, bracketed by the strict bounds."""
import numpy as np
import pytest

from pfem_skfem.drivers.pfem_loop import run as pfem_run
from pfem_skfem.drivers.step_bounds import loaded_facets, on_segments, step_bracket
from pfem_skfem.materials import Tresca
from pfem_skfem.problems.bounds import Support
from verification import penetration_rate as script

PRANDTL = 2 + np.pi           # a smooth strip footing on weightless Tresca soil, q / c


def first_step(V=100.0, steps=1):
    """The penetration scene (h = B / 8 about the footing) after ``steps`` steps: (args,
    the last step's StepResult)."""
    args = script.build_parser().parse_args(["--quick", "--engine", "pfem", "--h-pfem",
                                             "0.125", "--pfem-steps", "6"])
    state, scene, _ = script.pfem_scene(args, V)
    last = {}
    pfem_run(state, scene, steps, on_step=lambda s, rec, result: last.update(result=result))
    return args, last["result"]


def walls(args):
    W, D, e = args.W * args.B, args.D * args.B, 1e-3 * args.B
    return (Support(lambda x: (x[0] < e) | (x[0] > W - e), "x"),
            Support(lambda x: x[1] < -D + e, "xy"))


def test_segments_select_the_midpoints_on_them_and_nothing_beside():
    where = on_segments([[(0.0, 0.0), (1.0, 0.0)], [(1.0, 0.0), (1.0, 1.0)]], 1e-9)
    x = np.array([[0.5, 0.0], [1.0, 0.5], [0.5, 1e-6], [1.5, 0.0], [0.0, 0.0]]).T
    assert where(x).tolist() == [True, True, False, False, True]


def test_the_first_step_s_flat_geometry_brackets_prandtl():
    """At the first step the mesh is the particles at t = 0 (a flat surface) and the
    footing loads its whole width: the strict bounds of Tresca(c) bracket Prandtl's
    (2 + pi) c, on the step's mesh and on its refinement (closer: the bounds are strict on
    each mesh, and a refinement cannot widen them). A punch that took the symmetry line's
    facets too (a selection by position alone) gave 6.8 c."""
    args, result = first_step()
    segments = loaded_facets(result, 0)
    assert segments[:, :, 1].max() == pytest.approx(0.0, abs=1e-12)     # flat, at y = 0
    assert segments[:, :, 0].max() == pytest.approx(args.B / 2)         # the whole half
    c = 1.0
    to_q = 2 / args.B
    lo0, up0, n0 = step_bracket(result, 0, Tresca(c), supports=walls(args))
    lo1, up1, n1 = step_bracket(result, 0, Tresca(c), supports=walls(args), levels=1)
    assert n1 == 4 * n0
    assert lo0 <= lo1 * (1 + 1e-6) and up1 <= up0 * (1 + 1e-6)        # nested spaces
    assert lo1 * to_q <= PRANDTL <= up1 * to_q


def test_a_body_that_loads_nothing_is_refused():
    _, result = first_step()
    with pytest.raises(ValueError, match="body 7 pushed on no boundary node"):
        loaded_facets(result, 7)
