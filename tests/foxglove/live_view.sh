#!/usr/bin/env bash
# The Foxglove bridge while a recorded simulated room scan (tests/data/room_scan.mcap) is
# replayed into the room_measurement service, seen by clients made of Foxglove's own npm
# packages (foxglove_client.mjs), against what `scanbus echo` receives:
# - client A, there before any service: topics are advertised when their writers appear,
#   as cdr with ros2msg schemas it decodes; its scanner clouds are echo's (same stamps and
#   sizes, none lost), its RoomMeasurement is echo's (same walls, area, stamp); the room's
#   topics are withdrawn when the service stops;
# - client B joins after the room was measured: it gets the measurement (latched), as a
#   DDS reader joining late would;
# - client C drops its connection in the middle of a message: A and B do not notice.
set -euo pipefail
scanbus=$1
sample=$2
source "$(dirname "$0")/lib.sh"
foxglove_test_setup
start_bridge "$scanbus"

printf 'room_measurement:\n  scans: 3\n' > "$work/room.yaml"
start_client "$work/a.json" --topics /scanner/cloud,/room/measurement --timeout 100
client_a=$client_pid
start_client "$work/c.json" --topics /scanner/scan_cloud --leave-after-bytes 20000 --timeout 100
"$scanbus" run room_measurement --config "$work/room.yaml" > "$work/room.log" 2>&1 &
room=$!
pids+=("$room")
"$scanbus" echo rt/room/measurement --count 1 --timeout 100 > "$work/echo_room.json" 2> "$work/echo_room.log" &
echo_room=$!
"$scanbus" echo rt/scanner/cloud --timeout 100 > "$work/echo_cloud.jsonl" 2> "$work/echo_cloud.log" &
echo_cloud=$!
pids+=("$echo_cloud")
sleep 2  # discovery: echo's readers are matched before the replay starts
# Readers of scan_cloud: room_measurement and the bridge (for A); of cloud: echo and the bridge.
"$scanbus" replay "$sample" --rate 1 --topics rt/scanner/cloud rt/scanner/scan_cloud --wait-for-readers 2 \
  --json > "$work/replay.json" 2> "$work/replay.log" || { echo "FAIL: replay"; cat "$work/replay.log"; exit 1; }
wait "$echo_room" || { echo "FAIL: echo got no RoomMeasurement"; cat "$work/room.log" "$work/echo_room.log"; exit 1; }
client --topics /room/measurement --until /room/measurement:1 --timeout 30 > "$work/b.json" ||
  { echo "FAIL: late client B:"; head -c 2000 "$work/b.json"; exit 1; }
kill -TERM "$room"
wait "$room" || true
sleep 2  # the room service's writers are withdrawn
kill -0 "$bridge_pid" || { echo "FAIL: the bridge died"; cat "$work/bridge.log"; exit 1; }
kill -TERM "$client_a" "$echo_cloud"
wait "$client_a" "$echo_cloud" || true

python3 - "$work" << 'PY'
import json, sys
work = sys.argv[1]
a, b = json.load(open(f"{work}/a.json")), json.load(open(f"{work}/b.json"))
failures = []
def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok: failures.append(what)
def stamp(header): return header["stamp"]["sec"] + header["stamp"]["nanosec"] * 1e-9

check(a["serverInfo"]["capabilities"] == [], "serverInfo offers no optional capability")
advertised = {c["topic"] for c in a["advertised"]}
check({"/scanner/cloud", "/scanner/scan_cloud", "/room/measurement", "/room/walls"} <= advertised,
      f"replayed and room topics advertised as they appear ({len(advertised)} channels)")
check(all(c["encoding"] == "cdr" and c["schemaEncoding"] == "ros2msg" for c in a["advertised"]), "cdr, ros2msg")
check({"/room/measurement", "/room/walls", "/scanner/cloud"} <= set(a["unadvertised"]),
      "the topics are withdrawn when their writers stop")
decoded = [m for ms in a["messages"].values() for m in ms]
check(decoded and not any("decode_error" in m for m in decoded), f"client A decoded all {len(decoded)} messages")
check(not a["errors"], f"client A saw no error {a['errors']}")

echoed = [json.loads(line) for line in open(f"{work}/echo_cloud.jsonl")]
theirs = [(round(stamp(c["header"]), 6), c["width"]) for c in echoed]
ours = [(round(m["stamp"], 6), m["width"]) for m in a["messages"].get("/scanner/cloud", [])]
check(len(theirs) == 81 and ours == theirs, f"scanner clouds: {len(ours)} via Foxglove, {len(theirs)} via echo, same stamps and sizes")

room = json.load(open(f"{work}/echo_room.json"))
got = a["messages"].get("/room/measurement", [])
check(len(got) == 1, f"one RoomMeasurement via Foxglove ({len(got)})")
if got:
    check([w["length"] for w in got[0]["walls"]] == [w["length"] for w in room["walls"]]
          and got[0]["floor_area"] == room["floor_area"] and abs(got[0]["stamp"] - stamp(room["header"])) < 1e-9,
          f"same walls as echo: {[round(w['length'], 3) for w in room['walls']]}, {room['floor_area']:.2f} m2")
late = b["messages"].get("/room/measurement", [])
check(len(late) == 1 and late[0]["floor_area"] == room["floor_area"], "late client B gets the latched RoomMeasurement")
sys.exit(1 if failures else 0)
PY
grep -q "client 2 (.*) left" "$work/bridge.log" || { echo "FAIL: client C's leaving is not in the log"; exit 1; }
expect_clean_stop foxglove_bridge "$bridge_pid" TERM "$work/bridge.log"
