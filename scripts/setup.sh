#!/usr/bin/env bash
# Create .venv and install plansynth (building its Rust core) with every dependency,
# including every extra (baselines, test, docs, dev), at exactly the versions of
# requirements.lock (CPython 3.11 on Linux x86_64; hashes checked), so that every
# machine gets the same packages. Safe to rerun. The installer is pinned too (PIP_VERSION); the build backend
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
# Compile the package's bytecode, as installing a wheel does: an editable install under
# PYTHONDONTWRITEBYTECODE would otherwise compile every module at every start (0.1-0.25 s
# of each `plansynth` command, which bench grid times through the CLI). A stale file is
# ignored (Python checks the source's time stamp), so editing afterwards is safe.
python -m compileall -q python/plansynth
