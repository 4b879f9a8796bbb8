"""A PFEM run that stops and goes on (:class:`ResumableRun`), and its persistence.

A study of the thesis' size runs for hours to a day, longer than a working session: a run
saves its state and what its caller measures as it goes (``kept``) every k steps under
a name derived from its parameters (:func:`~pfem_skfem.harness.store.checkpoint_path`),
and a run with the same parameters finds that checkpoint and goes on from it, bit for bit
(the steps are the same calls of :func:`pfem_skfem.drivers.pfem_loop.run`). The
crash-safety of ``pfem-skfem run`` (issue 36) is the run's, so every resumable run has it:
one writer per checkpoint (a lock file), files written whole, and on Ctrl-C, SIGTERM, a
solver failure or a full disk the last completed step saved before the stop goes on.

:func:`save_run` and :func:`load_run` are the two files of a script's checkpoint (the
state, and ``kept`` beside it); :func:`sitting` names the machine a kept result was made
in; :class:`StepClock` the CPU seconds of each step a script keeps.
"""
from dataclasses import dataclass
import hashlib
import os
from pathlib import Path
import pickle
import platform
import signal
import socket
import threading
import time

from ..harness.progress import progress, progress_bar
from ..harness.store import DamagedFileError, _dump_pickle, checkpoint_path
from ..io import open_series
from ..pfem.state import load_checkpoint, save_checkpoint
from ..problems.conic import SolverError
from . import pfem_loop          # pfem_loop.run looked up at each step (tests replace it)
from .stopping import (TERM_RECEIVED, RunFolderError, RunLock, raise_if_terminated,
                       raise_terminated)

__all__ = ["ResumableRun", "StepClock", "save_run", "load_run", "sitting"]


def save_run(path, state, loop, driver=None):
    """Write a run's checkpoint at ``path``: the state
    (:func:`~pfem_skfem.pfem.state.save_checkpoint`) and the driver's own loop
    variables ``loop`` (a dict; pickled beside it as PATH.loop.pkl with the state's step,
    and ``driver``, the memory of the run's time-step policy, when there is one).
    Each file is written under a temporary name and then renamed, so that a stop while
    writing leaves the previous one whole (:func:`load_run` checks that the two are of
    the same step)."""
    path = Path(path)
    save_checkpoint(path, state)
    side = {"step": state.step, "loop": loop}
    if driver is not None:
        side["driver"] = driver
    _dump_pickle(side, path.with_name(path.stem + ".loop.pkl"))


def sitting():
    """The machine and boot a kept result was made in: host, processor (model, family,
    stepping, a digest of its feature flags), architecture and boot id. A PFEM run grows
    its round-off through remeshing, so two runs compared bit for bit (the density
    doubled, c = 0) must carry the same one."""
    info = {}
    try:
        with open("/proc/cpuinfo") as stream:
            for line in stream:
                key, _, value = line.partition(":")
                info.setdefault(key.strip(), value.strip())
    except OSError:
        pass
    try:
        with open("/proc/sys/kernel/random/boot_id") as stream:
            boot = stream.read().strip()[:8]
    except OSError:
        boot = "?"
    flags = hashlib.sha1(info.get("flags", "").encode()).hexdigest()[:8]
    model = info.get("model name", platform.processor())
    return (f"{platform.node()} ({model}, family {info.get('cpu family', '?')} model "
            f"{info.get('model', '?')} stepping {info.get('stepping', '?')}, flags {flags}, "
            f"{platform.machine()}), boot {boot}")


def load_run(path, driver=False):
    """(state, loop) written by :func:`save_run` (with ``driver``: (state, loop, driver),
    driver None when none was saved), or None when ``path`` has no checkpoint or its two
    files are not of the same step (a stop between the two renames)."""
    path = Path(path)
    side = path.with_name(path.stem + ".loop.pkl")
    if not (path.is_file() and side.is_file()):
        return None
    try:
        state = load_checkpoint(path)
        with open(side, "rb") as stream:
            saved = pickle.load(stream)
    except Exception as error:                   # noqa: BLE001 - any damage, named
        raise DamagedFileError(
            f"checkpoint {path} (with {side.name}) cannot be read ({type(error).__name__}: "
            f"{error}); delete both files to start that run again") from None
    if saved["step"] != state.step:
        return None
    return (state, saved["loop"], saved.get("driver")) if driver else (state, saved["loop"])


def _wait_for_lock(checkpoint, poll=5.0):
    """The lock of ``checkpoint`` (``<name>.lock`` beside it), waiting while another live
    run holds it: the same case twice in a sweep (or two sweeps) then runs once, and the
    second takes the first's checkpoint when it is released."""
    lock = RunLock(checkpoint.parent, checkpoint.stem + ".lock")
    told = False
    while True:
        try:
            return lock.acquire()
        except RunFolderError as busy:
            owner = lock.owner() or {}
            if owner.get("pid") == os.getpid() and owner.get("host") == socket.gethostname():
                raise                          # this process: waiting would never end
            if not told:
                progress(f"waiting for another run of {checkpoint.name}: {busy}")
                told = True
            time.sleep(poll)


@dataclass(frozen=True)
class Checkpoints:
    """Where a run keeps its checkpoint and how often.

    directory : where it is kept (``--checkpoint-dir``; None: not kept).
    label, keys : its name: ``label`` and a digest of ``keys`` (and of the scene's solver
        when it is not Clarabel, so no run resumes another solver's), the parameters that
        define the run (a dict of JSON values; :func:`~pfem_skfem.harness.store.checkpoint_path`).
        A checkpoint of another scene has another name, so a run never goes on from another
        run's state.
    every : steps between checkpoints (``--checkpoint-every``).
    state_alone : also go on from a checkpoint of the state without the kept measurements
        (written before they were kept, or by a stop between the two files); they are then
        the ones given.
    """

    directory: object = None
    label: str = None
    keys: dict = None
    every: int = 20
    state_alone: bool = False


@dataclass(frozen=True)
class Frames:
    """A VTU series ``name`` in ``directory`` written every ``every`` steps (none when either
    is unset), with its frame at t = 0; a resumed run keeps the frames up to its
    checkpoint."""

    directory: object = None
    name: str = "scene"
    every: int = 0


@dataclass(frozen=True)
class Bar:
    """A run's progress bar: ``total`` steps (None: no bar), its ``desc``, shown when
    ``verbose``."""

    total: int = None
    desc: str = None
    verbose: bool = False


class StepClock:
    """The process's CPU seconds of each step, for a run's ``kept``: started when made,
    :meth:`record` appends to ``kept[key]`` (made if a checkpoint of before lacks it) the
    seconds since the last record, or since the start."""

    def __init__(self, key="cpu_seconds"):
        self.key, self.last = key, time.process_time()

    def record(self, kept):
        now = time.process_time()
        kept.setdefault(self.key, []).append(now - self.last)
        self.last = now


class ResumableRun:
    """A PFEM run that can stop and go on: the scene, its state, and what the caller
    measures as it goes (``kept``, a dict of plain values and arrays), saved together
    every ``every`` steps and named by the run's parameters.

    Make one with :meth:`open` (which takes the state and ``kept`` from the run's
    checkpoint when there is one), then :meth:`advance` it; ``run.state`` and
    ``run.kept`` are the results. :meth:`step` is one step, the same call of
    :func:`pfem_skfem.drivers.pfem_loop.run` as a hand-written loop makes, so that the
    numbers do not depend on whether a run was stopped. Without a checkpoint
    it is a plain measured run: ``ResumableRun.open(scene, state, on_step=measure,
    bar=Bar(steps)).advance(lambda run: run.state.step >= steps)``.

    After each step ``run.record`` and ``run.result`` are that step's record and
    :class:`~pfem_skfem.drivers.pfem_loop.StepResult` (None for a step without a mesh),
    and ``run.step_scene`` the scene it ran (the time-step policy's, else ``scene``).

    Parameters
    ----------
    scene, state : the :class:`~pfem_skfem.scene.Scene` and its :class:`PFEMState`.
    kept : dict, optional
        The caller's measurements so far (saved with the state).
    checkpoint : Path, optional
        The checkpoint file (None: the run is not saved).
    every : int
        Steps between two checkpoints (0: only at the end and on a stop).
    series : :class:`pfem_skfem.io.TimeSeries`, optional
        Written every ``save_every`` steps.
    save_every : int
    bar : a tqdm-like bar (``update``, ``set_postfix_str``, ``close``), or None.
    save : callable ``save(state, kept)``, optional
        How a checkpoint is written (default: :func:`save_run` at ``checkpoint``).
    on_step : callable ``on_step(state, record, result)``, optional
        Called inside each step, after its VTU frame (the CLI's step records; a run's
        measurements without a checkpoint). A stop inside it saves the previous step's
        state with ``kept`` as it left it: measurements that a checkpoint keeps are
        taken in :meth:`advance`'s ``observe``, which sees ``run.record`` and
        ``run.result``.
    time_step : a time-step policy, optional
        The scene and start state of each step (``before(scene, state)``, ``after(scene,
        state)``, ``saved()``, ``restore(saved)``; e.g.
        :class:`~pfem_skfem.drivers.time_step.AdaptiveTimeStep`); its memory is saved in
        the checkpoint. None: ``scene`` at every step.
    """

    def __init__(self, scene, state, kept=None, *, checkpoint=None, every=20, series=None,
                 save_every=0, bar=None, save=None, on_step=None, time_step=None):
        if save is not None and time_step is not None:
            raise ValueError("a run with its own save cannot keep a time-step policy's memory")
        self.scene, self.state = scene, state
        self.kept = {} if kept is None else kept
        self.checkpoint = None if checkpoint is None else Path(checkpoint)
        self.every, self.series, self.save_every = every, series, save_every
        self.bar, self.on_step, self.time_step = bar, on_step, time_step
        self.record = self.result = None
        self.step_scene = scene
        self._save = save
        self.resumed = False
        self._clean = True            # state and kept agree (a stop may save them)
        self._lock = None             # the checkpoint's lock, held from open to advance's end

    @classmethod
    def open(cls, scene, state, kept=None, *, checkpoints=None, frames=None, bar=None,
             on_step=None, time_step=None):
        """A run of ``scene`` from ``state``, or from its checkpoint if the
        :class:`Checkpoints`' directory holds one; its VTU :class:`Frames` and its progress
        :class:`Bar` (each None: none); ``on_step``, ``time_step`` as the class takes them.
        """
        checkpoints, frames, bar_of = checkpoints or Checkpoints(), frames or Frames(), bar
        directory, label, keys = checkpoints.directory, checkpoints.label, checkpoints.keys
        every, state_alone = checkpoints.every, checkpoints.state_alone
        vtu_dir, vtu_name, save_every = frames.directory, frames.name, frames.every
        solver = getattr(getattr(scene, "config", None), "solver", "clarabel")
        if keys is not None and solver != "clarabel":
            keys = {**keys, "solver": solver}   # another solver's run is another run
        checkpoint = None if directory is None else checkpoint_path(directory, label, keys)
        resumed, lock = False, None
        if checkpoint is not None:
            lock = _wait_for_lock(checkpoint)     # one writer; a twin case takes its result
            try:
                saved = load_run(checkpoint, driver=True)
                driver = None
                if saved is not None:
                    (state, kept, driver), resumed = saved, True
                elif state_alone and checkpoint.is_file():
                    state, resumed = load_checkpoint(checkpoint), True
                if resumed and time_step is not None:
                    if driver is None or "time_step" not in driver:
                        raise DamagedFileError(
                            f"checkpoint {checkpoint} holds no time step to go on with; "
                            "delete it to start that run again")
                    time_step.restore(driver["time_step"])
            except BaseException:
                lock.release()
                raise
        series = (open_series(vtu_dir, vtu_name, state.time if resumed else None,
                              initial=None if resumed else (state, scene))
                  if vtu_dir is not None and save_every else None)
        bar = None
        if bar_of is not None and bar_of.total is not None:
            bar = progress_bar(total=bar_of.total, initial=min(state.step, bar_of.total),
                               disable=not bar_of.verbose, unit="step", desc=bar_of.desc)
        run = cls(scene, state, kept, checkpoint=checkpoint, every=every, series=series,
                  save_every=save_every, bar=bar, on_step=on_step, time_step=time_step)
        run.resumed, run._lock = resumed, lock
        return run

    def _stepped(self, state, record, result):
        self.record, self.result = record, result
        if self.on_step is not None:
            self.on_step(state, record, result)

    def step(self, snapshots=()):
        """One PFEM step: ``pfem_loop.run(state, scene, 1, series=..., save_every=...,
        snapshots=...)`` (the scene and start state the time-step policy gives, when the
        run has one); returns its snapshots ({step: dict})."""
        scene, state = self.scene, self.state
        if self.time_step is not None:
            scene, state = self.time_step.before(scene, state)
        state, more = pfem_loop.run(state, scene, 1, series=self.series,
                                    save_every=self.save_every, snapshots=snapshots,
                                    on_step=self._stepped)
        self._clean = False            # kept is the previous step's until observed
        self.state, self.step_scene = state, scene
        if self.time_step is not None:
            self.time_step.after(scene, state)
        return more

    def save(self):
        """Write the checkpoint (the state and ``kept``); nothing without one."""
        if self._save is not None:
            self._save(self.state, self.kept)
        elif self.checkpoint is not None:
            driver = (None if self.time_step is None
                      else {"time_step": self.time_step.saved()})
            save_run(self.checkpoint, self.state, self.kept, driver)

    def advance(self, done, observe=None, snapshots=(), postfix=None):
        """Step until ``done(run)``; after each step ``observe(run, snapshots)`` updates
        ``kept``, the bar moves, and every ``every`` steps the run is saved; at the end
        it is saved once more and the bar closed.

        ``snapshots``: step numbers to keep (as :func:`~pfem_skfem.drivers.pfem_loop.run`),
        or a callable ``snapshots(run)`` giving them before each step. ``postfix(run)``:
        the bar's text after each step. On Ctrl-C, SIGTERM (raised as
        :class:`~pfem_skfem.drivers.stopping.Terminated`), a solver failure or an OSError
        the last completed step is saved (when its measurements are complete) and the
        error raised again. Returns the run.
        """
        lock, self._lock = self._lock, None
        in_main = threading.current_thread() is threading.main_thread()   # signal's rule
        guarded = in_main and (self.checkpoint is not None or self._save is not None)
        if guarded:
            TERM_RECEIVED.clear()
        old = signal.signal(signal.SIGTERM, raise_terminated) if guarded else None
        try:
            while not done(self):
                more = self.step(snapshots(self) if callable(snapshots) else snapshots)
                if observe is not None:
                    observe(self, more)
                self._clean = True
                raise_if_terminated()          # a TERM swallowed inside the step
                if self.bar is not None:
                    if postfix is not None:
                        self.bar.set_postfix_str(postfix(self), refresh=False)
                    self.bar.update(1)
                if self.every and self.state.step % self.every == 0:
                    self.save()
            if self.bar is not None:
                self.bar.close()
            self.save()
        except (SolverError, KeyboardInterrupt, OSError) as error:
            if guarded:                        # a second TERM must not cut the save
                signal.signal(signal.SIGTERM, signal.SIG_IGN)
            if self.bar is not None:
                self.bar.close()
            # the state of the last completed step, when the caller's measurements of it
            # are complete (a stop inside observe leaves the previous checkpoint)
            error.saved_step, error.save_error = None, None
            if self._clean:
                try:
                    self.save()
                    error.saved_step = self.state.step
                except OSError as save_error:
                    error.save_error = save_error
            raise
        finally:
            if guarded:
                signal.signal(signal.SIGTERM, signal.SIG_DFL if old is None else old)
            if lock is not None:
                lock.release()
        return self
