#!/usr/bin/env bash
# Foxglove's timeline follows a replay: with sim_time the bridge offers the `time`
# capability, sends the protocol's time messages from rt/clock (`scanbus replay --clock`),
# and stamps samples with that time, so they carry the recording's time (the header stamps of
# tests/data/room_scan.mcap, recorded long before today), not the wall clock.
set -euo pipefail
scanbus=$1
sample=$2
source "$(dirname "$0")/lib.sh"
foxglove_test_setup
start_bridge "$scanbus" "  sim_time: true
"
start_client "$work/client.json" --topics /scanner/cloud --until /scanner/cloud:81 --timeout 60
client_pid_a=$client_pid
sleep 1
"$scanbus" replay "$sample" --rate 4 --clock --topics /scanner/cloud --wait-for-readers 1 --json \
  > "$work/replay.json" 2> "$work/replay.log" || { echo "FAIL: replay"; cat "$work/replay.log"; exit 1; }
wait "$client_pid_a" || { echo "FAIL: the client did not get 81 clouds:"; head -c 1500 "$work/client.json"; exit 1; }
python3 - "$work/client.json" << 'PY'
import json, sys, time
got = json.load(open(sys.argv[1]))
failures = []
def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok: failures.append(what)
check(got["serverInfo"]["capabilities"] == ["time"], f"serverInfo offers time: {got['serverInfo']['capabilities']}")
times = [int(t) * 1e-9 for t in got["times"]]
clouds = got["messages"]["/scanner/cloud"]
check(len(times) > 0 and times == sorted(times), f"{len(times)} time messages, never backwards")
first, last = clouds[0]["stamp"], clouds[-1]["stamp"]
check(all(first - 1 <= t <= last + 1 for t in times), "the time is the recording's (within its stamps)")
check(time.time() - last > 3600, f"... which lies {(time.time() - last) / 86400:.1f} days before the wall clock")
# A cloud that reaches the bridge before the clock's first tick (another reader, another
# thread; it happened under the sanitizers) carries the wall clock: only at the start.
late = [abs(int(m["receive_ns"]) * 1e-9 - m["stamp"]) for m in clouds]
before_clock = next((i for i, d in enumerate(late) if d < 0.5), len(late))
check(before_clock <= 8, f"{before_clock} clouds before the clock's first tick")
check(max(late[before_clock:], default=99) < 0.5,
      f"every cloud after it is stamped with the replay's time: at most {max(late[before_clock:], default=99):.3f} s "
      "from its header stamp")
sys.exit(1 if failures else 0)
PY
expect_clean_stop foxglove_bridge "$bridge_pid" TERM "$work/bridge.log"
