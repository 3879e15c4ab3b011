#!/usr/bin/env bash
# The recorder under publisher bursts (docs/recording.md "Losses"): COUNT LaserScans of
# 1,081 rays written on rt/scan as fast as the writer takes them, into `scanbus record
# --reliable` with a 64 KiB queue, so the recorder is the slow end.
# 1. RELIABLE/KEEP_ALL writer: every sample recorded, none lost.
# 2. RELIABLE writer with a 5-sample KEEP_LAST queue (bounded): samples the writer drops
#    are counted as lost, and recorded + lost = published (never silent).
# 3. The same into the recorder service (1 MiB queue, scans of 10,000 rays): its Health
#    counts the losses (samples_lost), and recorded + lost = published.
#   burst.sh SCANBUS MCAP_PROBE
set -uo pipefail
scanbus=$1
probe=$2
count=3000
work=$(mktemp -d)
cleanup() { jobs -p | xargs -r kill -9 2>/dev/null || true; rm -rf "$work"; }
trap cleanup EXIT
failures=0

for history in keep_all keep_last; do
  "$scanbus" record --reliable --topics rt/scan --queue-size 0.0625 --json --out "$work/$history.mcap" \
    > "$work/$history.json" 2> "$work/$history.log" &
  recorder=$!
  "$probe" burst "$count" 1081 "$history" > "$work/published.json" || { echo "FAIL $history: the burst"; exit 1; }
  sleep 1  # the recorder's queue drains into the file
  kill -INT "$recorder"
  wait "$recorder" || { echo "FAIL $history: recorder exit $?"; cat "$work/$history.log"; failures=$((failures + 1)); continue; }
  python3 - "$history" "$work/published.json" "$work/$history.json" <<'PY' || failures=$((failures + 1))
import json, sys
history, published, recorded = sys.argv[1], json.load(open(sys.argv[2]))["published"], json.load(open(sys.argv[3]))
messages, lost = recorded["messages"], recorded["lost"]
print(f"{history}: published {published}, recorded {messages}, counted lost {lost}")
if history == "keep_all":
    ok = messages == published and lost == 0
else:
    # A burst into a 5-sample writer queue against a recorder writing through 64 KiB must lose.
    ok = lost > 0 and messages + lost == published and recorded["lost_by_topic"].get("rt/scan") == lost
print("ok" if ok else "FAIL")
sys.exit(0 if ok else 1)
PY
done
printf 'recorder:\n  out: %s\n  topics: [rt/scan]\n  reliable: true\n  queue_size: 1\n' "$work/service.mcap" \
  > "$work/recorder.yaml"
"$scanbus" run recorder --config "$work/recorder.yaml" > "$work/service.log" 2>&1 &
recorder=$!
"$probe" burst "$count" 10000 keep_last > "$work/published.json" || { echo "FAIL service: the burst"; exit 1; }
sleep 2  # the queue drains, and Health reports
"$scanbus" health --once --json --timeout 2 > "$work/health.jsonl"
kill -INT "$recorder"
wait "$recorder" || { echo "FAIL service: recorder exit $?"; cat "$work/service.log"; exit 1; }
"$scanbus" info "$work/service.mcap" --json > "$work/info.json" || { echo "FAIL service: no valid file"; exit 1; }
python3 - "$work/published.json" "$work/health.jsonl" "$work/info.json" <<'PY' || failures=$((failures + 1))
import json, sys
published = json.load(open(sys.argv[1]))["published"]
health = [json.loads(line) for line in open(sys.argv[2]) if line.strip()]
recorder = [h for h in health if h["service"] == "recorder"]
counters = {c["name"]: c["value"] for c in recorder[0]["counters"]} if recorder else {}
lost, messages = counters.get("samples_lost", 0), json.load(open(sys.argv[3]))["messages"]
print(f"recorder service: published {published}, recorded {messages}, Health samples_lost {lost}")
ok = bool(recorder) and lost > 0 and messages + lost == published
print("ok" if ok else "FAIL")
sys.exit(0 if ok else 1)
PY
[ "$failures" -eq 0 ] || { echo "FAIL: $failures checks"; exit 1; }
echo "recorder bursts: nothing lost with KEEP_ALL, every loss counted with a bounded queue, in Health too"
