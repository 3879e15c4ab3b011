#!/usr/bin/env bash
# The MAV paper's four scenarios (3 minutes each) through the whole pipeline in one
# process, on noise seed 1 and on seed 5 (where barometer and scan matcher drift the same
# way: the fusion of the two alone missed there): in each, the fused height's RMSE is at
# most half of the barometer's and the fused cloud within 5 cm RMS of the true ground (issue
# 19's RTK target); in scenario IV the boxes' P is at least 99 % with the fused height and
# lower with the barometer alone. Half the integrated scan matcher is printed, not asserted:
# on these two seeds its start (one barometer sample) is within 5 cm and it drifts a few mm
# over flat ground, while the fusion keeps a 1-3 cm flight-long offset that its absolute
# sources leave (docs/performance.md, "Across noise seeds"). Bad input to the commands: a
# clear error, exit 2. bench/mav_seeds.sh sweeps more seeds.
set -uo pipefail
source "$(dirname "$0")/../integration/lib.sh"
scanbus=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0

echo "LASER 1.0 0 0.01 0.1 30 3 1.0 x 2.0" > "$work/bad.mavlog"
expect_error 2 "bad.mavlog:1: range 'x' is not a number" -- "$scanbus" eval mav --log "$work/bad.mavlog"
echo "x y z" > "$work/bad.xyz"
expect_error 2 "bad.xyz" -- "$scanbus" eval boxes "$work/bad.xyz" --truth 0.4,0.6
expect_error 1 "box size must be positive and under 5 m" -- "$scanbus" sim mav --box 6,0.4,0.3 --out "$work/x.mavlog"
printf 'META origin 52 13 34\nMETA laser_mount 0 0 -0.1 0 1.5708 0\nBARO 1.0 101000\n' > "$work/no_truth.mavlog"
expect_error 2 "no TRUTH records" -- "$scanbus" eval mav --log "$work/no_truth.mavlog"

for seed in 1 5; do
  "$scanbus" eval mav --seed $seed --json > "$work/seed_$seed.json" || exit 1
done
python3 - "$work"/seed_1.json "$work"/seed_5.json <<'PY' || failures=$((failures + 1))
import json, sys
ok = True
for name in sys.argv[1:]:
    print(name.rsplit("/", 1)[1])
    for flight in json.load(open(name)):
        rmse = flight["height_rmse_m"]
        best = min(rmse["barometer"], rmse["scan_matcher"])
        print(f"{flight['flight']}: height RMSE barometer {rmse['barometer']:.3f}, scan matcher "
              f"{rmse['scan_matcher']:.3f}, fused {rmse['fused']:.3f} m (ratio {rmse['fused'] / best:.2f}), "
              f"{flight['failed_matches']} failed matches, {flight['clearances']} clearances, "
              f"{flight['ground_cells']} ground cells, fusion {flight['fusion_ms_per_update']:.2f} ms per scan")
        ground = flight["ground_error_m"]["fused"]["rmse"]
        print(f"  fused ground RMSE {ground:.3f} m")
        ok &= rmse["fused"] <= 0.5 * rmse["barometer"] and ground <= 0.05
        if "boxes" in flight:
            p = {k: v["performance_percent"] if v["ok"] else 0.0 for k, v in flight["boxes"].items()}
            print(f"  boxes P: barometer {p['barometer']:.2f} %, scan matcher {p['scan_matcher']:.2f} %, fused {p['fused']:.2f} %")
            ok &= p["fused"] >= 99.0 and p["barometer"] < p["fused"]
assert ok, "a target was missed"
PY
[ "$failures" -eq 0 ]
