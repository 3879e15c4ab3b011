#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz: clang, AddressSanitizer, UndefinedBehaviorSanitizer)
# into build-fuzz/ and runs each for SECONDS (default 60) from its seed corpus, or only the
# TARGETs named. The corpus grows in build-fuzz/corpus/ across runs; the repository's seeds
# are read, never written. A crash, a leak or an input running over 10 s fails the run and
# leaves the input in build-fuzz/findings/TARGET/; fix it and copy the input to
# tests/fuzz/regressions/TARGET/ (tests/fuzz/README.md). A finding's report and its input
# (base64, up to 64 KiB) are printed, so one found in CI reproduces from the log. Progress
# on a terminal only.
#   scripts/fuzz.sh [SECONDS|--nightly] [TARGET ...]
# --nightly: 600 s per target (80 minutes for all eight), for a nightly job; CI runs 15.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
[ "$seconds" = --nightly ] && seconds=600
[ $# -gt 0 ] && shift
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(device_line firmware_commands carmen_log relations mav_log mcap_reader cloud_file config)
cmake -S . -B build-fuzz -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DSCANBUS_FUZZ=ON > build-fuzz-configure.log 2>&1 || { cat build-fuzz-configure.log; exit 1; }
cmake --build build-fuzz -j2 --target "${targets[@]/%/_fuzz}" > build-fuzz-build.log 2>&1 || { tail -50 build-fuzz-build.log; exit 1; }
failed=()
for target in "${targets[@]}"; do
  corpus=build-fuzz/corpus/$target findings=build-fuzz/findings/$target
  rm -rf "$findings"  # what is printed below is this run's
  mkdir -p "$corpus" "$findings"
  [ -t 1 ] && printf '%s: fuzzing for %s s ...\r' "$target" "$seconds"
  if build-fuzz/tests/fuzz/${target}_fuzz "$corpus" "tests/fuzz/corpus/$target" -max_total_time="$seconds" \
       -timeout=10 -rss_limit_mb=2048 -artifact_prefix="$findings/" -print_final_stats=1 > "$findings.log" 2>&1; then
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$findings.log")
    echo "$target: ${runs:-?} inputs in ${seconds} s, corpus $(ls "$corpus" | wc -l) files, no finding"
  else
    echo "$target: FINDING, input in $findings/ (log $findings.log):"
    # -a: the log can hold the input's bytes, and grep would then say only "binary file matches".
    grep -a -E "ERROR|SUMMARY|runtime error|#[0-9]+ 0x|Test unit written" "$findings.log" | head -30
    # CI's work tree is gone after the run: the input itself, to reproduce the finding from the log.
    for input in "$findings"/*; do
      [ "$(stat -c %s "$input")" -le 65536 ] && { echo "$(basename "$input") as base64:"; base64 -w 0 "$input"; echo; }
    done
    failed+=("$target")
  fi
done
[ ${#failed[@]} -eq 0 ] || { echo "fuzzing found problems in: ${failed[*]}"; exit 1; }
