#!/usr/bin/env bash
# Replays whose stamps jump (docs/recording.md "Stamps"): one message stamped 1e10 s (near
# where int64 nanoseconds overflow) among regular ones, and a recording paused for an hour.
# Neither may stall the replay: the lone stamp is skipped and counted, the pause replayed at
# once with nothing lost. The same for sensor_replay on a MAV log.
#   stamps.sh SCANBUS MCAP_PROBE
set -euo pipefail
scanbus=$1
probe=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# check NAME JSON PUBLISHED SKIPPED PAUSES START (epoch seconds)
check() {
  python3 - "$@" <<'PY'
import json, sys, time
name, path, published, skipped, pauses, start = sys.argv[1:]
seconds = time.time() - float(start)
result = json.load(open(path))
got = (result["published"], result["stamps_skipped"], result["pauses"])
assert got == (int(published), int(skipped), int(pauses)), (name, got, result)
print(f"ok   {name}: {got[0]} published, {got[1]} stamp skipped, {got[2]} pause taken up, in {seconds:.1f} s")
PY
}

"$probe" stamps "$work/jump.mcap" 0 0.1 0.2 1e10 0.3 0.4
start=$EPOCHREALTIME
timeout 20 "$scanbus" replay "$work/jump.mcap" --rate 1 --json > "$work/jump.json" ||
  { echo "FAIL: the replay with a stamp of 1e10 s did not end within 20 s"; exit 1; }
check "a stamp 1e10 s ahead" "$work/jump.json" 5 1 0 "$start"

"$probe" stamps "$work/back.mcap" 5e9 5000000000.1 1 5000000000.2 5000000000.3 1.8e10
start=$EPOCHREALTIME
timeout 20 "$scanbus" replay "$work/back.mcap" --rate 1 --json > "$work/back.json" ||
  { echo "FAIL: the replay with stamps far back and at the end far ahead did not end within 20 s"; exit 1; }
check "a stamp far back, one far ahead at the end" "$work/back.json" 4 2 0 "$start"

"$probe" stamps "$work/pause.mcap" 0 0.1 3600 3600.1 3600.2
start=$EPOCHREALTIME
timeout 20 "$scanbus" replay "$work/pause.mcap" --rate 1 --json > "$work/pause.json" ||
  { echo "FAIL: the replay of a recording paused for an hour did not end within 20 s"; exit 1; }
check "an hour's pause" "$work/pause.json" 5 0 1 "$start"

# sensor_replay: pressures at 10 Hz and one stamped 1e10 s.
{
  echo "# scanbus MAV log v1 (docs/mav_log.md)"
  for t in 0.0 0.1 0.2 10000000000 0.3 0.4; do echo "BARO $t 101325"; done
} > "$work/jump.mavlog"
printf 'sensor_replay:\n  log: %s\n  rate: 1\n' "$work/jump.mavlog" > "$work/sensor_replay.yaml"
timeout 20 "$scanbus" run sensor_replay --config "$work/sensor_replay.yaml" > "$work/sensor_replay.log" 2>&1 ||
  { echo "FAIL: sensor_replay of a log with a stamp of 1e10 s did not end cleanly within 20 s:"; cat "$work/sensor_replay.log"; exit 1; }
grep -q "stamped 10000000000 s jumps more than 60 s from its neighbours: skipped" "$work/sensor_replay.log" ||
  { echo "FAIL: sensor_replay did not report the stamp it skipped:"; cat "$work/sensor_replay.log"; exit 1; }
echo "ok   sensor_replay skipped the record stamped 1e10 s and ended"
