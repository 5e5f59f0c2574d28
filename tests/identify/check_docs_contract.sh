#!/bin/sh
# The project carries its own documentation: fails when a tracked file points at the old
# external design document again (it is not in the repository, so users cannot follow the
# pointer), or at a docs/*.md file that does not exist. Usage: check_docs_contract.sh ROOT
set -eu
root=$1
cd "$root"
# Written with a bracket so that this script does not match itself.
old='design[.]md'
docs='docs/[A-Za-z0-9_.-]+[.]md'
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  search() { git grep -n -I -E "$1" -- . || true; }
  names() { git grep -h -o -I -E "$1" -- . || true; }
else
  # A source tree without git (e.g. an unpacked archive): every file except build trees.
  search() { grep -rnI -E "$1" --exclude-dir=.git --exclude-dir='build*' . || true; }
  names() { grep -rhoI -E "$1" --exclude-dir=.git --exclude-dir='build*' . || true; }
fi
status=0
hits=$(search "$old")
if [ -n "$hits" ]; then
  echo "References to a design document that is not in the repository (point to docs/ instead):"
  echo "$hits"
  status=1
fi
for f in $(names "$docs" | sort -u); do
  if [ ! -f "$f" ]; then
    echo "Referenced but missing: $f"
    status=1
  fi
done
for f in docs/data-format.md docs/model.md; do
  [ -f "$f" ] || { echo "Missing: $f"; status=1; }
done
exit $status
