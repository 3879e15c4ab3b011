#!/usr/bin/env bash
# DDS Security (secure profile, scripts/make-security.sh): a project CA made here signs the
# services' identity, the governance and the permissions. Services on the secure profile
# work together: the recorded room scan's clouds, replayed, reach room_measurement and its
# RoomMeasurement reaches a secure reader. Participants without valid credentials get
# nothing: one without security at all, and one whose identity (CN=scanbus too) was signed
# by another CA. All on 127.0.0.1.
#   security_test.sh SCANBUS DATA_DIR
set -euo pipefail
scanbus=$1 data=$2
root=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
cleanup() { jobs -p | xargs -r kill -TERM 2>/dev/null || true; wait 2>/dev/null || true; rm -rf "$work"; }
trap cleanup EXIT
command -v openssl > /dev/null || { echo "SKIP: openssl is not installed"; exit 77; }

"$root/scripts/make-security.sh" "$work/project" > /dev/null
"$root/scripts/make-security.sh" "$work/other_ca" > /dev/null  # the same names, another CA
# Command prefixes, not shell functions: a function run with & is a subshell, and cleanup's
# TERM to its pid left the program running.
secure=(env SCANBUS_DDS_PROFILE_FILE="$work/project/secure.xml" SCANBUS_DDS_PROFILE=secure)
intruder=(env SCANBUS_DDS_PROFILE_FILE="$work/other_ca/secure.xml" SCANBUS_DDS_PROFILE=secure)

printf 'room_measurement:\n  scans: 3\n' > "$work/room.yaml"
"${secure[@]}" "$scanbus" run room_measurement --config "$work/room.yaml" > "$work/room.log" 2>&1 &
"${secure[@]}" "$scanbus" echo rt/room/measurement --count 1 --timeout 60 > "$work/secure.json" 2> "$work/secure.log" &
secure_reader=$!
"$scanbus" echo rt/room/measurement --count 1 --timeout 25 > "$work/plain.json" 2> "$work/plain.log" &
plain_reader=$!
"${intruder[@]}" "$scanbus" echo rt/room/measurement --count 1 --timeout 25 > "$work/intruder.json" 2> "$work/intruder.log" &
intruder_reader=$!
"${intruder[@]}" "$scanbus" health --once --json --timeout 20 > "$work/intruder_health.jsonl" 2>&1 &
intruder_health=$!
sleep 3
"${secure[@]}" "$scanbus" replay "$data/room_scan.mcap" --topics /scanner/scan_cloud --rate 0 --wait-for-readers 1 \
  --wait-timeout 30 > "$work/replay.log" 2>&1

wait "$secure_reader" || { echo "FAIL: no RoomMeasurement on the secure profile"; cat "$work/room.log" "$work/secure.log"; exit 1; }
"$root/tests/support/check_room.py" "$work/secure.json" 0.02 "ok   secure services together: replay -> room_measurement -> reader"
status=0
wait "$plain_reader" || status=$?
[ "$status" -ne 0 ] && [ ! -s "$work/plain.json" ] || { echo "FAIL: a participant without security read the room"; exit 1; }
echo "ok   a participant without security read nothing in 25 s"
status=0
wait "$intruder_reader" || status=$?
[ "$status" -ne 0 ] && [ ! -s "$work/intruder.json" ] || { echo "FAIL: an identity of another CA read the room"; exit 1; }
wait "$intruder_health" || true
grep -q '"service"' "$work/intruder_health.jsonl" && { echo "FAIL: an identity of another CA saw the services' Health"; exit 1; }
echo "ok   an identity signed by another CA read nothing and saw no service in 20 s"
echo "security: ok"
