#!/usr/bin/env bash
# Late readers of a large latched cloud, as `scanbus cloud save` is of cloud_assembly's map:
# the sender writes a cloud of 500,000 points (8 MB, near the shared-memory segment's
# 8 MiB) and a RoomMeasurement with no reader yet, and writes the cloud again every 0.5 s
# as cloud_assembly does while its map grows; three readers started one after another must
# each get both samples intact and the sender's Health within 20 s.
set -uo pipefail
source "$(dirname "$0")/lib.sh"
probe=$1
with_work
printf 'probe:\n  points: 500000\n  rewrite_period: 0.5\n' > "$work/sender.yaml"
printf 'probe:\n  points: 500000\n  timeout: 20\n' > "$work/receiver.yaml"
"$probe" latch --config "$work/sender.yaml" > "$work/sender.log" 2>&1 &
sender=$!
pids+=($sender)
sleep 1
for reader in 1 2 3; do
  started=$(date +%s%N)
  if "$probe" receive-latched --config "$work/receiver.yaml" > "$work/reader.out" 2> "$work/reader.err"; then
    echo "ok   late reader $reader: intact in $(( ($(date +%s%N) - started) / 1000000 )) ms"
  else
    fail "late reader $reader: $(grep -v '^ts=' "$work/reader.out" | tr '\n' ' ')"; tail -5 "$work/sender.log"
  fi
done
kill -0 "$sender" 2> /dev/null || { fail "sender died"; cat "$work/sender.log"; }
expect_clean_stop sender "$sender" TERM "$work/sender.log" || failures=$((failures + 1))
pids=()
[ "$failures" -eq 0 ]
