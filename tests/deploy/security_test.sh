#!/usr/bin/env bash
# DDS Security with one identity per service (scripts/make-security.sh): a project CA made
# here signs each service's identity, the governance and the permissions generated from the
# topic catalogue. Services on their own identities work together: the recorded room scan's
# clouds, replayed by the operator's identity, reach room_measurement and its
# RoomMeasurement reaches the operator's reader. Kept out:
# - scanner_io's identity cannot publish rt/room/measurement: room_measurement run with it
#   fails naming the topic, and the reader gets no measurement from it;
# - participants that read nothing: one without security, one whose identity was signed by
#   another CA, one whose certificate the CA revoked (the others refuse it), one whose
#   certificate expired (Fast DDS refuses to create it: validate_local_identity).
# All on 127.0.0.1.
#   security_test.sh SCANBUS DATA_DIR
set -euo pipefail
scanbus=$1 data=$2
root=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
cleanup() { jobs -p | xargs -r kill -TERM 2>/dev/null || true; wait 2>/dev/null || true; rm -rf "$work"; }
trap cleanup EXIT
command -v openssl > /dev/null || { echo "SKIP: openssl is not installed"; exit 77; }

"$root/scripts/make-security.sh" "$work/project" "$scanbus" > /dev/null
"$root/scripts/make-security.sh" "$work/other_ca" "$scanbus" > /dev/null  # the same names, another CA
"$root/scripts/make-security.sh" "$work/project" "$scanbus" --revoke recorder > /dev/null
"$root/scripts/make-security.sh" "$work/project" "$scanbus" --expired operator > /dev/null
# The revoked identity's holder does not check the list that names it.
sed '/identity_crl/d' "$work/project/recorder.secure.xml" > "$work/project/revoked.secure.xml"
# Command prefixes, not shell functions: a function run with & is a subshell, and cleanup's
# TERM to its pid left the program running.
as() { echo env SCANBUS_DDS_PROFILE_FILE="$1" SCANBUS_DDS_PROFILE=secure; }
read -r -a operator <<< "$(as "$work/project/operator.secure.xml")"
read -r -a room_service <<< "$(as "$work/project/room_measurement.secure.xml")"
read -r -a scanner_identity <<< "$(as "$work/project/scanner_io.secure.xml")"
read -r -a intruder <<< "$(as "$work/other_ca/operator.secure.xml")"
read -r -a revoked <<< "$(as "$work/project/revoked.secure.xml")"
read -r -a expired <<< "$(as "$work/project/operator_expired.secure.xml")"

printf 'room_measurement:\n  scans: 3\n' > "$work/room.yaml"
status=0
timeout 30 "${scanner_identity[@]}" "$scanbus" run room_measurement --config "$work/room.yaml" > "$work/forger.log" 2>&1 ||
  status=$?
[ "$status" -ne 0 ] && grep -q "cannot create writer on 'rt/room/measurement'" "$work/forger.log" ||
  { echo "FAIL: room_measurement ran with scanner_io's identity (exit $status):"; cat "$work/forger.log"; exit 1; }
echo "ok   scanner_io's identity may not publish rt/room/measurement: $(grep -o "cannot create writer on 'rt/room/measurement'" "$work/forger.log")"

"${room_service[@]}" "$scanbus" run room_measurement --config "$work/room.yaml" > "$work/room.log" 2>&1 &
"${operator[@]}" "$scanbus" echo rt/room/measurement --count 1 --timeout 60 > "$work/secure.json" 2> "$work/secure.log" &
secure_reader=$!
declare -A outsider
for who in plain intruder revoked expired; do
  case $who in
    plain) prefix=() ;;
    intruder) prefix=("${intruder[@]}") ;;
    revoked) prefix=("${revoked[@]}") ;;
    expired) prefix=("${expired[@]}") ;;
  esac
  "${prefix[@]}" "$scanbus" echo rt/room/measurement --count 1 --timeout 25 > "$work/$who.json" 2> "$work/$who.log" &
  outsider[$who]=$!
done
"${intruder[@]}" "$scanbus" health --once --json --timeout 20 > "$work/intruder_health.jsonl" 2>&1 &
intruder_health=$!
sleep 3
"${operator[@]}" "$scanbus" replay "$data/room_scan.mcap" --topics /scanner/scan_cloud --rate 0 --wait-for-readers 1 \
  --wait-timeout 30 > "$work/replay.log" 2>&1

wait "$secure_reader" || { echo "FAIL: no RoomMeasurement on the secure profile"; cat "$work/room.log" "$work/secure.log"; exit 1; }
"$root/tests/support/check_room.py" "$work/secure.json" 0.02 "ok   services on their own identities: replay -> room_measurement -> reader"
for who in plain intruder revoked expired; do
  status=0
  wait "${outsider[$who]}" || status=$?
  # (Fast DDS prints its own errors on stdout: the file may hold those, never a measurement.)
  [ "$status" -ne 0 ] && ! grep -q '"walls"' "$work/$who.json" || { echo "FAIL: the $who participant read the room"; exit 1; }
  echo "ok   the $who participant read nothing ($(tail -n 1 "$work/$who.log" | cut -c1-110))"
done
wait "$intruder_health" || true
grep -q '"service"' "$work/intruder_health.jsonl" && { echo "FAIL: an identity of another CA saw the services' Health"; exit 1; }
echo "ok   an identity signed by another CA saw no service's Health in 20 s"
echo "security: ok"
