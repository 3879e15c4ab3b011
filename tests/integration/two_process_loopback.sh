#!/usr/bin/env bash
# Two service processes over the built-in loopback profile: the receiver must get every
# typed sample intact (a 1,000,000-point cloud among them) and the sender's Health; then
# SIGTERM must stop the sender cleanly within 1 s.
set -euo pipefail
source "$(dirname "$0")/lib.sh"
probe=$1
work=$(mktemp -d)
trap 'kill -9 $(jobs -p) 2>/dev/null || true; rm -rf "$work"' EXIT

"$probe" receive > "$work/receiver.out" 2> "$work/receiver.err" &
receiver=$!
"$probe" send 2> "$work/sender.err" &
sender=$!

status=0
wait "$receiver" || status=$?
cat "$work/receiver.out"
if [ "$status" -ne 0 ]; then
  echo "receiver failed ($status)"; cat "$work/receiver.err" "$work/sender.err"; exit 1
fi

# Staying on this machine: every UDP socket of the sender is bound to 127.0.0.1 (no
# wildcard, no multicast discovery port).
if command -v ss > /dev/null; then
  sockets=$(ss -uanpH | grep "pid=$sender," | awk '{print $4}')
  echo "sender UDP sockets: $(echo $sockets)"
  [ -n "$sockets" ] || { echo "no UDP sockets found for the sender"; exit 1; }
  if echo "$sockets" | grep -v '^127\.0\.0\.1:'; then echo "sender has a socket off loopback"; exit 1; fi
fi

expect_clean_stop sender "$sender" TERM "$work/sender.err"
grep -q "intact: PointCloud2" "$work/receiver.out"
# 77: ctest's skip: the samples arrived, but nothing showed they stayed on loopback.
command -v ss > /dev/null || { echo "SKIP: the socket check: ss (iproute2, scripts/install-deps.sh) is not installed"; exit 77; }
