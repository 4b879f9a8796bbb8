"""Run persistence of the PFEM drivers: a run's state and its driver's own measurements
saved together (:func:`save_run`, :func:`load_run`) under
:func:`~pfem_skfem.harness.store.checkpoint_path`, and the machine a kept result was
made in (:func:`sitting`).
"""
from pathlib import Path

from ..harness.store import DamagedFileError, _dump_pickle, checkpoint_path

__all__ = ["checkpoint_path", "save_run", "load_run", "sitting"]


def save_run(path, state, loop):
    """Write a run's checkpoint at ``path``: the state
    (:func:`~pfem_skfem.drivers.pfem_loop.save_checkpoint`) and the driver's own loop
    variables ``loop`` (a dict; pickled beside it as PATH.loop.pkl with the state's step).
    Each file is written under a temporary name and then renamed, so that a stop while
    writing leaves the previous one whole (:func:`load_run` checks that the two are of
    the same step)."""
    from ..pfem.state import save_checkpoint
    path = Path(path)
    save_checkpoint(path, state)
    _dump_pickle({"step": state.step, "loop": loop}, path.with_name(path.stem + ".loop.pkl"))


def sitting():
    """The machine and boot a kept result was made in: host, processor (model, family,
    stepping, a digest of its feature flags), architecture and boot id. A PFEM run grows
    its round-off through remeshing, so two runs compared bit for bit (the density
    doubled, c = 0) must carry the same one."""
    import hashlib
    import platform
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


def load_run(path):
    """(state, loop) written by :func:`save_run`, or None when ``path`` has no checkpoint
    or its two files are not of the same step (a stop between the two renames)."""
    import pickle
    from ..pfem.state import load_checkpoint
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
    return (state, saved["loop"]) if saved["step"] == state.step else None
