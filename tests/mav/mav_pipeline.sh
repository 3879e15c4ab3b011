#!/usr/bin/env bash
# The MAV paper's pipeline over DDS, end to end: a MAV flight replayed through
# scan_matcher, pose_estimation and cloud_assembly, each its own process on the loopback
# profile, and what comes out of the bus measured against the truth.
#
#   mav_pipeline.sh SCANBUS CONFIG           a simulated 180 s scenario IV flight (two
#       boxes) replayed by sensor_replay; asserts the issue's figures: the fused height's
#       RMSE at most half of the better single source (barometer alone, or the paper's
#       barometer start plus scan-matcher changes, both from 'scanbus eval mav' on the same
#       log) and the boxes' P in the cloud assembled over the flight no more than 1 point
#       below the in-process P on the same log, and at least 97 % (the sweeps' lowest seeds):
#       the window's P moves over a point from run to run (97.81 % in one run and 99.44 % in
#       a CI run against 98.16 % at 0f18494, 99.04 against 99.14 % at 724b7ad), and P >= 99 % is
#       not met on every seed in process either (docs/performance.md), so a bound at 99 %
#       here was a coin toss; accuracy.mav_scenarios asserts it in process on its seeds.
#   mav_pipeline.sh SCANBUS CONFIG SAMPLE    a recorded sample (tests/data/*.mcap, truth
#       on rt/truth/pose) replayed by 'scanbus replay'; asserts that the services give what
#       'scanbus eval mav' gives in one process on the same sample (fused RMSE within 15 %
#       or 1 cm, box P no more than 1 point below) and that the fused height beats the
#       barometer's. Over terrain (the log's META carries its ground) also the window
#       cloud's height error against the true ground ('scanbus eval ground'): within 15 % or
#       1 cm of the in-process one, under 10 cm, and the terrain's tilt within 20 %; and the
#       elevation grid on rt/cloud/elevation against it, within 15 % or 1 cm of the
#       in-process grid's.
set -uo pipefail
source "$(dirname "$0")/../integration/lib.sh"
scanbus=$1
config=$2
sample=${3:-}
rate=${MAV_REPLAY_RATE:-4}
with_work
# Fast DDS's own warnings into each process's log: a service deaf to late subscribers
# (seen twice in CI, never here) then shows whether its shared-memory port was replaced.
export SCANBUS_DDS_LOG=warning

flight=${sample:-$work/flight.mavlog}
[ -n "$sample" ] || "$scanbus" sim mav --scenario 4 --duration 180 --out "$flight" || exit 1
"$scanbus" eval mav --log "$flight" --json > "$work/in_process.json" || exit 1
printf 'sensor_replay:\n  log: %s\n  rate: %s\n  wait_for_readers: 2\n' "$flight" "$rate" > "$work/replay.yaml"
# The shipped pose_estimation config waits 0.5 s of stamp time for a late IMU or GPS sample:
# 125 ms of wall time at 4x, which a loaded machine passed (fused 0.017 m for 0.014, boxes
# P 98.0 % in one CI run). A second of wall time, as the demo's launch gives it.
# The flight's last 3 s of poses settle once the input has ended: said after 1.5 s, not 5.
sed -e "s/^  max_wait: [0-9.]*/  max_wait: $(python3 -c "print(min(float('$rate'), 10.0))")/" \
  -e "s/^  input_ended_after: [0-9.]*/  input_ended_after: 1.5/" \
  "$config/services/pose_estimation.yaml" > "$work/pose_estimation.yaml"
grep -q "^  max_wait: " "$work/pose_estimation.yaml" || { echo "no max_wait in pose_estimation.yaml"; exit 1; }
grep -q "^  input_ended_after: 1.5" "$work/pose_estimation.yaml" || { echo "no input_ended_after in pose_estimation.yaml"; exit 1; }
# So a scan waits for its pose longer than the pose waits for its IMU sample: with the then
# shipped 2 s of stamp time (0.5 s of wall time at 4x) a loaded CI machine dropped 53 scans from the
# window (1,930,628 points for 1,949,761) and box P fell to 98.0 %, twice; the shipped 6 s
# leave 2.5 s beyond the settled pose's 3.5 s, 0.6 s of wall time at 4x. As the demo's launch.
sed "s/^  transform_timeout: [0-9.]*/  transform_timeout: 30/" \
  "$config/services/cloud_assembly.yaml" > "$work/cloud_assembly.yaml"
grep -q "^  transform_timeout: 30" "$work/cloud_assembly.yaml" || { echo "no transform_timeout in cloud_assembly.yaml"; exit 1; }
for service in scan_matcher pose_estimation cloud_assembly; do
  file="$config/services/$service.yaml"
  [ "$service" = scan_matcher ] && file="$config/mav/scan_matcher.yaml"
  [ "$service" = pose_estimation ] && file="$work/pose_estimation.yaml"
  [ "$service" = cloud_assembly ] && file="$work/cloud_assembly.yaml"
  "$scanbus" run "$service" --config "$file" > "$work/$service.log" 2>&1 &
  pids+=($!)
done
# The settled poses: what places the scans, and what 'scanbus eval mav' scores as fused.
"$scanbus" echo rt/pose/settled > "$work/poses.jsonl" 2> "$work/echo.log" &
echo_pid=$!
pids+=($echo_pid)
"$scanbus" echo rt/truth/pose > "$work/truth.jsonl" 2> "$work/echo_truth.log" &
truth_pid=$!
pids+=($truth_pid)
sleep 2  # discovery of the services before the first record
started=$(date +%s)
if [ -n "$sample" ]; then
  "$scanbus" replay "$sample" --rate "$rate" --wait-for-readers 1 --wait-timeout 20 > "$work/replay.log" 2>&1 ||
    { cat "$work/replay.log"; exit 1; }
else
  "$scanbus" run sensor_replay --config "$work/replay.yaml" > "$work/replay.log" 2>&1 || { cat "$work/replay.log"; exit 1; }
fi
echo "replay of ${flight##*/} at ${rate}x took $(( $(date +%s) - started )) s"
sleep 4  # the last poses (settled 1.5 s after the input ended) and the last cloud
kill -INT "$echo_pid" "$truth_pid"; wait "$echo_pid" "$truth_pid"
grep -h "samples lost" "$work"/*.log | tail -5  # where poses went missing, if any did
# Scans the cloud lost (scans_dropped) and why (its last error): Health, not the log, says it.
"$scanbus" health --once --timeout 5 | grep cloud_assembly || echo "no Health from cloud_assembly within 5 s"
# A silent service is diagnosed from its own words: alive or not, and its log's end.
services=(scan_matcher pose_estimation cloud_assembly)  # pids[0..2], as started
show_services() {
  for i in "${!services[@]}"; do
    if kill -0 "${pids[$i]}" 2> /dev/null; then echo "== ${services[$i]} (running):"
    else wait "${pids[$i]}"; echo "== ${services[$i]} (ended with status $?):"; fi
    grep -v "RTPS_" "$work/${services[$i]}.log" | tail -n 15
    middleware_warnings "$work/${services[$i]}.log"
  done
}
"$scanbus" cloud save --out "$work/assembled.pcd" --timeout 30 || { fail "no rt/cloud/assembled"; show_services; }
"$scanbus" cloud save --window 1700000000,1700000180 --out "$work/window.pcd" --timeout 10 || fail "no assemble reply"
"$scanbus" eval boxes "$work/window.pcd" --truth 0.4,0.6 --json > "$work/boxes_window.json"
"$scanbus" eval boxes "$work/assembled.pcd" --truth 0.4,0.6 --json > "$work/boxes_assembled.json"
"$scanbus" eval ground "$work/window.pcd" --log "$flight" --json > "$work/ground_window.json" 2> "$work/ground_window.log"
"$scanbus" cloud save --topic rt/cloud/elevation --out "$work/elevation.pcd" --timeout 10 > /dev/null || fail "no rt/cloud/elevation"
"$scanbus" eval ground "$work/elevation.pcd" --log "$flight" --cells 0.5 --json > "$work/ground_elevation.json" 2> "$work/ground_elevation.log"
"$scanbus" cloud render "$work/assembled.pcd" --view side --out "$work/side.png" > /dev/null || fail "render"

python3 - "$work" "$sample" <<'PY' || fail "figures"
import bisect, json, math, sys
work, sample = sys.argv[1], sys.argv[2]
def stamp_of(message):
    return message["header"]["stamp"]["sec"] + message["header"]["stamp"]["nanosec"] * 1e-9
truth_poses = sorted((json.loads(line) for line in open(f"{work}/truth.jsonl")), key=stamp_of)
truth = [(stamp_of(p), p["pose"]["position"]["z"]) for p in truth_poses]
reference = json.load(open(f"{work}/in_process.json"))[0]
scans = reference["scans"]
def true_height(t):
    # truth at 100 Hz: linear between neighbours
    i = min(max(int(round((t - truth[0][0]) * 100)), 1), len(truth) - 1)
    while i < len(truth) - 1 and truth[i][0] < t: i += 1
    while i > 1 and truth[i - 1][0] > t: i -= 1
    (t0, h0), (t1, h1) = truth[i - 1], truth[i]
    return h0 + (h1 - h0) * (t - t0) / (t1 - t0) if t1 > t0 else h0
poses = [json.loads(l) for l in open(f"{work}/poses.jsonl")]
errors = []
for p in poses:
    errors.append(p["pose"]["pose"]["position"]["z"] - true_height(stamp_of(p)))
rmse = math.sqrt(sum(e * e for e in errors) / len(errors))
base = reference["height_rmse_m"]
best = min(base["barometer"], base["scan_matcher"])
print(f"poses over DDS: {len(poses)} of {scans} scans ({len(truth)} truth samples); fused height RMSE {rmse:.3f} m "
      f"(in one process {base['fused']:.3f}); barometer {base['barometer']:.3f}, scan matcher {base['scan_matcher']:.3f}")
# Said, not asserted: poses whose attitude is off (one that went ahead without its IMU sample
# under load smears its scan through the cloud), for a failing run's diagnosis.
def roll_pitch(q):
    w, x, y, z = q["w"], q["x"], q["y"], q["z"]
    return (math.degrees(math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))),
            math.degrees(math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x))))))
try:
    stamps = [t for t, _ in truth]
    off = []
    for p in poses:
        i = min(bisect.bisect_left(stamps, stamp_of(p)), len(stamps) - 1)
        measured, true = roll_pitch(p["pose"]["pose"]["orientation"]), roll_pitch(truth_poses[i]["pose"]["orientation"])
        off.append(max(abs(measured[0] - true[0]), abs(measured[1] - true[1])))
    print(f"attitude over DDS: {sum(o > 1.0 for o in off)} of {len(off)} poses over 1 degree off the truth in roll "
          f"or pitch, worst {max(off):.2f} degrees")
except (KeyError, ValueError, TypeError) as e:
    print(f"attitude over DDS not compared: {e!r}")
assert len(poses) >= 0.98 * scans, "poses lost on the way"
if "boxes" in reference:
    window = json.load(open(f"{work}/boxes_window.json"))
    assembled = json.load(open(f"{work}/boxes_assembled.json"))
    expected_p = reference["boxes"]["fused"].get("performance_percent")
    print(f"boxes P: window {window.get('performance_percent', 'none')} %, continuous cloud "
          f"{assembled.get('performance_percent', 'none')} % (in one process {expected_p} %)")
if "ground_error_m" in reference:  # a flight over terrain: the services' cloud against the true ground
    ground = json.load(open(f"{work}/ground_window.json"))
    expected = reference["ground_error_m"]["fused"]
    print(f"ground model over DDS: RMSE {ground['rmse']:.3f} m, bias {ground['bias']:+.3f} m, slope off "
          f"{100 * ground.get('slope_error', float('nan')):.1f} % (in one process {expected['rmse']:.3f} m, "
          f"{expected['bias']:+.3f} m, {100 * expected.get('slope_error', float('nan')):.1f} %)")
    assert abs(ground["rmse"] - expected["rmse"]) <= max(0.15 * expected["rmse"], 0.01), "ground model differs"
    assert ground["rmse"] < 0.1, "ground model over 10 cm RMSE from the true ground"
    grid, expected_grid = json.load(open(f"{work}/ground_elevation.json")), reference["elevation_grid"]["error_m"]
    print(f"elevation grid over DDS: {grid['points']} cells, RMSE {grid['rmse']:.3f} m (in one process "
          f"{expected_grid['points']} cells, {expected_grid['rmse']:.3f} m)")
    assert abs(grid["rmse"] - expected_grid["rmse"]) <= max(0.15 * expected_grid["rmse"], 0.01), "elevation grid differs"
    if "slope_error" in expected:
        assert ground["slope_error"] < 0.2, "the terrain's tilt is lost"
if sample:
    assert abs(rmse - base["fused"]) <= max(0.15 * base["fused"], 0.01), "fused height differs from the in-process one"
    assert rmse < base["barometer"], "fused height no better than the barometer alone"
else:
    assert rmse <= 0.5 * best, "fused height not at most half of the better single source"
assert sample or "boxes" in reference, "the live flight's reference has no boxes"
if "boxes" in reference:  # scenario IV and the live flight; the other samples have no boxes
    # One-sided: the services must lose nothing against one process; a window above it is
    # not a loss. The same flight's window over DDS gave 97.81 % in one run and 99.44 % in a
    # CI run (in one process 98.16 % both times, fused RMSE 0.021 m both): IMU and GPS
    # samples arrive at different points of the stream from run to run, and P moves 1.6
    # points per centimetre of a box's length (its width/length 0.4/0.6 against 0.4/0.61).
    assert window["ok"] and window["performance_percent"] >= expected_p - 1.0, window
    assert window["performance_percent"] >= 97.0, window  # a floor about the sweeps' lowest seeds (96.8-97.4 %)
PY

for i in "${!services[@]}"; do
  pid=${pids[$i]} service=${services[$i]}
  kill -0 "$pid" 2> /dev/null || { fail "$service died early"; tail -n 15 "$work/$service.log"; continue; }
  expect_clean_stop "$service" "$pid" TERM "$work/$service.log" || failures=$((failures + 1))
done
pids=()
[ "$failures" -eq 0 ] && echo "mav pipeline: ok"
[ "$failures" -eq 0 ]
