#!/usr/bin/env bash
# A reader behind a stream that ends (docs/architecture.md, "A reader deaf for good"):
# `scanbus echo` is frozen (SIGSTOP) while a sender streams clouds to it over shared memory;
# the stream ends and the sender lingers (linger_for_lagging_readers) as the replays do;
# the reader continues 7 s after the end, past when Fast DDS 2.9.1 drops an exited writer's
# segment. It must then read what was queued and still hear a second sender, with no
# "Error receiving data" from Fast DDS. With the sender's linger at 0 the same reader
# retries one sample forever and hears nothing again (measured: docs/architecture.md).
#   lagging_reader.sh SCANBUS PROBE [LINGER]
set -uo pipefail
source "$(dirname "$0")/lib.sh"
scanbus=$1
probe=$2
linger=${3:-12}
with_work
SCANBUS_DDS_LOG=warning "$scanbus" echo rt/scanner/cloud > "$work/echo.out" 2> "$work/echo.err" &
reader=$!
pids+=($reader)
sleep 1
printf 'probe:\n  points: 100\n  rewrite_period: 0.01\n  stream_for: 2\n  linger: %s\n' "$linger" > "$work/stream.yaml"
"$probe" latch --config "$work/stream.yaml" > "$work/stream.log" 2>&1 &
pids+=($!)
# Frozen once the stream reaches it (the sender's segment then mapped, as a service's is).
wait_for_line "$work/echo.out" . 10 || fail "the reader got nothing from the stream in 10 s"
kill -STOP "$reader"
wait_for_line "$work/stream.log" "stream ended" 10 || fail "the stream did not end in 10 s"
sleep 7
kill -CONT "$reader"
sleep 2
before=$(wc -l < "$work/echo.out")
printf 'probe:\n  points: 100\n  rewrite_period: 0.1\n' > "$work/second.yaml"
"$probe" latch --config "$work/second.yaml" > "$work/second.log" 2>&1 &
pids+=($!)
sleep 4
after=$(wc -l < "$work/echo.out")
echo "reader: $before clouds by 2 s after it continued, $((after - before)) from a second sender in 4 s"
[ $((after - before)) -ge 10 ] || fail "the reader heard $((after - before)) clouds from the second sender in 4 s (40 sent)"
retries=$(grep -c "Error receiving data" "$work/echo.err")
[ "$retries" -eq 0 ] || fail "Fast DDS retried a sample $retries times: $(grep -m1 'Error receiving' "$work/echo.err" | cut -c1-160)"
[ "$failures" -eq 0 ] && echo "lagging reader: ok"
[ "$failures" -eq 0 ]
