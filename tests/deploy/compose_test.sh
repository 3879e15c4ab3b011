#!/usr/bin/env bash
# The docker-compose deployment, for real, on this machine: starts dockerd (host
# networking only, no bridge, no iptables), builds a Debian bookworm base image with
# debootstrap (no registry here), builds the project image on it, brings the deployment
# up with the simulator profile, and checks from the host side:
# a RoomMeasurement of the simulated room arrives (`scanbus echo`, walls within 2 cm of
# 5.47 m x 3.48 m), every service's container turns healthy (`scanbus health --check`),
# and the recorder, stopped, leaves a valid MCAP file holding the measurement. Tears
# everything down. All DDS traffic stays on 127.0.0.1 (config/dds/localhost_udp.xml).
# Exits 77 (a ctest skip) saying why when Docker cannot run here.
# The image: the build tree's own executables, staged by `cmake --install --strip` and packed
# by docker/Dockerfile.prebuilt (the same runtime image, without compiling the project again:
# 15 of CI's minutes); with SCANBUS_COMPOSE_FROM_SOURCE=1, docker/Dockerfile compiles it
# inside the image as a user would.
#   compose_test.sh SCANBUS BUILD_DIR
set -euo pipefail
scanbus=$1
build_dir=$2
root=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
skip() { echo "SKIP: $*"; exit 77; }
[ "$(id -u)" -eq 0 ] || skip "starting dockerd needs root"
for tool in docker dockerd docker-compose debootstrap; do
  command -v "$tool" > /dev/null || skip "$tool is not installed (scripts/install-deps.sh installs it)"
done

dockerd_pid=""
project="scanbus_test_$$"
compose=(docker-compose -p "$project" -f "$root/docker/docker-compose.yml" --profile sim)
cleanup() {
  "${compose[@]}" down -v --timeout 5 > /dev/null 2>&1 || true
  [ -n "$dockerd_pid" ] && kill "$dockerd_pid" 2> /dev/null && wait "$dockerd_pid" 2> /dev/null
  rm -rf "$work"
}
trap cleanup EXIT

if ! docker info > /dev/null 2>&1; then
  dockerd --bridge=none --iptables=false > "$work/dockerd.log" 2>&1 &
  dockerd_pid=$!
  for _ in $(seq 60); do docker info > /dev/null 2>&1 && break; sleep 0.5; done
  docker info > /dev/null 2>&1 || skip "dockerd does not start here: $(tail -n 1 "$work/dockerd.log")"
fi

base=scanbus-base:bookworm
if ! docker image inspect "$base" > /dev/null 2>&1; then
  echo "building $base with debootstrap"
  debootstrap --variant=minbase bookworm "$work/rootfs" http://deb.debian.org/debian > "$work/debootstrap.log" 2>&1 ||
    { tail -n 20 "$work/debootstrap.log"; echo "FAIL: debootstrap"; exit 1; }
  tar -C "$work/rootfs" -c . | docker import - "$base" > /dev/null
fi
started=$(date +%s)
if [ "${SCANBUS_COMPOSE_FROM_SOURCE:-0}" = 1 ]; then
  docker build --network host -f "$root/docker/Dockerfile" --build-arg BASE_IMAGE="$base" -t scanbus:test "$root" \
    > "$work/build.log" 2>&1 || { tail -n 40 "$work/build.log"; echo "FAIL: docker build"; exit 1; }
else
  context=$work/context
  cmake --install "$build_dir" --prefix "$work/stage" --strip > "$work/install.log" ||
    { cat "$work/install.log"; echo "FAIL: cmake --install"; exit 1; }
  mkdir -p "$context"
  cp -r "$work/stage/bin" "$context/bin"
  [ -x "$context/bin/scanbus" ] || { echo "FAIL: no scanbus executable under $build_dir"; exit 1; }
  "$root/docker/runtime-packages.sh" "$context/bin"/* > "$context/runtime-packages.txt"
  cp "$root/docker/runtime-setup.sh" "$context/"
  cp -r "$root/config" "$context/config"
  docker build --network host -f "$root/docker/Dockerfile.prebuilt" --build-arg BASE_IMAGE="$base" -t scanbus:test "$context" \
    > "$work/build.log" 2>&1 || { tail -n 40 "$work/build.log"; echo "FAIL: docker build"; exit 1; }
fi
echo "image scanbus:test built in $(( $(date +%s) - started )) s ($(docker image inspect -f '{{.Size}}' scanbus:test | awk '{printf "%.0f MB", $1 / 1e6}'))"
[ "$(docker run --rm --entrypoint id scanbus:test -u)" != 0 ] || { echo "FAIL: the image runs as root"; exit 1; }

export SCANBUS_IMAGE=scanbus:test SCANBUS_DOMAIN_ID=${SCANBUS_DOMAIN_ID:-0}
"${compose[@]}" up -d
"$scanbus" echo rt/room/measurement --count 1 --timeout 240 > "$work/measurement.json" 2> "$work/echo.log" ||
  { "${compose[@]}" logs --tail 30; echo "FAIL: no RoomMeasurement from the deployment"; exit 1; }
# 2 cm: the live simulator's noise differs run to run (seen: 11 mm); the 1 cm accuracy is
# held by the accuracy tests on fixed data, this checks the deployment delivers.
"$root/tests/support/check_room.py" "$work/measurement.json" 0.02 "deployment measured"

# Health: every running service's container turns healthy.
for _ in $(seq 60); do
  unhealthy=$(for id in $("${compose[@]}" ps -q); do docker inspect -f '{{.Name}} {{.State.Health.Status}}' "$id"; done |
    grep -v " healthy$" || true)
  [ -z "$unhealthy" ] && break
  sleep 2
done
if [ -n "$unhealthy" ]; then  # what the services say of themselves, and their last lines
  "$scanbus" health --once --timeout 3 || true
  "${compose[@]}" logs --tail 15
  echo "FAIL: not healthy: $unhealthy"
  exit 1
fi
echo "every container healthy: $(for id in $("${compose[@]}" ps -q); do docker inspect -f '{{.Name}}' "$id"; done | tr '\n' ' ')"

# The recorder closes its file on SIGTERM; the measurement is in it.
"${compose[@]}" stop --timeout 10 recorder > /dev/null
container=$("${compose[@]}" ps -q recorder)
docker cp "$container:/recordings/scanbus.mcap" "$work/recording.mcap"
"$scanbus" info --json "$work/recording.mcap" > "$work/info.json"
python3 - "$work/info.json" <<'PY'
import json, sys
info = json.load(open(sys.argv[1]))
counts = {t["topic"]: t["messages"] for t in info["topics"]}
print("recorder's file:", counts)
assert counts.get("/room/measurement", 0) >= 1 and counts.get("/scanner/scan_cloud", 0) >= 3, counts
PY
echo "compose deployment: ok"
