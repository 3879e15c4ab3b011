#!/usr/bin/env bash
# Builds the AVR image into OBJDIR (argument 1), quietly unless it fails.
set -uo pipefail
objdir=$1
mkdir -p "$objdir"
if ! make -C "$(dirname "$0")/scanner" OBJDIR="$objdir" > "$objdir/build.log" 2>&1; then
  cat "$objdir/build.log"
  exit 1
fi
"$(dirname "$0")/check_size.sh" "$objdir/scanner.elf"
