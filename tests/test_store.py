"""The names kept runs are found by (issue 37): pinned before the harness moved.

A long study's checkpoints (``runs/silo``) and kept sweep results (``runs/columns``,
``runs/columns_fine``) are named by a digest of the run's keyword parameters
(``checkpoint_path`` and ``result_path``). The commands of ``runs/README.md`` must
find the files that are there: a renamed keyword, a reordered digest or another JSON form
would start those studies again from step 0 (hours to a day each).
"""
from dataclasses import dataclass, field, replace
import importlib
import shlex
from pathlib import Path

import pytest

from pfem_skfem.harness.params import UNKEYED, Parameters, keys_of
from pfem_skfem.harness.store import checkpoint_path
from pfem_skfem.harness.sweeps import result_path
from verification import granular_column_axisymmetric, silo_discharge

ROOT = Path(__file__).resolve().parents[1]
RUNS = ROOT / "runs"

COLUMNS = ("--compare-mc 2 --density 1 --friction-study 20 30 40 --base-study 20 25 30 "
           "--mesh-study 6 10 14 --history --workers 2 --no-figures --results-dir runs/columns")
COLUMNS_FINE = ("--a 0.5 --nr 20 --base-study 20 30 --base-a 0.5 --workers 2 --no-figures "
                "--results-dir runs/columns_fine --checkpoint-dir runs/columns_fine "
                "--checkpoint-every 20")
SILO = (
    "--walls --dt-study --h-study 0.01 --B-study 0.16 0.08 0.04 --checkpoint-dir runs/silo "
    "--checkpoint-every 10 --workers 2 --no-figures",
    "--walls rough smooth --h 0.02 --B-study --checkpoint-dir runs/silo --checkpoint-every 10 "
    "--workers 1 --no-figures",
    "--B-study --checkpoint-dir runs/silo --checkpoint-every 10 --workers 1 --no-figures",
    "--walls smooth --dt-study --B-study --h 0.02 --outlet-depth 0.02 --checkpoint-dir "
    "runs/silo --checkpoint-every 10 --workers 1 --no-figures",
)

COLUMN_FILES = {
    "columns": """0cf3d739d261 2d30a38e08f6 30e97682e583 3b7e02444c91 3df1409d690a 46ee83997aa9
        495a1cc4f5b5 5e7efe8511bd 6faeea2691f3 710d62c63243 72a74f1c9057 733a6374698a
        a22d855c49c9 a69cb7352a5b ad3e7397fbef b673109c00d6 cd8a1d1fd743 cf39bced3ed0
        d495d301daa9 dd0468acde8a ddabf7712371 e3c115b9b93e ec0a3ce31dc2 f5bf8aafaa17""",
    "columns_fine": "074eee300361 eca04f85608d",
}
SILO_FILES = """outlet_B0.04-9a69db9d051e outlet_B0.08-29cf7765df69 outlet_B0.16-f7a69512d08a
    rough_dt0.01-40fe581ba32e rough_dt0.01-a83a1a144aad smooth_dt0.005-09909a4f7c6f
    smooth_dt0.005-cc83ea714070 smooth_dt0.01-22cb77c52841 smooth_dt0.01-7048447505b0
    smooth_dt0.01-83bc0fdb678b smooth_dt0.02-a0fada6b3e3c smooth_dt0.02-b8c4882864f7
    smooth_dt0.04-4cbf4f75c15e smooth_dt0.04-bc074ccf81d2"""

# the keywords of silo_discharge.run_case that name its checkpoint (its scene's parameters)
SILO_KEYS = ("W", "H", "Hh", "B", "h", "rho", "c", "phi", "mu", "g", "dt", "alpha", "floor",
             "passes", "outlet_depth")


class _Stop(Exception):
    pass


def _cases(script, options, monkeypatch):
    """The cases ``script.run`` hands to run_cases (itself or through run_groups) for
    ``options`` (nothing runs), and the keywords of that call."""
    got = {}

    def capture(function, cases, workers=1, **keywords):
        got.update(cases=[dict(c) for c in cases], keywords=keywords)
        raise _Stop

    from pfem_skfem.harness import sweeps
    with monkeypatch.context() as m:
        m.setattr(sweeps, "run_cases", capture)          # through sweeps.run_groups
        if hasattr(script, "run_cases"):                 # or called by the script itself
            m.setattr(script, "run_cases", capture)
        with pytest.raises(_Stop):
            script.run(script.build_parser().parse_args(shlex.split(options) + ["--quiet"]))
    return got["cases"], got["keywords"]


@pytest.fixture
def in_root(monkeypatch):
    monkeypatch.chdir(ROOT)                      # the commands name runs/... from the root


@pytest.mark.parametrize("folder,options", [("columns", COLUMNS),
                                            ("columns_fine", COLUMNS_FINE)])
def test_kept_column_results_keep_their_names(folder, options, in_root, monkeypatch, tmp_path):
    cases, keywords = _cases(granular_column_axisymmetric, options, monkeypatch)
    assert keywords["results_dir"] == f"runs/{folder}"
    names = {result_path(tmp_path, keywords["desc"], c).name for c in cases}
    expected = {f"columns_of_revolution-{d}.result.pkl" for d in COLUMN_FILES[folder].split()}
    assert names == expected
    if (RUNS / folder).is_dir():                 # the folder is deleted once its study is done
        assert expected == {p.name for p in (RUNS / folder).glob("*.result.pkl")}


def test_kept_silo_checkpoints_keep_their_names(in_root, monkeypatch, tmp_path):
    names = set()
    for options in SILO:
        cases, _ = _cases(silo_discharge, options, monkeypatch)
        for case in cases:
            assert case["checkpoint_dir"] == "runs/silo"
            keys = silo_discharge.Silo(**{k: case[k] for k in SILO_KEYS}).keys()
            names.add(checkpoint_path(tmp_path, f"silo_{case['label']}", keys).name)
    expected = {f"silo_{n}.npz" for n in SILO_FILES.split()}
    assert names == expected
    if (RUNS / "silo").is_dir():
        assert expected == {p.name for p in (RUNS / "silo").glob("*.npz")}


def test_a_runs_parameters_are_its_checkpoint_keys_but_the_unkeyed(tmp_path):
    """keys_of: every field of the dataclass by name, but those declared UNKEYED, and the
    keys given beside; Parameters.of reads the fields from a parsed command line."""
    @dataclass(frozen=True)
    class Run(Parameters):
        a: float
        n: int
        solver: str = field(default="clarabel", metadata=UNKEYED)

    run = Run(0.5, 4, "qoco")
    assert run.keys() == keys_of(run) == {"a": 0.5, "n": 4}
    assert keys_of(run, n=5, b=1) == {"a": 0.5, "n": 5, "b": 1}
    import argparse
    assert Run.of(argparse.Namespace(a=1.0, n=2, other=3), n=3) == Run(1.0, 3)
    assert (checkpoint_path(tmp_path, "run", run.keys())
            == checkpoint_path(tmp_path, "run", replace(run, solver="clarabel").keys()))


#: each script's run parameters for --quick, as the script builds them, and the checkpoint
#: keys the script wrote by hand before they were one dataclass (issue 52, item 4)
QUICK_KEYS = {
    "dam_break": (lambda m, args: m.DamBreak.of(args), "nx", 9,
                  dict(a=0.05715, n2=2.0, nx=8, steps=40, T_end=3.0, rho=1000.0, mu=0.001,
                       g=9.81, alpha_advected=3.0)),
    "consolidation_pfem": (lambda m, args: m.TerzaghiColumn.of(args), "E", 2e5,
                           dict(axisymmetric=False, loading="rise", H=1.0, W=0.2, n=10, q=100.0,
                                k=1e-08, gamma_w=9.81, E=100000.0, nu=0.2, rho=1.0, g=9.81,
                                c=1000.0, dTv=0.005)),
    "sensitive_clay": (lambda m, args: m.Bank.of(args, S_t=args.sensitivities[0]), "S_t", 3.0,
                       dict(S_t=1.0, height=1.0, width=6.0, n=5, N=6.0, gamma_r=0.2,
                            E_over_c=500.0, nu=0.45, mu=0.5, rho=2.0, g=9.8, dt=0.05,
                            max_drop=0.5)),
    "bingham_slump": (lambda m, args: m.Slump.of(args, k=args.k[0], material="bingham",
                                                 quasi_static=False), "k", 0.02,
                      dict(k=0.04, material="bingham", n_h=3.5, cfl=0.5, mu=10.0,
                           quasi_static=False, L0=0.1, H0=0.1, rho=1000.0, g=9.81, mu_f=5.0,
                           dt0=0.05, dt_max=50.0, fall_max=16.0, alpha_advected=3.0)),
    "soil_and_water": (lambda m, args: m.Tank.of(args), "block", [0.4, 0.3],
                       dict(beta=30.0, mu_slope=0.2, mu_floor=0.0, d=0.4, L=2.0, block=[0.4, 0.2],
                            c=2000.0, rho_w=1000.0, rho_c=1800.0, g=9.81, h=0.08, t_end=3.0,
                            steps=100, keep_area="on", thin=0.4, spread_mass="on",
                            alpha_advected=3.0, refine_interior=0.0, keep_surface="off",
                            keep_area_step=0.0)),
    "soil_and_water twins": (lambda m, args: m.Twins.of(args), "phi", 35.0,
                             dict(rho=1000.0, a=0.05715, nx=8, phi=30.0, g=9.81, twin_steps=40)),
    "silo_discharge": (lambda m, args: m.Silo.of(args, mu=0.0), "H", 0.3,
                       dict(W=0.5, H=0.2, Hh=0.35, B=0.08, h=0.04, rho=1.5, c=0.0, phi=31.0,
                            mu=0.0, g=9.8, dt=0.04, alpha=1.6, floor=0.005, passes=2,
                            outlet_depth=0.0)),
    "accretionary_wedge": (lambda m, args: m.Layer.of(args, phi_b=args.base_friction), "L", 0.6,
                           dict(h0=0.08, L=0.5, h=0.016, phi=30.0, rho=2.0, g=9.8,
                                mu_wall=0.5773502691896257, s=0.05, dt=0.16, alpha=1.4,
                                k_min=0.005, contact="zero-dilation", passes=3, phi_b=15.0,
                                steps=12)),
    "cylinder_soil": (lambda m, args: m.Cylinder(**m.options_of(args)), "H", 3.0,
                      dict(D=1.0, c=1.0, rho=1.6, g=9.8, mu=0.5773502691896257, uV=0.8, uH=2.0,
                           du=0.05, dt=0.2, W=6.0, H=2.5, h_fine=0.25, h_coarse=0.5, alpha=1.4,
                           contact="coulomb", theta1=1.0, theta2=1.0)),
}


@pytest.mark.parametrize("script", sorted(QUICK_KEYS))
def test_a_scripts_checkpoint_keys_come_from_the_object_that_builds_its_scene(script,
                                                                              tmp_path):
    """The quick run's parameters give today's keys exactly (names, values and types: the
    same checkpoint names), and a changed field changes both the scene and the checkpoint."""
    from pfem_skfem.scene.scene import scene_digest

    module = importlib.import_module(f"verification.{script.split()[0]}")
    build, name, value, keys = QUICK_KEYS[script]
    params = build(module, module.build_parser().parse_args(["--quick"]))
    assert params.keys() == keys
    assert {k: type(v) for k, v in params.keys().items()} == {k: type(v) for k, v in keys.items()}
    changed = replace(params, **{name: value})
    assert scene_digest(changed.scene()[1]) != scene_digest(params.scene()[1])
    assert (checkpoint_path(tmp_path, script, changed.keys())
            != checkpoint_path(tmp_path, script, params.keys()))


def test_the_dam_break_s_advected_alpha_keys_its_own_checkpoint_and_reaches_the_scene():
    """--alpha-advected 0 (the thesis' alpha-shape) keeps the keys of before the option; any
    other value, the default 3 included, is a key of its own and the scene's
    PFEMConfig.alpha_advected."""
    module = importlib.import_module("verification.dam_break")
    parse = module.build_parser().parse_args
    default = module.DamBreak.of(parse(["--quick"]))
    plain = module.DamBreak.of(parse(["--quick", "--alpha-advected", "0"]))
    kept = module.DamBreak.of(parse(["--quick", "--alpha-advected", "2"]))
    assert "alpha_advected" not in plain.keys()
    assert kept.keys() == plain.keys() | {"alpha_advected": 2.0}
    assert default.keys() == plain.keys() | {"alpha_advected": 3.0}
    assert kept.scene()[1].config.alpha_advected == 2.0
    assert default.scene()[1].config.alpha_advected == 3.0
    assert plain.scene()[1].config.alpha_advected == 0.0
