#!/usr/bin/env bash
# Soak: MINUTES (10) of a 100 Hz LaserScan of 1,081 rays (a simulated scenario I flight,
# `scanbus sim mav --laser-rate 100 --laser-rays 1081`) replayed in real time through
# scan_matcher, pose_estimation and cloud_assembly, each its own process on the loopback
# profile. bench/soak_monitor prints every PERIOD (30) s each service's resident memory and
# the scan -> pose and scan -> assembled cloud latencies, then judges the span after a
# 120 s warm-up: memory flat (within 5 % + 5 MB), pose latency median not growing
# (within 20 % + 2 ms), no sample lost by a service after the warm-up (Health
# samples_lost); exit 1 when one misses.
# cloud_assembly's buffers are bounded (window_age, window_points, max_voxels) and grow
# until full: with the defaults (600 s, 20 M points, 5 M voxels) they are still filling at
# minute 10 here (the 1 cm continuous map gains about 15,000 voxels a second from 2 cm
# range noise). The soak sets a 60 s window and 1 M voxels so both fill inside the warm-up,
# and then checks that they hold.
# Usage: bench/soak.sh [MINUTES] [PERIOD]
set -euo pipefail
cd "$(dirname "$0")/.."
minutes=${1:-10} period=${2:-30}
scripts/build.sh > /dev/null
export SCANBUS_DOMAIN_ID=${SCANBUS_DOMAIN_ID:-87}
scanbus=build/services/cli/scanbus
work=$(mktemp -d)
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2> /dev/null || true; done
  wait 2> /dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
seconds=$((minutes * 60))
[ -t 1 ] && echo "simulating a $((seconds + 20)) s flight at 100 Hz, 1,081 rays ..."
"$scanbus" sim mav --scenario 1 --duration $((seconds + 20)) --laser-rate 100 --laser-rays 1081 \
  --out "$work/flight.mavlog" > /dev/null
printf 'sensor_replay:\n  log: %s\n  rate: 1\n  truth: false\n  wait_for_readers: 4\n  wait_timeout: 30\n' \
  "$work/flight.mavlog" > "$work/replay.yaml"
cp config/services/cloud_assembly.yaml "$work/cloud_assembly.yaml"
sed -i 's/^  window_age: .*/  window_age: 60.0/; s/^  max_voxels: .*/  max_voxels: 1000000/' "$work/cloud_assembly.yaml"
watched=()
for service in scan_matcher pose_estimation cloud_assembly; do
  file=config/services/$service.yaml
  [ "$service" = scan_matcher ] && file=config/mav/scan_matcher.yaml
  [ "$service" = cloud_assembly ] && file=$work/cloud_assembly.yaml
  "$scanbus" run "$service" --config "$file" > "$work/$service.log" 2>&1 &
  pids+=($!)
  watched+=("$service=$!")
done
"$scanbus" run sensor_replay --config "$work/replay.yaml" > "$work/replay.log" 2>&1 &
pids+=($!)
build/bench/soak_monitor "$seconds" "$period" 120 "${watched[@]}" || status=$?
for service in scan_matcher pose_estimation cloud_assembly; do
  grep -q "level=error" "$work/$service.log" && { echo "$service logged errors:"; grep "level=error" "$work/$service.log" | head -5; }
done
exit "${status:-0}"
