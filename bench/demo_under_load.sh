#!/usr/bin/env bash
# The demo's MAV flight on a loaded machine: RUNS (3) runs of `scanbus demo --json` with LOAD
# (4) busy processes beside it, printing each run's boxes P, poses and fused height RMSE. On
# an idle machine every run gives the same figures; under load they must too (docs/testing.md:
# a loaded CI machine once lost the flight's last scans and P fell under 99 %).
#   bench/demo_under_load.sh [RUNS] [LOAD]
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-3} load=${2:-4}
scanbus=build/services/cli/scanbus
work=$(mktemp -d)
burners=()
trap 'kill "${burners[@]}" 2> /dev/null || true; rm -rf "$work"' EXIT
for _ in $(seq "$load"); do (while :; do :; done) & burners+=($!); done
for run in $(seq "$runs"); do
  "$scanbus" demo --json --out "$work/out" > "$work/demo.json"
  python3 - "$work/demo.json" "$run" <<'PY'
import json, sys
mav = json.load(open(sys.argv[1]))["mav"]
print(f"run {sys.argv[2]}: boxes P {mav['boxes_performance_percent']:.3f} %, poses {mav['poses']} of {mav['scans']}, "
      f"fused height RMSE {mav['height_rmse_m']['fused']:.7f} m")
PY
done
