#!/usr/bin/env bash
# Set up (if needed) and run the whole test suite: Rust core tests, then pytest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
. .venv/bin/activate
cargo test -q -p plansynth-core
python -m pytest -q -p no:cacheprovider "$@"
