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
from pfem_skfem import report as rep

ROOT = Path(__file__).resolve().parents[1]
ALARM = 10                                    # seconds before a script that started work is stopped
LIMIT = 1.0                                   # seconds a usage error may take

BAD = {
    "alpha_shape": [(["--h", "0"], "--h"), (["--alpha-step", "-0.1"], "--alpha-step"),
                    (["--radius", "x"], "--radius")],
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
                                     (["--base-study", "0"], "--base-study"),
                                     (["--mesh-study", "1"], "--mesh-study"),
                                     (["--courant", "0"], "--courant"),
                                     (["--volume-correction", "yes"], "--volume-correction")],
    "granular_column_mu_i": [(["--mu_2", "0.1"], "--mu_2"), (["--mu_s", "1.5"], "--mu_s"),
                             (["--nx", "1"], "--nx"), (["--nr", "1"], "--nr"),
                             (["--a", "0"], "--a"), (["--a_axi", "-1"], "--a_axi"),
                             (["--laws", "mu"], "--laws"), (["--phi", "95"], "--phi"),
                             (["--rho_axi", "3"], "--rho_axi"), (["--steps", "0"], "--steps"),
                             (["--h0_over_d", "0"], "--h0_over_d"),
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
    "inclined_plane_flow": [(["--theta", "95"], "--theta"), (["--ny", "0"], "--ny"),
                            (["--steps", "0"], "--steps"), (["--d", "0"], "--d"),
                            (["--mu_2", "0.3"], "--mu_2"), (["--theta_stop", "25"], "--theta_stop"),
                            (["--theta_fast", "30"], "--theta_fast"), (["--lag", "x"], "--lag"),
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
    (rep.positive_int, ["1", "12"], ["0", "-3", "1.5", "x"]),
    (rep.nonnegative_int, ["0", "7"], ["-1", "2.0"]),
    (rep.positive_float, ["1e-3", "4"], ["0", "-1", "inf", "nan", "x"]),
    (rep.nonnegative_float, ["0", "0.3"], ["-1e-9", "inf"]),
    (rep.workers, ["1", "4"], ["0", "-1"]),
    (rep.friction_angle, ["0.1", "45", "89.9"], ["0", "90", "95", "-5"]),
    (rep.poisson_ratio, ["-0.9", "0", "0.499"], ["-1", "0.5", "0.6"]),
    (rep.fraction, ["0", "0.5", "1"], ["-0.1", "1.1"]),
    (rep.theta_weight, ["0.5", "1"], ["0.49", "1.01"]),
    (rep.element_count, ["4", "1000"], ["3", "0"]),
])
def test_validators_accept_their_range_and_refuse_the_rest(validator, good, bad):
    import argparse
    for text in good:
        assert validator(text) == float(text)
    for text in bad:
        with pytest.raises(argparse.ArgumentTypeError, match=f"got '{text}'"):
            validator(text)
