#!/usr/bin/env bash
# The recorded room scan (tests/data/room_scan.mcap: the simulator's built-in room, thesis
# case 1, 5.47 m x 3.48 m x 2.50 m, scanned at 12 RPM three times) replayed by 'scanbus
# replay' into the room_measurement service: the RoomMeasurement on the bus holds every
# wall within 1 cm of the truth and the floor area within 1 %.
set -euo pipefail
scanbus=$1
sample=$2
work=$(mktemp -d)
cleanup() { jobs -p | xargs -r kill -TERM 2>/dev/null || true; wait 2>/dev/null || true; rm -rf "$work"; }
trap cleanup EXIT

printf 'room_measurement:\n  scans: 3\n' > "$work/room.yaml"
"$scanbus" run room_measurement --config "$work/room.yaml" > "$work/room.log" 2>&1 &
"$scanbus" echo rt/room/measurement --count 1 --timeout 120 > "$work/measurement.json" 2> "$work/echo.log" &
echo_pid=$!
sleep 2  # discovery
"$scanbus" replay "$sample" --rate 0 --topics rt/scanner/scan_cloud --wait-for-readers 1 --json > "$work/replay.json"
wait "$echo_pid" || { echo "FAIL: no RoomMeasurement"; cat "$work/room.log" "$work/echo.log"; exit 1; }
"$(dirname "$0")/../support/check_room.py" "$work/measurement.json" 0.01 "replayed room"
echo "room sample: ok"
