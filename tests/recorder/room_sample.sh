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
python3 - "$work/measurement.json" <<'PY'
import json, sys
room = json.loads(open(sys.argv[1]).readline())
lengths = sorted(wall["length"] for wall in room["walls"])
print("replayed room:", [round(length, 3) for length in lengths], "area", round(room["floor_area"], 3), "m2")
assert room["status"] == 0, room["message"]
assert len(lengths) == 4, lengths
for got, want in zip(lengths, [3.48, 3.48, 5.47, 5.47]):
    assert abs(got - want) <= 0.01, f"wall {got:.3f} m, the room's is {want} m"
assert abs(room["floor_area"] - 5.47 * 3.48) <= 0.01 * 5.47 * 3.48, room["floor_area"]
PY
echo "room sample: ok"
