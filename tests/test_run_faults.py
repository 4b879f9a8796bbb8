"""Faults and bad input of ``pfem-skfem run`` (issue 56, item 9; ../shared/RELIABILITY.md
R1-R6, R12, R13): each ends in a clean message and an exit code, never a traceback, and
never costs the user a file or a folder."""
import json

import numpy as np
import pytest

from pfem_skfem import cli
from pfem_skfem.scene.files import example_text


def _scene(tmp_path, name, *edits, file=None):
    """The example ``name`` with each (old, new) text replaced, written to tmp_path."""
    text = example_text(name)
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / (file or f"{name}.toml")
    path.write_text(text)
    return path


def _run(path, *args, out=None):
    out = path.with_suffix("") if out is None else out
    return cli.main(["run", str(path), "--out", str(out), "--no-progress", *map(str, args)])


def test_a_density_that_overflows_the_data_stops_with_exit_3_and_the_initial_state_kept(
        tmp_path, capsys):
    # R1: rho = 1e300 made the step's data non-finite; the check's ValueError escaped the
    # run loop as a traceback with no checkpoint (before the check: exit 3)
    path = _scene(tmp_path, "column", ("rho = 2.0 ", "rho = 1e300 "))
    assert _run(path, "--steps", 3, "--every", 0) == 3
    err = capsys.readouterr().err
    assert "non-finite" in err and "status NonFiniteData" in err and "in step 1;" in err
    assert "Traceback" not in err
    assert (path.with_suffix("") / "checkpoint.npz").is_file()   # step 0, resumable
