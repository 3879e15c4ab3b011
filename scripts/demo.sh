#!/usr/bin/env bash
# The main job on its built-in default: installs what is missing, builds if needed, then
# runs `scanbus demo` (services as separate processes on the loopback DDS profile).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh > build.log 2>&1 || { tail -50 build.log; exit 1; }
exec build/services/cli/scanbus demo "$@"
