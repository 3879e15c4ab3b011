#!/usr/bin/env bash
# Configures and builds scanbus into build/ (two jobs: PCL translation units are heavy).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo > build-configure.log 2>&1 || { cat build-configure.log; exit 1; }
cmake --build build -j2
