#!/usr/bin/env bash
# Set up (if needed) and run the whole test suite: Rust core tests, then pytest in
# two random orders (pytest-randomly; PLANSYNTH_TEST_ORDERS=3 for more), each seed
# printed, so that a test that only passes after another one fails here:
#   order 1: the whole suite, with its 20 slowest tests listed (CI keeps under 15 min);
#   the other orders: the whole suite but the documentation-command tests (marker
#   `commands`: each already runs in a fresh process, so their order cannot matter).
# The orders are independent pytest sessions, so they run at the same time (each in its
# own --basetemp), one per core: order 1 prints as it goes, the others when they end.
# PLANSYNTH_TEST_SERIAL=1 runs them one after another instead.
# Before pytest: the documentation site builds without a warning (`mkdocs build --strict`,
# into a temporary folder) and the code checks: the import contracts (`lint-imports`,
# [tool.importlinter] in pyproject.toml), `ruff check`, `ruff format --check` and
# `cargo fmt --check` (PLANSYNTH_LINT=0 skips them, for a quick local run).
# Rerun one order with the command printed above it. Arguments go to every pytest run;
# PLANSYNTH_TEST_SEEDS="s1 s2 s3" fixes the seeds.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
. .venv/bin/activate
cargo test -q -p plansynth-core
if [ "${PLANSYNTH_LINT:-1}" = 1 ]; then
  echo "== lint-imports, ruff check, ruff format --check, cargo fmt --check"
  lint_status=0
  lint-imports || lint_status=1
  ruff check || lint_status=1
  ruff format --check || lint_status=1
  cargo fmt --check || lint_status=1
  [ "$lint_status" = 0 ] || { echo "the code checks FAILED (see above)" >&2; exit 1; }
fi
echo "== mkdocs build --strict"
site=$(mktemp -d -t plansynth-site.XXXXXX)
NO_MKDOCS_2_WARNING=1 mkdocs build --strict --quiet --site-dir "$site" || { rm -rf "$site"; echo "the documentation site does not build" >&2; exit 1; }
rm -rf "$site"
orders=${PLANSYNTH_TEST_ORDERS:-2}
read -r -a seeds <<< "${PLANSYNTH_TEST_SEEDS:-$(python -c "import random; print(*(random.randrange(1, 2**31) for _ in range($orders)))")}"
work=$(mktemp -d -t plansynth-test.XXXXXX)
pids=()
trap 'kill "${pids[@]}" 2>/dev/null || true; rm -rf "$work"' EXIT
pytest_order() {
  local n=$1 seed=$2; shift 2
  echo "== pytest, random order $n of ${#seeds[@]}: seed $seed" \
       "(rerun: python -m pytest -p no:cacheprovider -p randomly --randomly-seed=$seed${*:+ ${*@Q}})"
  python -m pytest -q -p no:cacheprovider -p randomly --randomly-seed="$seed" --basetemp="$work/order$n" "$@"
}
if [ "${PLANSYNTH_TEST_SERIAL:-0}" = 1 ]; then
  pytest_order 1 "${seeds[0]}" "$@"
  for ((i = 1; i < ${#seeds[@]}; i++)); do
    pytest_order $((i + 1)) "${seeds[$i]}" -m "not commands" "$@"
  done
  exit 0
fi
for ((i = 1; i < ${#seeds[@]}; i++)); do
  pytest_order $((i + 1)) "${seeds[$i]}" -m "not commands" "$@" > "$work/order$((i + 1)).log" 2>&1 &
  pids+=($!)
done
status=0
pytest_order 1 "${seeds[0]}" --durations=20 "$@" || status=$?
for ((i = 1; i < ${#seeds[@]}; i++)); do
  rc=0
  wait "${pids[$((i - 1))]}" || rc=$?
  cat "$work/order$((i + 1)).log"
  [ "$rc" = 0 ] || status=$rc
done
exit "$status"
