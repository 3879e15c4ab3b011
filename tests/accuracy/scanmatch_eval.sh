#!/usr/bin/env bash
# The scan matcher on the real MIT CSAIL log (Freiburg benchmark), both with and without
# the odometry guess, against the published scan-matching row; a regression past it fails.
# Skips when ../shared is absent.
set -euo pipefail
TMPDIR_RESULT=$(mktemp)
scanbus=$1
data=$2/data/freiburg

# Bad input, on a two-scan log made here: clear messages, exit 2, never a crash.
work=$(mktemp -d)
trap 'rm -f "$TMPDIR_RESULT"; rm -rf "$work"' EXIT
for t in 1 2; do
  echo "FLASER 5 2.0 2.0 2.0 2.0 2.0 0 0 0 0 0 0 10$t.0 host 10$t.0" >> "$work/two.clf"
done
"$scanbus" scanmatch backtransform --log "$work/two.clf" --row 1 > "$work/out" 2>&1 && { echo "row 1 of 2 accepted"; exit 1; }
grep -q "has scans 0 to 1" "$work/out" || { cat "$work/out"; exit 1; }
echo "FLASER 3 1.0 x" > "$work/bad.clf"
status=0
"$scanbus" scanmatch eval --log "$work/bad.clf" --relations "$work/two.clf" > "$work/out" 2>&1 || status=$?
[ $status -eq 2 ] && grep -q "bad.clf:1" "$work/out" || { echo "exit $status"; cat "$work/out"; exit 1; }

status=0
"$scanbus" scanmatch eval --log "$work/bad.clf" --log "$work/bad.clf" --relations "$work/two.clf" > "$work/out" 2>&1 ||
  status=$?
[ $status -eq 2 ] && grep -q "give them in pairs" "$work/out" || { echo "exit $status"; cat "$work/out"; exit 1; }

# Several logs: one row each and the mean of the logs (the recorded sample twice: the mean is each).
sample=$(dirname "$0")/../data
"$scanbus" scanmatch eval --log "$sample/mit_csail.mcap" --relations "$sample/mit_csail.relations" \
  --log "$sample/mit_csail.mcap" --relations "$sample/mit_csail.relations" > "$work/table"
[ "$(grep -c '^mit_csail.mcap ' "$work/table")" -eq 2 ] && grep -q "^mean of the logs" "$work/table" ||
  { echo "no table of two logs and their mean:"; cat "$work/table"; exit 1; }
"$scanbus" scanmatch eval --log "$sample/mit_csail.mcap" --relations "$sample/mit_csail.relations" \
  --log "$sample/mit_csail.mcap" --relations "$sample/mit_csail.relations" --json > "$work/logs.json"
python3 - "$work/logs.json" "$work/table" <<'PY'
import json, sys
logs = json.load(open(sys.argv[1]))["logs"]
assert len(logs) == 2 and logs[0]["translational_error_m"] == logs[1]["translational_error_m"], logs
mean = [line for line in open(sys.argv[2]) if line.startswith("mean of the logs")][0].split()
assert abs(float(mean[4]) - logs[0]["translational_error_m"]["mean"]) < 5e-4, (mean, logs[0])
print(f"two logs: one row each, mean {mean[4]} m")
PY

if [ ! -f "$data/mit-csail.clf" ]; then
  # 77: ctest's skip (SKIP_RETURN_CODE); the checks above passed, the accuracy was not measured.
  echo "SKIP: $data/mit-csail.clf not found (../shared absent): the accuracy on MIT CSAIL is not measured"
  exit 77
fi
for guess in "" "--odometry-guess"; do
  "$scanbus" scanmatch eval --log "$data/mit-csail.clf" --relations "$data/mit-csail.relations" $guess --json \
    > "$TMPDIR_RESULT" 2>&1 || { cat "$TMPDIR_RESULT"; exit 1; }
  python3 - "$TMPDIR_RESULT" "$guess" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
odometry = sys.argv[2] != ""
short = r["short_relations"]
print(("with" if odometry else "without"), "odometry guess:",
      f"all {r['translational_error_m']['mean']:.3f} +- {r['translational_error_m']['std']:.3f} m,",
      f"<= 10 s {short['translational_error_m']['mean']:.3f} +- {short['translational_error_m']['std']:.3f} m,",
      f"{r['scans_per_second']:.0f} scans/s")
assert r["relations"] == 1172 and r["relations_missing"] == 0, r
# Relations up to 10 s apart (pairwise odometry drifts on longer ones): well past the
# published scan-matching row (0.106 +- 0.325 m).
assert short["translational_error_m"]["mean"] < 0.035, short
assert short["translational_error_m"]["std"] < 0.05, short
# All relations, up to 391 s apart: the published scan-matching row of Kuemmerle et al.
# (0.106 +- 0.325 m) is the bound, in both modes. Today: 0.068 +- 0.139 m without the
# odometry guess, 0.098 +- 0.227 m with it (docs/performance.md).
assert r["translational_error_m"]["mean"] < 0.106, r["translational_error_m"]
assert r["translational_error_m"]["std"] < 0.325, r["translational_error_m"]
PY
done

# BacktransformLaserScan: a picture and a verdict for one pair, one verdict per pair for
# the whole log (today 29 of 1987 pairs suspect: a median residual over 3 cm).
"$scanbus" scanmatch backtransform --log "$data/mit-csail.clf" --row 100 --out "$work/pair.png" | grep -q ": ok$"
[ -s "$work/pair.png" ]
"$scanbus" scanmatch backtransform --log "$data/mit-csail.clf" --all --json > "$TMPDIR_RESULT"
python3 - "$TMPDIR_RESULT" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
assert len(r["pairs"]) == 1987, len(r["pairs"])
print(f"backtransform: {r['suspect']} of {len(r['pairs'])} pairs suspect, median residual {r['median_of_medians_m']:.4f} m")
assert r["suspect"] < 60 and r["median_of_medians_m"] < 0.015, {k: r[k] for k in ("suspect", "median_of_medians_m")}
PY
