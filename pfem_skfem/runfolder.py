"""The output folder of a resumable run, kept safe: nothing deleted silently, one writer
at a time, files written whole.

A run is hours of CPU, so its folder is guarded against the ways it was lost before:
a second run into it (refused unless the caller resumes or overwrites), two processes
at once (a lock file naming its owner), a stop between two files (the step records
travel inside the checkpoint, history.json is a copy rebuilt from it) and a full disk
(checked before each frame, see :class:`pfem_skfem.io.TimeSeries`). Plain functions of
paths and arrays, so that any run loop (the CLI's, a script's) can use them.

The steps are a :class:`~pfem_skfem.drivers.resumable.ResumableRun`'s, which holds the
crash-safety every resumable run shares (SIGTERM raised as :class:`Terminated`, the last
completed step saved on any stop); this module adds what a run *folder* needs: its lock,
the refusal to overwrite, the scene's copy and digest, and ``history.json``.
"""
from dataclasses import replace
import json
import os
from pathlib import Path
import sys
import time

from .discretisation.geometry import as_geometry
from .harness.progress import progress
from .drivers.resumable import ResumableRun
from .drivers.stopping import DEFAULT_CHECKPOINT_EVERY, RunFolderError, RunLock, Terminated
from .io import STEP_UNITS, TimeSeries, initial_fields, write_text_atomic
from .pfem.state import CheckpointError, load_checkpoint, save_checkpoint
from .problems.conic import SolverError
from . import runreport
from .scene import scene_digest
from .scene.files import load_scene, scene_to_toml

#: The files a run writes into its folder (besides ``<series>_NNNN.vtu``).
RUN_FILES = ("checkpoint.npz", "history.json", "scene.toml", "scene.pvd")
#: Bytes a VTU frame leaves free (with twice the checkpoint's size): a full disk stops the
#: run at a frame, before the checkpoint that keeps its steps cannot be written.
RESERVE = 1 << 20


def check_output_dir(out):
    """Refuse, before any work, a folder that cannot be created or written.

    Parameters
    ----------
    out : path of the output folder (it need not exist).

    Raises
    ------
    RunFolderError naming the path: it is a file, lies below a file, or is not writable.
    """
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise RunFolderError(f"{out} is a file, not a folder")
    probe = out
    while not probe.exists():                  # the first existing ancestor must be a folder
        probe = probe.parent
    if not probe.is_dir():
        raise RunFolderError(f"{out} lies below {probe}, which is a file")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise RunFolderError(f"{probe} is not writable" +
                             ("" if probe == out else f" (cannot create {out})"))


def run_files(out, series="scene"):
    """The files of a run found in ``out`` (sorted; empty when it holds none)."""
    out = Path(out)
    if not out.is_dir():
        return []
    found = [out / name for name in RUN_FILES if (out / name).exists()]
    return sorted(found + list(out.glob(f"{series}_*.vtu")))


def clear_run(out, series="scene"):
    """Delete the files of a run in ``out`` (and stale temporary checkpoints); nothing else."""
    out = Path(out)
    for path in run_files(out, series) + list(out.glob("checkpoint.*.tmp.npz")):
        path.unlink()


def history_columns(records):
    """The records as the driver's ``state.history`` holds them: {key: [values]}, each
    record's values appended in its own key order (as ``drivers.pfem_loop.run`` does)."""
    history = {}
    for rec in records:
        for k, val in rec.items():
            history.setdefault(k, []).append(val)
    return history


def read_history(path):
    """The records of ``history.json`` (a list of dicts with a "step"); None if missing.

    Raises
    ------
    RunFolderError when the file is damaged (not JSON, or not a list of step records).
    """
    path = Path(path)
    if not path.exists():
        return None
    try:
        records = json.loads(path.read_text())
        if not isinstance(records, list) or not all(isinstance(r, dict) and "step" in r
                                                    for r in records):
            raise ValueError("not a list of step records")
    except (ValueError, UnicodeDecodeError) as err:
        raise RunFolderError(f"{path} is damaged ({err})") from None
    return records


# -- a run in its folder ------------------------------------------------------------------
def run_in_folder(scene, out, last, *, resume=False, overwrite=False, progress=None,
                  force=False):
    """Run ``scene`` to step ``last`` in folder ``out``, under the folder's lock, every
    file written whole, the last completed step checkpointed on any stop.

    Parameters
    ----------
    scene : the Scene (its ``output`` says how often a VTU and a checkpoint are written;
        a checkpoint_every of 0 means :data:`DEFAULT_CHECKPOINT_EVERY`).
    out : the output folder (pathlib.Path).
    last : the step to reach.
    resume : go on from the folder's checkpoint (refused if it is of another scene).
    overwrite : replace the run the folder holds (refused otherwise).
    progress : None, or a factory ``progress(first, last)`` of a callable
        (step, steps, record) with a ``close()`` (the CLI's progress bar).
    force : a run whose steps broke a bound of :mod:`pfem_skfem.runreport` (a particle
        moved more than a spacing, the area changed by more than 5 %) exits 0 after the
        warning, not :data:`~pfem_skfem.runreport.EXIT_TOO_LONG_STEPS`.

    Returns
    -------
    The exit code: 0 done, 4 done but a step broke a bound of
    :mod:`~pfem_skfem.runreport` (dt too long; 0 with ``force``), 130 Ctrl-C, 143 SIGTERM,
    3 a solver failure or a full disk (each with the last completed step checkpointed, and
    a line on stderr saying so). Before the first step a line says what the run is, after
    it what it will cost, and at the end why it stopped and its main figures.

    Raises
    ------
    RunFolderError before any work when the folder cannot be used as asked.
    """
    out = Path(out)
    if resume and not (out / "checkpoint.npz").is_file():
        raise RunFolderError(_NOTHING_TO_RESUME.format(out=out))
    created = not out.exists()
    try:
        with RunLock(out):
            return _run_locked(scene, out, last, resume, progress, overwrite, force)
    finally:
        if created and out.is_dir() and not any(out.iterdir()):
            out.rmdir()                              # refused before writing: leave no trace


_NOTHING_TO_RESUME = ("nothing to resume in {out}/: it holds no checkpoint.npz (no step of a "
                      "run was saved there); run without --resume to start the run again")


def _same_scene_copy(copy, scene):
    """Whether ``copy`` (a run folder's scene.toml) is ``scene`` as run (t_end and [output]
    aside): a folder of a stopped run of this scene."""
    try:
        ran = load_scene(copy)
    except (OSError, ValueError):
        return False
    return replace(ran, t_end=None, output=scene.output) == replace(scene, t_end=None)


def _resume_state(scene, out, digest):
    """The checkpoint's state and step records; history.json is checked against them."""
    checkpoint, history, copy = out / "checkpoint.npz", out / "history.json", out / "scene.toml"
    if not checkpoint.is_file():
        raise RunFolderError(_NOTHING_TO_RESUME.format(out=out))
    if not copy.is_file():
        raise RunFolderError(f"nothing to resume in {out}/: its scene.toml is missing (the "
                             "scene the checkpoint was made of); restore it, or start again "
                             "with --overwrite")
    try:
        ran = load_scene(copy)
    except ValueError as err:
        raise RunFolderError(f"{copy} is damaged ({err}); start again with --overwrite") \
            from None
    # the numbers of the run must be the same; its length and output may change
    if replace(ran, t_end=None, output=scene.output) != replace(scene, t_end=None):
        raise RunFolderError(f"the scene differs from the one run in {out}/scene.toml: "
                             "resume only the same scene (t_end and [output] may change)")
    try:
        state, meta = load_checkpoint(checkpoint, meta=True)
    except CheckpointError as err:
        raise RunFolderError(f"{err}: it cannot be resumed; delete it or start again with "
                             "--overwrite (or run into another --out)") from None
    if meta.get("scene_digest", digest) != digest:
        raise RunFolderError(f"{checkpoint} belongs to another scene than {copy} (its scene "
                             "digest differs): it cannot be resumed; start again with "
                             "--overwrite")
    try:
        on_disk = read_history(history) or []
    except RunFolderError as err:
        print(f"pfem-skfem run: {err}; rebuilt from the checkpoint", file=sys.stderr)
        on_disk = []
    if "records" in meta:                            # the checkpoint's records are the truth
        records = meta["records"]
        mine = [r["step"] for r in on_disk if r["step"] <= state.step]
        if mine and mine != [r["step"] for r in records]:
            print(f"pfem-skfem run: {history} disagrees with the checkpoint ({len(mine)} of "
                  f"{len(records)} steps); rebuilt from the checkpoint", file=sys.stderr)
    else:                                            # a checkpoint of an older version
        records = [r for r in on_disk if r["step"] <= state.step]
        if [r["step"] for r in records] != list(range(1, state.step + 1)):
            raise RunFolderError(f"{history} does not hold steps 1-{state.step} of the "
                                 "checkpoint (written by an older version, without its "
                                 "records): restore it, or start again with --overwrite")
    return replace(state, history=history_columns(records)), records


def _run_locked(scene, out, last, resume, progress, overwrite, force):
    checkpoint, history, copy = out / "checkpoint.npz", out / "history.json", out / "scene.toml"
    digest = scene_digest(scene)
    for tmp in list(out.glob("checkpoint.*.tmp.npz")) + list(out.glob(".*.tmp")):
        tmp.unlink(missing_ok=True)                  # left by a killed writer; we hold the lock
    held = run_files(out)
    if held and not resume and not overwrite and _no_step_kept(out, scene):
        say(f"{out}/ holds no saved step of this scene (a run stopped before its first "
            "checkpoint): it is started again there")
        overwrite = True
    if held and not resume:
        if not overwrite:
            names = ", ".join(p.name for p in held[:4]) + (", ..." if len(held) > 4 else "")
            raise RunFolderError(
                f"{out}/ holds the results of another run ({names}): nothing written. "
                "Continue it with --resume, replace it with --overwrite, or write elsewhere "
                "with --out DIR")
        clear_run(out)
    if resume:
        state, records = _resume_state(scene, out, digest)
    else:
        state, records = scene.initial_state(), []
    size = checkpoint.stat().st_size if checkpoint.exists() else 0
    kept = "1 MB" + " and twice the checkpoint's size" * bool(size)
    series = (TimeSeries(out, "scene", note=STEP_UNITS, reserve=2 * size + RESERVE,
                         reserve_for=f"{kept} for the checkpoint and history.json")
              if scene.output.every else None)
    if series is not None:           # the steps up to the checkpoint's (none on a new run)
        try:
            series.resume(state.time if resume else float("-inf"))
        except ValueError as err:
            raise RunFolderError(str(err)) from None
    write_text_atomic(copy, scene_to_toml(scene, header="the scene as run by pfem-skfem run"))
    first = state.step
    if first >= last:
        print(f"{out}/ is already at step {first} (>= {last}): nothing to run")
        return 0
    say(runreport.start_line(scene, state, first, last, out))
    if series is not None and not resume:            # the frame at t = 0
        try:
            series.write(0.0, *initial_fields(state, scene.alpha,
                                              as_geometry(scene.geometry).axisymmetric,
                                              scene.water))
        except OSError as err:                       # a full disk: no step computed
            print(f"pfem-skfem run: stopped before step {first + 1}: {err}; no step was "
                  "computed: free some space (or write no VTU: --every 0) and run the same "
                  "command again", file=sys.stderr)
            return 3
    every = scene.output.checkpoint_every or DEFAULT_CHECKPOINT_EVERY

    saved = [state.step if resume else None]       # the step of the folder's checkpoint

    def save(st, _):
        """The checkpoint with the records up to its step (one file: they agree), then
        history.json as a copy of those records (the run's ``kept`` is ``records``)."""
        kept = [r for r in records if r["step"] <= st.step]
        save_checkpoint(checkpoint, replace(st, history=history_columns(kept)),
                        meta={"scene_digest": digest, "records": kept})
        saved[0] = st.step
        write_text_atomic(history, json.dumps(kept, indent=1) + "\n")

    bar = None if progress is None else progress(first, last)
    # the run's steps one at a time (the same steps as one call of pfem_loop.run: each
    # step's state owns its history), checkpointed every ``every`` and on any stop
    started, warned = time.perf_counter(), len(records) > 0 and _warn_once(records, scene)

    def on_step(st, record, result):
        nonlocal warned
        records.append(record)
        if st.step == first + 1:
            say(runreport.estimate_line(record, time.perf_counter() - started, last - first))
        if not warned:
            warned = _warn_once(records, scene, len(records) - 1)
        if bar is not None:
            bar(st.step - first, last - first, record)

    run = ResumableRun(scene, state, checkpoint=checkpoint, every=every, series=series,
                       save_every=scene.output.every, save=save, on_step=on_step)
    try:
        run.advance(lambda run: run.state.step >= last or run.state.n == 0)
    except (SolverError, KeyboardInterrupt, OSError) as err:
        if bar is not None:
            bar.close()
        n = run.state.step
        if err.save_error is not None:
            print(f"pfem-skfem run: the checkpoint of step {n} could not be "
                  f"written ({err.save_error}); the folder keeps the previous one",
                  file=sys.stderr)
        if isinstance(err, SolverError):
            what = f"solver failed ({err}; status {err.status})"
        else:
            what = {KeyboardInterrupt: "interrupted", Terminated: "terminated (SIGTERM)"}.get(
                type(err), f"stopped: {err}")
        print(f"pfem-skfem run: {what} in step {n + 1}; "
              f"{_kept_message(out, n, saved[0])}", file=sys.stderr)
        say(runreport.figures(run.state, records))
        return {KeyboardInterrupt: 130, Terminated: 143}.get(type(err), 3)
    state = run.state
    if bar is not None:
        bar.close()                                  # a run that ended early
    vtus = f"scene.pvd ({len(series.entries)} VTU), " if series is not None else ""
    print(f"steps {first + 1}-{state.step} (t = {state.time:.6g}) written to {out}/: {vtus}"
          "history.json, scene.toml, checkpoint.npz")
    print(f"stopped: {runreport.why_stopped(scene, state, records, last)}")
    print(runreport.figures(state, records))
    if warned:
        say(f"the steps were too long from step {warned}"
            + ("; --force: exit 0" if force else f": exit {runreport.EXIT_TOO_LONG_STEPS} "
               "(--force to accept them)"))
        return 0 if force else runreport.EXIT_TOO_LONG_STEPS
    return 0


def _no_step_kept(out, scene):
    """Whether ``out`` holds a run of ``scene`` stopped before its first checkpoint (no
    checkpoint.npz, no history.json, its scene.toml the same scene): nothing in it can be
    resumed and a new run writes the same files, so a plain rerun may take it."""
    return (not (out / "checkpoint.npz").exists() and not (out / "history.json").exists()
            and _same_scene_copy(out / "scene.toml", scene))


def _kept_message(out, n, saved):
    """What a stopped run at step ``n`` left in ``out``: its checkpoint of step ``saved``
    (None: none was written), and how to go on."""
    if saved is None:
        done = f"steps 1-{n} were computed but" if n else "no step was computed and"
        return (f"{done} no checkpoint could be written, so nothing in {out}/ can be "
                "resumed: run the same command again (without --resume) to start afresh")
    kept = (f"steps 1-{saved} are" if saved > 1 else
            ("step 1 is" if saved == 1 else "the initial state is"))
    lost = ("" if saved == n else f" (step {n} was not saved)" if n == saved + 1
            else f" (steps {saved + 1}-{n} were not saved)")
    return f"{kept} in {out}/{lost} (--resume continues from step {saved})"


def say(text):
    """A line of ``pfem-skfem run`` on stderr, above the progress bar."""
    progress(f"pfem-skfem run: {text}")


def _warn_once(records, scene, i=None):
    """Warn of the first record (from ``i``; None: any) whose step broke a bound of
    :mod:`runreport`, naming dt; its step, or False when none did."""
    found = runreport.first_too_long(records) if i is None else (
        i if runreport.step_too_long(records, i) else None)
    if found is None:
        return False
    say(runreport.too_long_message(records, found, scene.config.dt))
    return records[found]["step"]
