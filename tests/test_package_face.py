"""The package face (issue 37): the docstring of pfem_skfem numbers the PFEM step and runs
it, as a doctest, on a 3 x 3 particle scene."""
import doctest

import pfem_skfem


def test_the_package_docstring_runs():
    result = doctest.testmod(pfem_skfem, optionflags=doctest.NORMALIZE_WHITESPACE,
                             verbose=False)
    assert result.attempted >= 10
    assert result.failed == 0
