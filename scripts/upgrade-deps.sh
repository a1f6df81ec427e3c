#!/usr/bin/env bash
# For maintainers: move the lock to the newest releases pyproject.toml allows, but only
# if the whole suite passes with them.
#
#   bash scripts/upgrade-deps.sh              # newest releases
#   bash scripts/upgrade-deps.sh --keep       # re-resolve keeping today's pins where allowed
#                                             # (e.g. after adding a dependency), tested the same way
#   bash scripts/upgrade-deps.sh --lowest     # check pyproject's lower bounds: the lowest versions
#                                             # it allows, tested the same way; never writes the lock
#   bash scripts/upgrade-deps.sh -o FILE      # a trial run: write the tested lock to FILE, leave
#                                             # requirements.lock alone (combines with --keep)
#
# 1. resolve a new lock (scripts/lock-deps.sh) into a temporary folder;
# 2. copy the checkout there, create a throwaway venv, install exactly the new lock and
#    plansynth (building the Rust core);
# 3. run cargo test and the whole pytest suite in random order (seed printed);
# 4. only if all of that passes, show what changed and write the new lock to
#    requirements.lock (or to FILE with -o). Otherwise requirements.lock is left as it
#    was, and the folder is kept.
# Then commit requirements.lock (and rerun scripts/setup.sh to use it here).
set -euo pipefail
here=$(pwd)
cd "$(dirname "$0")/.."
repo=$(pwd)
mode=--upgrade
target=requirements.lock
while [ $# -gt 0 ]; do
  case "$1" in
    --keep) mode= ;;
    --lowest) mode=--lowest ;;
    -o|--output) [ $# -ge 2 ] || { echo "$0: $1 needs a file" >&2; exit 2; }; target="$2"; shift ;;
    *) echo "usage: $0 [--keep | --lowest] [-o FILE]" >&2; exit 2 ;;
  esac
  shift
done
case "$target" in /*) ;; requirements.lock) target="$repo/$target" ;; *) target="$here/$target" ;; esac
work=$(mktemp -d -t plansynth-upgrade.XXXXXX)
echo "working in $work"
if [ -n "$mode" ]; then
  bash scripts/lock-deps.sh "$mode" -o "$work/requirements.lock"
else
  bash scripts/lock-deps.sh -o "$work/requirements.lock"
fi
mkdir "$work/src"
git ls-files -co --exclude-standard -z | tar --null -T - -cf - | tar -xf - -C "$work/src"
cp "$work/requirements.lock" "$work/src/requirements.lock"
# The copy lives elsewhere, so data that sits beside the checkout (the shared reactive
# suite, ../shared/grid-reactive/) is passed on by its path.
if [ -z "${PLANSYNTH_REACTIVE_SUITE:-}" ] && [ -d "$repo/../shared/grid-reactive" ]; then
  PLANSYNTH_REACTIVE_SUITE=$(cd "$repo/../shared/grid-reactive" && pwd)
  export PLANSYNTH_REACTIVE_SUITE
fi
(
  cd "$work/src"
  CARGO_TARGET_DIR="$work/target" bash scripts/setup.sh
  . .venv/bin/activate
  CARGO_TARGET_DIR="$work/target" cargo test -q -p plansynth-core
  python -m pytest -q -p no:cacheprovider -p randomly
) || { echo "the suite FAILED with the new lock: requirements.lock is unchanged (see $work)" >&2; exit 1; }
if [ "$mode" = --lowest ]; then
  echo "the suite passed with the lowest versions pyproject.toml allows (requirements.lock unchanged)"
  rm -rf "$work"
  exit 0
fi
echo "the suite passed with the new lock; changes (< requirements.lock, > the new lock):"
diff <(grep -E '^[a-zA-Z0-9]' requirements.lock 2>/dev/null | sed 's/ .*//') \
     <(grep -E '^[a-zA-Z0-9]' "$work/requirements.lock" | sed 's/ .*//') || true
cp "$work/requirements.lock" "$target"
rm -rf "$work"
if [ "$target" = "$repo/requirements.lock" ]; then
  echo "wrote requirements.lock: commit it, and rerun scripts/setup.sh to use it here"
else
  echo "wrote $target (requirements.lock unchanged)"
fi
