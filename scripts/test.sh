#!/usr/bin/env bash
# Set up .venv and run the tests (the README's test command; .ci/run calls this file).
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -m venv .venv && .venv/bin/pip install -e ".[test]" && .venv/bin/python -m pytest -q "$@"
