#!/usr/bin/env bash
# The Foxglove bridge under 1,000,000-point PointCloud2 samples (16 MB) at 10 Hz, with
# `scanbus echo` reading the same topic beside it: for each cloud, the time from the bridge's
# DDS delivery (the receive time in the frame) to its arrival at a local Foxglove client
# (Foxglove's own ws-protocol package in Node, tests/foxglove/foxglove_client.mjs) is the
# latency the bridge adds. Prints clouds published, received via Foxglove and via echo, and the
# added latency's median, 90th percentile and maximum.
# Usage: bench/foxglove_latency.sh [SECONDS] [POINTS] (default 20 s, 1,000,000 points).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
points=${2:-1000000}
scripts/build.sh scanbus recording_publisher > /dev/null
export SCANBUS_DOMAIN_ID=${SCANBUS_DOMAIN_ID:-112}
source tests/foxglove/lib.sh
foxglove_test_setup
start_bridge build/services/cli/scanbus
start_client "$work/client.json" --topics /scanner/cloud --timeout $((seconds + 60))
client_pid_fox=$client_pid
build/services/cli/scanbus echo rt/scanner/cloud --timeout $((seconds + 60)) > "$work/echo.jsonl" 2> /dev/null &
echo_pid=$!
pids+=("$echo_pid")
build/bench/recording_publisher "$points" 10 "$seconds" 2 > "$work/published.json" 2> "$work/publisher.log"
sleep 2  # the last clouds arrive
kill -TERM "$client_pid_fox" "$echo_pid"
wait "$client_pid_fox" "$echo_pid" || true
python3 - "$work" "$points" << 'PY'
import json, statistics, sys
work, points = sys.argv[1], int(sys.argv[2])
published = json.load(open(f"{work}/published.json"))["published"]
clouds = json.load(open(f"{work}/client.json"))["messages"].get("/scanner/cloud", [])
echoed = sum(1 for _ in open(f"{work}/echo.jsonl"))
added = sorted((int(m["arrive_ns"]) - int(m["receive_ns"])) * 1e-6 for m in clouds)
ok = [m for m in clouds if m.get("width") == points]
print(f"{points} points, {published} clouds published; via Foxglove {len(clouds)} ({len(ok)} whole), via echo {echoed}")
if added:
    p90 = added[int(0.9 * (len(added) - 1))]
    print(f"latency added by the bridge (ms): median {statistics.median(added):.2f}, p90 {p90:.2f}, max {added[-1]:.2f}")
PY
