#!/usr/bin/env bash
# The fused ground model as surveyors open it: a flight over a known slope through
# `scanbus eval mav --out`, its elevation GeoTIFF read by GDAL's own tools (gdalinfo -stats,
# gdal_translate to XYZ) and checked against the truth: projection centred on the log's
# origin, corners where the map frame puts them, every cell's height on the ellipsoid.
# `scanbus cloud dem` grids the fused PCD again, and refuses bad input by name.
set -euo pipefail
source "$(dirname "$0")/lib.sh"
scanbus=$1
if ! command -v gdalinfo > /dev/null || ! command -v gdal_translate > /dev/null; then
  echo "SKIP: gdalinfo and gdal_translate (Debian gdal-bin, scripts/install-deps.sh) are not installed"
  exit 77
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0

cat > "$work/slope.yaml" <<'YAML'
terrain:
  slope: [0.04, -0.02]   # dz/dx, dz/dy through the origin
YAML
"$scanbus" sim mav --scenario 1 --duration 30 --seed 5 --terrain "$work/slope.yaml" --out "$work/flight.mavlog" > /dev/null
"$scanbus" eval mav --log "$work/flight.mavlog" --out "$work" --json > "$work/eval.json"
tif="$work/flight.mavlog_fused_dem.tif"
gdalinfo -json -stats "$tif" > "$work/info.json"
gdal_translate -q -b 1 -of XYZ "$tif" "$work/heights.xyz"
"$scanbus" cloud dem "$work/flight.mavlog_fused.pcd" --origin "$(grep '^META origin' "$work/flight.mavlog" | awk '{print $3","$4","$5}')" \
  --cell 0.5 --out "$work/again.tif"
gdal_translate -q -b 1 -of XYZ "$work/again.tif" "$work/again.xyz"

python3 - "$work" <<'PY'
import json, math, re, sys
work = sys.argv[1]
origin = None
for line in open(f"{work}/flight.mavlog"):
    if line.startswith("META origin"):
        origin = [float(v) for v in line.split()[2:5]]
lat0, lon0, alt0 = origin
info = json.load(open(f"{work}/info.json"))
wkt = info["coordinateSystem"]["wkt"]
assert "Transverse Mercator" in wkt, wkt
def parameter(name):
    return float(re.search(f'PARAMETER\\["{name}",([-0-9.eE]+)', wkt).group(1))
assert abs(parameter("Latitude of natural origin") - lat0) < 1e-9, wkt
assert abs(parameter("Longitude of natural origin") - lon0) < 1e-9, wkt
x0, cell, _, y0, _, negative = info["geoTransform"]
assert cell == 0.5 and negative == -0.5, info["geoTransform"]
# GDAL's own corner in degrees against the map-frame metres (sphere, well within 0.5 m here).
ul = info["wgs84Extent"]["coordinates"][0][0]
east = math.radians(ul[0] - lon0) * 6378137 * math.cos(math.radians(lat0))
north = math.radians(ul[1] - lat0) * 6356752
assert abs(east - x0) < 0.5 and abs(north - y0) < 0.5, (ul, east, north, x0, y0)
bands = info["bands"]
assert [b["description"] for b in bands] == ["height", "stdev", "count"], bands

def heights(path):
    cells = {}
    for line in open(path):
        x, y, h = map(float, line.split())
        if not math.isnan(h):
            cells[(x, y)] = h
    return cells

cells = heights(f"{work}/heights.xyz")
# The truth at each cell's centre: the slope through the origin on the origin's altitude
# (the ellipsoid drops 2 mm 150 m out: nothing at this size).
errors = sorted(abs(h - (alt0 + 0.04 * x - 0.02 * y)) for (x, y), h in cells.items())
rmse = math.sqrt(sum(e * e for e in errors) / len(errors))
print(f"{len(cells)} cells, height error RMSE {rmse:.3f} m, p95 {errors[int(0.95 * len(errors))]:.3f} m, "
      f"worst {errors[-1]:.3f} m")
assert len(cells) > 200, len(cells)
assert rmse < 0.05 and errors[int(0.95 * len(errors))] < 0.1, rmse
stats = bands[0]
assert abs(stats["mean"] - sum(cells.values()) / len(cells)) < 1e-3, stats
evaluation = json.load(open(f"{work}/eval.json"))[0]["elevation_grid"]
assert evaluation["cells"] == len(cells), (evaluation, len(cells))
again = heights(f"{work}/again.xyz")
assert len(again) == len(cells) and max(abs(again[k] - cells[k]) for k in cells) < 0.002, "cloud dem differs"
PY

expect_exit 2 "latitude must be within" -- "$scanbus" cloud dem "$work/flight.mavlog_fused.pcd" --origin 95,13,34 --out "$work/bad.tif"
expect_exit 2 "nonexistent" -- "$scanbus" cloud dem "$work/flight.mavlog_fused.pcd" --origin 52,13,34 --out /nonexistent/dem.tif
printf 'not a cloud\n' > "$work/bad.xyz"
expect_exit 2 "bad.xyz" -- "$scanbus" cloud dem "$work/bad.xyz" --origin 52,13,34 --out "$work/bad.tif"
[ "$failures" -eq 0 ]
