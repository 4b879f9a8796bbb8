"""Files named by a digest of their parameters and written whole, and JSON values.

A long run's checkpoint (:func:`checkpoint_path`) and a sweep's kept result
(:func:`pfem_skfem.harness.sweeps.result_path`) are found again by the parameters that
define them (``tests/test_store.py`` pins the names the kept runs of ``runs/`` have); a
file is written under a temporary name and renamed, so that a stop while writing leaves
the previous one whole. Before any work, :func:`output_path_problem` says why a path an
option names cannot be written (the parser's check of ``--json``, ``--outdir``, ...).
"""
import json
import math
from pathlib import Path

import numpy as np


class DamagedFileError(RuntimeError):
    """A kept file (a checkpoint, a sweep's result) that cannot be read: its message names
    the file and what to do."""


def _plain(v):
    """A JSON value for ``v``: numpy scalars and arrays as Python numbers and lists."""
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, (np.floating, np.integer)):
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    if isinstance(v, np.bool_):
        return bool(v)
    return v



def checkpoint_path(directory, label, keys):
    """The checkpoint file of one run in ``directory`` (created): ``label`` and a digest of
    ``keys`` (the parameters that define the run, a dict of JSON values), so that a run
    never goes on from another run's state. Returns a Path."""
    if not str(label) or any(c in str(label) for c in "/\\"):
        raise ValueError(f"label must be a file name part, got {label!r}")
    return _named_by(directory, label, keys, ".npz")


def _named_by(directory, label, keys, suffix, default=float):
    """``directory``/``label``-digest``suffix`` (the directory created), the digest that
    of ``keys`` as sorted JSON (``default`` for values JSON has no form for)."""
    import hashlib
    text = json.dumps({k: keys[k] for k in sorted(keys)}, default=default)
    digest = hashlib.sha256(text.encode()).hexdigest()[:12]
    folder = Path(directory)
    folder.mkdir(parents=True, exist_ok=True)
    return folder / f"{label}-{digest}{suffix}"


def _dump_pickle(value, path):
    """Pickle ``value`` at ``path`` under a temporary name and then rename it, so that a
    stop while writing leaves the previous file whole (or none)."""
    import os
    import pickle
    path = Path(path)
    with open(path.with_suffix(".tmp"), "wb") as stream:
        pickle.dump(value, stream)
    os.replace(path.with_suffix(".tmp"), path)


def output_path_problem(path, kind="file"):
    """Why ``path`` cannot be written as a ``kind`` ("file" or "directory"), or None.

    Nothing is created: the nearest existing folder on the way must be a folder in which a
    file can be made (a probe file, removed); an existing ``path`` must be of its kind (and
    a file writable)."""
    import tempfile
    target = Path(path).expanduser()
    if target.exists():
        if kind == "file" and target.is_dir():
            return f"{path} is a directory, not a file"
        if kind == "directory" and not target.is_dir():
            return f"{path} exists and is not a directory"
        if kind == "file":
            try:
                with open(target, "r+b"):
                    pass
            except OSError as error:
                return f"cannot write {path} ({error.strerror or error})"
            return None
        folder = target
    else:
        folder = target.parent
        while not folder.exists() and folder != folder.parent:
            folder = folder.parent
        if not folder.is_dir():
            return f"{folder} (on the way to {path}) is a file, not a directory"
    try:
        with tempfile.TemporaryFile(dir=folder, prefix=".write-probe-"):
            pass
    except OSError as error:
        return f"cannot write in {folder} ({error.strerror or error})"
    return None
