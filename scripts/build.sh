#!/usr/bin/env bash
# Configures and builds scanbus into build/ (two jobs: PCL translation units are heavy):
# everything, or only the TARGETs named (scripts/demo.sh needs only `scanbus`).
#   scripts/build.sh [TARGET ...]
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo > build-configure.log 2>&1 || { cat build-configure.log; exit 1; }
targets=()
for target in "$@"; do targets+=(--target "$target"); done
cmake --build build -j2 "${targets[@]}"
