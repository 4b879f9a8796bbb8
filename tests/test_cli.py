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
    data = json.loads((tmp_path / "strip_footing.quick.json").read_text())
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


def test_unknown_case_is_a_usage_error_with_a_suggestion(tmp_path, capsys):
    """A misspelt case exits 2 (a usage error, not 1: a failed check) and names the case
    meant (issue 56 item 5)."""
    assert cli.main(["verify", "strip_footin", "--json-dir", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "unknown case 'strip_footin'" in err and "did you mean 'strip_footing'" in err
    assert cli.main(["verify", "no_such_case", "--json-dir", str(tmp_path)]) == 2
    assert "unknown case 'no_such_case'" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())                  # nothing run, nothing written


def test_verify_uses_the_cores_by_default(monkeypatch):
    """--jobs defaults to the cores the process may use (issue 56 item 2)."""
    monkeypatch.setattr(cli.os, "sched_getaffinity", lambda pid: {0, 1, 2}, raising=False)
    assert cli.default_jobs() == 3
    assert cli.build_parser().parse_args(["verify"]).jobs == 3
    assert cli.build_parser().parse_args(["verify", "--jobs", "1"]).jobs == 1


def test_list_gives_every_case_its_quick_time(capsys):
    """Every case of ``list`` shows its --quick CPU time, and the total is stated
    (issue 56 item 2): a new case adds its time to cli.QUICK_SECONDS."""
    assert set(cli.QUICK_SECONDS) == set(cli.available_cases())
    assert cli.main(["list"]) == 0
    out = capsys.readouterr().out
    for case in cli.available_cases():
        line = next(ln for ln in out.splitlines() if ln.startswith(case + " "))
        assert f"(--quick: {cli.QUICK_SECONDS[case]} s CPU)" in line, line
    assert f"all at --quick: {sum(cli.QUICK_SECONDS.values())} s CPU" in out


def test_quick_figures_are_kept_apart_from_full_size_ones(tmp_path):
    """A --quick run writes its figures under OUTDIR/quick/<case>/, never replacing the
    full-size run's in OUTDIR/<case>/ (issue 56 item 5)."""
    from pfem_skfem.harness.figures import figure_dir
    from verification import alpha_shape
    parser = alpha_shape.build_parser()
    full = parser.parse_args(["--outdir", str(tmp_path)])
    quick = parser.parse_args(["--quick", "--outdir", str(tmp_path)])
    assert figure_dir(full, "alpha_shape") == tmp_path / "alpha_shape"
    assert figure_dir(quick, "alpha_shape") == tmp_path / "quick" / "alpha_shape"
    (tmp_path / "alpha_shape").rmdir()
    (tmp_path / "quick" / "alpha_shape").rmdir()
    case, code, _, _, log = cli.run_case("alpha_shape", quick=True, json_dir=tmp_path,
                                         outdir=tmp_path, figures=True, extra=[])
    assert code == 0, log
    assert list((tmp_path / "quick" / "alpha_shape").glob("*.png"))
    assert not (tmp_path / "alpha_shape").exists()


def test_help_and_list_import_no_science():
    """``pfem-skfem --help``, ``list`` and ``run --help``'s parser build import neither numpy
    nor scipy, cvxpy or the scene (they cost ~1.4 s of CPU before; issue 56 item 8)."""
    code = ("import sys, contextlib, io\n"
            "from pfem_skfem import cli\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            "    cli.main(['list'])\n"
            "    try:\n"
            "        cli.main(['--help'])\n"
            "    except SystemExit:\n"
            "        pass\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] in "
            "('numpy', 'scipy', 'cvxpy', 'skfem') or m.startswith('pfem_skfem.scene')))\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert proc.stdout.strip() == "[]", proc.stdout


def test_summary_shows_intervals_with_infinite_ends(tmp_path, capsys):
    """The sliding box checks the dilation order against [0.03, inf)."""
    code = cli.main(["verify", "sliding_box", "--quick", "--no-figures",
                     "--json-dir", str(tmp_path), "--outdir", str(tmp_path)])
    out = capsys.readouterr().out
    assert code == 0
    assert "[0.03,inf]" in out


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


# -- pfem-skfem run: the run folder, crash safety, help (issue 36) ------------------------
import os  # noqa: E402
import shutil  # noqa: E402
import signal  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from pfem_skfem import io as pio  # noqa: E402
from pfem_skfem import runfolder  # noqa: E402
from pfem_skfem.pfem import state as pstate  # noqa: E402
from pfem_skfem.pfem.state import load_checkpoint  # noqa: E402
from pfem_skfem.scene.files import EXAMPLES, example_text  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def _run(*args):
    return cli.main(["run", *map(str, args), "--no-progress"])


@pytest.fixture
def column(tmp_path):
    """The column example in tmp_path (run it with --steps 2-3 to keep tests fast)."""
    path = tmp_path / "column.toml"
    path.write_text(example_text("column"))
    return path


def _steps(out):
    return [r["step"] for r in json.loads((out / "history.json").read_text())]


def test_a_run_into_a_folder_holding_another_run_is_refused(column, tmp_path, capsys):
    out = tmp_path / "o"
    assert _run(column, "--out", out, "--steps", 3) == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    assert _run(column, "--out", out, "--steps", 2) == 2
    err = capsys.readouterr().err
    assert str(out) in err and "--resume" in err and "--overwrite" in err and "--out" in err
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before     # nothing touched
    assert _run(column, "--out", out, "--steps", 2, "--overwrite") == 0
    assert _steps(out) == [1, 2] and not (out / "scene_0003.vtu").exists()


def test_a_folder_locked_by_a_live_run_is_refused_and_a_stale_lock_taken_over(column,
                                                                              tmp_path, capsys):
    out = tmp_path / "o"
    out.mkdir()
    live = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        (out / "run.lock").write_text(json.dumps({"pid": live.pid, "host": os.uname().nodename,
                                                  "started": "today"}))
        assert _run(column, "--out", out, "--steps", 1) == 2
        err = capsys.readouterr().err
        assert "in use" in err and str(live.pid) in err and not (out / "history.json").exists()
    finally:
        live.kill()
        live.wait()
    # its owner is gone: the lock is stale
    assert _run(column, "--out", out, "--steps", 1) == 0
    assert _steps(out) == [1] and not (out / "run.lock").exists()


def test_checkpoint_temporary_files_are_unique_to_each_writer(tmp_path, monkeypatch):
    from pfem_skfem.scene.files import scene_from_toml
    state = scene_from_toml(example_text("column")).initial_state()
    names, real = [], np.savez_compressed
    monkeypatch.setattr(pstate.np, "savez_compressed",
                        lambda f, **kw: (names.append(Path(f).name), real(f, **kw)))
    pstate.save_checkpoint(tmp_path / "checkpoint.npz", state)
    pstate.save_checkpoint(tmp_path / "checkpoint.npz", state)
    assert len(set(names)) == 2 and "checkpoint.tmp.npz" not in names
    assert [p.name for p in tmp_path.iterdir()] == ["checkpoint.npz"]


def test_outputs_are_written_beside_the_scene_file_and_named(tmp_path, monkeypatch, capsys):
    (tmp_path / "some" / "dir").mkdir(parents=True)
    scene = tmp_path / "some" / "dir" / "column_long.toml"
    scene.write_text(example_text("column"))
    monkeypatch.chdir(tmp_path)
    assert _run("some/dir/column_long.toml", "--steps", 1) == 0
    assert (tmp_path / "some" / "dir" / "column_run" / "history.json").exists()
    assert not (tmp_path / "column_run").exists()
    captured = capsys.readouterr()
    assert "some/dir/column_run" in captured.out + captured.err


def test_git_ignores_what_the_readme_s_cli_examples_write():
    if not (ROOT / ".git").exists():
        pytest.skip("not a git checkout")
    paths = ["column.toml", "silo.toml", "column_run/scene.pvd", "silo_run/x.vtu",
             "results/strip_footing.json", "results/strip_footing/fig.png"]
    proc = subprocess.run(["git", "check-ignore", *paths], cwd=ROOT, capture_output=True,
                          text=True)
    assert sorted(proc.stdout.split()) == sorted(paths)


def test_every_example_is_named_by_run_help_and_its_header_is_true(capsys):
    from pfem_skfem.scene.files import scene_from_toml
    with pytest.raises(SystemExit):
        cli.main(["run", "--help"])
    help_text = " ".join(capsys.readouterr().out.split())
    for name in EXAMPLES:
        assert name in help_text
        text = example_text(name)
        scene = scene_from_toml(text)
        steps = cli.steps_until(scene.t_end, scene.config.dt)
        line = next(ln for ln in text.splitlines() if ln.startswith("t_end"))
        assert f"{steps} steps" in line, (name, line)           # the comment on t_end
        assert f"t_end = {scene.t_end:g} here" in " ".join(text.split()) or name != "column"
        assert scene.output.checkpoint_every > 0                # a stop loses little


def test_the_silo_example_states_the_script_s_default_spacing():
    import inspect
    from verification.silo_discharge import Silo
    default = inspect.signature(Silo).parameters["h"].default
    header = " ".join(example_text("silo").split())
    assert f"the script's default {default:g}" in header


def test_the_hint_after_writing_an_example_names_a_command_that_works(tmp_path, capsys,
                                                                      monkeypatch):
    monkeypatch.setattr(sys, "argv", [str(Path(sys.executable).parent / "pfem-skfem")])
    monkeypatch.setenv("PATH", "/usr/bin:/bin")                  # no activated venv
    assert cli.main(["run", "--example", "column", str(tmp_path / "c.toml")]) == 0
    command = capsys.readouterr().out.split("run it with: ")[1].split()[0]
    assert shutil.which(command) or Path(command).is_file(), command


def test_quick_results_are_named_apart_from_full_size_ones(tmp_path, monkeypatch):
    seen = []

    def fake(cmd, **kw):
        seen.append(cmd[cmd.index("--json") + 1])
        return subprocess.CompletedProcess(cmd, 0, "", "")
    monkeypatch.setattr(cli.subprocess, "run", fake)
    for quick in (True, False):
        cli.run_case("strip_footing", quick=quick, json_dir=tmp_path, outdir=tmp_path,
                     figures=False, extra=[])
    assert [Path(p).name for p in seen] == ["strip_footing.quick.json", "strip_footing.json"]


def test_top_level_help_is_plain_text_naming_every_command(capsys):
    with pytest.raises(SystemExit):
        cli.main(["--help"])
    out = capsys.readouterr().out
    assert "``" not in out
    for command in ("list", "verify", "run"):
        assert f"  {command} " in out


def test_list_gives_each_case_a_description(capsys):
    assert cli.main(["list"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == len(cli.available_cases()) + 2           # a blank line, the total
    footing = next(ln for ln in lines if ln.startswith("strip_footing "))
    assert "footing" in footing.split(None, 1)[1] and "(--quick: 10 s CPU)" in footing


def test_sigterm_checkpoints_as_ctrl_c_does(column, tmp_path):
    out = tmp_path / "o"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    # no periodic checkpoint: the one found afterwards is SIGTERM's
    proc = subprocess.Popen([sys.executable, "-m", "pfem_skfem.cli", "run", str(column),
                             "--out", str(out), "--steps", "500", "--every", "1",
                             "--checkpoint-every", "1000", "--quiet"],
                            stderr=subprocess.PIPE, text=True, env=env)
    start = time.time()
    # step 3's VTU is written inside step 3, so step 2 is complete (step 2's own VTU is
    # written before step 2 ends: a TERM then leaves step 1 checkpointed, rightly)
    while not (out / "scene_0003.vtu").exists() and time.time() - start < 120:
        time.sleep(0.05)
    os.kill(proc.pid, signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 143, err
    assert "terminated" in err and "--resume" in err
    n = load_checkpoint(out / "checkpoint.npz").step
    assert n >= 2 and _steps(out) == list(range(1, n + 1))
    assert _run(column, "--out", out, "--steps", n + 1, "--resume") == 0
    assert _steps(out) == list(range(1, n + 2))


def test_a_scene_without_checkpoint_interval_still_checkpoints(column, tmp_path, monkeypatch):
    saved = []
    real = pstate.save_checkpoint
    monkeypatch.setattr(runfolder, "save_checkpoint",
                        lambda p, s, **kw: (saved.append(s.step), real(p, s, **kw)))
    monkeypatch.setattr(runfolder, "DEFAULT_CHECKPOINT_EVERY", 2)
    assert _run(column, "--out", tmp_path / "o", "--steps", 3, "--checkpoint-every", 0,
                "--every", 0) == 0
    assert saved == [2, 3]


@pytest.mark.parametrize("damage", ["missing", "short", "corrupt"])
def test_history_is_rebuilt_from_the_checkpoint_on_resume(column, tmp_path, damage, capsys):
    out = tmp_path / "o"
    assert _run(column, "--out", out, "--steps", 2, "--every", 0) == 0
    history = out / "history.json"
    if damage == "missing":
        history.unlink()
    elif damage == "short":
        history.write_text(json.dumps(json.loads(history.read_text())[:1]))
    else:
        history.write_text(history.read_text()[:50])
    assert _run(column, "--out", out, "--steps", 3, "--resume", "--every", 0) == 0
    assert _steps(out) == [1, 2, 3]
    if damage == "corrupt":
        assert "damaged" in capsys.readouterr().err


def test_ctrl_c_during_a_vtu_write_leaves_a_consistent_checkpoint(column, tmp_path,
                                                                  monkeypatch):
    real, calls = pio.write_vtu, []

    def interrupted(*a, **kw):
        calls.append(1)
        if len(calls) == 4:                           # t = 0, steps 1, 2; then step 3
            raise KeyboardInterrupt
        return real(*a, **kw)
    monkeypatch.setattr(pio, "write_vtu", interrupted)
    out = tmp_path / "o"
    assert _run(column, "--out", out, "--steps", 5, "--checkpoint-every", 1) == 130
    state, meta = load_checkpoint(out / "checkpoint.npz", meta=True)
    assert state.step == 2 and state.history["step"] == [1, 2]
    assert [r["step"] for r in meta["records"]] == [1, 2] == _steps(out)


@pytest.mark.parametrize("damage", ["missing", "corrupt"])
def test_a_missing_or_damaged_pvd_on_resume_deletes_no_vtu(column, tmp_path, damage, capsys):
    out = tmp_path / "o"
    assert _run(column, "--out", out, "--steps", 2) == 0
    vtus = sorted(p.name for p in out.glob("scene_*.vtu"))
    if damage == "missing":
        (out / "scene.pvd").unlink()
    else:
        (out / "scene.pvd").write_text("<VTKFile><Coll")
    assert _run(column, "--out", out, "--steps", 3, "--resume") == 2
    err = capsys.readouterr().err
    assert "scene.pvd" in err and ("missing" in err or "damaged" in err)
    assert sorted(p.name for p in out.glob("scene_*.vtu")) == vtus


@pytest.mark.parametrize("where", ["file", "below_file", "unwritable"])
def test_an_output_folder_that_cannot_be_written_is_refused_before_any_work(
        column, tmp_path, where, monkeypatch, capsys):
    (tmp_path / "f").write_text("a file")
    out = {"file": tmp_path / "f", "below_file": tmp_path / "f" / "o",
           "unwritable": tmp_path / "ro" / "o"}[where]
    if where == "unwritable":
        (tmp_path / "ro").mkdir()
        real = os.access
        monkeypatch.setattr(runfolder.os, "access",
                            lambda p, m: False if Path(p).name == "ro" else real(p, m))
    monkeypatch.setattr(cli, "_advance", lambda *a, **kw: pytest.fail("work started"))
    assert _run(column, "--out", out, "--steps", 1) == 2
    err = capsys.readouterr().err
    assert str(tmp_path / ("ro" if where == "unwritable" else "f")) in err


def test_a_full_disk_stops_before_the_vtu_writer_and_keeps_the_checkpoint(column, tmp_path,
                                                                          monkeypatch, capsys):
    real, frames = shutil.disk_usage, []

    def usage(path):
        frames.append(1)
        u = real(path)
        return u._replace(free=0) if len(frames) > 3 else u     # full at the step-3 frame
    monkeypatch.setattr(shutil, "disk_usage", usage)
    out = tmp_path / "o"
    assert _run(column, "--out", out, "--steps", 5) == 3
    assert "disk" in capsys.readouterr().err
    assert load_checkpoint(out / "checkpoint.npz").step == 2 == len(_steps(out))
    monkeypatch.setattr(shutil, "disk_usage", real)
    assert _run(column, "--out", out, "--steps", 4, "--resume") == 0
    assert len(list(out.glob("scene_*.vtu"))) == 5 and _steps(out) == [1, 2, 3, 4]


def test_a_damaged_checkpoint_is_named_with_what_to_do(column, tmp_path, capsys):
    out = tmp_path / "o"
    assert _run(column, "--out", out, "--steps", 1, "--every", 0) == 0
    (out / "checkpoint.npz").write_bytes(os.urandom(2000))
    assert _run(column, "--out", out, "--steps", 2, "--resume") == 2
    err = capsys.readouterr().err
    assert "checkpoint.npz is damaged" in err and "--overwrite" in err
    assert "allow_pickle" not in err


def test_a_checkpoint_of_another_scene_is_not_resumed(column, tmp_path, capsys):
    other = tmp_path / "other.toml"
    other.write_text(example_text("column").replace("rho = 2.0 ", "rho = 3.0 "))
    assert _run(column, "--out", tmp_path / "a", "--steps", 1, "--every", 0) == 0
    assert _run(other, "--out", tmp_path / "b", "--steps", 1, "--every", 0) == 0
    shutil.copy(tmp_path / "b" / "checkpoint.npz", tmp_path / "a" / "checkpoint.npz")
    assert _run(column, "--out", tmp_path / "a", "--steps", 2, "--resume") == 2
    assert "another scene" in capsys.readouterr().err


def test_an_infinite_t_end_is_a_clear_error(tmp_path, capsys):
    path = tmp_path / "inf.toml"
    path.write_text(example_text("column").replace("\nt_end = ", "\nt_end = inf #", 1))
    assert _run(path, "--out", tmp_path / "o") == 2
    assert "t_end" in capsys.readouterr().err and not (tmp_path / "o").exists()


def test_an_example_onto_a_path_that_cannot_be_written_is_a_usage_error(tmp_path, capsys):
    assert cli.main(["run", "--example", "column", str(tmp_path / "no" / "c.toml")]) == 2
    assert "cannot write" in capsys.readouterr().err


def test_run_takes_the_solver_of_every_step(column, tmp_path, monkeypatch):
    """--solver overrides the scene's config.solver (issue 40); the step is given it."""
    pytest.importorskip("qoco")
    from pfem_skfem.problems import nonassociated
    seen, real = [], nonassociated.dynamic_increment

    def spy(*args, **kwargs):
        seen.append(kwargs["solver"])
        return real(*args, **kwargs)
    monkeypatch.setattr(nonassociated, "dynamic_increment", spy)
    assert _run(column, "--out", tmp_path / "q", "--steps", 1, "--solver", "qoco") == 0
    assert seen and set(seen) == {"qoco"}
    with pytest.raises(SystemExit):
        _run(column, "--steps", 1, "--solver", "gurobi")
