#!/usr/bin/env bash
# Prints the AVR image's flash and static RAM use and fails when it does not fit the
# ATmega328P: 32,256 bytes of flash (32 KiB less the 512-byte bootloader) and 1,536 bytes
# of static RAM (2 KiB less 512 left for the stack).
set -euo pipefail
elf=$1
read -r text data bss < <(avr-size -A "$elf" | awk '$1==".text"{t=$2} $1==".data"{d=$2} $1==".bss"{b=$2} END{print t, d, b}')
flash=$((text + data))
ram=$((data + bss))
echo "AVR image $elf: flash ${flash} of 32256 bytes, static RAM ${ram} of 1536 bytes"
[ "$flash" -le 32256 ] || { echo "flash over budget"; exit 1; }
[ "$ram" -le 1536 ] || { echo "static RAM over budget"; exit 1; }
