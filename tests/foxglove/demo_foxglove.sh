#!/usr/bin/env bash
# `scanbus demo --foxglove PORT --no-mav`: the bridge runs beside the room scan, and after the
# result the services keep running, so a Foxglove client that connects then still gets the
# room (latched); Ctrl-C (SIGINT) ends the demo with status 0 and leaves no process behind.
set -euo pipefail
scanbus=$1
source "$(dirname "$0")/lib.sh"
foxglove_test_setup
port=$((20000 + SCANBUS_DOMAIN_ID))
url=ws://127.0.0.1:$port
"$scanbus" demo --foxglove "$port" --no-mav --out "$work/demo" > "$work/demo.log" 2>&1 &
demo=$!
pids+=("$demo")
for _ in $(seq 1200); do
  grep -q "keep running for Foxglove at $url" "$work/demo.log" && break
  kill -0 "$demo" 2> /dev/null || { echo "FAIL: the demo ended:"; cat "$work/demo.log"; exit 1; }
  sleep 0.1
done
grep -q "keep running" "$work/demo.log" || { echo "FAIL: no result in 120 s:"; cat "$work/demo.log"; exit 1; }
grep -q "^Foxglove: open $url" "$work/demo.log" || { echo "FAIL: the address is not printed first"; exit 1; }
client --topics /room/measurement,/room/walls --until /room/measurement:1,/room/walls:1 --timeout 30 > "$work/client.json" ||
  { echo "FAIL: no room via Foxglove after the demo's result:"; head -c 2000 "$work/client.json"; exit 1; }
python3 - "$work/client.json" "$work/demo.log" << 'PY'
import json, re, sys
got = json.load(open(sys.argv[1]))["messages"]["/room/measurement"][0]
printed = float(re.search(r"floor area ([0-9.]+) m2", open(sys.argv[2]).read()).group(1))
assert abs(got["floor_area"] - printed) < 0.006, (got["floor_area"], printed)
print(f"ok   the room via Foxglove after the result: {got['floor_area']:.2f} m2, {len(got['walls'])} walls, as printed")
PY
# Ctrl-C: the demo stops its services one after another (each within 1 s), then exits 0.
kill -INT "$demo"
status=0
timeout 10 tail --pid="$demo" -f /dev/null || { echo "FAIL: the demo still runs 10 s after SIGINT"; exit 1; }
wait "$demo" || status=$?
[ "$status" -eq 0 ] || { echo "FAIL: the demo exited with $status after SIGINT:"; tail -5 "$work/demo.log"; exit 1; }
echo "ok   the demo ended on SIGINT with status 0"
sleep 1
left=$(pgrep -f -- "--config $work/demo/" || true)
[ -z "$left" ] || { echo "FAIL: processes left behind: $(pgrep -fa -- "--config $work/demo/")"; exit 1; }
echo "ok   no service left behind"
