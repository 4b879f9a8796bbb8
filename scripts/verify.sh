#!/usr/bin/env bash
# Set up .venv and run the main job: every verification case at --quick size, one
# summary table, JSON results in results/<case>.quick.json (a full-size run writes
# results/<case>.json, so neither replaces the other). Extra arguments go to `pfem-skfem verify`
# (e.g. case names).
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -m venv .venv && .venv/bin/pip install -e . && .venv/bin/pfem-skfem verify --quick --json-dir results "$@"
