#!/usr/bin/env bash
# The recorded room scan (tests/data/room_scan.mcap: the simulator's built-in room, thesis
# case 1, 5.47 m x 3.48 m x 2.50 m, scanned at 12 RPM three times) replayed by 'scanbus
# replay' into the room_measurement service: the RoomMeasurement on the bus holds every
# wall within 1 cm of the truth and the floor area within 1 %; again with the service frozen
# while the clouds go out.
set -euo pipefail
scanbus=$1
sample=$2
work=$(mktemp -d)
# CONT too: a service left frozen (SIGSTOP, below) would hold its TERM, and wait, for ever.
cleanup() { jobs -p | xargs -r kill -TERM 2>/dev/null || true; jobs -p | xargs -r kill -CONT 2>/dev/null || true; wait 2>/dev/null || true; rm -rf "$work"; }
trap cleanup EXIT

printf 'room_measurement:\n  scans: 3\n' > "$work/room.yaml"
"$scanbus" run room_measurement --config "$work/room.yaml" > "$work/room.log" 2>&1 &
first_room_pid=$!
"$scanbus" echo rt/room/measurement --count 1 --timeout 120 > "$work/measurement.json" 2> "$work/echo.log" &
echo_pid=$!
sleep 2  # discovery
"$scanbus" replay "$sample" --rate 0 --topics rt/scanner/scan_cloud --wait-for-readers 1 --json > "$work/replay.json"
wait "$echo_pid" || { echo "FAIL: no RoomMeasurement"; cat "$work/replay.json" "$work/room.log" "$work/echo.log"; exit 1; }
"$(dirname "$0")/../support/check_room.py" "$work/measurement.json" 0.02 "replayed room"

# The same at --rate 0 while room_measurement is frozen (SIGSTOP) for 3 s: scan_cloud is
# latched (KEEP_LAST 1), so the replay must wait for each cloud's acknowledgement, or the
# next would replace one the service never got (no room from 1 of 3 clouds). --wait-for-readers 2
# holds the clouds until a second reader (echo) joins, which happens after the freeze.
kill -TERM "$first_room_pid"; wait "$first_room_pid" 2>/dev/null || true
"$scanbus" run room_measurement --config "$work/room.yaml" > "$work/room2.log" 2>&1 &
room_pid=$!
"$scanbus" echo rt/room/measurement --count 1 --timeout 60 > "$work/measurement2.json" 2> "$work/echo2.log" &
echo_pid=$!
sleep 2  # discovery
"$scanbus" replay "$sample" --rate 0 --topics rt/scanner/scan_cloud --wait-for-readers 2 --json > "$work/replay2.json" &
replay_pid=$!
sleep 3  # the replay and room_measurement discover each other
kill -STOP "$room_pid"
"$scanbus" echo rt/scanner/scan_cloud --count 1 --timeout 30 > /dev/null 2>&1 &
sleep 3
kill -CONT "$room_pid"
wait "$replay_pid" || { echo "FAIL: replay"; exit 1; }
wait "$echo_pid" || { echo "FAIL: no RoomMeasurement after the freeze"; cat "$work/replay2.json" "$work/room2.log" "$work/echo2.log"; exit 1; }
"$(dirname "$0")/../support/check_room.py" "$work/measurement2.json" 0.02 "room replayed into a frozen service"
echo "room sample: ok"
