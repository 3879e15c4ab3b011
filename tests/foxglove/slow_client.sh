#!/usr/bin/env bash
# Flow control: 100,000-point clouds at 10 Hz (1.6 MB each) for 12 s through the bridge to
# two clients, one of which reads nothing for 10 s (its socket paused), with a 16 MiB queue
# per client:
# - the client that keeps up gets every cloud, with no gap while the other one stalls;
# - the stalled client is told how many messages it lost (status), gets the newest clouds
#   when it reads again, and the bridge's Health counts the drops;
# - the bridge's memory stays bounded: its peak grows by far less than the 160 MB of clouds
#   that the stalled client missed.
set -euo pipefail
scanbus=$1
publisher=$2
source "$(dirname "$0")/lib.sh"
foxglove_test_setup
start_bridge "$scanbus" "  client_queue_size: 16
"
start_client "$work/fast.json" --topics /scanner/cloud --timeout 60
fast=$client_pid
start_client "$work/stalled.json" --topics /scanner/cloud --stall 10 --timeout 60
stalled=$client_pid
"$scanbus" echo rt/scanbus/health --timeout 40 > "$work/health.jsonl" 2> /dev/null &
health=$!
pids+=("$health")
sleep 1
rss_kb() { awk -v key="$1:" '$1 == key { print $2 }' "/proc/$bridge_pid/status"; }
baseline=$(rss_kb VmRSS)
"$publisher" 100000 10 12 1 > "$work/published.json" 2> "$work/publisher.log" ||
  { echo "FAIL: publisher"; cat "$work/publisher.log"; exit 1; }
sleep 3  # the stalled client reads again and catches up; Health is published
peak=$(rss_kb VmHWM)
kill -TERM "$fast" "$stalled"
wait "$fast" "$stalled" || true
sleep 1.5
kill -TERM "$health"
wait "$health" || true

python3 - "$work" "$baseline" "$peak" << 'PY'
import json, sys
work, baseline_kb, peak_kb = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
published = json.load(open(f"{work}/published.json"))["published"]
fast, stalled = json.load(open(f"{work}/fast.json")), json.load(open(f"{work}/stalled.json"))
failures = []
def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok: failures.append(what)
got = fast["messages"].get("/scanner/cloud", [])
check(len(got) == published and all(m["width"] == 100000 for m in got),
      f"the client that keeps up got {len(got)} of {published} clouds")
times = [int(m["receive_ns"]) * 1e-9 for m in got]
gap = max((b - a for a, b in zip(times, times[1:])), default=99)
check(gap < 0.5, f"no gap while the other client stalls: longest {gap:.3f} s between clouds")
late = stalled["messages"].get("/scanner/cloud", [])
drops = [s for s in stalled["statuses"] if "dropped" in s["message"]]
check(bool(drops), "the stalled client is told: " + (drops[-1]["message"] if drops else "nothing"))
check(bool(late) and late[-1]["stamp"] == published - 1 and len(late) < published,
      f"the stalled client got {len(late)} clouds, the newest last")
healths = [json.loads(line) for line in open(f"{work}/health.jsonl")]
ours = [h for h in healths if h["service"] == "foxglove_bridge"]
counters = {c["name"]: c["value"] for c in ours[-1]["counters"]} if ours else {}
check(counters.get("messages_dropped", 0) == published - len(late),
      f"Health counts the drops: {counters.get('messages_dropped')} (the stalled client missed {published - len(late)})")
growth_mb = (peak_kb - baseline_kb) / 1024
check(growth_mb < 64, f"the bridge's peak memory grew by {growth_mb:.0f} MiB (160 MB of clouds were missed)")
sys.exit(1 if failures else 0)
PY
expect_clean_stop foxglove_bridge "$bridge_pid" TERM "$work/bridge.log"
