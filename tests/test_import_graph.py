"""The import graph runs with the data flow (issue 37): no arrow from the scene to the
drivers, none from the materials to the problems, none from the harness to the science.

The imports are read from the source with ``ast`` (those inside functions too), so the
test checks whatever exists: a unit not there yet is skipped, not failed."""
import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "pfem_skfem"
# what the harness may not import: every unit of the physics, the engine and its backends
SCIENCE = ("discretisation", "materials", "materials_axisymmetric", "materials_rate", "problems",
           "pfem", "scene", "drivers", "io", "operators", "operators_dynamic", "fields",
           "geometry", "elements", "periodic", "meshes")


def module_name(path):
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imported(path):
    """The absolute names of the modules that ``path`` imports (``from a import b``: a and
    a.b, since b may be a module)."""
    name = module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    names = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")
                anchor = anchor[:len(anchor) - (node.level - 1)]
                base = ".".join(anchor + ([base] if base else []))
            names.add(base)
            names.update(f"{base}.{alias.name}" for alias in node.names)
    return names


def unit_modules(unit):
    """The source files of ``pfem_skfem/<unit>`` (a folder or a module), or None."""
    folder, module = PACKAGE / unit, PACKAGE / f"{unit}.py"
    if folder.is_dir():
        return sorted(folder.rglob("*.py"))
    return [module] if module.is_file() else None


def arrows(unit, targets):
    files = unit_modules(unit)
    if files is None:
        pytest.skip(f"pfem_skfem/{unit} does not exist yet")
    bad = []
    for path in files:
        for name in sorted(imported(path)):
            if any(name == f"pfem_skfem.{t}" or name.startswith(f"pfem_skfem.{t}.")
                   for t in targets):
                bad.append(f"{path.relative_to(PACKAGE.parent)} imports {name}")
    return bad


def test_the_scene_does_not_import_the_drivers():
    assert arrows("scene", ["drivers"]) == []


def test_the_materials_do_not_import_the_problems():
    if not (PACKAGE / "materials").is_dir():
        pytest.skip("pfem_skfem/materials/ does not exist yet")
    assert arrows("materials", ["problems"]) == []


def test_the_harness_imports_no_science():
    assert arrows("harness", SCIENCE) == []


def test_the_discretisation_imports_nothing_above_it():
    assert arrows("discretisation", [u for u in SCIENCE if u != "discretisation"]) == []


def test_the_reader_sees_relative_imports():
    """The parser resolves ``from ..x import y`` (else the tests above would pass vacuously)."""
    names = imported(PACKAGE / "scene" / "scene.py")
    assert "pfem_skfem.scene.config" in names
    assert "pfem_skfem.pfem.state.initial_state" in names
