#!/usr/bin/env bash
# Installs the Debian bookworm packages scanbus needs to build, test and run; does nothing
# when they are all present. Needs root (or sudo). `--build-only`: just what building the
# services needs.
set -euo pipefail

# What building the services needs (`--build-only`: the container image's build stage).
packages=(
  cmake g++ make pkg-config
  libfastrtps-dev libfastcdr-dev fastddsgen
  libpcl-dev libceres-dev libeigen3-dev libgeographiclib-dev
  libzstd-dev liblz4-dev zlib1g-dev
  libyaml-cpp-dev libcli11-dev nlohmann-json3-dev libspdlog-dev libcairo2-dev libnanoflann-dev libdxflib-dev libgdal-dev
)
build_only=false
[ "${1:-}" = "--build-only" ] && build_only=true
if ! $build_only; then
  # Tests, benchmarks, the firmware's AVR build, tools the tests drive, the deployment test,
  # the fuzzing (clang's libFuzzer and sanitizer runtimes), the format check.
  packages+=(
    git fastdds-tools
    libgtest-dev libgmock-dev libbenchmark-dev
    gcc-avr avr-libc binutils-avr arduino-core-avr arduino-mk
    iproute2 procps python3 python3-ezdxf gdal-bin
    docker.io docker-compose debootstrap
    cyclonedds-dev cyclonedds-tools openssl
    clang libclang-rt-14-dev clang-format
  )
fi

missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
# Node.js and npm run the MCAP interoperability check (tests/recorder): Debian's, unless
# some other Node.js is already on the PATH.
$build_only || { command -v node > /dev/null && command -v npm > /dev/null; } || missing+=(nodejs npm)
[ ${#missing[@]} -eq 0 ] && exit 0

echo "installing: ${missing[*]}"
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -q
$sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
