#!/usr/bin/env bash
# Several hosts, made here as network namespaces joined by a bridge in a namespace of its
# own (10.231.N.0/24, nothing in the machine's own namespace): host A runs a Fast DDS
# Discovery Server and replays the recorded room scan's clouds (tests/data/room_scan.mcap)
# in a loop, host B runs room_measurement, host C reads rt/room/measurement. Every scanbus
# process uses config/dds/discovery_client.xml (CLIENT of A's server, UDP, no multicast).
# Checks: measurements reach C across the hosts; with B's link cut none arrive; after the
# link is back they arrive again without restarting anything. Exits 77 (a ctest skip)
# saying why when network namespaces cannot be made here.
#   multihost_test.sh SCANBUS DATA_DIR
set -euo pipefail
scanbus=$1 data=$2
root=$(cd "$(dirname "$0")/../.." && pwd)
skip() { echo "SKIP: $*"; exit 77; }
[ "$(id -u)" -eq 0 ] || skip "making network namespaces needs root"
command -v ip > /dev/null || skip "ip (iproute2) is not installed"
command -v fast-discovery-server > /dev/null || skip "fast-discovery-server (fastdds-tools) is not installed"

tag=$$
switch="sbsw$tag"
subnet="10.231.$(( tag % 200 + 20 ))"
work=$(mktemp -d)
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2> /dev/null || true; done
  wait 2> /dev/null || true
  for host in a b c; do ip netns del "sb$host$tag" 2> /dev/null || true; done
  ip netns del "$switch" 2> /dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

ip netns add "$switch" 2> "$work/netns.err" || skip "cannot make a network namespace: $(cat "$work/netns.err")"
ip -n "$switch" link add bridge type bridge
ip -n "$switch" link set bridge up
number=1
for host in a b c; do
  ns="sb$host$tag"
  ip netns add "$ns"
  # Made inside the switch namespace, one end moved to the host: nothing in the root one.
  ip -n "$switch" link add "to_$host" type veth peer name eth0 netns "$ns"
  ip -n "$switch" link set "to_$host" master bridge up
  ip -n "$ns" addr add "$subnet.$number/24" dev eth0
  ip -n "$ns" link set eth0 up
  ip -n "$ns" link set lo up
  number=$((number + 1))
done
server="$subnet.1"
sed "s/<address>127.0.0.1<\/address>/<address>$server<\/address>/" "$root/config/dds/discovery_client.xml" > "$work/client.xml"
# Only in the background: exec makes the job's pid ($!) the program's, so cleanup's TERM
# reaches it (without, it reached the job's subshell and left the program running).
on() { local host=$1; shift; exec ip netns exec "sb$host$tag" env SCANBUS_DDS_PROFILE_FILE="$work/client.xml" SCANBUS_DDS_PROFILE=discovery_client "$@"; }

on a fast-discovery-server -i 0 -l "$server" -p 11811 > "$work/server.log" 2>&1 &
pids+=($!)
printf 'room_measurement:\n  scans: 3\n' > "$work/room.yaml"
on b "$scanbus" run room_measurement --config "$work/room.yaml" > "$work/room.log" 2>&1 &
pids+=($!)
on c "$scanbus" echo rt/room/measurement > "$work/measurements.jsonl" 2> "$work/echo.log" &
pids+=($!)
on a "$scanbus" replay "$data/room_scan.mcap" --topics /scanner/scan_cloud --rate 4 --loop \
  --wait-for-readers 1 --wait-timeout 30 > "$work/replay.log" 2>&1 &
pids+=($!)

measurements() { wc -l < "$work/measurements.jsonl"; }
wait_for_more_than() {  # COUNT SECONDS: true once more than COUNT measurements arrived
  for _ in $(seq $(( $2 * 10 ))); do [ "$(measurements)" -gt "$1" ] && return 0; sleep 0.1; done
  return 1
}
wait_for_more_than 1 60 || { echo "FAIL: no measurements across the hosts"; cat "$work/room.log" "$work/replay.log"; exit 1; }
echo "ok   across three hosts: $(measurements) measurements reached C (server $server on A, room_measurement on B)"

ip -n "$switch" link set to_b down
sleep 2  # what was on its way
cut=$(measurements)
sleep 15  # past the 10 s lease: A and C forget B, and must find it again through the server
during=$(( $(measurements) - cut ))
[ "$during" -eq 0 ] || { echo "FAIL: $during measurements arrived while B was cut off"; exit 1; }
echo "ok   B's link cut for 17 s (past the lease): no measurements"

ip -n "$switch" link set to_b up
restored=$(measurements)
wait_for_more_than "$restored" 60 || { echo "FAIL: no measurements within 60 s of B's link coming back"; tail -5 "$work/room.log"; exit 1; }
"$root/tests/support/check_room.py" "$work/measurements.jsonl" 0.02 "ok   link back: measurements again; the last"
for pid in "${pids[@]}"; do kill -0 "$pid" 2> /dev/null || { echo "FAIL: a process died"; exit 1; }; done
echo "multihost: ok"
