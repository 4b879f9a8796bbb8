"""The trussed frame at another member depth (issue 56, the option audit).

``--width 2`` failed max_rel_diff_force 0.090 against 0.04 at the quick size. The conic truss
is right there: F as solved (equilibrium along the directions at the start of an increment)
errs by 1.85 %, as at the default; the gate reads F from the bar forces along the directions
at the end, which adds the bar forces at the loaded node turned through one increment's
rotation, the rotation gap (0.109 at w = 2, 0.040 at w = 4), a first-order term that grows
as the member depth shrinks. The tolerance is max(4 %, gap) (see the script's docstring).
"""
import numpy as np

from verification import trussed_frame


def test_a_slender_frame_passes_within_the_rotation_gap():
    args = trussed_frame.build_parser().parse_args(["--quick", "--width", "2", "--no-figures",
                                                    "--quiet"])
    report = trussed_frame.run(args)
    assert report.passed
    ex = report.extra
    F, solved, ref = (np.array(ex[k]) for k in ("F", "F_as_solved", "F_reference"))
    scale = np.abs(ref).max()
    gap = np.abs(F - solved).max() / scale
    diff = np.abs(F - ref).max() / scale
    assert ex["max_rel_diff_force_as_solved"] < 0.025          # the conic truss: as at w = 4
    assert 0.04 < diff < gap                                   # the gate: within the gap
