"""A script's own options declared as a table (:func:`pfem_skfem.harness.declare.own_options`)
and a case's keywords read back from them (:func:`~pfem_skfem.harness.declare.option_values`)."""
import argparse

import pytest

from pfem_skfem.harness.declare import option_values, own_options
from pfem_skfem.harness.options import nonnegative_int, opt


def test_own_options_are_spelt_with_hyphens_and_validated():
    parser = argparse.ArgumentParser()
    own_options(parser, B=opt(1.0, "footing width"),
                mc_width=opt(1.2, "half-width", why="over the mechanism's reach"),
                uniform=opt(2, "refinements", type=nonnegative_int),
                ny=opt([4, 8], "elements through the depth", nargs="+"))
    helps = {a.dest: (a.option_strings, a.help) for a in parser._actions}
    assert helps["mc_width"] == (["--mc-width"], "half-width; over the mechanism's reach")
    assert helps["B"] == (["--B"], "footing width")
    args = parser.parse_args(["--mc-width", "2", "--ny", "3", "5"])
    assert (args.B, args.mc_width, args.uniform, args.ny) == (1.0, 2.0, 2, [3, 5])
    for bad in (["--B", "0"], ["--uniform", "-1"]):       # positive_float by default
        with pytest.raises(SystemExit):
            parser.parse_args(bad)
    with pytest.raises(TypeError, match="--B|B needs"):
        own_options(argparse.ArgumentParser(), B=1.0)


def test_option_values_are_a_case_s_keywords():
    args = argparse.Namespace(nr=10, steps=400, floor=0.005)
    assert option_values(args, "nr", "steps", k_min="floor") == \
        dict(nr=10, steps=400, k_min=0.005)
    assert list(option_values(args, "steps", "nr")) == ["steps", "nr"]
