#!/usr/bin/env bash
# The scan matcher on the real Freiburg benchmark logs (MIT CSAIL, MIT Killian Court), both
# with and without the odometry guess, against the published scan-matching rows; a regression
# past them fails. Skips when ../shared is absent. SCANBUS_TEST_FREIBURG_LOGS names the logs
# measured (default both; the sanitized build runs mit-csail alone: Killian passed the time limit there).
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

# 77 below: ctest's skip (SKIP_RETURN_CODE); the checks above passed, the accuracy was not measured.
# Each log with the same defaults, in both modes, against its published scan-matching row
# (Kuemmerle et al. 2009): MIT CSAIL 0.106 +- 0.325 m, MIT Killian Court 1.651 +- 4.138 m.
logs=${SCANBUS_TEST_FREIBURG_LOGS:-mit-csail mit-killian}
for log in $logs; do
  case $log in mit-csail | mit-killian) ;; *) echo "SCANBUS_TEST_FREIBURG_LOGS: no log '$log' (mit-csail, mit-killian)"; exit 1 ;; esac
done
for log in $logs; do
  if [ ! -f "$data/$log.clf" ]; then
    echo "SKIP: $data/$log.clf not found: the accuracy on $log is not measured"
    exit 77
  fi
  for guess in "" "--odometry-guess"; do
    "$scanbus" scanmatch eval --log "$data/$log.clf" --relations "$data/$log.relations" $guess --max-span 10 --json \
      > "$TMPDIR_RESULT" 2>&1 || { cat "$TMPDIR_RESULT"; exit 1; }
    python3 - "$TMPDIR_RESULT" "$guess" "$log" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
odometry, log = sys.argv[2] != "", sys.argv[3]
short = r["short_relations"]
print(log, ("with" if odometry else "without"), "odometry guess:",
      f"all {r['translational_error_m']['mean']:.3f} +- {r['translational_error_m']['std']:.3f} m,",
      f"<= 10 s {short['translational_error_m']['mean']:.3f} +- {short['translational_error_m']['std']:.3f} m,",
      f"{r['scans_per_second']:.0f} scans/s")
published = {"mit-csail": (1172, 0.106, 0.325), "mit-killian": (4677, 1.651, 4.138)}[log]
assert r["relations"] == published[0] and r["relations_missing"] == 0, r
# Relations up to 10 s apart: well past the published rows. Today 0.027 / 0.026 m on CSAIL,
# 0.046 / 0.031 m on Killian (without / with the odometry guess; docs/performance.md).
assert short["translational_error_m"]["mean"] < (0.035 if log == "mit-csail" else 0.06), short
assert short["translational_error_m"]["std"] < 0.1, short
# All relations (CSAIL up to 391 s apart, Killian's loops up to 4900 s): the published row is
# the bound. Today CSAIL 0.070 / 0.031 m, Killian 1.374 / 1.505 m; the same logs with every
# 50th scan left out land at 0.081 / 0.094 and 2.943 / 2.326 m (docs/performance.md): Killian
# passes on this exact log, not with margin.
assert r["translational_error_m"]["mean"] < published[1], r["translational_error_m"]
# The spread: CSAIL's is within its row's; Killian's is 3.3 / 4.3 m against 4.138 (a few
# loop relations tens of metres off), so it is only kept from growing further.
assert r["translational_error_m"]["std"] < (published[2] if log == "mit-csail" else 5.0), r["translational_error_m"]
PY
  done
done

# BacktransformLaserScan (Algorithm 3.1): the running matcher's increments carried back, scored
# by nearest-point distances. A picture and a verdict for one pair, one verdict per pair for
# each whole log (today CSAIL 7 of 1987 pairs suspect, median 0.0141 m; Killian 61 of 17479,
# median 0.0267 m: its rays are 1 degree apart, CSAIL's 0.5).
"$scanbus" scanmatch backtransform --log "$data/${logs%% *}.clf" --row 100 --out "$work/pair.png" | grep -q ": ok$"
[ -s "$work/pair.png" ]
for log in $logs; do
  "$scanbus" scanmatch backtransform --log "$data/$log.clf" --all --json > "$TMPDIR_RESULT"
  python3 - "$TMPDIR_RESULT" "$log" <<'PY'
import json, sys
r, log = json.load(open(sys.argv[1])), sys.argv[2]
pairs, median_bound = {"mit-csail": (1987, 0.016), "mit-killian": (17479, 0.029)}[log]
assert len(r["pairs"]) == pairs, len(r["pairs"])
print(f"backtransform {log}: {r['suspect']} of {len(r['pairs'])} pairs suspect, median residual {r['median_of_medians_m']:.4f} m")
assert r["suspect"] < 0.01 * pairs and r["median_of_medians_m"] < median_bound, {k: r[k] for k in ("suspect", "median_of_medians_m")}
PY
done
