#!/usr/bin/env bash
# Soak: MINUTES (10) of a 100 Hz LaserScan of 1,081 rays (a simulated scenario I flight,
# `scanbus sim mav --laser-rate 100 --laser-rays 1081`) replayed in real time through
# scan_matcher, pose_estimation and cloud_assembly, each its own process on the loopback
# profile. bench/soak_monitor prints every PERIOD (30) s each service's resident memory and
# the scan -> pose and scan -> assembled cloud latencies, then judges the span after a
# 120 s warm-up (memory flat, latency not growing, nothing lost; soak_monitor.cpp says how);
# exit 1 when a target is missed.
# --faults: the room pipeline runs beside it (the simulated scanner on a pty, 10x real
# time, scanner_io scanning without end, room_measurement measuring every scan); from
# minute 1 one service is killed (SIGKILL) and started again every minute, in turn, and the
# serial device is unplugged (its simulator killed) every 90 s from 45 s, so never as a
# service is killed, and plugged in again (a new simulator on the same path) after
# UNPLUG_FOR (3) s. The monitor then also judges
# that each restart publishes again within 5 s, each replug gives a revolution within 5 s,
# and that no scan and no whole room scan was lost except while a service on its way was
# down. Both pipelines use the UDP-only loopback profile here: Fast DDS 2.9 leaves a
# SIGKILLed participant's shared-memory port behind (docs/faults.md).
# cloud_assembly's buffers are bounded (window_age, window_points, max_voxels) and grow
# until full: with the defaults (600 s, 20 M points, 5 M voxels) they are still filling at
# minute 10 here (the 1 cm continuous map gains about 15,000 voxels a second from 2 cm
# range noise). The soak sets a 60 s window and 1 M voxels so both fill inside the warm-up,
# and then checks that they hold.
# Usage: bench/soak.sh [--faults] [MINUTES] [PERIOD]
set -euo pipefail
cd "$(dirname "$0")/.."
faults=false
[ "${1:-}" = --faults ] && { faults=true; shift; }
minutes=${1:-10} period=${2:-30} unplug_for=${UNPLUG_FOR:-3}
scripts/build.sh scanbus soak_monitor > /dev/null
export SCANBUS_DOMAIN_ID=${SCANBUS_DOMAIN_ID:-114}
$faults && export SCANBUS_DDS_PROFILE_FILE=$PWD/config/dds/localhost_udp.xml
scanbus=$PWD/build/services/cli/scanbus
work=$(mktemp -d)
declare -A pid  # by service; the simulators' as "sim"
others=()
cleanup() {
  for p in "${pid[@]}" "${others[@]}"; do kill -TERM "$p" 2> /dev/null || true; done
  wait 2> /dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
seconds=$((minutes * 60))
[ -t 1 ] && echo "simulating a $((seconds + 20)) s flight at 100 Hz, 1,081 rays ..."
"$scanbus" sim mav --scenario 1 --duration $((seconds + 20)) --laser-rate 100 --laser-rays 1081 \
  --out "$work/flight.mavlog" > /dev/null
printf 'sensor_replay:\n  log: %s\n  rate: 1\n  truth: false\n  wait_for_readers: 4\n  wait_timeout: 30\n' \
  "$work/flight.mavlog" > "$work/sensor_replay.yaml"
cp config/mav/scan_matcher.yaml config/services/pose_estimation.yaml "$work/"
cp config/services/cloud_assembly.yaml "$work/cloud_assembly.yaml"
sed -i 's/^  window_age: .*/  window_age: 60.0/; s/^  max_voxels: .*/  max_voxels: 1000000/' "$work/cloud_assembly.yaml"
printf 'scanner_io:\n  port: %s\n  scans: 0\n' "$work/tty" > "$work/scanner_io.yaml"
sed 's/^  scans: 3 .*/  scans: 1/' config/services/room_measurement.yaml > "$work/room_measurement.yaml"

event() { echo "$(date +%s.%N) $*" >> "$work/events"; }
start() {  # start SERVICE
  "$scanbus" run "$1" --config "$work/$1.yaml" >> "$work/$1.log" 2>&1 &
  pid[$1]=$!
}
plug_in() {
  "$scanbus" sim scanner --speed 10 --link "$work/tty" >> "$work/sim.log" 2>&1 &
  pid[sim]=$!
}
watched=(scan_matcher pose_estimation cloud_assembly)
$faults && watched+=(scanner_io room_measurement)
$faults && plug_in
for service in "${watched[@]}"; do start "$service"; done
start sensor_replay
touch "$work/events"
build/bench/soak_monitor --seconds "$seconds" --period "$period" --warm-up 120 \
  --services "$(IFS=,; echo "${watched[*]}")" --events "$work/events" &
monitor=$!
others+=($monitor)
if $faults; then
  SECONDS=0
  next_kill=60 next_unplug=45 replug_at=0 turn=0
  while kill -0 "$monitor" 2> /dev/null; do
    sleep 0.2
    if [ "$SECONDS" -ge "$next_kill" ] && [ "$next_kill" -lt "$seconds" ]; then
      victim=${watched[$((turn % ${#watched[@]}))]}
      kill -KILL "${pid[$victim]}" 2> /dev/null || echo "$victim had already exited"; event kill "$victim"
      wait "${pid[$victim]}" 2> /dev/null || true
      start "$victim"; event start "$victim"
      turn=$((turn + 1)) next_kill=$((next_kill + 60))
    fi
    if [ "$SECONDS" -ge "$next_unplug" ] && [ "$next_unplug" -lt "$seconds" ]; then
      kill -KILL "${pid[sim]}" 2> /dev/null || echo "the scanner simulator had already exited"; event unplug
      wait "${pid[sim]}" 2> /dev/null || true
      rm -f "$work/tty"  # what a vanished device node looks like
      replug_at=$((SECONDS + unplug_for)) next_unplug=$((next_unplug + 90))
    fi
    if [ "$replug_at" -gt 0 ] && [ "$SECONDS" -ge "$replug_at" ]; then
      plug_in; event replug
      replug_at=0
    fi
  done
fi
wait "$monitor" || status=$?
for service in "${watched[@]}"; do
  grep -q "level=error" "$work/$service.log" && { echo "$service logged errors:"; grep "level=error" "$work/$service.log" | head -5; }
done
exit "${status:-0}"
