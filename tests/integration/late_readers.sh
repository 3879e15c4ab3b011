#!/usr/bin/env bash
# Late readers of a large latched cloud, as `scanbus cloud save` is of cloud_assembly's map:
# a sender writes a cloud of 500,000 points (8 MB, near the shared-memory segment's 8 MiB)
# and a RoomMeasurement before any reader exists. Two passes: the cloud written once (only
# latching can deliver it), then written again every 0.5 s as cloud_assembly does while its
# map grows. In each, two readers started one after another must each get both samples
# intact and the sender's Health within 20 s.
set -uo pipefail
source "$(dirname "$0")/lib.sh"
probe=$1
with_work
printf 'probe:\n  points: 500000\n  timeout: 20\n' > "$work/reader.yaml"
for rewrite in 0 0.5; do
  printf 'probe:\n  points: 500000\n  rewrite_period: %s\n' "$rewrite" > "$work/sender.yaml"
  "$probe" latch --config "$work/sender.yaml" > "$work/sender.log" 2>&1 &
  sender=$!
  pids=($sender)
  wait_for_line "$work/sender.log" "latched 2 samples" 10 || { fail "sender wrote nothing in 10 s"; cat "$work/sender.log"; }
  written="written once"; [ "$rewrite" = 0 ] || written="written every $rewrite s"
  for reader in 1 2; do
    started=$(date +%s%N)
    if "$probe" receive-latched --config "$work/reader.yaml" > "$work/reader.out" 2> "$work/reader.err"; then
      echo "ok   cloud $written: late reader $reader intact in $(( ($(date +%s%N) - started) / 1000000 )) ms"
    else
      fail "cloud $written: late reader $reader: $(tr '\n' ' ' < "$work/reader.out")"
      tail -n 5 "$work/reader.err" "$work/sender.log"
    fi
  done
  kill -0 "$sender" 2> /dev/null || { fail "sender died"; cat "$work/sender.log"; }
  expect_clean_stop sender "$sender" TERM "$work/sender.log" || failures=$((failures + 1))
  pids=()
done
[ "$failures" -eq 0 ]
