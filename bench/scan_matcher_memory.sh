#!/usr/bin/env bash
# Issue 20: the scan matcher service runs a 2-hour log in constant resident memory. MIT Killian
# Court (../shared/data/freiburg, 17,480 scans over 7,677 s) is replayed over DDS (loopback
# profile) at RATE (100) times its pace into `scanbus run scan_matcher` with the shipped
# config; the service's resident memory (VmRSS) is sampled every second. The verdict: the
# largest RSS over the second half of the log is above the largest over its first half
# (after a 10 % warm-up) by at most 2 MiB: Fast DDS's shared-memory segments
# are most of the 110 MiB, so the bound is absolute. Exit 1 when not. MAP_KEYFRAMES overrides the
# map's size (a large one shows what an unbounded map does).
# Usage: bench/scan_matcher_memory.sh [RATE] [MAP_KEYFRAMES]
set -euo pipefail
cd "$(dirname "$0")/.."
rate=${1:-100} map_keyframes=${2:-}
log=../shared/data/freiburg/mit-killian.clf
[ -f "$log" ] || { echo "SKIP: $log not found"; exit 77; }
scripts/build.sh scanbus > /dev/null
export SCANBUS_DOMAIN_ID=${SCANBUS_DOMAIN_ID:-113}
scanbus=$PWD/build/services/cli/scanbus
work=$(mktemp -d)
cleanup() { jobs -p | xargs -r kill -TERM 2> /dev/null || true; wait 2> /dev/null || true; rm -rf "$work"; }
trap cleanup EXIT

"$scanbus" scanmatch convert --log "$log" --out "$work/killian.mcap" > /dev/null
sed 's/^qos: {}.*/qos:\n  rt\/scan: {reliability: reliable, history: keep_all}/' config/services/scan_matcher.yaml \
  > "$work/scan_matcher.yaml"
[ -n "$map_keyframes" ] && sed -i "s/^    map_keyframes: .*/    map_keyframes: $map_keyframes/" "$work/scan_matcher.yaml"
"$scanbus" run scan_matcher --config "$work/scan_matcher.yaml" > "$work/scan_matcher.log" 2>&1 &
matcher=$!
"$scanbus" replay "$work/killian.mcap" --rate "$rate" --wait-for-readers 1 --json > "$work/replay.json" &
replay=$!
start=$(date +%s)
while kill -0 "$replay" 2> /dev/null; do
  echo "$(($(date +%s) - start)) $(awk '/VmRSS/ {print $2}' /proc/$matcher/status)" >> "$work/rss.txt"
  sleep 1
done
wait "$replay"
python3 - "$work/rss.txt" "$work/scan_matcher.log" <<'PY'
import sys
samples = [tuple(map(int, line.split())) for line in open(sys.argv[1]) if len(line.split()) == 2]
n = len(samples)
if n < 10:
    sys.exit(f"only {n} samples of the service's memory: the replay ended too soon (see the service's log)")
warm, half = n // 10, n // 2
first = max(kb for _, kb in samples[warm:half])
second = max(kb for _, kb in samples[half:])
for i in range(0, n, max(1, n // 10)):
    print(f"t {samples[i][0]:4d} s: {samples[i][1] / 1024:.1f} MiB")
print(f"{n} samples; largest RSS, first half after warm-up {first / 1024:.1f} MiB, second half {second / 1024:.1f} MiB")
failed = [l for l in open(sys.argv[2]) if "match failed" in l]
print(f"matches failed (service log): {len(failed)}")
ok = second <= first + 2048
print("constant memory: " + ("yes" if ok else "NO"))
sys.exit(0 if ok else 1)
PY
