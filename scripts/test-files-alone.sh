#!/usr/bin/env bash
# Run every test file on its own, each in a fresh pytest process, so that a file that
# only passes after another one has run (its fixtures, its imports, library state it
# never set up) fails here. Each file runs once in file order (-p no:randomly) and, with
# --random, once more in a random order (-p randomly, seed printed).
#
#   bash scripts/test-files-alone.sh                  # every tests/**/test_*.py
#   bash scripts/test-files-alone.sh --random         # also a random order per file
#   bash scripts/test-files-alone.sh tests/reach/test_cli.py ...   # just these files
#
# Extra pytest arguments go after `--`. Prints one line per file and run, then the files
# that failed with the command that reruns each; exit status 1 if any did.
# Not part of CI: it starts a fresh interpreter per file (several minutes in all).
set -euo pipefail
cd "$(dirname "$0")/.."
random=0
files=()
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --random) random=1 ;;
    --) shift; extra=("$@"); break ;;
    *) files+=("$1") ;;
  esac
  shift
done
if [ ${#files[@]} -eq 0 ]; then
  mapfile -t files < <(find tests -name 'test_*.py' | sort)
fi
py=.venv/bin/python
[ -x "$py" ] || py=python
failed=()
for f in "${files[@]}"; do
  modes=("-p no:randomly")
  [ "$random" = 1 ] && modes+=("-p randomly --randomly-seed=$(( (RANDOM << 15 | RANDOM) + 1 ))")
  for mode in "${modes[@]}"; do
    start=$SECONDS
    # shellcheck disable=SC2086  # $mode is two or three words on purpose
    rc=0
    "$py" -m pytest -q -p no:cacheprovider $mode "$f" ${extra[@]+"${extra[@]}"} >/dev/null 2>&1 || rc=$?
    if [ "$rc" = 0 ]; then
      echo "ok     $((SECONDS - start))s  $f  ($mode)"
    elif [ "$rc" = 5 ]; then  # every test of the file is slow (deselected without --runslow)
      echo "ok     $((SECONDS - start))s  $f  ($mode; no test without --runslow)"
    else
      echo "FAILED $((SECONDS - start))s  $f  ($mode)"
      failed+=("$py -m pytest -q -p no:cacheprovider $mode $f")
    fi
  done
done
echo "${#files[@]} files, ${#failed[@]} failed run(s)"
if [ ${#failed[@]} -gt 0 ]; then
  printf '  rerun: %s\n' "${failed[@]}"
  exit 1
fi
