#!/usr/bin/env bash
# Kill -9 and restart in the MAV pipeline (docs/testing.md "Faults"): a 75 s scenario I
# flight replayed in real time through scan_matcher, pose_estimation and cloud_assembly,
# each its own process. One after another, each service is killed with SIGKILL and
# started again 1 s later:
# - pose_estimation: poses resume (the new process calibrates the barometer afresh), and
#   cloud_assembly drops the scans in the gap of poses, naming it;
# - scan_matcher: matches and poses resume (its first scan has no predecessor);
# - cloud_assembly: it gets the static transform again (TRANSIENT_LOCAL from
#   pose_estimation) and a late subscriber gets an assembled cloud.
# No other service dies or stops working because one did; none logs a crash.
#   mav_kill_restart.sh SCANBUS CONFIG
set -uo pipefail
source "$(dirname "$0")/../integration/lib.sh"
scanbus=$1
config=$2
with_work KILL
lines() { wc -l < "$1" 2> /dev/null || echo 0; }
# grows FILE BY SECONDS: FILE gains BY lines within SECONDS.
grows() {
  local target=$(( $(lines "$1") + $2 )) deadline=$((SECONDS + $3))
  while [ "$(lines "$1")" -lt "$target" ]; do
    [ "$SECONDS" -ge "$deadline" ] && return 1
    sleep 0.2
  done
}

"$scanbus" sim mav --scenario 1 --duration 75 --out "$work/flight.mavlog" > /dev/null || exit 1
printf 'sensor_replay:\n  log: %s\n  rate: 1\n  truth: false\n  wait_for_readers: 3\n  wait_timeout: 30\n' \
  "$work/flight.mavlog" > "$work/sensor_replay.yaml"
cp "$config/mav/scan_matcher.yaml" "$work/scan_matcher.yaml"
cp "$config/services/pose_estimation.yaml" "$work/pose_estimation.yaml"
# Scans wait up to 30 s for their pose (6 s shipped): a slow restart on a loaded machine must
# not time the gap's scans out before the new process's poses show the gap.
sed 's/^  transform_timeout: .*/  transform_timeout: 30.0/' "$config/services/cloud_assembly.yaml" > "$work/cloud_assembly.yaml"
declare -A pid_of
start() {
  "$scanbus" run "$1" --config "$work/$1.yaml" >> "$work/$1.log" 2>&1 &
  pid_of[$1]=$!
  pids+=($!)
}
for service in scan_matcher pose_estimation cloud_assembly; do start "$service"; done
"$scanbus" echo rt/pose > "$work/poses.jsonl" 2> /dev/null &
pids+=($!)
"$scanbus" echo rt/scan_match > "$work/matches.jsonl" 2> /dev/null &
pids+=($!)
"$scanbus" health --json --timeout 600 > "$work/health.jsonl" 2> /dev/null &
pids+=($!)
start sensor_replay
# 300 poses (10 s): past the fusion's 3 s window, so that settled poses came before the kill.
grows "$work/poses.jsonl" 300 60 || { fail "no poses at the start"; tail -3 "$work"/*.log; exit 1; }
echo "pipeline running: $(lines "$work/poses.jsonl") poses"

restart() {  # restart SERVICE: SIGKILL, 1 s, start again
  kill -9 "${pid_of[$1]}"; wait "${pid_of[$1]}" 2> /dev/null
  sleep 1
  start "$1"
}
others_alive() {
  for service in scan_matcher pose_estimation cloud_assembly; do  # (sensor_replay ends with its log)
    [ "$service" = "$1" ] && continue
    kill -0 "${pid_of[$service]}" 2> /dev/null || fail "$service died after $1 was killed"
  done
}

restart pose_estimation
# 30 s: a restarted service under the sanitizers, beside another test on 2 cores, took over 15 s
# (its start, discovery, the barometer's fresh calibration); a passing run moves on at once.
grows "$work/poses.jsonl" 100 30 && echo "ok   poses resumed after pose_estimation was killed and restarted" ||
  { fail "no poses within 30 s of pose_estimation's restart"; tail -5 "$work/pose_estimation.log"; }
others_alive pose_estimation
# The scans between the killed process's last settled pose and the new one's first are dropped
# with the gap named (max_pose_gap), not placed on a straight line across the restart.
wait_for_line "$work/health.jsonl" 'falls in a gap.*"service":"cloud_assembly"' 30 &&
  echo "ok   cloud_assembly dropped the scans in the poses' gap: $(grep -m1 -o "stamp [^\"]* interpolated)" "$work/health.jsonl")" ||
  { fail "cloud_assembly did not name the poses' gap across pose_estimation's restart"; grep cloud_assembly "$work/health.jsonl" | tail -2; }

restart scan_matcher
grows "$work/matches.jsonl" 100 30 && grows "$work/poses.jsonl" 100 30 &&
  echo "ok   matches and poses resumed after scan_matcher was killed and restarted" ||
  { fail "no matches or poses within 30 s of scan_matcher's restart"; tail -5 "$work/scan_matcher.log"; }
others_alive scan_matcher

restart cloud_assembly
sleep 3  # scans, which wait 3.5 s for their settled pose, then its periodic publication (retried below)
# Up to 30 s: under the sanitizers and a loaded CI machine 10 s was once too short.
if "$scanbus" echo rt/cloud/assembled -n 1 --timeout 30 > /dev/null 2>&1; then
  echo "ok   a late subscriber got an assembled cloud from the restarted cloud_assembly"
else
  fail "no assembled cloud from the restarted cloud_assembly"; tail -5 "$work/cloud_assembly.log"
  "$scanbus" health --once --json | grep cloud_assembly
fi
others_alive cloud_assembly
grep -l "terminate called\|Segmentation\|Aborted" "$work"/*.log && fail "a service crashed"
[ "$failures" -eq 0 ] || { echo "FAIL: $failures checks"; exit 1; }
echo "kill -9 and restart: the MAV pipeline resumed after each service"
