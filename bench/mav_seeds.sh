#!/usr/bin/env bash
# The MAV targets across noise seeds: `scanbus eval mav` (four 3-minute scenarios) for each
# seed, one markdown row per seed (fused height RMSE, its ratio to the better single source
# in each scenario, scenario IV's box P with each height, the fused cloud's height error
# against the true ground: RMSE and bias, worst scenario, beside the same scenario's cloud
# built with the true height (what no height estimate removes); the fused elevation grid's cells
# against it: RMSE, worst scenario) and a summary (also: fused below
# GPS altitude alone, the fused height's sigma coverage; the same for the fused height as first
# solved, before it settled; the sigma's coverage pooled over all poses; the terrain's tilt within
# 10 %, also at the true height). Extra arguments go to `scanbus
# eval mav` (e.g. --no-ground, --gps float, --noise-scale 2). About 30 s per seed on one
# core over flat ground. MAV_SEEDS_KEEP=DIR keeps each seed's JSON there.
#   bench/mav_seeds.sh [--seeds 1-10] [eval mav options, e.g. --terrain config/terrain/slope_mound.yaml]
set -euo pipefail
cd "$(dirname "$0")/.."
first=1 last=10
if [ "${1:-}" = "--seeds" ]; then
  first=${2%-*} last=${2#*-}
  shift 2
fi
scanbus=${SCANBUS:-build/services/cli/scanbus}
[ -x "$scanbus" ] || scripts/build.sh > /dev/null
if [ -n "${MAV_SEEDS_KEEP:-}" ]; then
  work=$MAV_SEEDS_KEEP
  mkdir -p "$work"
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
for seed in $(seq "$first" "$last"); do
  [ -t 2 ] && printf '\rseed %s of %s-%s ' "$seed" "$first" "$last" >&2
  "$scanbus" eval mav --seed "$seed" --json "$@" > "$work/$seed.json" 2> "$work/$seed.log" || {
    cat "$work/$seed.log" >&2
    exit 1
  }
done
[ -t 2 ] && printf '\r%30s\r' "" >&2
python3 - "$work" "$first" "$last" <<'PY'
import json, statistics, sys
folder, first, last = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
print("| seed | fused RMSE | GPS RMSE | ratio I | II | III | IV | scenario IV P: barometer | scan matcher | fused | ground RMSE fused (worst) | its bias | at the true height | elevation grid RMSE (worst) |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
ratios, held, p_fused, ground, below_gps, within, grids, floors = [], 0, [], [], 0, [], [], []
solved_below_gps, gains, solved_within, tilts = 0, [], [], []
for seed in range(first, last + 1):
    flights = json.load(open(f"{folder}/{seed}.json"))
    row, fused, gps, worst, grid = [], [], [], None, None
    for flight in flights:
        e = flight.get("elevation_grid", {}).get("error_m")
        if e and (grid is None or e["rmse"] > grid): grid = e["rmse"]
        g = flight.get("ground_error_m", {}).get("fused")
        if g and g.get("slope_error") is not None:  # the true ground tilts 1 % or more
            truth = flight["ground_error_m"].get("true_height", {}).get("slope_error")
            tilts.append((g["slope_error"], truth if truth is not None else float("nan")))
        if g and (worst is None or g["rmse"] > worst["rmse"]):
            worst, floor = g, flight["ground_error_m"].get("true_height")
        rmse = flight["height_rmse_m"]
        ratio = rmse["fused"] / min(rmse["barometer"], rmse["scan_matcher"])
        ratios.append(ratio)
        held += ratio <= 0.5
        row.append(f"{ratio:.2f}")
        fused.append(rmse["fused"])
        if "gps" in rmse:
            gps.append(rmse["gps"])
            below_gps += rmse["fused"] < rmse["gps"]
            solved_below_gps += rmse["fused_immediate"] < rmse["gps"]
        gains.append(rmse["fused_immediate"] - rmse["fused"])
        if None not in flight["fused_within_sigma"].values():  # null: no fused sigma in the flight
            within.append(dict(flight["fused_within_sigma"], poses=flight["poses"]))
        solved_within.append(flight["fused_immediate_within_sigma"]["1"])
    boxes = flights[-1].get("boxes", {})
    p = {k: (v["performance_percent"] if v["ok"] else 0.0) for k, v in boxes.items()}
    if p: p_fused.append(p["fused"])
    cells = [f"{p[k]:.2f} %" for k in ("barometer", "scan_matcher", "fused")] if p else ["", "", ""]
    if worst: ground.append(worst["rmse"])
    cells += [f"{worst['rmse']:.3f} m", f"{worst['bias']:+.3f} m"] if worst else ["", ""]
    cells += [f"{floor['rmse']:.3f} m" if worst and floor else ""]
    if worst and floor: floors.append(floor["rmse"])
    cells += [f"{grid:.3f} m" if grid is not None else ""]
    if grid is not None: grids.append(grid)
    gps_text = f"{min(gps):.3f}-{max(gps):.3f} m" if gps else "-"
    print(f"| {seed} | {min(fused):.3f}-{max(fused):.3f} m | {gps_text} | " + " | ".join(row) + " | " + " | ".join(cells) + " |")
print()
print(f"fused <= half the better source: {held} of {len(ratios)} flights; ratio median {statistics.median(ratios):.2f}, "
      f"worst {max(ratios):.2f}; fused below GPS altitude alone: {below_gps} of {len(ratios)}")
print(f"the fused height as first solved (rt/pose; the fused above is as it settled, what places the scans): "
      f"below GPS altitude alone {solved_below_gps} of {len(ratios)}; settling lowered the RMSE by median "
      f"{1000 * statistics.median(gains):.1f} mm, between {1000 * min(gains):+.1f} and {1000 * max(gains):+.1f} mm; "
      f"within 1 sigma median {statistics.median(solved_within):.0%}")
one = [w["1"] for w in within]
two = [w["2"] for w in within]
# Pooled over every pose of every flight: what "calibrated" asks (a flight's error is mostly one
# offset for the whole flight, so a single flight's share is near 0 or 100 %).
poses = max(sum(w["poses"] for w in within), 1)
pooled = [sum(w[k] * w["poses"] for w in within) / poses for k in ("1", "2")]
print(f"fused height within 1 / 2 sigma, pooled over all poses: {pooled[0]:.1%} / {pooled[1]:.1%} "
      f"(a calibrated sigma: 68.3 / 95.4 %); by flight, 1 sigma median {statistics.median(one):.0%} "
      f"({min(one):.0%}-{max(one):.0%}), 2 sigma median {statistics.median(two):.0%} ({min(two):.0%}-{max(two):.0%})")
if ground:
    print(f"fused ground RMSE, worst scenario of each seed: median {statistics.median(ground):.3f} m, worst {max(ground):.3f} m")
if floors:
    print(f"the same scenarios' ground at the true height: median {statistics.median(floors):.3f} m, worst {max(floors):.3f} m")
if tilts:
    print(f"the terrain's tilt within 10 %: {sum(t <= 0.1 for t, _ in tilts)} of {len(tilts)} flights "
          f"(worst {max(t for t, _ in tilts):.1%}); at the true height {sum(t <= 0.1 for _, t in tilts)} "
          f"(worst {max(t for _, t in tilts):.1%})")
if grids:
    print(f"elevation grid RMSE, worst scenario of each seed: median {statistics.median(grids):.3f} m, worst {max(grids):.3f} m")
if p_fused:
    print(f"scenario IV P fused >= 99 %: {sum(p >= 99 for p in p_fused)} of {len(p_fused)} seeds; median "
          f"{statistics.median(p_fused):.2f} %, lowest {min(p_fused):.2f} %")
PY
