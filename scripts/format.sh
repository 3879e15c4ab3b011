#!/usr/bin/env bash
# Formats every C++ source of the tree with .clang-format (clang-format 14, Debian bookworm's),
# or with --check lists the files it would change and fails (ctest format.check).
#   scripts/format.sh [--check]
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-format > /dev/null || { echo "clang-format missing: scripts/install-deps.sh installs it"; exit 1; }
# Tracked files and new ones not yet added (not the ignored build tree).
mapfile -t files < <(git ls-files --cached --others --exclude-standard '*.cpp' '*.hpp' '*.h' '*.ino')
if [ "${1:-}" = "--check" ]; then
  unformatted=()
  for file in "${files[@]}"; do
    clang-format --dry-run --Werror "$file" > /dev/null 2>&1 || unformatted+=("$file")
  done
  [ ${#unformatted[@]} -eq 0 ] && { echo "ok   ${#files[@]} files formatted"; exit 0; }
  printf 'not formatted (scripts/format.sh fixes it): %s\n' "${unformatted[@]}"
  exit 1
fi
clang-format -i "${files[@]}"
