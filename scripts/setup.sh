#!/usr/bin/env bash
# Create .venv and install plansynth (building its Rust core) with every dependency,
# including the test and benchmark extras, at exactly the versions of requirements.lock
# (CPython 3.11 on Linux x86_64; hashes checked), so that every machine gets the same
# packages. Safe to rerun. The installer is pinned too (PIP_VERSION); the build backend
# (maturin) comes from the lock, so nothing unpinned is fetched.
# Maintainers: scripts/lock-deps.sh and scripts/upgrade-deps.sh regenerate the lock.
set -euo pipefail
cd "$(dirname "$0")/.."
PIP_VERSION=26.3
PY=${PYTHON:-python3.11}
command -v "$PY" >/dev/null 2>&1 || PY=python3
if [ ! -x .venv/bin/python ]; then
  "$PY" -m venv .venv
fi
. .venv/bin/activate
python -m pip install -q "pip==$PIP_VERSION"
python -m pip install -q -r requirements.lock
python -m pip install -q --no-deps --no-build-isolation -e .
