"""--solver on every verification script and on ``pfem-skfem verify`` (issue 40, item 1)."""
import importlib
import subprocess

import pytest

from pfem_skfem import cli
from pfem_skfem.harness.options import SOLVER_NAMES
from pfem_skfem.problems.conic import SOLVERS

CASES = cli.available_cases()


@pytest.mark.parametrize("case", CASES)
def test_every_solving_script_takes_the_solver_and_refuses_others(case, capsys):
    parser = importlib.import_module(f"verification.{case}").build_parser()
    if case in cli.NO_SOLVER:                   # no conic solve: no option that does nothing
        assert "--solver" not in parser.format_help()
        return
    assert parser.parse_args([]).solver == "clarabel"
    assert parser.parse_args(["--solver", "qoco"]).solver == "qoco"
    with pytest.raises(SystemExit):
        parser.parse_args(["--solver", "nope"])
    err = capsys.readouterr().err
    assert "--solver" in err and all(name in err for name in SOLVER_NAMES)


@pytest.mark.parametrize("case", ["granular_column_mu_i", "inclined_plane_flow"])
def test_mu_i_s_exponential_cones_refuse_qoco_when_parsed(case, capsys):
    parser = importlib.import_module(f"verification.{case}").build_parser()
    assert "exponential" in parser.format_help()
    with pytest.raises(SystemExit):
        parser.parse_args(["--solver", "qoco", "--lag", "implicit"])
    assert "exp" in capsys.readouterr().err


def test_the_rotating_bar_gives_every_increment_the_solver(monkeypatch):
    from pfem_skfem.problems import bar
    from verification import rotating_bar
    seen, solve = [], bar.solve

    def record(problem, **kw):
        seen.append(kw.get("solver"))
        return solve(problem, **kw)
    monkeypatch.setattr(bar, "solve", record)
    args = rotating_bar.build_parser().parse_args(["--quick", "--no-figures", "--quiet",
                                                   "--steps", "4", "8"])
    args.solver = "scs" if SOLVERS["qoco"].unavailable() else "qoco"
    rotating_bar.run(args)
    assert seen and set(seen) == {args.solver}


def test_verify_passes_the_solver_to_every_script_that_solves(tmp_path, monkeypatch):
    seen = {}

    def fake(cmd, **kw):
        seen[cmd[1]] = cmd
        return subprocess.CompletedProcess(cmd, 0, "", "")
    monkeypatch.setattr(cli.subprocess, "run", fake)
    for case in ("strip_footing", "alpha_shape"):
        cli.run_case(case, quick=True, json_dir=tmp_path, outdir=tmp_path, figures=False,
                     extra=[], solver="qoco")
    cmds = {k.rsplit("/", 1)[-1]: v for k, v in seen.items()}
    assert cmds["strip_footing.py"][-2:] == ["--solver", "qoco"]
    assert "--solver" not in cmds["alpha_shape.py"]
    ran = []
    monkeypatch.setattr(cli, "run_case", lambda case, **kw: ran.append(kw["solver"]) or (
        case, 0, 0.0, tmp_path / "x.json", ""))
    cli.main(["verify", "strip_footing", "--solver", "qoco", "--json-dir", str(tmp_path),
              "--quiet"])
    assert ran == ["qoco"]
