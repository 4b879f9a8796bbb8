"""Bad options are usage errors before any work: exit code 2, a message naming the option.

Each verification script runs in-process (its ``main``) with one bad value of each
kind it takes (a count, an angle, Poisson's ratio, a positive or non-negative number,
a worker count, inconsistent options); it must stop with ``SystemExit(2)`` within a
second, before any mesh is built or any problem solved, and its message on stderr must
name the option given. A validation that is missing lets the script start its work:
the alarm of ``ALARM`` seconds turns that into a failure.

Adding a script is one entry in ``BAD``: its name -> [(argv, the option the message
must name), ...]; ``test_every_script_has_bad_options`` fails until it is there.
"""
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

BAD = {
    "alpha_shape": [(["--h", "0"], "--h"), (["--alpha-step", "-0.1"], "--alpha-step"),
                    (["--radius", "x"], "--radius")],
    "bingham_slump": [(["--k", "0"], "--k"), (["--k", "1.5"], "--k"), (["--mu", "0"], "--mu"),
                      (["--n-h", "1"], "--n-h"), (["--cfl", "3"], "--cfl"),
                      (["--mu-f", "-1"], "--mu-f"), (["--study-k", "0.03"], "--study-k"),
                      (["--materials", "sand"], "--materials"),
                      (["--alpha-tol", "0"], "--alpha-tol"),
                      (["--stretch-tol", "1.5"], "--stretch-tol"),
                      (["--bound-rounds", "0"], "--bound-rounds"),
                      (["--bound-max-elements", "2.5"], "--bound-max-elements"),
                      (["--bound-target-gap", "-1"], "--bound-target-gap"),
                      (["--bound-size", "0"], "--bound-size")],
    "buried_pipe": [(["--elements", "0"], "--elements"), (["--mu", "-0.1"], "--mu"),
                    (["--r", "-1"], "--r"), (["--dt", "0"], "--dt"), (["--g", "-9.8"], "--g"),
                    (["--elements", "3"], "--elements"), (["--depth", "20"], "--depth")],
    "accretionary_wedge": [(["--phi", "95"], "--phi"), (["--steps", "0"], "--steps"),
                           (["--mu-wall", "-0.1"], "--mu-wall"),
                           (["--base-friction", "40"], "--base-friction"), (["--h", "0.05"], "--h"),
                           (["--stability-steps", "1"], "--stability-steps"),
                           (["--save-every", "-1"], "--save-every"),
                           (["--passes", "2"], "--passes"),
                           (["--increment-study", "0"], "--increment-study"),
                           (["--workers", "0"], "--workers"),
                           (["--scheduler", "x:0"], "--scheduler")],
    "limit_bounds": [(["--elements", "0"], "--elements"), (["--phi", "0"], "--phi"),
                     (["--theta", "0"], "--theta"), (["--target-gap", "-1"], "--target-gap"),
                     (["--uniform", "-1"], "--uniform"), (["--slope-phi", "95"], "--slope-phi"),
                     (["--B", "7"], "--B"), (["--cut-size", "1.5"], "--cut-size")],
    "cantilever": [(["--nx", "0"], "--nx"), (["--nu", "0.5"], "--nu"),
                   (["--theta1", "0.3"], "--theta1"), (["--steps", "-1"], "--steps"),
                   (["--dt", "0"], "--dt"), (["--g", "-1"], "--g"),
                   (["--t-end", "0.01", "--dt", "0.1", "--steps", "1.5"], "--steps")],
    "circular_footing": [(["--elements", "0"], "--elements"), (["--phi", "95"], "--phi"),
                         (["--nu", "0.6"], "--nu"), (["--increments", "0"], "--increments"),
                         (["--tol", "-1"], "--tol")],
    "cylinder_soil": [(["--mu", "-1"], "--mu"), (["--du", "0"], "--du"),
                      (["--theta1", "0.3"], "--theta1"), (["--c", "0"], "--c"),
                      (["--h-fine", "0.5", "--h-coarse", "0.3"], "--h-fine"),
                      (["--save-every", "-1"], "--save-every"),
                      (["--dt-study", "0"], "--dt-study"), (["--mesh-study", "-1"], "--mesh-study"),
                      (["--workers", "0"], "--workers"), (["--scheduler", "x:0"], "--scheduler")],
    "granular_column_axisymmetric": [(["--phi", "95"], "--phi"),
                                     (["--scheduler", "x:0"], "--scheduler"),
                                     (["--steps", "0"], "--steps"),
                                     (["--nr", "1"], "--nr"), (["--a", "0"], "--a"),
                                     (["--settle", "-1"], "--settle"),
                                     (["--workers", "0"], "--workers"),
                                     (["--base-study", "90"], "--base-study"),
                                     (["--mesh-study", "1"], "--mesh-study"),
                                     (["--courant", "0"], "--courant"),
                                     (["--volume-correction", "yes"], "--volume-correction")],
    "granular_column_mu_i": [(["--mu-2", "0.1"], "--mu-2"), (["--mu-s", "1.5"], "--mu-s"),
                             (["--nx", "1"], "--nx"), (["--nr", "1"], "--nr"),
                             (["--a", "0"], "--a"), (["--a-axi", "-1"], "--a-axi"),
                             (["--laws", "mu"], "--laws"), (["--phi", "95"], "--phi"),
                             (["--rho-axi", "3"], "--rho-axi"), (["--steps", "0"], "--steps"),
                             (["--h0-over-d", "0"], "--h0-over-d"),
                             (["--settle", "-1"], "--settle"), (["--workers", "0"], "--workers"),
                             (["--scheduler", "x:0"], "--scheduler"),
                             (["--volume-correction", "yes"], "--volume-correction")],
    "granular_column_plane": [(["--phi", "95"], "--phi"), (["--scheduler", "x:0"], "--scheduler"),
                              (["--contact", "zero-dilation", "--passes", "2"], "--passes"),
                              (["--steps", "0"], "--steps"),
                              (["--settle", "-1"], "--settle"), (["--workers", "0"], "--workers"),
                              (["--nx", "1"], "--nx"), (["--nu", "-1"], "--nu"),
                              (["--mu", "-0.5"], "--mu"), (["--save-every", "-1"], "--save-every"),
                              (["--a", "0"], "--a"), (["--time-steps", "0"], "--time-steps")],
    "fluid_films": [(["--theta", "95"], "--theta"), (["--mu", "-1"], "--mu"),
                    (["--tau-y", "-1"], "--tau-y"), (["--ny", "0"], "--ny"),
                    (["--tau-y", "100"], "--tau-y"), (["--tau-y-stop", "10"], "--tau-y-stop"),
                    (["--ny", "8"], "--ny")],
    "dam_break": [(["--mu", "-1"], "--mu"), (["--nx", "0"], "--nx"), (["--nx", "3"], "--nx"),
                  (["--n2", "0"], "--n2"), (["--steps", "0"], "--steps"),
                  (["--save-every", "-1"], "--save-every")],
    "hydrostatics": [(["--rho-s", "0"], "--rho-s"), (["--rho-s", "900"], "--rho-s"),
                     (["--n", "0"], "--n"), (["--b", "0.15"], "--b"), (["--h-b", "0.3"], "--h-b"),
                     (["--c", "-1"], "--c"), (["--dt", "0"], "--dt")],
    "soil_and_water": [(["--phi", "95"], "--phi"), (["--nx", "0"], "--nx"), (["--nx", "2"], "--nx"),
                       (["--a", "0"], "--a"), (["--tol-area", "-1"], "--tol-area"),
                       (["--beta", "90"], "--beta"), (["--mu-slope", "0.6"], "--mu-slope"),
                       (["--d", "1.2"], "--d"), (["--h", "0"], "--h"), (["--c", "-1"], "--c"),
                       (["--keep-area", "maybe"], "--keep-area"),
                       (["--mu-floor", "-0.1"], "--mu-floor"), (["--thin", "1"], "--thin"),
                       (["--tol-speed", "0"], "--tol-speed"),
                       (["--tol-refused", "2"], "--tol-refused"),
                       (["--spread-mass", "maybe"], "--spread-mass"),
                       (["--alpha-advected", "-1"], "--alpha-advected"),
                       (["--tol-energy", "0"], "--tol-energy"),
                       (["--refine-interior", "-1"], "--refine-interior"),
                       (["--keep-surface", "maybe"], "--keep-surface"),
                       (["--keep-area-step", "-0.1"], "--keep-area-step")],
    "inclined_plane_flow": [(["--theta", "95"], "--theta"), (["--ny", "0"], "--ny"),
                            (["--steps", "0"], "--steps"), (["--d", "0"], "--d"),
                            (["--mu-2", "0.3"], "--mu-2"), (["--theta-stop", "25"], "--theta-stop"),
                            (["--theta-fast", "30"], "--theta-fast"), (["--lag", "x"], "--lag"),
                            (["--rho", "3000"], "--rho")],
    "inclined_rod": [(["--steps", "0", "10"], "--steps"), (["--steps", "10", "10"], "--steps"),
                     (["--E", "0"], "--E"), (["--tol", "-1"], "--tol")],
    "plastic_vibration": [(["--steps", "0"], "--steps"), (["--nu", "0.6"], "--nu"),
                          (["--theta2", "1.5"], "--theta2"), (["--ny", "-2"], "--ny")],
    "rotating_bar": [(["--steps", "0", "8"], "--steps"), (["--theta", "270"], "--theta"),
                     (["--steps", "1", "2"], "--steps"), (["--L0", "0"], "--L0")],
    "silo_discharge": [(["--phi", "95"], "--phi"), (["--scheduler", "x:0"], "--scheduler"),
                       (["--h", "0"], "--h"), (["--c", "-1"], "--c"),
                       (["--workers", "0"], "--workers"), (["--passes", "0"], "--passes"),
                       (["--save-every", "-1"], "--save-every"),
                       (["--dt-study", "0"], "--dt-study"), (["--r2-min", "1.5"], "--r2-min"),
                       (["--B", "10"], "--B")],
    "landslide_yangbaodi": [(["--phi", "95"], "--phi"), (["--h", "0"], "--h"),
                            (["--h", "20"], "--h"), (["--profile", "/no/such/profile.csv"], "--profile"),
                            (["--mu-study", "0"], "--mu-study"), (["--rho-study", "-1"], "--rho-study"),
                            (["--theta1", "0.3"], "--theta1"), (["--workers", "0"], "--workers"),
                            (["--t-after", "0.01"], "--t-after"), (["--rest", "2"], "--rest"),
                            (["--hold", "top"], "--hold"), (["--save-every", "-1"], "--save-every"),
                            (["--volume-correction", "1"], "--volume-correction")],
    "sliding_box": [(["--steps", "0"], "--steps"), (["--theta", "0"], "--theta"),
                    (["--mu", "0"], "--mu"), (["--contact", "zero-dilation"], "--contact")],
    "strip_footing": [(["--elements", "0"], "--elements"), (["--elements", "-5"], "--elements"),
                      (["--phi", "95"], "--phi"), (["--nu", "0.6"], "--nu"),
                      (["--increments", "0"], "--increments"),
                      (["--mc-increments", "0"], "--mc-increments"),
                      (["--tol-tresca", "-0.1"], "--tol-tresca"), (["--c", "nan"], "--c"),
                      (["--elements", "1"], "--elements"), (["--mc-elements", "2"], "--mc-elements")],
    "thick_cylinder": [(["--phi", "90"], "--phi"), (["--nu", "0.5"], "--nu"),
                       (["--nr", "0"], "--nr"), (["--a", "2", "--b", "1"], "--a"),
                       (["--increments", "0"], "--increments"), (["--phi", "45"], "--phi")],
    "trussed_frame": [(["--steps", "0"], "--steps"), (["--uV", "-1"], "--uV"),
                      (["--tol", "-1"], "--tol"), (["--width", "7"], "--width")],
}
CASES = [(name, argv, option) for name, rows in BAD.items() for argv, option in rows]


class StartedWork(Exception):
    """The script went on past its options."""


@pytest.fixture
def alarm():
    def stop(signum, frame):
        raise StartedWork(f"still running after {ALARM} s: the bad option was not caught")
    old = signal.signal(signal.SIGALRM, stop)
    signal.alarm(ALARM)
    yield
    signal.alarm(0)
    signal.signal(signal.SIGALRM, old)


def test_every_script_has_bad_options():
    scripts = {p.stem for p in (ROOT / "verification").glob("*.py") if not p.stem.startswith("_")}
    assert scripts - set(BAD) == set(), "add the scripts' bad options to BAD"
    assert set(BAD) - scripts == set(), "BAD names scripts that are not in verification/"


@pytest.mark.parametrize("name, argv, option", CASES,
                         ids=[f"{n}:{' '.join(a)}" for n, a, _ in CASES])
def test_a_bad_option_is_a_usage_error_naming_it(name, argv, option, tmp_path, capsys, alarm):
    script = importlib.import_module(f"verification.{name}")
    t0 = time.perf_counter()
    with pytest.raises(SystemExit) as exit_:
        script.main([*argv, "--quiet", "--no-figures", "--outdir", str(tmp_path)])
    seconds = time.perf_counter() - t0
    err = capsys.readouterr().err
    assert exit_.value.code == 2, err
    message = err.strip().splitlines()[-1]
    assert option in message, f"the message does not name {option}: {message}"
    assert seconds < LIMIT, f"{seconds:.2f} s before the usage error"


def test_the_script_exits_with_code_2_from_the_command_line():
    proc = subprocess.run([sys.executable, str(ROOT / "verification" / "strip_footing.py"),
                           "--elements", "0"], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    assert "argument --elements: must be a number of elements >= 4, got '0'" in proc.stderr


@pytest.mark.parametrize("argv, option", [
    (["verify", "--jobs", "0"], "--jobs"),
    (["run", "x.toml", "--steps", "0"], "--steps"),
    (["run", "x.toml", "--every", "-1"], "--every"),
    (["run", "x.toml", "--checkpoint-every", "-2"], "--checkpoint-every"),
])
def test_the_cli_checks_its_options(argv, option, capsys):
    with pytest.raises(SystemExit) as exit_:
        cli.main(argv)
    assert exit_.value.code == 2
    assert option in capsys.readouterr().err.strip().splitlines()[-1]


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


@pytest.mark.parametrize("name", sorted(BAD))
def test_help_says_each_default_once(name):
    parser = importlib.import_module(f"verification.{name}").build_parser()
    formatter = parser._get_formatter()
    for action in parser._actions:
        text = (formatter._get_help_string(action) or "").replace("%(default)s", "")
        assert text.lower().count("default") <= 1, (action.dest, text)
    text = " ".join(parser.format_help().split())
    assert "(default: False)" not in text and "(default: None)" not in text


@pytest.mark.parametrize("name", sorted(BAD))
def test_each_option_takes_its_default_given_back(name):
    """A default written out on the command line parses to itself: a validator that
    refuses its own default would refuse every value a user gives (--n-h 5 did)."""
    parser = importlib.import_module(f"verification.{name}").build_parser()
    for action in parser._actions:
        if action.type is None or action.default is None or isinstance(action.default, str):
            continue
        for value in (action.default if isinstance(action.default, (list, tuple))
                      else [action.default]):
            assert action.type(str(value)) == value, (action.dest, value)


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
