#!/usr/bin/env bash
# Another vendor reads scanbus: an Eclipse Cyclone DDS subscriber (cyclone_subscriber.c)
# and `scanbus echo` (Fast DDS) take the same samples, and what Cyclone decoded must equal
# what Fast DDS decoded, field by field:
# - PointCloud2: the recorded room scan's clouds (tests/data/room_scan.mcap) replayed on
#   rt/scanner/scan_cloud: stamp, frame, size, fields, point step and the data's byte sum;
# - RoomMeasurement: what the room_measurement service makes of those clouds;
# - LaserScan: the MIT CSAIL log's first 10 s (tests/data/mit_csail.mcap) on rt/scan.
# Cyclone is held to 127.0.0.1 without multicast, as scanbus's profile is.
set -euo pipefail
scanbus=$1 cyclone=$2 data=$3
work=$(mktemp -d)
cleanup() { jobs -p | xargs -r kill -TERM 2>/dev/null || true; wait 2>/dev/null || true; rm -rf "$work"; }
trap cleanup EXIT
export CYCLONEDDS_URI='<CycloneDDS><Domain Id="any"><General><Interfaces><NetworkInterface address="127.0.0.1"/></Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>60</MaxAutoParticipantIndex><Peers><Peer address="127.0.0.1"/></Peers></Discovery></Domain></CycloneDDS>'

wait_ready() { for _ in $(seq 100); do grep -q ready "$1" && return 0; sleep 0.1; done; echo "FAIL: $1 never ready"; exit 1; }

# Clouds and the room measurement.
printf 'room_measurement:\n  scans: 3\n' > "$work/room.yaml"
"$scanbus" run room_measurement --config "$work/room.yaml" > "$work/room.log" 2>&1 &
"$cyclone" cloud rt/scanner/scan_cloud 3 90 > "$work/cyclone_cloud.jsonl" 2> "$work/cyclone_cloud.log" &
cyclone_cloud=$!
"$cyclone" room rt/room/measurement 1 90 > "$work/cyclone_room.jsonl" 2> "$work/cyclone_room.log" &
cyclone_room=$!
"$scanbus" echo rt/scanner/scan_cloud --count 3 --timeout 90 > "$work/fast_cloud.jsonl" &
fast_cloud=$!
"$scanbus" echo rt/room/measurement --count 1 --timeout 90 > "$work/fast_room.jsonl" &
fast_room=$!
wait_ready "$work/cyclone_cloud.log"
wait_ready "$work/cyclone_room.log"
# Three readers of the clouds: Cyclone's, scanbus echo's, room_measurement's.
"$scanbus" replay "$data/room_scan.mcap" --rate 1 --topics /scanner/scan_cloud --wait-for-readers 3 --wait-timeout 30 \
  > "$work/replay_room.log" 2>&1
for pid in $cyclone_cloud $cyclone_room $fast_cloud $fast_room; do
  wait "$pid" || { echo "FAIL: a subscriber came back short"; cat "$work"/cyclone_*.log; exit 1; }
done

# Scans: as many as the first 10 s hold.
scans=$("$scanbus" replay "$data/mit_csail.mcap" --rate 0 --end 10 --json | python3 -c "import json,sys; print(json.load(sys.stdin)['published'])")
"$cyclone" scan rt/scan "$scans" 60 > "$work/cyclone_scan.jsonl" 2> "$work/cyclone_scan.log" &
cyclone_scan=$!
wait_ready "$work/cyclone_scan.log"
"$scanbus" echo rt/scan --count "$scans" --timeout 60 > "$work/fast_scan.jsonl" &
fast_scan=$!
sleep 1
"$scanbus" replay "$data/mit_csail.mcap" --rate 5 --end 10 --wait-for-readers 2 --wait-timeout 30 > "$work/replay_scan.log" 2>&1
wait "$cyclone_scan" && wait "$fast_scan" || { echo "FAIL: scans came back short"; cat "$work/cyclone_scan.log"; exit 1; }

python3 - "$work" <<'PY'
import json, sys
work = sys.argv[1]
def lines(name): return [json.loads(l) for l in open(f"{work}/{name}.jsonl")]
def stamp(h): return round(h["stamp"]["sec"] + h["stamp"]["nanosec"] * 1e-9, 6)
failures = 0
def check(what, mine, theirs):
    global failures
    same = mine == theirs
    failures += not same
    print(("ok   " if same else "FAIL ") + what + ("" if same else f": Fast DDS {mine}, Cyclone {theirs}"))

fast = [(stamp(c["header"]), c["header"]["frame_id"], c["height"], c["width"], [f["name"] for f in c["fields"]],
         c["point_step"], c["data"]["bytes"], c["data"]["sum"]) for c in lines("fast_cloud")]
cyc = [(round(c["stamp"], 6), c["frame_id"], c["height"], c["width"], c["fields"], c["point_step"], c["data_size"],
        c["data_sum"]) for c in lines("cyclone_cloud")]
check(f"PointCloud2: {len(cyc)} clouds of {[c[3] for c in cyc]} points, stamps, frames, fields and data sums", fast, cyc)

room_fast, room_cyc = lines("fast_room")[0], lines("cyclone_room")[0]
mine = ([round(w["length"], 6) for w in room_fast["walls"]], len(room_fast["corners"]), round(room_fast["floor_area"], 6),
        room_fast["status"])
theirs = ([round(w, 6) for w in room_cyc["walls"]], room_cyc["corners"], round(room_cyc["floor_area"], 6), room_cyc["status"])
check(f"RoomMeasurement: walls {mine[0]}, {mine[1]} corners, floor {mine[2]:.3f} m2", mine, theirs)

fast = [(stamp(s["header"]), s["header"]["frame_id"], len(s["ranges"]), sum(round(r * 1000) for r in s["ranges"]))
        for s in lines("fast_scan")]
cyc = [(round(s["stamp"], 6), s["frame_id"], s["ranges"], s["range_sum_mm"]) for s in lines("cyclone_scan")]
check(f"LaserScan: {len(cyc)} scans of {cyc[0][2]} ranges, stamps, frames and ranges (mm sums)", fast, cyc)
sys.exit(1 if failures else 0)
PY
echo "cyclone interop: ok"
