"""The import graph runs with the data flow (issue 37): no arrow from the scene to the
drivers, none from the materials to the problems, none from the harness to the science,
and no cycle anywhere (issue 52).

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


def imports(path):
    """(line, module, names) of every import statement of ``path``, at module level or
    inside a function: ``import a.b`` gives (line, "a.b", []), ``from ..a import b, c``
    (line, "<package>.a", ["b", "c"]) with the relative name made absolute."""
    name = module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield node.lineno, alias.name, []
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")
                anchor = anchor[:len(anchor) - (node.level - 1)]
                base = ".".join(anchor + ([base] if base else []))
            yield node.lineno, base, [alias.name for alias in node.names]


def imported(path):
    """The absolute names of the modules that ``path`` imports (``from a import b``: a and
    a.b, since b may be a module)."""
    names = set()
    for _, base, members in imports(path):
        names.add(base)
        names.update(f"{base}.{member}" for member in members)
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


def package_graph():
    """{module: {imported module: line}} over every package-internal import, module-level
    and inside functions; ``from a import b`` is an arrow to a.b when b is a module of the
    package, else to a (the implicit import of a module's parent packages is left out)."""
    modules = {module_name(path): path for path in PACKAGE.rglob("*.py")}
    graph = {}
    for name, path in modules.items():
        arrows = graph.setdefault(name, {})
        for line, base, members in imports(path):
            targets = [f"{base}.{m}" if f"{base}.{m}" in modules else base for m in members]
            for target in targets or [base]:
                if target in modules and target != name:
                    arrows.setdefault(target, line)
    return graph


def cycles(graph):
    """The strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_the_package_has_no_import_cycle():
    """No module reaches itself through the package's imports, those deferred into
    functions included (a cycle there is hidden until the function runs)."""
    graph = package_graph()
    assert "pfem_skfem.runfolder" in graph["pfem_skfem.cli"]   # read inside functions too
    found = []
    for component in cycles(graph):
        arrows = [f"  {a} -> {b} (line {graph[a][b]})"
                  for a in component for b in sorted(graph[a]) if b in component]
        found.append(f"cycle among {', '.join(component)}:\n" + "\n".join(arrows))
    assert not found, "\n".join(found)


def test_the_cycle_finder_finds_a_cycle():
    """A three-module ring and a two-module one, beside an acyclic tail (else the test
    above could pass vacuously)."""
    graph = {"a": {"b": 1}, "b": {"c": 1}, "c": {"a": 1, "d": 1}, "d": {},
             "e": {"f": 1}, "f": {"e": 1}}
    assert cycles(graph) == [["a", "b", "c"], ["e", "f"]]
