#!/usr/bin/env bash
# Sensor faults through the MAV pipeline (docs/faults.md): a 40 s scenario I flight with
# three faults written into its log, replayed at 2x through scan_matcher, pose_estimation
# and cloud_assembly, each its own process:
#   10-12 s  the laser returns zeros          -> matches fail (scan_matcher matches_failed)
#   18-19 s  the laser returns garbage        -> the matcher fails or its changes are gated
#   25-28 s  the barometer jumps by +10 m     -> left out (pose_estimation pressures_outlying)
# Asserts: no service dies or crashes, Health shows each fault, and the fused height stays
# near the truth: within 0.15 m through the barometer's jump (taken in, it would move the
# height by metres), 0.5 m while the laser is blind (the barometer alone), 0.2 m elsewhere.
#   sensor_faults.sh SCANBUS CONFIG
set -uo pipefail
source "$(dirname "$0")/../integration/lib.sh"
scanbus=$1
config=$2
with_work

"$scanbus" sim mav --scenario 1 --duration 40 --out "$work/clean.mavlog" > /dev/null || exit 1
python3 - "$work/clean.mavlog" "$work/flight.mavlog" <<'PY'
import random, sys
random.seed(5)
start = None
with open(sys.argv[1]) as clean, open(sys.argv[2], "w") as out:
    for line in clean:
        f = line.split()
        if f and f[0] in ("LASER", "BARO"):
            t = float(f[1])
            start = t if start is None else start
            t -= start
            if f[0] == "LASER" and (10 <= t < 12 or 18 <= t < 19):
                n = int(f[6])
                ranges = ["0"] * n if t < 12 else [f"{random.uniform(0.5, 8):.3f}" for _ in range(n)]
                line = " ".join(f[:7] + ranges) + "\n"
            elif f[0] == "BARO" and 25 <= t < 28:
                line = f"BARO {f[1]} {float(f[2]) - 120:.2f}\n"  # about +10 m
        out.write(line)
PY
printf 'sensor_replay:\n  log: %s\n  rate: 2\n  wait_for_readers: 3\n  wait_timeout: 30\n' "$work/flight.mavlog" \
  > "$work/replay.yaml"
declare -A pid_of
for service in scan_matcher pose_estimation cloud_assembly; do
  file="$config/services/$service.yaml"
  [ "$service" = scan_matcher ] && file="$config/mav/scan_matcher.yaml"
  "$scanbus" run "$service" --config "$file" > "$work/$service.log" 2>&1 &
  pid_of[$service]=$!
  pids+=($!)
done
"$scanbus" echo rt/pose > "$work/poses.jsonl" 2> /dev/null &
echo_pid=$!
"$scanbus" echo rt/truth/pose > "$work/truth.jsonl" 2> /dev/null &
truth_pid=$!
pids+=($echo_pid $truth_pid)
"$scanbus" run sensor_replay --config "$work/replay.yaml" > "$work/replay.log" 2>&1 || { cat "$work/replay.log"; exit 1; }
sleep 1
"$scanbus" health --once --json --timeout 3 > "$work/health.jsonl"
kill -INT "$echo_pid" "$truth_pid"; wait "$echo_pid" "$truth_pid"
for service in scan_matcher pose_estimation cloud_assembly; do
  kill -0 "${pid_of[$service]}" 2> /dev/null || fail "$service died"
done
grep -l "terminate called\|Segmentation\|Aborted" "$work"/*.log && fail "a service crashed"

python3 - "$work" <<'PY' || fail "Health or heights"
import json, sys
work = sys.argv[1]
counters = {}
for line in open(f"{work}/health.jsonl"):
    h = json.loads(line)
    counters[h["service"]] = {c["name"]: c["value"] for c in h["counters"]}
ok = True
def check(service, name, at_least):
    global ok
    value = counters.get(service, {}).get(name, 0)
    good = value >= at_least
    ok &= good
    print(f"{'ok  ' if good else 'FAIL'} {service} {name} = {value} (want >= {at_least})")
check("scan_matcher", "matches_failed", 20)        # 2 s of zeros at 30 Hz, at least a third
check("pose_estimation", "pressures_outlying", 20)  # 3 s at 10 Hz
stamp = lambda p: p["header"]["stamp"]["sec"] + p["header"]["stamp"]["nanosec"] * 1e-9
truth = sorted((stamp(p), p["pose"]["pose"]["position"]["z"] if "pose" in p["pose"] else p["pose"]["position"]["z"])
               for p in map(json.loads, open(f"{work}/truth.jsonl")))
poses = [(stamp(p), p["pose"]["pose"]["position"]["z"]) for p in map(json.loads, open(f"{work}/poses.jsonl"))]
import bisect
times = [t for t, _ in truth]
# Worst error by phase: the laser's faults leave the barometer alone (its 0.3 m noise,
# smoothed by the climb-rate limit); the barometer's jump is left out.
phases = {"laser zeros 10-13 s": (10, 13, 0.5), "laser garbage 18-20 s": (18, 20, 0.5),
          "barometer jump 25-29 s": (25, 29, 0.15), "the rest after 5 s": (5, 1e9, 0.2)}
worst = dict.fromkeys(phases, 0.0)
for t, z in poses:
    i = min(max(bisect.bisect_left(times, t), 1), len(times) - 1)
    (t0, z0), (t1, z1) = truth[i - 1], truth[i]
    err = abs(z - (z0 + (z1 - z0) * (t - t0) / (t1 - t0) if t1 > t0 else z0))
    at = t - times[0]
    phase = next((name for name, (a, b, _) in phases.items() if a <= at < b), None)
    if phase: worst[phase] = max(worst[phase], err)
good = len(poses) > 1000
ok &= good
print(f"{'ok  ' if good else 'FAIL'} {len(poses)} poses")
for name, (_, _, limit) in phases.items():
    good = worst[name] < limit
    ok &= good
    print(f"{'ok  ' if good else 'FAIL'} {name}: fused height at most {worst[name]:.3f} m from the truth (limit {limit} m)")
sys.exit(0 if ok else 1)
PY
[ "$failures" -eq 0 ] || { echo "FAIL: $failures checks"; exit 1; }
echo "sensor faults: each visible in Health, none a crash, the height held"
