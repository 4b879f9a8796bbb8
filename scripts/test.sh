#!/usr/bin/env bash
# Set up .venv and run the tests (the README's test command; .ci/run calls this file),
# one pytest-xdist worker per core (a file with a module fixture marks itself as one
# xdist_group, kept on one worker, and every test reading a script's quick run, the session
# fixture quick_run of tests/conftest.py, is in that script's group, so the run is made
# once); `bash scripts/test.sh -n 0` runs them in one process.
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -m venv .venv && .venv/bin/pip install -e ".[test]" && .venv/bin/python -m pytest -q -n auto --dist loadgroup "$@"
