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


def test_every_particle_leaving_in_step_1_while_vtus_are_written_ends_cleanly(
        tmp_path, capsys):
    # R2: the base removed at t = 0, gravity -1e7 and an outlet 1 cm below: every particle
    # leaves in step 1; the VTU of that step raised an IndexError (io.step_fields)
    path = _scene(tmp_path, "column",
                  ("gravity = [0.0, -9.8]", "gravity = [0.0, -1e7]"),
                  ('name = "base" ', 'name = "base"\nremoved_at = 0.0\n#'),
                  ("# -- the numerical choices",
                   '[[outlets]]\nname = "drain"\n[outlets.zone]\ntype = "HalfPlane"\n'
                   'point = [0.0, -0.01]\nnormal = [0.0, -1.0]\n\n# -- the numerical choices'))
    assert _run(path, "--steps", 3, "--every", 1) == 0
    out, err = capsys.readouterr()
    assert "Traceback" not in err and "no material left" in out
    run = path.with_suffix("")
    assert (run / "scene_0001.vtu").is_file() and (run / "checkpoint.npz").is_file()
