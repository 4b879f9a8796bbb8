#!/usr/bin/env bash
# Set up .venv and run the main job: every verification case at --quick size, one
# summary table, JSON results in results/<case>.quick.json and figures in
# results/quick/<case>/ (a full-size run writes results/<case>.json and results/<case>/, so
# neither replaces the other), one process per core (--jobs; about 3 minutes on two).
# Extra arguments go to `pfem-skfem verify` (e.g. case names, --jobs 1).
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -m venv .venv && .venv/bin/pip install -e . && .venv/bin/pfem-skfem verify --quick --json-dir results "$@"
