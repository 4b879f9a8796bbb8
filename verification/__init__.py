"""The verification scripts, one per thesis benchmark, importable from the repository root.

``from verification import strip_footing`` gives the script as a module: its model
and reference functions, ``QUICK``, ``build_parser`` and ``run(args) -> Report``
(see :mod:`pfem_skfem.harness.report`). Each also runs as
``python verification/<case>.py`` and under ``pfem-skfem verify``.
"""
