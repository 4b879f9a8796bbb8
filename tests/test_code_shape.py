"""The package's shape as CONTRIBUTING states it: small modules, short parameter lists."""
import ast
from pathlib import Path

import pfem_skfem

PACKAGE = Path(pfem_skfem.__file__).parent


def modules():
    return sorted(PACKAGE.rglob("*.py"))


def test_every_function_takes_fewer_than_twelve_parameters():
    # named parameters (positional and keyword, self and cls left out); a **settings that
    # passes a solver's settings through is not counted: what grows with every term or
    # option goes into a record (a ScaledStep, StepFacts, Checkpoints) instead
    long = []
    for path in modules():
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                a = node.args
                names = [x.arg for x in a.posonlyargs + a.args + a.kwonlyargs
                         if x.arg not in ("self", "cls")]
                if len(names) >= 12:
                    long.append(f"{path.relative_to(PACKAGE)}:{node.lineno} {node.name} "
                                f"({len(names)})")
    assert not long, "functions with 12 parameters or more: " + "; ".join(long)


def test_no_module_is_over_600_lines():
    big = [f"{p.relative_to(PACKAGE)} ({n})" for p in modules()
           if (n := len(p.read_text().splitlines())) > 600]
    assert not big, "modules over 600 lines: " + ", ".join(big)
