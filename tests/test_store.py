"""The names kept runs are found by (issue 37): pinned before the harness moved.

A long study's checkpoints (``runs/silo``) and kept sweep results (``runs/columns``,
``runs/columns_fine``) are named by a digest of the run's keyword parameters
(``checkpoint_path`` and ``result_path``). The commands of ``runs/README.md`` must
find the files that are there: a renamed keyword, a reordered digest or another JSON form
would start those studies again from step 0 (hours to a day each).
"""
import shlex
from pathlib import Path

import pytest

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
            keys = {k: case[k] for k in SILO_KEYS}
            names.add(checkpoint_path(tmp_path, f"silo_{case['label']}", keys).name)
    expected = {f"silo_{n}.npz" for n in SILO_FILES.split()}
    assert names == expected
    if (RUNS / "silo").is_dir():
        assert expected == {p.name for p in (RUNS / "silo").glob("*.npz")}
