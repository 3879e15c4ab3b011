#!/bin/sh
# Prints the Debian packages owning every shared library the given executables load, one a
# line: what an image needs installed to run them. Used by docker/Dockerfile's build stage
# and by tests/deploy/compose_test.sh for the host's own build (docker/Dockerfile.prebuilt).
#   docker/runtime-packages.sh EXECUTABLE...
set -eu
for library in $(ldd "$@" | awk '/=> \//{print $3}' | sort -u); do
  # usrmerge: ldd may name /lib/... while dpkg knows /usr/lib/..., or the reverse.
  dpkg -S "$library" 2>/dev/null || dpkg -S "$(readlink -f "$library")" 2>/dev/null \
    || dpkg -S "/usr$library" 2>/dev/null || dpkg -S "${library#/usr}"
done | cut -d: -f1 | sort -u
