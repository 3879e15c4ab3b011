#!/usr/bin/env bash
# cloud_assembly with scans but no transform for them (pose_estimation not running, so no
# rt/tf_static and no rt/tf): after a second its Health says the scans wait and names the
# frames no transform joins, before any scan is dropped (transform_timeout, 6 s of stamps).
#   missing_frames.sh SCANBUS
set -uo pipefail
source "$(dirname "$0")/../integration/lib.sh"
scanbus=$1
with_work

"$scanbus" sim mav --scenario 1 --duration 20 --out "$work/flight.mavlog" > /dev/null || exit 1
printf 'service:\n  health_period: 0.2\n' > "$work/cloud_assembly.yaml"
printf 'sensor_replay:\n  log: %s\n  rate: 1\n  wait_for_readers: 1\n' "$work/flight.mavlog" > "$work/sensor_replay.yaml"
"$scanbus" health --json --timeout 8 > "$work/health.jsonl" 2> /dev/null &
health=$!
"$scanbus" run cloud_assembly --config "$work/cloud_assembly.yaml" > "$work/cloud_assembly.log" 2>&1 &
pids+=($!)
"$scanbus" run sensor_replay --config "$work/sensor_replay.yaml" > "$work/sensor_replay.log" 2>&1 &
pids+=($!)
wait "$health"
python3 - "$work/health.jsonl" <<'PY' || { tail -n 5 "$work"/*.log; exit 1; }
import json, sys
samples = [json.loads(line) for line in open(sys.argv[1]) if line.strip()]
mine = [s for s in samples if s["service"] == "cloud_assembly"]
assert mine, "no Health from cloud_assembly"
counters = [{c["name"]: c["value"] for c in s["counters"]} for s in mine]
said = [i for i, s in enumerate(mine) if s["last_error"].startswith("scans waiting")]
assert said, [s["last_error"] for s in mine]
first = mine[said[0]]
assert "'laser' to 'map'" in first["last_error"], first["last_error"]
assert counters[said[0]].get("frames_missing") == 1 and counters[said[0]].get("scans_dropped", 0) == 0, counters[said[0]]
print("ok   cloud_assembly without transforms said, before dropping any scan:", first["last_error"][:160])
PY
