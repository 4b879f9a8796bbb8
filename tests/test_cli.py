"""The command line: case discovery, a run, the summary table and the exit code."""
import json

from pfem_skfem import cli


def test_lists_the_strip_footing_case():
    assert "strip_footing" in cli.available_cases()


def test_verify_runs_a_case_writes_json_and_exits_zero(tmp_path, capsys):
    # a coarse mesh overshoots Prandtl by about 7 % (thesis Fig 3.4): tolerance 15 %
    code = cli.main(["verify", "strip_footing", "--quick", "--no-figures",
                     "--json-dir", str(tmp_path), "--outdir", str(tmp_path),
                     "--extra", "--phi", "--elements", "100", "--increments", "5",
                     "--tol-tresca", "0.15"])
    out = capsys.readouterr().out
    data = json.loads((tmp_path / "strip_footing.json").read_text())
    assert data["case"] == "strip_footing"
    assert {"name", "value", "reference", "source", "rel_error", "tolerance", "pass"} <= set(
        data["quantities"][0])
    assert "Nc" in out and "1/1 case(s) passed" in out
    assert code == 0


def test_verify_exits_non_zero_when_a_check_fails(tmp_path, capsys):
    # an impossible tolerance makes the footing's Nc check fail
    code = cli.main(["verify", "strip_footing", "--quick", "--no-figures",
                     "--json-dir", str(tmp_path), "--outdir", str(tmp_path),
                     "--extra", "--phi", "--elements", "100", "--increments", "5",
                     "--tol-tresca", "1e-9"])
    assert code == 1
    assert "failed: strip_footing" in capsys.readouterr().out


def test_unknown_case_is_an_error(tmp_path):
    import pytest
    with pytest.raises(SystemExit, match="unknown case"):
        cli.main(["verify", "no_such_case", "--json-dir", str(tmp_path)])


def test_summary_shows_intervals_with_infinite_ends(tmp_path, capsys):
    """The sliding box checks the dilation order against [0.4, inf)."""
    code = cli.main(["verify", "sliding_box", "--quick", "--no-figures",
                     "--json-dir", str(tmp_path), "--outdir", str(tmp_path)])
    out = capsys.readouterr().out
    assert code == 0
    assert "[0.4,inf]" in out


def test_every_script_runs_as_a_file():
    """``python verification/NAME.py`` (how ``pfem-skfem verify`` runs a case) imports and
    parses: a script importing a sibling as ``verification.x`` must find the repository
    root itself (the script's own folder is first on the path, not the root)."""
    import os
    import subprocess
    import sys
    root = cli.verification_dir()
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    for case in cli.available_cases():
        proc = subprocess.run([sys.executable, str(root / f"{case}.py"), "--help"],
                              capture_output=True, text=True, cwd=root.parent.parent,
                              env=env)
        assert proc.returncode == 0, f"{case}: {proc.stderr[-500:]}"
