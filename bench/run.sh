#!/usr/bin/env bash
# Builds and runs the benchmarks on one core (taskset), 5 repetitions, and prints medians.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh > /dev/null
for bench in room_measurement_bench scan_matcher_bench pose_estimation_bench mcap_writer_bench; do
  taskset -c 0 build/bench/$bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
    --benchmark_min_time=0.5 "$@"
done
