"""How a verification script runs (the contract of :mod:`.report`) and its machinery:
options, progress bars, sweeps on Dask, files named by their parameters, figures.

A leaf of the package: it imports nothing of the science (``tests/test_harness.py``), so
that the engine's modules can be read without it and it can be read without them.
"""
