#!/usr/bin/env bash
# Set up (if needed) and run the whole test suite: Rust core tests, then pytest in
# three random orders (pytest-randomly), each seed printed, so that a test that only
# passes after another one fails here:
#   order 1: the whole suite;
#   orders 2 and 3: the whole suite but the README-command tests (marker `commands`:
#   each already runs in a fresh process, so their order cannot matter), to keep CI
#   within about 10 minutes.
# Rerun one order with the command printed above it. Arguments go to every pytest run;
# PLANSYNTH_TEST_SEEDS="s1 s2 s3" fixes the seeds.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
. .venv/bin/activate
cargo test -q -p plansynth-core
read -r -a seeds <<< "${PLANSYNTH_TEST_SEEDS:-$(python -c 'import random; print(*(random.randrange(1, 2**31) for _ in range(3)))')}"
pytest_order() {
  local n=$1 seed=$2; shift 2
  echo "== pytest, random order $n of ${#seeds[@]}: seed $seed" \
       "(rerun: python -m pytest -p no:cacheprovider -p randomly --randomly-seed=$seed $*)"
  python -m pytest -q -p no:cacheprovider -p randomly --randomly-seed="$seed" "$@"
}
pytest_order 1 "${seeds[0]}" "$@"
for i in 1 2; do
  pytest_order $((i + 1)) "${seeds[$i]}" -m "not commands" "$@"
done
