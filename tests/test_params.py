"""harness.params.keys_of: a run's parameters (a dataclass) as its checkpoint keys."""
from dataclasses import dataclass

import pytest

from pfem_skfem.harness.params import keys_of
from pfem_skfem.harness.store import checkpoint_path


@dataclass(frozen=True)
class Run:
    a: float
    n: int = 4
    solver: str = "clarabel"


def test_keys_are_the_fields_less_those_omitted_with_the_given_beside(tmp_path):
    run = Run(0.5)
    assert keys_of(run) == {"a": 0.5, "n": 4, "solver": "clarabel"}
    assert keys_of(run, omit=("solver",), n=8, extra="x") == {"a": 0.5, "n": 8, "extra": "x"}
    # the keys name the checkpoint: a field changed, another file
    one, other = (checkpoint_path(tmp_path, "run", keys_of(r, omit=("solver",)))
                  for r in (run, Run(0.5, n=5)))
    assert one != other
    assert checkpoint_path(tmp_path, "run", keys_of(Run(0.5, solver="scs"), omit=("solver",))) \
        == one


def test_omitting_a_name_that_is_no_field_is_an_error():
    with pytest.raises(ValueError, match="no field"):
        keys_of(Run(0.5), omit=("solvr",))
