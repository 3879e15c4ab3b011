#!/usr/bin/env bash
# Kill -9 and restart (docs/testing.md "Faults"). The room pipeline as separate processes:
# simulator on a pty (10x real time) -> scanner_io (one scan per start) -> room_measurement
# (one scan per room).
# 1. room_measurement killed with SIGKILL and started again, while the scanner is idle:
#    the new process gets the last scan cloud from scanner_io (TRANSIENT_LOCAL) and
#    publishes a room again; scanner_io kept running.
# 2. Late-joining subscribers get the last RoomMeasurement and the last PointCloud2s.
# 3. scanner_io killed and started again: it finds the device, scans again, and
#    room_measurement (not restarted) measures the new scan.
#   kill_restart.sh SCANBUS CONFIG
set -uo pipefail
source "$(dirname "$0")/../integration/lib.sh"
scanbus=$1
config=$2
with_work KILL

# wait_lines FILE N SECONDS: FILE holds at least N lines within SECONDS.
wait_lines() {
  local deadline=$((SECONDS + $3))
  while [ "$( (wc -l < "$1") 2> /dev/null || echo 0)" -lt "$2" ]; do
    [ "$SECONDS" -ge "$deadline" ] && return 1
    sleep 0.2
  done
}
alive() { kill -0 "$1" 2> /dev/null; }

"$scanbus" sim scanner --speed 10 --link "$work/tty" > "$work/sim.log" 2>&1 &
pids+=($!)
printf 'scanner_io:\n  port: %s\n  scans: 1\n' "$work/tty" > "$work/scanner_io.yaml"
sed 's/^  scans: 3 .*/  scans: 1/' "$config/services/room_measurement.yaml" > "$work/room_measurement.yaml"
start() {  # start SERVICE: runs it in the background, its pid in $started
  "$scanbus" run "$1" --config "$work/$1.yaml" >> "$work/$1.log" 2>&1 &
  started=$!
  pids+=($started)
}
start scanner_io; scanner_io=$started
start room_measurement; room=$started
"$scanbus" echo rt/room/measurement > "$work/rooms.jsonl" 2> "$work/echo.log" &
pids+=($!)
wait_lines "$work/rooms.jsonl" 1 90 || { fail "no first RoomMeasurement within 90 s"; tail -5 "$work"/*.log; exit 1; }
echo "first room measured"

# 1. room_measurement dies; the scanner is idle (one scan done), so only the latched scan
#    cloud can give the restarted service something to measure.
kill -9 "$room"; wait "$room" 2> /dev/null
start room_measurement; room=$started
if wait_lines "$work/rooms.jsonl" 2 20; then
  echo "ok   room_measurement restarted after SIGKILL measured the latched scan cloud"
else
  fail "restarted room_measurement published no room within 20 s"
fi
alive "$scanner_io" || fail "scanner_io died when room_measurement did"

# 2. Late joiners.
for topic in rt/room/measurement rt/scanner/scan_cloud rt/scanner/cloud; do
  if "$scanbus" echo "$topic" -n 1 --timeout 5 > /dev/null 2>&1; then
    echo "ok   a late subscriber got the last sample of $topic"
  else
    fail "a late subscriber got nothing on $topic within 5 s"
  fi
done

# 3. scanner_io dies mid-nothing and comes back: the device is still there, idle.
kill -9 "$scanner_io"; wait "$scanner_io" 2> /dev/null
start scanner_io; scanner_io=$started
if wait_lines "$work/rooms.jsonl" 3 90; then
  echo "ok   scanner_io restarted after SIGKILL scanned again; room_measurement measured it without a restart"
else
  fail "no room from the restarted scanner_io within 90 s"; tail -5 "$work/scanner_io.log" "$work/room_measurement.log"
fi
alive "$room" || fail "room_measurement died when scanner_io did"
"$scanbus" echo rt/scanner/cloud -n 1 --timeout 5 > /dev/null 2>&1 ||
  fail "a late subscriber got no PointCloud2 from the restarted scanner_io"
# Every room published across the kills is the room (the simulator's built-in 5.47 x 3.48 m
# room, as tests/integration/cli_demo.sh checks), not only a sample. Rooms 1 and 2 are the
# first scan's (the second from the latched cloud), later ones the restarted scanner_io's.
# A scan that lost lines on the link (scanner_io's warning) may give a refusal that names the
# gap, never a wrong room with status ok. Once under the sanitizers the third room was
# refused ("no wall seen over 41 degrees"); whether its scan had lost lines was not in the
# output then, so on failure the scans' log lines are printed below.
python3 - "$work/rooms.jsonl" "$work/scanner_io.log" <<'PY' || fail "a published RoomMeasurement is not the room"
import json, sys
rooms = [json.loads(line) for line in open(sys.argv[1]) if line.strip()]
scans_lost = ["lines lost on the link" in line for line in open(sys.argv[2]) if "scan complete" in line]
assert rooms, "no room"
for i, room in enumerate(rooms):
    scan = 0 if i < 2 else len(scans_lost) - 1
    if room["status"] != 0 and 0 <= scan < len(scans_lost) and scans_lost[scan]:
        assert "no wall seen over" in room["message"], (i, room["status"], room["message"])
        print(f"note scan {scan + 1} lost lines on the link; room {i + 1} refused: {room['message']}")
        continue
    assert room["status"] == 0, (i, room["status"], room["message"])
    walls = sorted((w["length"], w["length_uncertainty"]) for w in room["walls"])
    # Within 4 of the wall's own sigmas (5-12 mm), 3 cm at least: the room, not a partial cloud's.
    # At this 20 RPM setting on a loaded machine a wall came out 20.4 mm off (under the sanitizers)
    # and 20.8 mm off (sigma 5.1 mm, a CI clone beside the compose test): the sigmas are calibrated
    # at the thesis's 12 RPM (docs/room_evaluation.md), the fast scan's timing is not in them.
    assert len(walls) == 4 and all(abs(got - want) < max(0.03, 4 * sigma)
                                   for (got, sigma), want in zip(walls, [3.48, 3.48, 5.47, 5.47])), (i, walls)
    assert abs(room["floor_area"] - 5.47 * 3.48) < 0.01 * 5.47 * 3.48, (i, room["floor_area"])
print(f"ok   all {len(rooms)} RoomMeasurements: the 5.47 x 3.48 m room, or a refusal naming a lossy scan's gap")
PY
[ "$failures" -eq 0 ] || { grep -h "scan complete" "$work/scanner_io.log" || echo "no scan completed"; echo "FAIL: $failures checks"; exit 1; }
echo "kill -9 and restart: the room pipeline resumed each time"
