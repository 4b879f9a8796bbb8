"""Every option of the verification scripts moved once off its --quick value, offline:
the runs of :mod:`pfem_skfem.harness.audit` (book/studies.md, "Options away from their
defaults"). A script beside the package: the harness imports nothing outside it, and the
case list and the quick times are the CLI's.

Run: python scripts/audit_options.py --all --json /tmp/audit.json   (or name scripts)
"""
import argparse
import json
import math
from pathlib import Path
import sys

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from pfem_skfem.cli import QUICK_SECONDS, available_cases                  # noqa: E402
from pfem_skfem.harness.audit import audit_script, option_moves            # noqa: E402


def main(argv=None):
    """The audit of the scripts named (or ``--all``, cheapest first by their quick CPU
    seconds), a line a run, ``--json`` the rows."""
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scripts", nargs="*", help="scripts of verification/ (default: --all)")
    p.add_argument("--all", action="store_true", help="every script, cheapest first")
    p.add_argument("--max-quick", type=float, default=math.inf,
                   help="only the scripts whose --quick takes at most this many CPU s")
    p.add_argument("--list", action="store_true", help="the moved values, no run")
    p.add_argument("--limit", type=float, default=600,
                   help="wall-clock seconds a run may take before it is stopped")
    p.add_argument("--json", metavar="PATH", help="write the rows to PATH (after each script)")
    args = p.parse_args(argv)
    names = args.scripts or (available_cases() if args.all else [])
    names = sorted((n for n in names if QUICK_SECONDS.get(n, 0) <= args.max_quick),
                   key=lambda n: QUICK_SECONDS.get(n, math.inf))
    rows = []
    for name in names:
        if args.list:
            for dest, moved, why in option_moves(name):
                print(f"{name:28s} --{dest:20s} {' '.join(moved) if moved else '-':34s} {why}")
            continue
        rows += audit_script(name, log=sys.stdout, limit=args.limit)
        if args.json:
            Path(args.json).write_text(json.dumps(rows, indent=1))
    failing = [r for r in rows if r.get("code")]
    if rows:
        print(f"{len(failing)} of {sum(1 for r in rows if r['argv'])} moved options fail; "
              f"{sum(r.get('cpu_s', 0) for r in rows):.0f} s CPU")
    return 1 if failing else 0


if __name__ == "__main__":
    sys.exit(main())
