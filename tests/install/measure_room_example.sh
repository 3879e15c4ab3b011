#!/usr/bin/env bash
# The installed package as another project sees it: `cmake --install` of this build into a
# fresh prefix, examples/measure_room configured with find_package(scanbus) against it, built,
# and run on a simulated room; its area must be the one `scanbus room measure` prints.
# Usage: measure_room_example.sh BUILD_DIR SOURCE_DIR SCANBUS
set -euo pipefail
build=$1 source=$2 scanbus=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
for header in config.hpp room_measurement/room_measurement.hpp cloud_io/cloud_files.hpp sensor/laser_scan.hpp; do
  [ -f "$work/prefix/include/scanbus/$header" ] || { echo "FAIL: $header not installed"; exit 1; }
done
if [ -e "$work/prefix/include/scanbus/dds.hpp" ]; then echo "FAIL: a DDS header was installed"; exit 1; fi
cmake -S "$source/examples/measure_room" -B "$work/example" -DCMAKE_PREFIX_PATH="$work/prefix" > "$work/configure.log" 2>&1 ||
  { cat "$work/configure.log"; echo "FAIL: find_package(scanbus) against the install"; exit 1; }
cmake --build "$work/example" > "$work/build.log" 2>&1 || { cat "$work/build.log"; echo "FAIL: building the example"; exit 1; }

"$scanbus" eval rooms --category box --count 1 --out "$work/rooms" > /dev/null
set +e
"$work/example/measure_room" "$work/rooms/box_1.pcd" > "$work/example.txt"; code=$?
set -e
cat "$work/example.txt"
[ "$code" -eq 0 ] || { echo "FAIL: the example exited $code"; exit 1; }
"$scanbus" room measure "$work/rooms/box_1.pcd" --json > "$work/cli.json"
python3 - "$work/example.txt" "$work/cli.json" <<'PY'
import json, re, sys
example = float(re.search(r"^area ([0-9.]+) m2", open(sys.argv[1]).read(), re.M).group(1))
cli = json.load(open(sys.argv[2]))["area_m2"]
assert abs(example - cli) < 1e-3, (example, cli)
print(f"ok   the installed libraries measure {example:.4f} m2, scanbus room measure {cli:.4f} m2")
PY
"$work/example/measure_room" "$work/missing.pcd" 2> "$work/missing.txt" && { echo "FAIL: a missing file measured"; exit 1; }
grep -q "missing.pcd" "$work/missing.txt" || { cat "$work/missing.txt"; echo "FAIL: the error does not name the file"; exit 1; }
echo "ok   a missing file is an error naming it"
