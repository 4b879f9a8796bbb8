"""Timing scripts, importable from the repository root (``from benchmarks import static_step``)."""
