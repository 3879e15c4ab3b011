#!/usr/bin/env bash
# The MAV laser's scan plane calibrated as a user does it: a hover-turn log through
# `scanbus calibrate scan-plane`, its rotation against the simulated unit's (META
# true_laser_misalignment), the YAML it prints read back by `scanbus eval mav` through
# `--calibration-log`; a flight that does not turn enough and a malformed log are refused by name.
set -euo pipefail
source "$(dirname "$0")/lib.sh"
scanbus=$1
with_work

"$scanbus" sim mav --pattern hover-turn --duration 91 --seed 9 --out "$work/hover.mavlog" > /dev/null
"$scanbus" calibrate scan-plane --log "$work/hover.mavlog" --json > "$work/calibration.json"
"$scanbus" calibrate scan-plane --log "$work/hover.mavlog" > "$work/calibration.txt"
"$scanbus" sim mav --scenario 1 --duration 20 --seed 9 --out "$work/flight.mavlog" > /dev/null
"$scanbus" eval mav --log "$work/flight.mavlog" --calibration-log "$work/hover.mavlog" --json > "$work/eval.json"
python3 - "$work" <<'PY' || failures=$((failures + 1))
import json, math, re, sys
work = sys.argv[1]
truth = next(float(l.split()[4]) for l in open(f"{work}/hover.mavlog") if l.startswith("META true_laser_misalignment"))
c = json.load(open(f"{work}/calibration.json"))
assert c["ok"], c
error = c["rotation_deg"] - math.degrees(truth)
print(f"rotation {c['rotation_deg']:.3f} +- {c['sigma_deg']:.3f} deg, true {math.degrees(truth):.3f}, error {error:+.4f}")
assert abs(error) < 3 * c["sigma_deg"] + 0.01, "the calibration misses the simulated unit's rotation"
text = open(f"{work}/calibration.txt").read()
printed = float(re.search(r"scan_plane_rotation: (-?[0-9.]+)", text).group(1))
assert abs(printed - c["rotation_deg"]) < 0.001, text
applied = json.load(open(f"{work}/eval.json"))[0]["scan_plane_calibration"]
assert abs(applied["rotation_deg"] - c["rotation_deg"]) < 1e-9, applied
PY

"$scanbus" sim mav --pattern hover-turn --duration 30 --seed 9 --out "$work/short.mavlog" > /dev/null
expect_exit 1 "3 whole turns are needed" -- "$scanbus" calibrate scan-plane --log "$work/short.mavlog"
expect_exit 2 "the scan plane is not measured" -- "$scanbus" eval mav --log "$work/flight.mavlog" \
  --calibration-log "$work/short.mavlog"
echo "IMU 1700000000 0 0 0" > "$work/broken.mavlog"
expect_exit 2 "broken.mavlog:1" -- "$scanbus" calibrate scan-plane --log "$work/broken.mavlog"
exit "$failures"
