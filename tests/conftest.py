"""Fixtures shared by the test files: each verification script's ``--quick`` run, once.

``quick_run(name, *extra)`` runs ``verification/<name>.py`` at ``--quick`` with ``extra``
and draws its figures, each checked before it is saved
(:func:`pfem_skfem.harness.figures.inspect_figures`), once per test session: the case of
``tests/test_verification.py`` and the physics tests of the script's own file
(``test_silo.py``, ...) read the same run. A script has one quick run: asking for it with
other options is an error, not a second run.

With pytest-xdist a session is one worker: every test that reads the quick run of ``name``
is marked ``pytest.mark.xdist_group(name)``, so that ``--dist loadgroup`` (scripts/test.sh)
keeps them on one worker and the run is computed once. (pytest 9.2 with pytest-xdist 3.8
ignores the groups, pytest-dev/pytest-xdist#1386: then a run is made once per worker.)
"""
import importlib

import pytest

from pfem_skfem.harness.figures import inspect_figures


@pytest.fixture(scope="session")
def quick_run(tmp_path_factory):
    """``quick_run(name, *extra) -> (Report, {file: problems})``, computed once per name."""
    runs = {}

    def run(name, *extra):
        if name not in runs:
            script = importlib.import_module(f"verification.{name}")
            out = tmp_path_factory.mktemp(name)
            runs[name] = extra, inspect_figures(script, ["--quick", *extra], out)
        given, result = runs[name]
        if given != extra:
            raise ValueError(f"the quick run of {name} is shared: asked with {list(extra)}, "
                             f"made with {list(given)}")
        return result

    return run


class _Opened(Exception):
    """Raised in place of a run: the first --quick case, or a run's checkpoint keys."""


@pytest.fixture
def quick_case_keys(monkeypatch):
    """``quick_case_keys(module, runner, first) -> (case, keys)``: the first case of a
    script's ``--quick`` run (``module.run`` stopped at its study runner, the function
    ``module.<runner>``, whose arguments ``first`` reads the case from) and the checkpoint
    keys that ``module.run_case(**case)`` opens its run with (the run not made)."""
    def keys(module, runner, first):
        cases = []

        def stop(*args, **kwargs):
            cases.append(first(*args, **kwargs))
            raise _Opened
        monkeypatch.setattr(module, runner, stop)
        with pytest.raises(_Opened):
            module.run(module.build_parser().parse_args(["--quick"]))

        def opened(scene, state, loop, checkpoints, frames, bar):
            raise _Opened(checkpoints.keys)
        monkeypatch.setattr(module.ResumableRun, "open", opened)
        with pytest.raises(_Opened) as got:
            module.run_case(**cases[0])
        return cases[0], got.value.args[0]

    return keys
