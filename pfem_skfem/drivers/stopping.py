"""How a run stops safely: one writer at a time (:class:`RunLock`), and SIGTERM raised in
the run as :class:`Terminated` (a KeyboardInterrupt) so that the last completed step is
saved as on Ctrl-C.

A leaf: it imports nothing of the package, so that the run loop
(:class:`~pfem_skfem.drivers.resumable.ResumableRun`), the run folder
(:mod:`pfem_skfem.runfolder`) and the command line can all use it, one way down.
"""
import json
import os
from pathlib import Path
import socket
import threading
import time

__all__ = ["DEFAULT_CHECKPOINT_EVERY", "LOCK", "RunFolderError", "RunLock", "Terminated",
           "TERM_RECEIVED", "raise_terminated", "raise_if_terminated"]

#: A checkpoint every this many steps when the scene asks for none (output.checkpoint_every
#: = 0): a stop (a kill, a crash) then loses at most this many steps.
DEFAULT_CHECKPOINT_EVERY = 20

#: The lock file of a run folder.
LOCK = "run.lock"


class RunFolderError(Exception):
    """The folder cannot be used as asked; the message says why and what to do."""


def _alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:                    # another user's process
        return True
    return True


class RunLock:
    """A lock file ``run.lock`` (or ``name``) in the folder naming its owner (pid, host,
    start time).

    Taken with an exclusive create, so two processes cannot both hold it. A lock whose
    owner is a process of this host that no longer runs is stale and taken over; a
    live owner, or one on another host (which cannot be checked), is refused.

    Use as a context manager; :meth:`acquire` creates the folder.
    """

    def __init__(self, directory, name=LOCK):
        self.path = Path(directory) / name
        self.held = False

    def owner(self):
        """The owner recorded in the lock file (a dict), or None if unreadable."""
        try:
            return json.loads(self.path.read_text())
        except (OSError, ValueError):
            return None

    def acquire(self):
        """Take the lock (creating the folder); RunFolderError if another run holds it."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        me = {"pid": os.getpid(), "host": socket.gethostname(),
              "started": time.strftime("%Y-%m-%d %H:%M:%S %Z")}
        for _ in range(3):
            try:
                fd = os.open(self.path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
            except FileExistsError:
                owner = self.owner()
                if owner is None and time.time() - self._mtime() < 10:
                    time.sleep(0.2)            # being written by its owner right now
                    continue
                if owner is not None and (owner.get("host") != me["host"]
                                          or _alive(int(owner.get("pid", -1)))):
                    raise RunFolderError(
                        f"{self.path.parent}/ is in use by another run (pid {owner.get('pid')} "
                        f"on {owner.get('host')}, started {owner.get('started')}): wait for "
                        f"it, or choose another output folder; if that run is known to be "
                        f"gone, delete {self.path}") from None
                self.path.unlink(missing_ok=True)  # stale: its owner is dead
                continue
            with os.fdopen(fd, "w") as f:
                json.dump(me, f)
            self.held = True
            return self
        raise RunFolderError(f"cannot take the lock {self.path}")

    def _mtime(self):
        try:
            return self.path.stat().st_mtime
        except OSError:
            return 0.0

    def release(self):
        """Remove the lock file if this process holds it."""
        if self.held:
            owner = self.owner()
            if owner is not None and owner.get("pid") == os.getpid():
                self.path.unlink(missing_ok=True)
            self.held = False

    def __enter__(self):
        return self.acquire()

    def __exit__(self, *exc):
        self.release()


class Terminated(KeyboardInterrupt):
    """SIGTERM (``kill``, ``timeout``, a batch system) raised in the run, to be handled
    as Ctrl-C is (a KeyboardInterrupt): checkpoint the last step and stop."""


#: set by the SIGTERM handler: a TERM that lands in a finaliser or a callback (where
#: Python only prints "Exception ignored") is still seen after the step (measured: a run
#: went on after such a TERM when the machine was loaded)
TERM_RECEIVED = threading.Event()


def raise_terminated(signum, frame):
    """The SIGTERM handler of a run: note the TERM (:data:`TERM_RECEIVED`) and raise
    :class:`Terminated`."""
    TERM_RECEIVED.set()
    raise Terminated()


def raise_if_terminated():
    """Raise :class:`Terminated` if a SIGTERM came that was swallowed on its way."""
    if TERM_RECEIVED.is_set():
        raise Terminated()
