#!/bin/sh
# Inside an image: installs the packages listed in /usr/share/scanbus/runtime-packages.txt
# (docker/runtime-packages.sh) and makes the unprivileged user the services run as, with
# the recordings folder it writes. Shared by docker/Dockerfile and docker/Dockerfile.prebuilt.
set -eu
apt-get update -q
DEBIAN_FRONTEND=noninteractive xargs -a /usr/share/scanbus/runtime-packages.txt \
  apt-get install -y -q --no-install-recommends
rm -rf /var/lib/apt/lists/*
useradd --system --uid 10001 --create-home --home-dir /home/scanbus scanbus
mkdir -p /recordings
chown scanbus:scanbus /recordings
