"""A script's own options declared as a table (:func:`pfem_skfem.harness.declare.own_options`)
and a case's keywords read back from them (:func:`~pfem_skfem.harness.declare.option_values`,
:func:`~pfem_skfem.harness.declare.keywords_of`); a row (validator, default, help), a switch
and a list of choices each the option argparse would get from its ``add_argument``."""
import argparse

import pytest

from pfem_skfem.harness.declare import option_values, own_options
from pfem_skfem.harness.options import (in_range, nonnegative_int, opt, positive_float,
                                        positive_int)


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


def table_parser():
    p = argparse.ArgumentParser()
    return own_options(
        p, mu_f=(positive_float, 5.0, "friction coefficient of the floor"),
        contact=(("coulomb", "smooth"), "coulomb", "contact rule"),
        studies=(bool, True, "the twins"), keep_runs=(bool, False, "pickle the runs"),
        k=opt([0.04, 0.02], "yield numbers", type=in_range(0, 1), nargs="+"),
        block=opt([0.4, 0.2], "block [m]", type=positive_float, nargs=2,
                  metavar=("LENGTH", "THICKNESS")),
        t_hold=opt(10.0, "held phase [s]", why="builds the stress", type=positive_float,
                   dest="hold_time"),
        steps=(positive_int, 80, "steps"))


def test_each_row_is_an_option_of_its_name_default_validator_and_help():
    p = table_parser()
    actions = {a.dest: a for a in p._actions if a.option_strings}
    assert [a.option_strings for a in actions.values()][1:] == [
        ["--mu-f"], ["--contact"], ["--studies", "--no-studies"], ["--keep-runs"], ["--k"],
        ["--block"], ["--t-hold"], ["--steps"]]
    assert actions["mu_f"].type is positive_float and actions["mu_f"].default == 5.0
    assert actions["mu_f"].help == "friction coefficient of the floor"
    assert actions["contact"].choices == ("coulomb", "smooth")
    assert actions["hold_time"].help == "held phase [s]; builds the stress"
    args = p.parse_args([])
    assert (args.studies, args.keep_runs, args.k, args.block, args.hold_time, args.steps) == (
        True, False, [0.04, 0.02], [0.4, 0.2], 10.0, 80)
    args = p.parse_args(["--no-studies", "--keep-runs", "--k", "0.1", "--block", "1", "2",
                         "--t-hold", "3", "--mu-f", "0.5"])
    assert (args.studies, args.keep_runs, args.k, args.block, args.hold_time, args.mu_f) == (
        False, True, [0.1], [1.0, 2.0], 3.0, 0.5)


@pytest.mark.parametrize("argv", [["--mu-f", "0"], ["--contact", "rough"], ["--k", "2"],
                                  ["--steps", "1.5"]])
def test_a_row_refuses_what_its_validator_refuses(argv, capsys):
    with pytest.raises(SystemExit) as exit_:
        table_parser().parse_args(argv)
    assert exit_.value.code == 2 and argv[0] in capsys.readouterr().err


def test_the_keywords_of_a_case_are_its_options_and_what_is_given():
    from types import SimpleNamespace

    from pfem_skfem.harness.declare import keywords_of

    def run_case(a, n2, *, rho, mu=1e-3, label, outdir=None, **more):
        return a, n2, rho, mu, label, outdir, more

    args = SimpleNamespace(a=0.05, n2=2.0, rho=1000.0, mu=0.0, outdir="results", nx=16)
    keywords = keywords_of(run_case, args, label="base", outdir=None)
    assert keywords == dict(a=0.05, n2=2.0, rho=1000.0, mu=0.0, outdir=None, label="base")
    assert run_case(**keywords) == (0.05, 2.0, 1000.0, 0.0, "base", None, {})


def test_the_checkpoints_are_a_case_s_keywords_only_where_asked():
    from pfem_skfem.harness.declare import checkpoint_keywords
    from pfem_skfem.harness.options import checkpoint_options

    parser = checkpoint_options(argparse.ArgumentParser(), "column")
    assert checkpoint_keywords(parser.parse_args([])) == {}      # kept results keep their names
    args = parser.parse_args(["--checkpoint-dir", "runs/x", "--checkpoint-every", "5"])
    assert checkpoint_keywords(args) == {"checkpoint_dir": "runs/x", "checkpoint_every": 5}
    assert checkpoint_keywords(argparse.Namespace()) == {}
