#!/usr/bin/env bash
# Set up .venv and build the book into book/_build/html (needs npm once, to fetch
# MathJax for offline maths). Extra arguments go to book/build.py (e.g. --pages silo;
# any Sphinx warning fails the build, --allow-warnings lists them without failing).
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -m venv .venv && .venv/bin/pip install -e ".[book]" && .venv/bin/python book/build.py "$@"
