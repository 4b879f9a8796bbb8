"""The harness is a leaf (issue 37): it imports nothing of the science."""
import ast
from pathlib import Path

import pfem_skfem

PACKAGE = Path(pfem_skfem.__file__).resolve().parent
HARNESS = PACKAGE / "harness"


def _imports(path):
    """The modules ``path`` imports (relative imports made absolute), at any depth."""
    tree = ast.parse(path.read_text())
    package = ["pfem_skfem", *path.relative_to(PACKAGE).parent.parts]
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[:len(package) - node.level + 1]
                found.append(".".join(base + ([node.module] if node.module else [])))
            else:
                found.append(node.module)
    return found


def test_the_harness_imports_no_science_module():
    files = sorted(HARNESS.glob("*.py"))
    assert {f.stem for f in files} >= {"report", "options", "progress", "sweeps", "store",
                                       "figures"}
    for path in files:
        for name in _imports(path):
            if name == "pfem_skfem" or name.startswith("pfem_skfem."):
                assert name == "pfem_skfem.harness" or name.startswith("pfem_skfem.harness."), \
                    f"{path.name} imports {name}"


def test_quick_sizes_leave_every_option_the_user_gave():
    """--quick sets the options the user did not give, and none that were given, even at
    their default value (a --steps 300 at the default 300 once became the quick 100 and
    silently tripled the time step of a run asked for by hand)."""
    from pfem_skfem.harness.options import base_parser, positive_int
    parser = base_parser("x", quick=dict(steps=100, n=4))
    parser.add_argument("--steps", type=positive_int, default=300)
    parser.add_argument("--n", type=positive_int, default=16)
    args = parser.parse_args(["--quick"])
    assert (args.steps, args.n) == (100, 4)
    args = parser.parse_args(["--quick", "--steps", "300"])
    assert (args.steps, args.n) == (300, 4)
    args = parser.parse_args(["--quick", "--n=16", "--steps", "7"])
    assert (args.steps, args.n) == (7, 16)
    args = parser.parse_args(["--steps", "300"])
    assert (args.steps, args.n) == (300, 16)
