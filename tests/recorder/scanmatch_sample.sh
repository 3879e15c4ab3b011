#!/usr/bin/env bash
# The real MIT CSAIL laser log (tests/data/mit_csail.mcap, converted from the Freiburg
# benchmark's CARMEN log) replayed by 'scanbus replay' into the scan_matcher service: the
# poses on rt/scan_match, scored against the benchmark's relations, equal the in-process
# evaluation of the same sample and stay within the published scan-matching row
# (0.106 m mean translational error).
set -euo pipefail
scanbus=$1
config=$2
data=$3
work=$(mktemp -d)
cleanup() { jobs -p | xargs -r kill -TERM 2>/dev/null || true; wait 2>/dev/null || true; rm -rf "$work"; }
trap cleanup EXIT

# Reliable, every sample kept, both ways: the replay goes as fast as the matcher takes it.
sed 's/^qos: {}.*/qos:\n  rt\/scan: {reliability: reliable, history: keep_all}\n  rt\/scan_match: {reliability: reliable, history: keep_all}/' \
  "$config/services/scan_matcher.yaml" > "$work/scan_matcher.yaml"
"$scanbus" run scan_matcher --config "$work/scan_matcher.yaml" > "$work/scan_matcher.log" 2>&1 &
scans=$("$scanbus" info "$data/mit_csail.mcap" --json | python3 -c "import json,sys; print(json.load(sys.stdin)['messages'])")
"$scanbus" echo rt/scan_match --count "$scans" --timeout 120 > "$work/matches.jsonl" 2> "$work/echo.log" &
echo_pid=$!
sleep 2  # discovery
"$scanbus" replay "$data/mit_csail.mcap" --rate 0 --wait-for-readers 1 --json > "$work/replay.json"
wait "$echo_pid" || { echo "FAIL: $(wc -l < "$work/matches.jsonl") of $scans scan matches arrived"; cat "$work/echo.log"; exit 1; }
python3 - "$work" <<'PY'
import json, sys
work = sys.argv[1]
with open(f"{work}/trajectory.txt", "w") as out:
    for line in open(f"{work}/matches.jsonl"):
        m = json.loads(line)
        stamp = m["header"]["stamp"]["sec"] + m["header"]["stamp"]["nanosec"] * 1e-9
        out.write(f"{stamp:.6f} {m['pose']['x']} {m['pose']['y']} {m['pose']['theta']}\n")
PY
"$scanbus" scanmatch score --trajectory "$work/trajectory.txt" --relations "$data/mit_csail.relations" --json > "$work/dds.json"
"$scanbus" scanmatch eval --log "$data/mit_csail.mcap" --relations "$data/mit_csail.relations" --json > "$work/in_process.json"
python3 - "$work" <<'PY'
import json, sys
work = sys.argv[1]
dds, local = json.load(open(f"{work}/dds.json")), json.load(open(f"{work}/in_process.json"))
d, l = dds["translational_error_m"], local["translational_error_m"]
print(f"over DDS: {dds['relations']} relations, {d['mean']:.4f} +- {d['std']:.4f} m; "
      f"in one process: {l['mean']:.4f} +- {l['std']:.4f} m")
assert dds["relations"] == 1172 and dds["relations_missing"] == 0, dds
assert abs(d["mean"] - l["mean"]) <= 0.002, "the service's poses differ from the in-process matcher's"
assert d["mean"] <= 0.106, "past the published scan-matching row"
PY
echo "scan matcher sample: ok"
