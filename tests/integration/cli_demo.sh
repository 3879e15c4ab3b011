#!/usr/bin/env bash
# The main job end to end, and the CLI against a running service: `scanbus demo` runs
# the room's and the MAV's services as their own processes and writes plausible results; `scanbus health --check`,
# `scanbus echo` and `scanbus topics` see the running service.
set -euo pipefail
source "$(dirname "$0")/lib.sh"
scanbus=$1
work=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$work"' EXIT

# SCANBUS_TEST_DEMO_MAV=0: the room only (scripts/sanitize.sh; the sanitizers' slowdown
# would make the 8x replay outrun the services).
# The JSON is printed on failure too: it says which part failed.
mav_flight=--mav-rate=8
[ "${SCANBUS_TEST_DEMO_MAV:-1}" = 0 ] && mav_flight=--no-mav
"$scanbus" demo --json --out "$work/out" "$mav_flight" > "$work/demo.json" ||
  { cat "$work/demo.json"; echo "FAIL: scanbus demo exited non-zero"; exit 1; }
cat "$work/demo.json"
python3 - "$work/demo.json" <<'PY'
import json, os, sys
result = json.load(open(sys.argv[1]))
assert result["revolutions"] == 3 * 27, result
# 20 RPM: about 146 measurements in each of 81 revolutions, less the rays that leave
# through the doorway and the simulated dropouts.
assert 10000 <= result["points"] <= 81 * 151, result
room = result["room"]
assert room["status"] == "ok", room
walls = sorted((w["length_m"], w["length_sigma_m"]) for w in room["walls"])
lengths = [length for length, _ in walls]
assert len(walls) == 4, walls
# 4 of its sigmas, 3 cm at least: at the demo's 20 RPM on a loaded machine walls came out 2 cm
# off (tests/faults/kill_restart.sh); the sigmas are calibrated at the thesis's 12 RPM.
for (got, sigma), want in zip(walls, [3.48, 3.48, 5.47, 5.47]):
    assert abs(got - want) < max(0.03, 4 * sigma), (got, sigma, want)
assert abs(room["area_m2"] - 5.47 * 3.48) < 0.01 * 5.47 * 3.48, room["area_m2"]
assert abs(room["ceiling_height_m"] - 2.5) < 0.05, room["ceiling_height_m"]
# What the service measured, carried over DDS: its point counts, time and the area's sigma.
assert 0.9 * result["points"] <= room["points_in"] <= 1.1 * result["points"], (room["points_in"], result["points"])
assert 0 < room["points_after_filter"] <= room["points_valid"] <= room["points_in"], room
assert room["elapsed_ms"] > 0 and room["area_sigma_m2"] and room["area_sigma_m2"] > 0, room
print("demo room:", [round(l, 3) for l in lengths], "area", round(room["area_m2"], 2), "from", room["points_in"],
      "points in", round(room["elapsed_ms"], 1), "ms")
mav = result.get("mav")
if mav is None:
    assert os.environ.get("SCANBUS_TEST_DEMO_MAV") == "0", "the demo gave no MAV result"
    print("demo MAV: left out (SCANBUS_TEST_DEMO_MAV=0)")
else:
    # Scenario IV through the services: every scan's pose, the fused height well under the
    # barometer's, the boxes found and measured. Not P >= 99 %: the issue's target is not met
    # on every seed (docs/performance.md) and this flight's P moves by a point with small
    # changes (99.04 % at 18a270f, 97.81 % since GPS altitude's bias is Gauss-Markov,
    # 0f18494; the log's millimetre ranges alone move it 1.4 points against 'eval mav'). The
    # floor, 97 %, is about the sweeps' lowest seeds (96.8-97.4 %); a broken pipeline gives
    # far less.
    assert mav["poses"] >= 0.98 * mav["scans"], mav
    assert mav["height_rmse_m"]["fused"] < 0.5 * mav["height_rmse_m"]["barometer"], mav
    assert mav["boxes_ok"] and mav["boxes_performance_percent"] >= 97.0, mav
    print("demo MAV: fused height RMSE", round(mav["height_rmse_m"]["fused"], 3), "m, boxes P",
          round(mav["boxes_performance_percent"], 2), "%")
    result["files"] += mav["files"]
for path in result["files"]:
    with open(path, "rb") as f:
        head = f.read(16)
    # PCD, PNG, or DXF (dxflib's comment line, then the HEADER section)
    assert head.startswith(b"#") or head.startswith(b"\x89PNG") or head.lstrip().startswith(b"999"), (path, head)
print("demo output plausible")
PY

# `scanbus scan` of a shipped room other than the default.
"$scanbus" scan --room "$(dirname "$0")/../../config/rooms/l_shaped.yaml" --out "$work/l_shaped.pcd" --speed 40 --json \
  > "$work/scan.json"
python3 - "$work/scan.json" <<'PY'
import json, sys
result = json.load(open(sys.argv[1]))
assert result["revolutions"] == 27 and result["points"] > 3000, result
assert open(result["file"], "rb").read(5) == b"# .PC", result
print("scan of the L-shaped room:", result["points"], "points")
PY

# The simulator in real time and scanner_io left running for the CLI to look at.
"$scanbus" sim scanner --link "$work/scanner.tty" > "$work/sim.log" 2>&1 &
for _ in $(seq 100); do [ -e "$work/scanner.tty" ] && break; sleep 0.05; done
printf 'service:\n  health_period: 0.2\nscanner_io:\n  port: %s\n' "$work/scanner.tty" > "$work/scanner_io.yaml"
"$scanbus" run scanner_io --config "$work/scanner_io.yaml" 2> "$work/scanner_io.log" &
scanner_io=$!
"$scanbus" health --check scanner_io --timeout 20
"$scanbus" echo rt/scanner/status --count 1 --timeout 20 | python3 -c '
import json, sys
status = json.loads(sys.stdin.readline())
assert status["device"].endswith("scanner.tty") and status["state"] in (1, 2), status
print("echo rt/scanner/status:", status["message"])'
"$scanbus" echo rt/scanbus/health --count 2 --timeout 20 | python3 -c '
import json, sys
lines = [json.loads(l) for l in sys.stdin]
assert len(lines) == 2 and all("counters" in l for l in lines), lines
print("echo rt/scanbus/health: 2 samples")'
"$scanbus" topics | grep -q "rt/scanner/scan_cloud"
if "$scanbus" echo rt/no_such --count 1 --timeout 1 2> "$work/err"; then echo "unknown topic accepted"; exit 1; fi
grep -q "unknown topic 'rt/no_such'" "$work/err"
# SIGINT (Ctrl-C) stops a service cleanly within 1 s.
expect_clean_stop scanner_io "$scanner_io" INT "$work/scanner_io.log"
echo "cli ok"
