"""A PFEM run that stops and goes on (:class:`pfem_skfem.drivers.resumable.ResumableRun`):
a run stopped at step k and resumed from its checkpoint is the run that never stopped,
bit for bit (the state's arrays and what the caller measured), and a run never goes on
from another scene's checkpoint."""
from dataclasses import fields
from pathlib import Path

import numpy as np
import pytest

from pfem_skfem.drivers import pfem_loop
from pfem_skfem.drivers.resumable import Checkpoints, load_run, ResumableRun, StepClock
from pfem_skfem.harness.store import checkpoint_path
from verification.granular_column_plane import granular_column

STEPS = 6
KEYS = dict(a=1.0, nx=6)


def _run(directory, stop=STEPS, keys=KEYS, every=2):
    """The column of ``keys`` to step ``stop``, measuring the top speed of each step."""
    state, scene = granular_column(keys["a"], keys["nx"])

    def observe(run, more):
        run.kept["speed"].append(float(np.max(np.linalg.norm(run.state.v, axis=1))))
        run.kept["snaps"].update({k: v["x"] for k, v in more.items()})

    run = ResumableRun.open(
        scene, state, {"speed": [], "snaps": {}},
        checkpoints=Checkpoints(directory=directory, label="column", keys=keys, every=every))
    return run.advance(lambda run: run.state.step >= stop, observe, snapshots={2, 5})


def _clock(key):
    """A record's wall-clock time (seconds, t_solve, t_conic, ...): not a result."""
    return key == "seconds" or key.startswith("t_")


def _same(a, b):
    _same_state(a.state, b.state)
    assert a.kept["speed"] == b.kept["speed"]
    assert a.kept["snaps"].keys() == b.kept["snaps"].keys()
    for k in a.kept["snaps"]:
        assert np.array_equal(a.kept["snaps"][k], b.kept["snaps"][k])


@pytest.fixture(scope="module")
def whole(tmp_path_factory):
    return _run(tmp_path_factory.mktemp("whole"))


def test_a_run_stopped_and_resumed_is_the_run_that_never_stopped(whole, tmp_path):
    first = _run(tmp_path, stop=3)                   # stopped at step 3 (saved at 2 and 3)
    assert first.state.step == 3 and not first.resumed
    again = _run(tmp_path)
    assert again.resumed
    assert again.kept["speed"][:3] == first.kept["speed"]
    _same(again, whole)


def test_a_run_interrupted_in_a_step_goes_on_from_the_last_completed_one(whole, tmp_path,
                                                                        monkeypatch):
    calls = []
    real = pfem_loop.run

    def interrupted(*args, **kwargs):
        calls.append(1)
        if len(calls) == 4:                          # Ctrl-C in step 4
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    with monkeypatch.context() as m:
        m.setattr(pfem_loop, "run", interrupted)
        with pytest.raises(KeyboardInterrupt) as stop:
            _run(tmp_path, every=0)                  # no periodic checkpoint: only the stop's
    assert stop.value.saved_step == 3
    path = checkpoint_path(tmp_path, "column", KEYS)
    state, kept = load_run(path)
    assert state.step == 3 and len(kept["speed"]) == 3
    assert not list(tmp_path.glob("*.lock"))         # the lock is released
    _same(_run(tmp_path), whole)


def test_a_run_never_goes_on_from_another_scenes_checkpoint(tmp_path):
    _run(tmp_path, stop=2)
    other = dict(KEYS, a=0.5)                        # another mass
    run = _run(tmp_path, stop=1, keys=other)         # its own name: from the start
    assert not run.resumed and run.state.step == 1
    # another scene's checkpoint under this scene's name is refused before any step
    mine, theirs = (checkpoint_path(tmp_path, "column", k) for k in (other, KEYS))
    for suffix in ("", ".loop.pkl"):
        name = (lambda p: p.with_name(p.stem + suffix)) if suffix else (lambda p: p)
        name(theirs).replace(name(mine))
    with pytest.raises(ValueError, match="does not belong to the scene"):
        _run(tmp_path, stop=3, keys=other)


ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.skipif(not (ROOT / "runs" / "silo").is_dir(), reason="runs/silo deleted")
def test_the_kept_silo_runs_are_found_and_read_back(tmp_path):
    """The thesis' silo at 1 cm (runs/README.md, command 3): the five finished runs are
    taken from their checkpoints (a copy: the end writes them again), not one step is run,
    and the table is the book's (book/data/silo_discharge_1cm.json), timings aside."""
    import json
    import shutil
    from verification import silo_discharge
    from pfem_skfem.harness.report import run_script

    shutil.copytree(ROOT / "runs" / "silo", tmp_path / "silo")
    report = run_script(silo_discharge, "--B-study", "--checkpoint-dir", str(tmp_path / "silo"),
                        "--checkpoint-every", "10", "--workers", "1", "--no-figures")
    book = json.loads((ROOT / "book" / "data" / "silo_discharge_1cm.json").read_text())
    assert report.as_json()["quantities"] == book["quantities"]

    def untimed(value):
        if isinstance(value, dict):
            return {k: untimed(v) for k, v in value.items() if not k.startswith("seconds")}
        return [untimed(v) for v in value] if isinstance(value, list) else value
    mine = json.loads(json.dumps(report.as_json()["extra"]))
    assert untimed(mine) == untimed(book["extra"])
    assert not list((tmp_path / "silo").glob("*.lock"))


def test_one_writer_per_checkpoint(tmp_path):
    """A run holds its checkpoint's lock from open to the end of advance; a second open of
    the same run in this process is refused (another process waits for it)."""
    from pfem_skfem.drivers.stopping import RunFolderError
    state, scene = granular_column(KEYS["a"], KEYS["nx"])
    first = ResumableRun.open(
        scene, state, {},
        checkpoints=Checkpoints(directory=tmp_path, label="column", keys=KEYS))
    with pytest.raises(RunFolderError, match="in use by another run"):
        ResumableRun.open(
            scene, state, {},
            checkpoints=Checkpoints(directory=tmp_path, label="column", keys=KEYS))
    first.advance(lambda run: run.state.step >= 1)
    assert not list(tmp_path.glob("*.lock"))
    again = ResumableRun.open(
        scene, state, {},
        checkpoints=Checkpoints(directory=tmp_path, label="column", keys=KEYS))
    assert again.resumed and again.state.step == 1
    again.advance(lambda run: True)


def test_another_solver_s_run_has_its_own_checkpoint(tmp_path):
    # a run with QOCO must not go on from Clarabel's checkpoint (nor the reverse): the
    # solver joins the name, and Clarabel's names stay those of the runs kept in runs/
    from dataclasses import replace
    state, scene = granular_column(KEYS["a"], KEYS["nx"])
    clarabel = ResumableRun.open(
        scene, state, {},
        checkpoints=Checkpoints(directory=tmp_path, label="column", keys=KEYS))
    qoco = replace(scene, config=replace(scene.config, solver="qoco"))
    other = ResumableRun.open(
        qoco, state, {},
        checkpoints=Checkpoints(directory=tmp_path, label="column", keys=KEYS))
    assert clarabel.checkpoint == checkpoint_path(tmp_path, "column", KEYS)
    assert other.checkpoint == checkpoint_path(tmp_path, "column", {**KEYS, "solver": "qoco"})
    assert other.checkpoint != clarabel.checkpoint
    for run in (clarabel, other):
        run._lock.release()


@pytest.mark.parametrize("stop_in", [8, 14], ids=["falling", "settling"])
def test_the_column_of_revolution_stopped_by_ctrl_c_goes_on_bit_for_bit(tmp_path, monkeypatch,
                                                                        stop_in):
    """granular_column_axisymmetric.run_case on its ResumableRun: Ctrl-C in step 8 keeps
    step 7 (with the deposit history measured so far), and the run started again from it
    returns the uninterrupted run's result; so does Ctrl-C in step 14, in the steps after
    t_stop (12) that the run takes on towards rest."""
    from verification import granular_column_axisymmetric as column
    case = dict(a=0.5, nr=4, steps=12, phi=20.0, settle=0.7, history=True)
    whole = column.run_case(**case)
    assert len(whole["t_bar"]) == 14                  # two steps after t_stop: settle = 0.7
    calls, real = [], pfem_loop.run

    def interrupted(*args, **kwargs):
        calls.append(1)
        if len(calls) == stop_in:
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    with monkeypatch.context() as m:
        m.setattr(pfem_loop, "run", interrupted)
        with pytest.raises(KeyboardInterrupt) as stop:
            column.run_case(**case, checkpoint_dir=tmp_path, checkpoint_every=5)
    assert stop.value.saved_step == stop_in - 1
    again = column.run_case(**case, checkpoint_dir=tmp_path, checkpoint_every=5)
    timing = {"seconds", "seconds_per_step", "sitting", "pvd"}
    assert whole.keys() == again.keys()
    for key in whole.keys() - timing:
        assert _equal(whole[key], again[key]), key


def _equal(a, b):
    """Equal bit for bit, NaN equal to NaN, through dicts, lists and arrays."""
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_equal(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)) and not all(np.isscalar(v) for v in a):
        return len(a) == len(b) and all(_equal(x, y) for x, y in zip(a, b))
    if isinstance(a, (list, tuple, np.ndarray, float, np.floating)):
        a, b = np.asarray(a), np.asarray(b)
        return a.shape == b.shape and np.array_equal(a, b, equal_nan=a.dtype.kind == "f")
    return a == b


def test_a_script_s_vtu_series_starts_at_t_0_and_states_its_units(tmp_path):
    """Issue 36, item 8: every VTU series a run writes (the scripts' too, through
    pfem_skfem.io.open_series) has the frame at t = 0 and the fields' units in its PVD."""
    from pfem_skfem.drivers.pfem_loop import run
    from pfem_skfem.io import open_series
    from pfem_skfem.scene import scene_from_toml
    from pfem_skfem.scene.files import example_text

    scene = scene_from_toml(example_text("column"))
    state = scene.initial_state()
    series = open_series(tmp_path / "vtu", "column", initial=(state, scene))
    run(state, scene, 2, series=series, save_every=1)
    pvd = (tmp_path / "vtu" / "column.pvd").read_text()
    assert [t for t, _ in series.entries][:1] == [0.0] and len(series.entries) == 3
    assert "units:" in pvd and "Pa" in pvd
    resumed = open_series(tmp_path / "vtu", "column", resume_at=series.entries[1][0],
                          initial=(state, scene))          # a resumed run writes no t = 0 again
    assert len(resumed.entries) == 2


@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")
def test_a_sigterm_swallowed_inside_a_step_still_stops_the_run(tmp_path):
    """A TERM whose exception lands in a finaliser is only printed by Python ("Exception
    ignored"): seen in CI, the run went on. The run must still stop after that step,
    with it checkpointed."""
    import signal
    from pfem_skfem.drivers.stopping import TERM_RECEIVED, Terminated, raise_terminated

    class Finaliser:                      # where a signal's exception is swallowed
        def __del__(self):
            raise_terminated(signal.SIGTERM, None)

    def observe(run, more):
        if run.state.step == 2:
            Finaliser()                   # made and collected: its TERM is swallowed

    state, scene = granular_column(KEYS["a"], KEYS["nx"])
    run = ResumableRun.open(
        scene, state, {},
        checkpoints=Checkpoints(directory=tmp_path, label="column", keys=KEYS, every=100))
    try:
        with pytest.raises(Terminated):
            run.advance(lambda run: run.state.step >= STEPS, observe)
    finally:                              # the TERM seen: not a TERM of the next test's runs
        TERM_RECEIVED.clear()
    assert run.state.step == 2
    saved = load_run(checkpoint_path(tmp_path, "column", KEYS))
    assert saved is not None and saved[0].step == 2


def _adaptive(directory, stop, every=0):
    """The column of KEYS under an adaptive time step (the driver's policy), to ``stop``."""
    from pfem_skfem.drivers.time_step import AdaptiveTimeStep
    state, scene = granular_column(KEYS["a"], KEYS["nx"])
    dt0 = scene.config.dt
    policy = AdaptiveTimeStep(dt0, 16 * dt0, move=0.5, spacing=float(np.median(state.h)))
    run = ResumableRun.open(
        scene, state, {"dt": []},
        checkpoints=Checkpoints(directory=directory, label="adaptive", keys=KEYS, every=every),
        time_step=policy)
    return run.advance(lambda run: run.state.step >= stop,
                       lambda run, more: run.kept["dt"].append(run.step_scene.config.dt))


def test_a_run_under_an_adaptive_time_step_goes_on_with_its_time_step(tmp_path, monkeypatch):
    """The time-step policy's memory (the next dt) travels in the checkpoint: a run
    stopped by Ctrl-C in step 4 and resumed takes the uninterrupted run's steps."""
    whole = _adaptive(None, STEPS)
    assert len(set(whole.kept["dt"])) > 1                 # the step did change
    assert whole.state.time == pytest.approx(sum(whole.kept["dt"]))
    calls, real = [], pfem_loop.run

    def interrupted(*args, **kwargs):
        calls.append(1)
        if len(calls) == 4:
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    with monkeypatch.context() as m:
        m.setattr(pfem_loop, "run", interrupted)
        with pytest.raises(KeyboardInterrupt) as stop:
            _adaptive(tmp_path, STEPS)
    assert stop.value.saved_step == 3
    again = _adaptive(tmp_path, STEPS)
    assert again.resumed and again.kept["dt"] == whole.kept["dt"]
    _same_state(again.state, whole.state)


def _same_state(a, b):
    """Two PFEM states field by field, bit for bit (the history's clock times left out)."""
    for f in fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if f.name == "history":
            assert x.keys() == y.keys()
            x = {k: v for k, v in x.items() if not _clock(k)}
            y = {k: v for k, v in y.items() if not _clock(k)}
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and np.array_equal(x, y), f.name
        else:
            assert x == y, f.name


def test_the_plane_columns_keys_are_its_scenes_parameters_and_todays_for_quick(
        quick_case_keys):
    """Issue 52, item 4: one ColumnRun builds the plane column's scene and its checkpoint
    keys (a field that changes the scene changes the keys); --quick's case keys its
    checkpoint as before (the same dict, hence the same file name)."""
    from dataclasses import replace
    from verification import granular_column_plane as column
    _, keys = quick_case_keys(column, "run_cases",
                              lambda run_case, cases, *args, **kwargs: cases[0])
    assert keys == dict(         # written out from the keys before issue 52
        a=1.0, nx=10, steps=100, phi=31.0, mu=None, material="tresca-mc", remesh="alpha",
        passes=2, alpha=1.6, floor=0.005, g=9.8, rho=2.0, d0=1.0, contact="coulomb", E=None,
        nu=0.3, settle=4.0, refine_surface=2.0, bulge=True, soil=None)
    params = column.ColumnRun(a=1.0, nx=6, steps=20, phi=31.0, mu=None)
    rougher = replace(params, mu=0.6)
    assert rougher.keys() == params.keys() | {"mu": 0.6}
    floors = [p.scene()[1].bodies[0].shape.mu for p in (params, rougher)]
    assert floors == pytest.approx([np.tan(np.radians(31.0)), 0.6])
    assert replace(params, solver="scs").keys() == params.keys()      # no state's part


def test_the_step_clock_keeps_each_steps_cpu_seconds_from_the_start(monkeypatch):
    """StepClock: the CPU seconds since the last record (the first since the clock was made),
    appended to kept's series, made where a checkpoint of before lacks it."""
    import time
    ticks = iter([10.0, 10.5, 12.0])
    monkeypatch.setattr(time, "process_time", lambda: next(ticks))
    clock, kept = StepClock(), {"dt": [0.1]}
    clock.record(kept)
    clock.record(kept)
    assert kept == {"dt": [0.1], "cpu_seconds": [0.5, 1.5]}
