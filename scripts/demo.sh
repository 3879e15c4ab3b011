#!/usr/bin/env bash
# The main job on its built-in default: installs what is missing, builds the one executable
# the demo runs if needed (not the tests and benchmarks: scripts/test.sh builds those), then
# runs `scanbus demo` (services as separate processes on the loopback DDS profile).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh scanbus > build.log 2>&1 || { tail -50 build.log; exit 1; }
exec build/services/cli/scanbus demo "$@"
