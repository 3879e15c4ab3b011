#!/usr/bin/env bash
# `scanbus room measure` from files: units, JSON, floor plans, bad input (exit 2 with a
# clear message, never a crash), `room calibrate`, and the real room scan in ../shared when it is there.
set -uo pipefail
source "$(dirname "$0")/lib.sh"
scanbus=$1
shared=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }

# A synthetic 4.2 m x 3.1 m room in centimetres (walls only, 1 cm noise), scanner inside.
python3 - "$work/room_cm.xyz" <<'PY'
import random, sys
random.seed(7)
x0, y0, x1, y1 = -180.0, -120.0, 240.0, 190.0
with open(sys.argv[1], "w") as out:
    out.write("# x y z in cm\n")
    for (ax, ay, bx, by) in [(x0, y0, x1, y0), (x1, y0, x1, y1), (x1, y1, x0, y1), (x0, y1, x0, y0)]:
        steps = int(max(abs(bx - ax), abs(by - ay)) / 3)
        for i in range(steps + 1):
            t = i / steps
            for z in range(-120, 131, 5):
                nx, ny = (by - ay), -(bx - ax)
                norm = (nx * nx + ny * ny) ** 0.5
                e = random.gauss(0, 1.0)
                out.write(f"{ax + t * (bx - ax) + e * nx / norm:.2f} {ay + t * (by - ay) + e * ny / norm:.2f} {z}\n")
PY
"$scanbus" room measure "$work/room_cm.xyz" --unit cm --json --plan "$work/plan.svg" > "$work/out.json"
status=$?
python3 - "$work/out.json" <<'PY' || fail "synthetic room in cm"
import json, sys
room = json.load(open(sys.argv[1]))
assert room["status"] == "ok", room
lengths = sorted(w["length_m"] for w in room["walls"])
assert len(lengths) == 4, lengths
for got, want in zip(lengths, [3.1, 3.1, 4.2, 4.2]):
    assert abs(got - want) < 0.01, (got, want)
assert abs(room["area_m2"] - 4.2 * 3.1) < 0.05, room["area_m2"]
for key in ("corners", "ceiling_height_m", "points_in", "points_after_filter", "elapsed_ms"):
    assert key in room, key
print("ok   synthetic room in cm:", [round(l, 3) for l in lengths], "area", round(room["area_m2"], 3))
PY
[ "$status" -eq 0 ] || fail "exit $status for a measurable room"
grep -q "<svg" "$work/plan.svg" || fail "no SVG floor plan"

# The plan as DXF, opened by a reader other than the writer's (Debian's python3-ezdxf, run by
# the system Python that has it): it audits clean, WALLS close the room, one dimension per
# wall says its length.
"$scanbus" room measure "$work/room_cm.xyz" --unit cm --plan "$work/plan.dxf" > /dev/null || fail "DXF plan"
/usr/bin/python3 - "$work/plan.dxf" "$work/out.json" <<'PY' || fail "DXF plan read back"
import json, math, sys
import ezdxf
doc = ezdxf.readfile(sys.argv[1])
room = json.load(open(sys.argv[2]))
auditor = doc.audit()
assert not auditor.has_errors, [str(e) for e in auditor.errors]
assert doc.header.get("$INSUNITS") == 6, doc.header.get("$INSUNITS")
msp = doc.modelspace()
walls = [l for l in msp.query("LINE") if l.dxf.layer == "WALLS"]
xy = lambda v: (v.x, v.y)
drawn = sum(math.dist(xy(l.dxf.start), xy(l.dxf.end)) for l in walls)
assert abs(drawn - room["perimeter_m"]) < 1e-3, (drawn, room["perimeter_m"])
labels = [t.dxf.text for t in msp.query("TEXT") if t.dxf.layer == "DIMENSIONS"]
assert len(labels) == len(room["walls"]), labels
for label, wall in zip(labels, room["walls"]):
    assert label.startswith(f'{wall["length_m"]:.3f} m'), (label, wall["length_m"])
# Per wall: 2 extension lines, 2 ticks, then the dimension line, as long as the wall.
dimension_lines = [l for l in msp.query("LINE") if l.dxf.layer == "DIMENSIONS"]
assert len(dimension_lines) == 5 * len(room["walls"]), len(dimension_lines)
for line, wall in zip(dimension_lines[4::5], room["walls"]):
    assert abs(math.dist(xy(line.dxf.start), xy(line.dxf.end)) - wall["length_m"]) < 1e-3, wall
print("ok   DXF plan read by ezdxf:", len(walls), "wall lines,", len(labels), "dimensions,", round(drawn, 3), "m")
PY

# The same room as PCL's binary_compressed PCD (fields one after another, LZF: literal runs
# only), read as the xyz; then with its sizes damaged (PCL trusts them: found by fuzzing).
python3 - "$work/room_cm.xyz" "$work" <<'PY'
import struct, sys
points = [l.split() for l in open(sys.argv[1]) if not l.startswith("#")]
fields = b"".join(struct.pack(f"<{len(points)}f", *(float(p[axis]) for p in points)) for axis in range(3))
lzf = b"".join(bytes([len(fields[i:i + 32]) - 1]) + fields[i:i + 32] for i in range(0, len(fields), 32))
header = (f"VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH {len(points)}\nHEIGHT 1\n"
          f"POINTS {len(points)}\nDATA binary_compressed\n").encode()
for name, compressed, uncompressed in [("compressed", len(lzf), len(fields)), ("compressed_short", len(lzf), 12),
                                       ("compressed_past_end", len(lzf) + 1, len(fields))]:
    open(f"{sys.argv[2]}/room_{name}.pcd", "wb").write(header + struct.pack("<II", compressed, uncompressed) + lzf)
PY
"$scanbus" room measure "$work/room_compressed.pcd" --unit cm --json > "$work/compressed.json" || fail "binary_compressed PCD"
python3 -c 'import json,sys; a,b=(json.load(open(f)) for f in sys.argv[1:]); assert abs(a["area_m2"]-b["area_m2"])<1e-3 and a["points_in"]==b["points_in"], (a, b)' \
  "$work/out.json" "$work/compressed.json" && echo "ok   binary_compressed PCD reads as the xyz" || fail "binary_compressed PCD differs from the xyz"
expect_exit 2 "uncompressed size 12 is not the" -- "$scanbus" room measure "$work/room_compressed_short.pcd"
expect_exit 2 "past the file's" -- "$scanbus" room measure "$work/room_compressed_past_end.pcd"
printf 'FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nPOINTS 1\nDATA ascii\nSIZE 8 8 8\n1 2 3\n' > "$work/second_header.pcd"
expect_exit 2 "the data starts with a header line, SIZE" -- "$scanbus" room measure "$work/second_header.pcd"
printf 'FIELDS x y z\nSIZE 2 4 4\nTYPE F F F\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n' > "$work/half_float.pcd"
expect_exit 2 "field type 'F' of size '2'" -- "$scanbus" room measure "$work/half_float.pcd"

: > "$work/empty.xyz"
expect_exit 2 "no points" -- "$scanbus" room measure "$work/empty.xyz"
head -c 3000 /dev/urandom > "$work/corrupt.pcd"
expect_exit 2 "not a readable pcd file" -- "$scanbus" room measure "$work/corrupt.pcd"
printf '# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1000\nHEIGHT 1\nPOINTS 1000\nDATA binary\n\x01\x02' > "$work/truncated.pcd"
expect_exit 2 "not a readable pcd file" -- "$scanbus" room measure "$work/truncated.pcd"
expect_exit 2 "input_error" -- "$scanbus" room measure "$work/corrupt.pcd" --json
head -c 3000 /dev/urandom > "$work/corrupt.ply"
expect_exit 2 "not a readable ply file" -- "$scanbus" room measure "$work/corrupt.ply"
printf 'ply\nformat ascii 1.0\nelement vertex 100\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n' > "$work/short.ply"
expect_exit 2 "not a readable ply file" -- "$scanbus" room measure "$work/short.ply"
printf '1 2 3\n4 five 6\n' > "$work/bad.xyz"
expect_exit 2 "bad.xyz:2: expected three numbers x y z" -- "$scanbus" room measure "$work/bad.xyz"
printf 'nan nan nan\n' > "$work/nan.xyz"
for _ in $(seq 200); do printf 'nan 1 2\n' >> "$work/nan.xyz"; done
expect_exit 1 "too_few_points" -- "$scanbus" room measure "$work/nan.xyz" --json
touch "$work/x.las"
expect_exit 2 "unknown format '.las'" -- "$scanbus" room measure "$work/x.las"
expect_exit 2 "cannot open" -- "$scanbus" room measure "$work/missing.pcd"
printf 'room_measurement:\n  voxel_leef: 0.1\n' > "$work/bad.yaml"
expect_exit 2 "unknown key 'room_measurement.voxel_leef'" -- "$scanbus" room measure "$work/room_cm.xyz" --config "$work/bad.yaml"
# The service's own file (service, dds sections and all) is a valid --config.
"$scanbus" room measure "$work/room_cm.xyz" --unit cm --config "$(dirname "$0")/../../config/services/room_measurement.yaml" \
  > "$work/service_config.txt" 2>&1 || { cat "$work/service_config.txt"; fail "service config rejected by room measure"; }

# `room calibrate`: one simulated unit's scans of ten rooms give its terms and the config that
# applies them; a file that cannot be read is named, the others still calibrate (exit 2).
"$scanbus" eval rooms --seed 3001 --count 10 --category box doors windows furniture near_wall --unit-seed 9 \
  --out "$work/unit" > "$work/unit.txt" || fail "eval rooms --unit-seed"
grep -q "^unit 9 (simulated): range noise " "$work/unit.txt" || { head -3 "$work/unit.txt"; fail "eval rooms did not say what unit 9 is"; }
"$scanbus" room calibrate "$work"/unit/*.pcd > "$work/calibration.txt" || fail "room calibrate exit $?"
sed -n '/^room_measurement:/,$p' "$work/calibration.txt" > "$work/unit.yaml"
grep -q "range_bias: " "$work/unit.yaml" || { cat "$work/calibration.txt"; fail "room calibrate printed no config"; }
# Its JSON names every term's estimate, sigma and the servo's part of that sigma.
"$scanbus" room calibrate "$work"/unit/*.pcd --json > "$work/calibration.json" || fail "room calibrate --json exit $?"
python3 - "$work/calibration.json" <<'PY' || fail "room calibrate --json lacks a term"
import json, sys
c = json.load(open(sys.argv[1]))
for term, unit in (("range_bias", "m"), ("lever_arm", "m"), ("pitch_offset", "rad")):
    estimate, sigma, servo = c[f"{term}_{unit}"], c[f"{term}_sigma_{unit}"], c[f"{term}_servo_sigma_{unit}"]
    assert abs(estimate) < 1 and 0 <= servo <= sigma and sigma > 0, (term, estimate, servo, sigma)
assert c["pitch_offset_servo_sigma_rad"] > 0  # every scan's steps see the walls: the servo's part is there
assert "range_bias: " in c["config"]
PY
"$scanbus" room measure "$work/unit/box_3001.pcd" --config "$work/unit.yaml" > "$work/calibrated.txt" 2>&1 ||
  { cat "$work/calibrated.txt"; fail "room measure with the calibration's config"; }
expect_exit 2 "missing.pcd: cannot open" -- "$scanbus" room calibrate "$work/missing.pcd" "$work"/unit/box_*.pcd
grep -q "range_bias: " "$work/stdout" || fail "room calibrate lost the other scans to a missing file"
expect_exit 1 "at least two scans" -- "$scanbus" room calibrate "$work/unit/box_3001.pcd"

# The real scan: an open room. A result or a clear status, the same twice, never a crash.
real="$shared/data/rooms/room_scan1.pcd"
if [ -f "$real" ]; then
  first=$(timeout 60 "$scanbus" room measure "$real" --json); first_status=$?
  second=$(timeout 60 "$scanbus" room measure "$real" --json); second_status=$?
  python3 - "$first" "$second" "$first_status" <<'PY' || fail "real room scan"
import json, sys
a, b, code = json.loads(sys.argv[1]), json.loads(sys.argv[2]), int(sys.argv[3])
assert a["status"] in ("ok", "walls_do_not_close", "too_few_walls"), a["status"]
assert (code == 0) == (a["status"] == "ok"), (code, a["status"])
assert a["status"] == b["status"] and abs(a["area_m2"] - b["area_m2"]) < 1e-9, (a["status"], b["status"])
print(f"ok   real room_scan1.pcd: {a['status']} ({a['message']}), {a['points_in']} points, {a['elapsed_ms']:.0f} ms")
PY
  [ "$first_status" -le 1 ] || fail "real scan exit $first_status"
fi

[ "$failures" -eq 0 ] || exit 1
# 77: ctest's skip (SKIP_RETURN_CODE): everything above passed, the real scan was not tried.
[ -f "$real" ] || { echo "SKIP: the real room scan: $real not found (../shared absent)"; exit 77; }
