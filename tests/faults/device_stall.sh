#!/usr/bin/env bash
# A serial device that stops talking without hanging up (docs/faults.md "A stalled device"):
# the simulator on its pty frozen with SIGSTOP mid-scan, then resumed with SIGCONT. The port
# stays open the whole time, so only scanner_io's watchdog can tell: it must report the
# stall (log, Health counter `stalls`, ScannerStatus), reset the session with back-off while
# the device is silent, and finish a whole scan once it speaks again.
#   device_stall.sh SCANBUS
set -uo pipefail
source "$(dirname "$0")/../integration/lib.sh"
scanbus=$1
with_work KILL

"$scanbus" sim scanner --speed 10 --link "$work/tty" > "$work/sim.log" 2>&1 &
sim=$!
pids+=($sim)
printf 'service:\n  health_period: 0.2\nscanner_io:\n  port: %s\n  scans: 1\n  stall_timeout: 1.0\n  reconnect_min: 0.2\n  reconnect_max: 1.0\n' \
  "$work/tty" > "$work/scanner_io.yaml"
"$scanbus" run scanner_io --config "$work/scanner_io.yaml" > "$work/scanner_io.log" 2>&1 &
pids+=($!)
"$scanbus" echo rt/scanner/status > "$work/status.jsonl" 2> /dev/null &
pids+=($!)
"$scanbus" echo rt/scanner/cloud -n 3 --timeout 60 > "$work/revolutions.jsonl" 2> /dev/null ||
  { fail "no revolution within 60 s"; tail -5 "$work"/*.log; exit 1; }
echo "scanning: 3 revolutions published"

kill -STOP "$sim"
echo "simulator frozen (SIGSTOP) mid-scan for 4 s"
sleep 4
stalls=$(grep -c "device stalled: no line for" "$work/scanner_io.log")
if [ "$stalls" -ge 2 ]; then
  echo "ok   $stalls stalls reported while frozen: $(grep -m1 -o 'device stalled: [^"]*' "$work/scanner_io.log")"
else
  fail "$stalls stalls reported in 4 s of silence (wanted the first within 1 s, more with back-off)"
fi
grep -q '"message":"device stalled' "$work/status.jsonl" && echo "ok   ScannerStatus said the device stalled" ||
  fail "no ScannerStatus said the device stalled"
"$scanbus" health --json --timeout 2 > "$work/health.json" 2> /dev/null
python3 - "$work/health.json" <<'PY' || fail "Health does not count the stalls"
import json, sys
samples = [json.loads(line) for line in open(sys.argv[1]) if line.strip()]
stalls = [c["value"] for s in samples if s["service"] == "scanner_io" for c in s["counters"] if c["name"] == "stalls"]
assert stalls and max(stalls) >= 1, samples
print(f"ok   Health of scanner_io counts {max(stalls)} stalls")
PY

kill -CONT "$sim"
echo "simulator resumed (SIGCONT)"
if wait_for_line "$work/scanner_io.log" "scan complete" 90; then
  echo "ok   a whole scan completed after the device spoke again ($(grep -m1 -o 'scan complete: [0-9]* points' "$work/scanner_io.log"))"
else
  fail "no whole scan within 90 s of the device resuming"; tail -20 "$work/scanner_io.log" "$work/sim.log"
fi
[ "$failures" -eq 0 ] || { echo "FAIL: $failures checks"; exit 1; }
echo "stalled device: reported, reset with back-off, scanning again"
