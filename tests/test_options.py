"""Bad options are usage errors before any work: exit code 2, a message naming the option.

Each verification script runs in-process (its ``main``) with every bad value its options'
validators are known to refuse (:func:`pfem_skfem.harness.options.bad_values`: below and
above the range, a fraction for a count, NaN, a name not among the choices), and with the
rows of ``CHECKS``: values each option's validator accepts but the script's ``check``
refuses (options that cannot go together). It must stop with ``SystemExit(2)`` within a
second, before any mesh is built or any problem solved, and its message on stderr must
name the option given. A validation that is missing lets the script start its work: the
alarm of ``ALARM`` seconds turns that into a failure. Every option that takes a value is
refused somewhere: ``test_every_option_can_be_refused`` fails for one with neither a
known validator nor a row in ``CHECKS``.

One spelling (CONTRIBUTING.md, ``options.OPTION_SPELLING``): the parsers of every script
and of ``pfem-skfem`` are walked; and an option of a shared group (``GROUPS``) is declared
through its group, not by hand, unless it names another thing (``OTHER_MEANINGS``; a
symbol that names another thing in many scripts, ``SYMBOLS_OF_SEVERAL``, is checked only
where the script uses its group).
"""
import argparse
import importlib
from pathlib import Path
import signal
import subprocess
import sys
import time

import pytest

from pfem_skfem import cli
from pfem_skfem.drivers import resumable
from pfem_skfem.harness import options, progress, report, store, sweeps

ROOT = Path(__file__).resolve().parents[1]
ALARM = 10                                    # seconds before a script that started work is stopped
LIMIT = 1.0                                   # seconds a usage error may take
SCRIPTS = sorted(p.stem for p in (ROOT / "verification").glob("*.py")
                 if not p.stem.startswith("_"))

# values the option's validator accepts and the script's check refuses: name -> [(argv, the
# option the message must name), ...]
CHECKS = {
    "bingham_slump": [(["--study-k", "0.03"], "--study-k")],
    "buried_pipe": [(["--depth", "20"], "--depth"), (["--dt", "0.01"], "--dt")],
    "accretionary_wedge": [(["--base-friction", "40"], "--base-friction"),
                           (["--h", "0.05"], "--h"), (["--passes", "2"], "--passes"),
                           (["--contact", "coulomb", "--stability-steps", "4"],
                            "--stability-steps")],
    "limit_bounds": [(["--B", "7"], "--B"), (["--cut-size", "1.5"], "--cut-size")],
    "effective_bounds": [(["--B", "13"], "--B"), (["--gamma", "9"], "--gamma"),
                         (["--phi", "26.6"], "--phi"),
                         # the upper bound locks towards the slope's angle: phi' <= 23 deg,
                         # and tan(phi') <= 1/2 - slope size / 4 on coarse meshes
                         (["--quick", "--phi", "25"], "--phi"), (["--phi", "23.5"], "--phi"),
                         (["--slope-size", "0.6"], "--slope-size"),
                         (["--y-w", "0.5", "0.3"], "--y-w"),
                         (["--Delta-h", "0.5", "0.3"], "--Delta-h")],
    "cantilever": [(["--t-end", "0.01", "--dt", "0.1"], "--steps"), (["--steps", "3"], "--steps"),
                   (["--d-form", "cone"], "--d-form")],
    "plastic_vibration": [(["--d-form", "cone"], "--d-form")],
    "consolidation": [(["--b", "50"], "--b"), (["--h-min", "10"], "--h-min")],
    "cylinder_soil": [(["--h-fine", "0.5", "--h-coarse", "0.3"], "--h-fine")],
    "granular_column_mu_i": [(["--mu-2", "0.1"], "--mu-2"), (["--rho-axi", "3"], "--rho-axi"),
                             (["--solver", "qoco", "--lag", "implicit"], "--solver"),
                             (["--lag", "friction"], "--lag"),
                             (["--density-factor", "2.5"], "--density-factor")],
    "granular_column_plane": [(["--contact", "zero-dilation", "--passes", "2"], "--passes")],
    "fluid_films": [(["--tau-y", "100"], "--tau-y"), (["--tau-y-stop", "10"], "--tau-y-stop"),
                    (["--ny", "8"], "--ny")],
    "dam_break": [(["--nx", "3"], "--nx")],
    "hydrostatics": [(["--rho-s", "900"], "--rho-s"), (["--b", "0.15"], "--b"),
                     (["--h-b", "0.3"], "--h-b")],
    "soil_and_water": [(["--nx", "2"], "--nx"), (["--mu-slope", "0.6"], "--mu-slope"),
                       (["--d", "1.2"], "--d")],
    "inclined_plane_flow": [(["--mu-2", "0.3"], "--mu-2"),
                            (["--theta-stop", "25"], "--theta-stop"),
                            (["--theta-fast", "30"], "--theta-fast"), (["--rho", "3000"], "--rho"),
                            (["--solver", "qoco", "--lag", "implicit"], "--solver"),
                            (["--lag", "friction"], "--lag"),
                            (["--quick", "--theta", "32.4"], "--theta"),
                            (["--theta-2", "32.5"], "--theta-2")],
    "inclined_rod": [(["--steps", "10", "10"], "--steps")],
    "rotating_bar": [(["--theta", "270"], "--theta"), (["--steps", "1", "2"], "--steps")],
    "silo_discharge": [(["--B", "10"], "--B")],
    "landslide_yangbaodi": [(["--h", "20"], "--h"),
                            (["--profile", "/no/such/profile.csv"], "--profile"),
                            (["--t-after", "0.01"], "--t-after"), (["--rest", "2"], "--rest")],
    "sliding_box": [(["--contact", "zero-dilation"], "--contact")],
    "sensitive_clay": [(["--sensitivities", "1"], "--sensitivities"),
                       (["--sensitivities", "1", "10", "3"], "--sensitivities"),
                       (["--sensitivities", "3", "10"], "--sensitivities"),
                       (["--ell", "0.3"], "--ell"),                     # nothing reads it
                       (["--regularisation", "nonlocal"], "--ell"),     # no length
                       (["--regularisation", "fracture-energy", "--ell", "0.1"], "--ell"),
                       (["--mesh-study", "6", "12", "--ell", "0.1"], "--ell"),  # < H / 6
                       (["--mesh-study", "12"], "--mesh-study"),
                       (["--mesh-study", "12", "6", "--ell", "0.25"], "--mesh-study"),
                       (["--mesh-study", "6", "12", "--ell", "0.25", "--study-regularisations",
                         "nonlocal"], "--study-regularisations"),      # nothing to compare
                       (["--study-sensitivities", "3"], "--study-sensitivities"),
                       (["--convergence", "0.2"], "--convergence")],
    "biaxial_band": [(["--r0", "0.6"], "--r0"), (["--c-r", "30"], "--c-r"),
                     (["--h", "0.3"], "--h"), (["--h", "0.1"], "--h"),   # h <= 0.08 W
                     (["--width", "0.9", "--h", "0.075"], "--h")],
    "softening_layer": [(["--c-r", "30"], "--c-r"), (["--rows", "200"], "--rows"),
                        (["--rows", "10"], "--rows"), (["--ell", "0.005"], "--ell"),
                        (["--gamma-95", "0.001"], "--gamma-95"),
                        (["--viscous-G", "10"], "--viscous-G"),
                        (["--L", "1.25"], "--t-end"), (["--eta", "4"], "--t-end"),
                        (["--max-drop", "0.04"], "--max-drop"), (["--dt", "0.009"], "--dt"),
                        (["--row-kinematics", "p2"], "--row-kinematics")],
    "softening_cylinder": [(["--c-r", "30"], "--c-r"), (["--H", "-2000"], "--H"),
                           (["--gamma-95", "0.001"], "--gamma-95")],
    "thick_cylinder": [(["--a", "2", "--b", "1"], "--a"), (["--phi", "45"], "--phi")],
    "trussed_frame": [(["--width", "7"], "--width")],
}
CHECK_CASES = [(name, argv, option) for name, rows in CHECKS.items() for argv, option in rows]

# options of a shared group's name declared by hand, for they name another thing
OTHER_MEANINGS = {
    ("fluid_films", "--h"): "the film's depth h, not a particle spacing",
    ("inclined_plane_flow", "--h"): "the layer's depth h, not a particle spacing",
}

# a group's symbol that other scripts use for another thing: declared through its group where
# the script uses that group (a softening run's --H), by hand elsewhere (a height H)
SYMBOLS_OF_SEVERAL = {"--H": "a height elsewhere (a slope's, a column's)",
                      "--k": "bingham_slump's yield numbers k = tau_y / (rho g H0)",
                      "--increments": "the footings' and the cylinder's load increments"}

# options of a bare float: any number is meant, or the script's check says what is not
ANY_NUMBER = {("accretionary_wedge", "--taper"): "a surface slope may dip either way",
              ("rotating_bar", "--theta"): "either way; CHECKS: within (0, 180] degrees"}

# free text: a path (checked when parsed: OUTPUT_PATHS), a file read by the script, a name
FREE = {"json", "outdir", "results_dir", "checkpoint_dir", "json_dir", "out", "extra", "example"}


def _parser(name):
    if name == "cli":
        return cli.build_parser()
    return importlib.import_module(f"verification.{name}").build_parser()


def _actions(parser, command=()):
    """(the subcommand's words, action) of every option of ``parser`` and its subcommands."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for word, sub in action.choices.items():
                yield from _actions(sub, (*command, word))
        elif action.option_strings:
            yield command, action


def _bad_argvs(action):
    """A command line for each value the option of ``action`` is known to refuse (an option
    of N values: the bad one first, then its defaults)."""
    rest = ([str(v) for v in action.default[1:]] if isinstance(action.nargs, int)
            and action.nargs > 1 else [])
    return [[action.option_strings[0], bad, *rest] for bad in options.bad_values(action)]


class StartedWork(Exception):
    """The script went on past its options."""


@pytest.fixture
def alarm():
    """Arms the alarm (called before each command line)."""
    def stop(signum, frame):
        raise StartedWork(f"still running after {ALARM} s: the bad option was not caught")
    old = signal.signal(signal.SIGALRM, stop)
    yield lambda: signal.alarm(ALARM)
    signal.alarm(0)
    signal.signal(signal.SIGALRM, old)


def _refused(main, argv, option, capsys, arm):
    """Why ``main(argv)`` is not a usage error naming ``option`` within LIMIT s, or None."""
    arm()
    t0 = time.perf_counter()
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    seconds = time.perf_counter() - t0
    signal.alarm(0)
    err = capsys.readouterr().err
    if exit_.value.code != 2:
        return f"{argv}: exit code {exit_.value.code}: {err}"
    message = err.strip().splitlines()[-1]
    if option not in message:
        return f"{argv}: the message does not name {option}: {message}"
    if seconds > LIMIT:
        return f"{argv}: {seconds:.2f} s before the usage error"
    return None


def test_every_script_is_walked():
    assert set(CHECKS) <= set(SCRIPTS) and len(SCRIPTS) >= 25


@pytest.mark.parametrize("name", SCRIPTS)
def test_every_bad_value_is_a_usage_error_naming_its_option(name, tmp_path, capsys, alarm):
    script = importlib.import_module(f"verification.{name}")
    tail = ["--quiet", "--no-figures", "--outdir", str(tmp_path)]
    problems = [_refused(script.main, [*argv, *tail], action.option_strings[0], capsys, alarm)
                for _, action in _actions(script.build_parser())
                for argv in _bad_argvs(action)]
    assert len(problems) >= 5 and [p for p in problems if p] == []


@pytest.mark.parametrize("name, argv, option", CHECK_CASES,
                         ids=[f"{n}:{' '.join(a)}" for n, a, _ in CHECK_CASES])
def test_options_that_cannot_go_together_are_a_usage_error(name, argv, option, tmp_path,
                                                           capsys, alarm):
    script = importlib.import_module(f"verification.{name}")
    argv = [*argv, "--quiet", "--no-figures", "--outdir", str(tmp_path)]
    assert _refused(script.main, argv, option, capsys, alarm) is None


def test_the_cli_refuses_every_bad_value(capsys, alarm):
    problems = [_refused(cli.main, [*command, *argv], action.option_strings[0], capsys, alarm)
                for command, action in _actions(cli.build_parser())
                for argv in _bad_argvs(action)]
    assert len(problems) >= 8 and [p for p in problems if p] == []


def test_the_script_exits_with_code_2_from_the_command_line():
    proc = subprocess.run([sys.executable, str(ROOT / "verification" / "strip_footing.py"),
                           "--elements", "0"], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    assert "argument --elements: must be a number of elements >= 4, got '0'" in proc.stderr


@pytest.mark.parametrize("name", [*SCRIPTS, "cli"])
def test_every_option_can_be_refused(name):
    """An option that takes a value has a validator whose refusals are known, or its script
    checks it (a row in CHECKS), or it is free text (FREE)."""
    checked = {option for _, option in CHECKS.get(name, [])}
    for _, action in _actions(_parser(name)):
        if action.nargs == 0 or action.dest in FREE:
            continue
        if action.type in (float, int):                 # "x" only: any number
            assert (name, action.option_strings[0]) in ANY_NUMBER, \
                f"{name}: {action.option_strings[0]} takes any number: give it a range"
        elif not options.bad_values(action):
            assert set(action.option_strings) & checked, \
                f"{name}: {action.option_strings[0]} accepts anything: give it a validator"


@pytest.mark.parametrize("name", [*SCRIPTS, "cli"])
def test_one_spelling(name):
    """Hyphens join the parts of an option's name (CONTRIBUTING.md), in every script and in
    the command line."""
    for _, action in _actions(_parser(name)):
        for text in action.option_strings:
            assert options.OPTION_SPELLING.fullmatch(text), f"{name}: {text}"


@pytest.mark.parametrize("name", SCRIPTS)
def test_a_group_option_is_declared_by_its_group(name):
    """``--rho``, ``--dt``, ``--k-min``, ... are declared once, in harness/options.py, with
    their validator; a script gives their defaults (and, where it must, its help)."""
    shared = {options.option_name(key): group for group, specs in options.GROUPS.items()
              if group != "adaptive" for key in specs}
    actions = [action for _, action in _actions(_parser(name))]
    used = {getattr(action, "option_group", None) for action in actions}
    for action in actions:
        for text in action.option_strings:
            if text in SYMBOLS_OF_SEVERAL and shared.get(text) not in used:
                continue                                # a height H, not a softening modulus
            if text in shared and (name, text) not in OTHER_MEANINGS:
                assert getattr(action, "option_group", None) == shared[text], \
                    f"{name}: {text} by hand: declare it with {shared[text]}_options"


def test_the_harness_knows_each_solver_s_cones():
    """The copy the parser checks --solver with (the harness imports no science module)."""
    from pfem_skfem.problems.conic import SOLVERS
    assert options.SOLVER_CONES == {name: backend.cones for name, backend in SOLVERS.items()}


def test_the_groups_declare_what_a_script_gives():
    parser = argparse.ArgumentParser()
    options.material_options(parser, units="Pa", rho=1000.0,
                             phi=options.opt([30.0], nargs="+", why="the thesis'"))
    options.pfem_options(parser, k_min=options.opt(0.005, dest="floor"))
    options.adaptive_options(parser, "mc", what="the footing", rounds=5)
    options.time_options(parser, save_every=0)
    args = parser.parse_args(["--phi", "20", "35", "--k-min", "0.01"])
    assert (args.rho, args.phi, args.floor, args.mc_rounds, args.save_every) == \
        (1000.0, [20.0, 35.0], 0.01, 5, 0)
    helps = {a.dest: a.help for a in parser._actions}
    assert helps["rho"] == "density [kg/m3]" and helps["phi"].endswith("; the thesis'")
    assert helps["mc_rounds"] == "adaptive rounds (the footing)"
    with pytest.raises(TypeError, match="no option psi"):
        options.material_options(parser, psi=0.0)


def test_the_saturated_and_softening_groups_declare_their_symbols():
    """``--M-inv``, ``--Tv-end``, ``--c-p``: the symbol's case kept, its parts hyphenated;
    the help's unit from ``units``; a script's validator (``opt(type=...)``) replaces the
    group's."""
    parser = argparse.ArgumentParser()
    options.saturated_options(parser, k=1e-8, gamma_w=9.81, M_inv=0.0, Tv_end=1.0)
    options.softening_options(parser, c_p=20.0, H=-20.0,
                              ell=options.opt(0.2, type=options.positive_float))
    args = parser.parse_args(["--M-inv", "1e-5", "--Tv-end", "2", "--c-p", "30"])
    assert (args.k, args.gamma_w, args.M_inv, args.Tv_end, args.c_p, args.H, args.ell) == \
        (1e-8, 9.81, 1e-5, 2.0, 30.0, -20.0, 0.2)
    helps = {a.dest: a.help for a in parser._actions}
    assert helps["gamma_w"] == "unit weight of water gamma_w [kN/m3]"
    assert helps["M_inv"] == "1/M, the storage (inverse Biot modulus) [1/kPa]"
    assert helps["c_p"] == "peak strength c_p [kPa]"
    for argv in (["--H", "5"], ["--ell", "0"], ["--k", "0"]):
        with pytest.raises(SystemExit):
            parser.parse_args(argv)


@pytest.mark.parametrize("group", sorted(options.GROUPS))
def test_each_group_option_refuses_what_it_says(group):
    """Each option of a group has known bad values (one at least), and its parser refuses
    each of them."""
    parser = argparse.ArgumentParser(exit_on_error=False)
    options._declare(parser, group, dict.fromkeys(options.GROUPS[group]))
    for action in parser._actions[1:]:
        bad = options.bad_values(action)
        assert bad, action.dest
        for text in bad:
            with pytest.raises(argparse.ArgumentError, match=action.option_strings[0]):
                parser.parse_args([action.option_strings[0], text])


@pytest.mark.parametrize("validator, good, bad", [
    (options.positive_int, ["1", "12"], ["0", "-3", "1.5", "x"]),
    (options.nonnegative_int, ["0", "7"], ["-1", "2.0"]),
    (options.positive_float, ["1e-3", "4"], ["0", "-1", "inf", "nan", "x"]),
    (options.nonnegative_float, ["0", "0.3"], ["-1e-9", "inf"]),
    (options.workers, ["1", "4"], ["0", "-1"]),
    (options.friction_angle, ["0", "0.1", "45", "89.9"], ["90", "95", "-5", "-0.1"]),   # TOML's
    (options.positive_angle("cot phi"), ["0.1", "45"], ["0", "90", "-5"]),
    (options.poisson_ratio, ["-0.9", "0", "0.499"], ["-1", "0.5", "0.6"]),
    (options.fraction, ["0", "0.5", "1"], ["-0.1", "1.1"]),
    (options.theta_weight, ["0.5", "1"], ["0.49", "1.01"]),
    (options.element_count, ["4", "1000"], ["3", "0"]),
])
def test_validators_accept_their_range_and_refuse_the_rest(validator, good, bad):
    import argparse
    for text in good:
        assert validator(text) == float(text)
    for text in bad:
        with pytest.raises(argparse.ArgumentTypeError, match=f"got '{text}'"):
            validator(text)


# -- issue 36: one rule for angles, output paths checked before the work, one line on ^C --
@pytest.mark.parametrize("name, argv, words", [
    ("strip_footing", ["--phi", "0"], ["cot phi", "Tresca"]),
    ("thick_cylinder", ["--phi", "0"], ["cot phi"]),
    ("granular_column_plane", ["--phi", "0"], ["without strength"]),
    ("silo_discharge", ["--phi", "0"], ["without strength", "--c"]),
    ("landslide_yangbaodi", ["--mu-deg", "0"], ["divides by mu"]),
    ("silo_discharge", ["--outlet-depth", "-0.3"], ["inside the hopper"]),
    ("silo_discharge", ["--outlet-depth", "-1"], ["inside the hopper"]),
    ("granular_column_plane", ["--nu", "0.3"], ["--E"]),
    ("granular_column_plane", ["--h0", "0.2", "--d0", "0.1"], ["--h0"]),
])
def test_a_script_says_why_it_refuses(name, argv, words, capsys):
    with pytest.raises(SystemExit) as exit_:
        importlib.import_module(f"verification.{name}").build_parser().parse_args(argv)
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert all(w in err for w in words), err


def test_phi_0_is_an_angle_where_the_physics_allows_it():
    """TOML's [0, 90): a cohesive mass of phi = 0, a smooth base (phi_s = 0)."""
    silo = importlib.import_module("verification.silo_discharge")
    assert silo.build_parser().parse_args(["--phi", "0", "--c", "5"]).phi == 0
    slide = importlib.import_module("verification.landslide_yangbaodi")
    assert slide.build_parser().parse_args(["--phi", "0", "--c", "50"]).phi == 0
    axi = importlib.import_module("verification.granular_column_axisymmetric")
    assert axi.build_parser().parse_args(["--base-study", "0"]).base_study == [0.0]


def test_the_plane_column_takes_a_size_in_metres():
    plane = importlib.import_module("verification.granular_column_plane")
    args = plane.build_parser().parse_args(["--a", "0.5", "2", "--h0", "0.1"])
    assert [plane._size(args, a) for a in args.a] == [{"d0": 0.2}, {"d0": 0.05}]
    args = plane.build_parser().parse_args([])
    assert plane._size(args, 2.0) == {} and args.nu == plane.NU    # the default: as before
    assert plane._size(plane.build_parser().parse_args(["--d0", "0.3"]), 2.0) == {"d0": 0.3}


@pytest.fixture
def afile(tmp_path):
    path = tmp_path / "afile"
    path.write_text("hi\n")
    return path


@pytest.mark.parametrize("name, option, target", [
    ("strip_footing", "--json", "{dir}"), ("strip_footing", "--json", "/proc/nope/x.json"),
    ("strip_footing", "--json", "{file}/x.json"), ("strip_footing", "--outdir", "{file}"),
    ("sliding_box", "--outdir", "{file}/sub"), ("cylinder_soil", "--json", "{dir}"),
    ("granular_column_plane", "--results-dir", "{file}"),
    ("silo_discharge", "--checkpoint-dir", "{file}"),
])
def test_an_unwritable_output_is_a_usage_error_before_the_work(name, option, target, afile,
                                                                tmp_path, capsys):
    path = target.format(dir=tmp_path, file=afile)
    with pytest.raises(SystemExit) as exit_:
        importlib.import_module(f"verification.{name}").build_parser().parse_args(
            ["--quick", option, path])
    assert exit_.value.code == 2
    assert f"argument {option}:" in capsys.readouterr().err


def test_a_writable_output_is_not_created_when_parsed(tmp_path):
    sb = importlib.import_module("verification.sliding_box")
    args = sb.build_parser().parse_args(["--json", str(tmp_path / "a" / "b.json"),
                                         "--outdir", str(tmp_path / "out")])
    assert args.json and not (tmp_path / "a").exists() and not (tmp_path / "out").exists()
    assert list(tmp_path.iterdir()) == []                       # the probe file is gone


@pytest.mark.parametrize("name", SCRIPTS)
def test_help_says_each_default_once(name):
    parser = importlib.import_module(f"verification.{name}").build_parser()
    formatter = parser._get_formatter()
    for action in parser._actions:
        text = (formatter._get_help_string(action) or "").replace("%(default)s", "")
        assert text.lower().count("default") <= 1, (action.dest, text)
    text = " ".join(parser.format_help().split())
    assert "(default: False)" not in text and "(default: None)" not in text


@pytest.mark.parametrize("name", [*SCRIPTS, "cli"])
def test_each_option_takes_its_default_given_back(name):
    """A default written out on the command line parses to itself: a validator that
    refuses its own default would refuse every value a user gives (--n-h 5 did); a
    default among the choices."""
    parser = _parser(name)
    for _, action in _actions(parser):
        if action.default is None or action.nargs == 0 or action.default is argparse.SUPPRESS:
            continue
        values = (action.default if isinstance(action.default, (list, tuple))
                  else [action.default])
        for value in values:
            if action.choices is not None:
                assert value in action.choices, (name, action.dest, value)
            if action.type is not None:
                assert action.type(str(value)) == value, (name, action.dest, value)


def test_quick_says_its_sizes_as_options():
    text = " ".join(importlib.import_module("verification.bingham_slump").build_parser()
                    .format_help().split())
    assert "--k 0.04 0.02, --n-h 3.5, --no-studies," in text


def test_help_keeps_the_stated_defaults():
    text = " ".join(importlib.import_module("verification.strip_footing").build_parser()
                    .format_help().split())
    assert "(default: the finest)" in text and "(default: results)" in text


def test_ctrl_c_in_a_script_is_one_line(capsys):
    def run(args):
        raise KeyboardInterrupt
    code = report.script_main(lambda: options.base_parser("x"), run, None, [])
    assert code == 130
    err = capsys.readouterr().err
    assert "Traceback" not in err and err.strip().endswith("interrupted")


def test_an_unreachable_scheduler_is_a_usage_error(capsys):
    def run(args):
        with sweeps._dask_client(1, "tcp://127.0.0.1:1"):
            pass
    from unittest import mock
    with mock.patch("distributed.Client", side_effect=OSError("timed out")):
        with pytest.raises(SystemExit) as exit_:
            report.script_main(lambda: options.base_parser("x"), run, None, [])
    assert exit_.value.code == 2 and "--scheduler tcp://127.0.0.1:1" in capsys.readouterr().err


@pytest.mark.parametrize("damage", [b"", b"not a pickle at all"])
def test_a_damaged_kept_result_names_its_file(tmp_path, damage, capsys):
    cases = [dict(value=2.0, reference=1.0)]
    path = sweeps.result_path(tmp_path, "cases", cases[0])
    path.write_bytes(damage)
    with pytest.raises(store.DamagedFileError, match=str(path.name)) as error:
        sweeps.run_cases(report.relative_error, cases, results_dir=tmp_path)
    assert "delete it" in str(error.value)

    def run(args):
        sweeps.run_cases(report.relative_error, cases, results_dir=tmp_path)
    assert report.script_main(lambda: options.base_parser("x"), run, None, []) == 1
    err = capsys.readouterr().err
    assert "Traceback" not in err and path.name in err


def test_a_damaged_checkpoint_names_its_files(tmp_path):
    path = tmp_path / "run-abc.npz"
    path.write_bytes(b"PK\x03\x04 truncated")
    path.with_name(path.stem + ".loop.pkl").write_bytes(b"")
    with pytest.raises(store.DamagedFileError, match="run-abc.npz.*delete both"):
        resumable.load_run(path)


def test_progress_bars_in_a_log_are_plain_lines(monkeypatch):
    """Stacked bars (a sweep's cases) move the cursor (ESC [A) on a terminal; in a log
    each redraw is a line of its own."""
    import io
    log = io.StringIO()
    monkeypatch.setattr(sys, "stderr", log)
    outer = progress.progress_bar(total=3, desc="cases", mininterval=0)
    inner = progress.progress_bar(total=2, desc="case 0", leave=False, mininterval=0)
    for bar in (inner, inner, outer):
        bar.update(1)
    inner.close()
    outer.close()
    text = log.getvalue()
    assert "\x1b[" not in text and "\r" not in text
    assert any(line.startswith("case 0:") and "2/2" in line for line in text.splitlines())


def test_a_bar_callback_counts_each_round_and_shows_the_latest(monkeypatch):
    import io
    from types import SimpleNamespace
    log = io.StringIO()
    monkeypatch.setattr(sys, "stderr", log)
    bar = progress.progress_bar(total=2, desc="rounds", unit="round", mininterval=0)
    shown = progress.bar_callback(bar, lambda r: f"{r.elements} el")
    for n in (100, 400):
        shown(SimpleNamespace(elements=n))
    assert bar.n == 2 and log.getvalue().splitlines()[-1].endswith("400 el]")
    progress.bar_callback(bar)(None)                          # no postfix: counts only
    assert bar.n == 3
    bar.close()
