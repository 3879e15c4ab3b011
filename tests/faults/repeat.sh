#!/usr/bin/env bash
# Runs one ctest again and again, stopping at the first failure, with LOAD busy processes
# beside it (CI runs its tests two at a time on two cores): how a flaky test is caught and
# a fix shown (docs/faults.md). Not in CI: 20 runs of a fault test take 10 minutes.
#   tests/faults/repeat.sh [BUILD_DIR] TEST_NAME [RUNS] [LOAD]
#   e.g. tests/faults/repeat.sh build faults.mav_kill_restart 20 2
set -euo pipefail
build=${1:?build directory}
name=${2:?test name}
runs=${3:-20}
load=${4:-0}
burners=()
trap 'kill "${burners[@]}" 2> /dev/null || true' EXIT
for _ in $(seq "$load"); do (while :; do :; done) & burners+=($!); done
for run in $(seq "$runs"); do
  start=$SECONDS
  if ctest --test-dir "$build" -R "^${name//./\\.}\$" --output-on-failure > "/tmp/repeat_${name}.log" 2>&1; then
    echo "run $run of $runs: passed in $((SECONDS - start)) s"
  else
    echo "run $run of $runs: FAILED after $((SECONDS - start)) s (output in /tmp/repeat_${name}.log)"
    exit 1
  fi
done
echo "$name: $runs of $runs passed with $load busy processes beside it"
