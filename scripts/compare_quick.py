"""Compare two folders of `pfem-skfem verify --quick --json-dir` JSON, bit for bit.

Usage: python scripts/compare_quick.py BASELINE_DIR NEW_DIR [case ...]
(record BASELINE_DIR with `.venv/bin/pfem-skfem verify --quick --json-dir BASELINE_DIR` before
moving code, NEW_DIR the same way after; CONTRIBUTING.md, "Refactoring").
Every value, reference, tolerance, pass flag, param and extra entry must be equal; keys
that hold timings (named seconds*, wall_time*, *_time, t_compile, t_conic, t_solve, ...)
and the landslide's 'profile' path are ignored. The top-level 'tables' key is skipped too:
tables (Report.add_table) print what the quantities and extra hold. Exit 1 on any difference.
"""
import json
import sys
from pathlib import Path

TIMING_PREFIX = ("seconds", "wall_time", "wall", "t_compile", "t_conic", "t_solve", "t_detect",
                 "t_remesh", "t_map", "t_assemble", "t_move", "solve_time", "compile_time",
                 "time_s", "time_reference", "sitting", "elapsed")


def timing(key):
    key = str(key)
    return key.startswith(TIMING_PREFIX) \
        or key.endswith(("_seconds", "_time_s", "_wall", "_solve_s")) \
        or key in {"profile", "machine", "boot"}


def diff(a, b, path, out):
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b), key=str):
            if timing(k):
                continue
            if k not in a or k not in b:
                out.append(f"{path}.{k}: only in {'new' if k in b else 'baseline'}")
            else:
                diff(a[k], b[k], f"{path}.{k}", out)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append(f"{path}: length {len(a)} vs {len(b)}")
        for i, (x, y) in enumerate(zip(a, b)):
            diff(x, y, f"{path}[{i}]", out)
    elif a != b and not (a != a and b != b):        # NaN == NaN here
        out.append(f"{path}: {a!r} vs {b!r}")


def main(base, new, cases):
    base, new = Path(base), Path(new)
    files = sorted(base.glob("*.json")) if not cases else [base / f"{c}.quick.json" for c in cases]
    bad = 0
    for f in files:
        g = new / f.name
        if not g.exists():
            print(f"{f.name}: missing in {new}"); bad += 1; continue
        out = []
        a, b = json.loads(f.read_text()), json.loads(g.read_text())
        a.pop("tables", None), b.pop("tables", None)      # what quantities and extra hold
        qa = {q["name"]: q for q in a.get("quantities", [])}
        qb = {q["name"]: q for q in b.get("quantities", [])}
        a["quantities"], b["quantities"] = qa, qb
        diff(a, b, f.stem, out)
        print(f"{f.name}: {'identical' if not out else f'{len(out)} difference(s)'}")
        for line in out[:20]:
            print("   ", line)
        bad += bool(out)
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3:])
