#!/usr/bin/env bash
# The whole build and test suite with AddressSanitizer and UndefinedBehaviorSanitizer
# (gcc, -DSCANBUS_SANITIZE=ON) in build-sanitize/. Any report fails the test that caused it.
# CI runs it (.ci/run); docs/testing.md says what it found and what it leaves out.
#   scripts/sanitize.sh [ctest arguments]
set -euo pipefail
cd "$(dirname "$0")/.."
# -O1 -g1: the lightest build that still gives ASan line numbers (the time is CI's, 2 cores).
cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=None -DCMAKE_C_FLAGS="-O1 -g1" -DCMAKE_CXX_FLAGS="-O1 -g1" \
  -DSCANBUS_SANITIZE=ON -DSCANBUS_BUILD_BENCH=OFF \
  > build-sanitize-configure.log 2>&1 || { cat build-sanitize-configure.log; exit 1; }
cmake --build build-sanitize -j2 > build-sanitize-build.log 2>&1 || { tail -50 build-sanitize-build.log; exit 1; }
# new_delete_type_mismatch is off: Fast DDS 2.9 itself deletes its StatisticsReaderImpl
# (64 bytes) through the 56-byte RTPSReader (libfastrtps' ~RTPSReader), on every reader's
# deletion; ASan's other checks stay on.
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=1:new_delete_type_mismatch=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/tests/sanitizers/lsan.supp:print_suppressions=0
# The demo without its MAV flight: under the sanitizers it had to replay at 2x to keep every
# pose and still lost box accuracy when the machine was loaded (tests/integration/cli_demo.sh);
# the services it runs are under the sanitizers in faults.mav_kill_restart and faults.sensor_faults.
export SCANBUS_TEST_DEMO_MAV=0
# The scan matcher's accuracy on MIT CSAIL alone (its bad-input checks and backtransform
# pictures with it): with Killian's 17,479 scans too it passed its time limit in CI here.
export SCANBUS_TEST_FREIBURG_LOGS=mit-csail
# Left out: the tests tests/sanitizers/left_out.txt names, each with why: a ctest name per
# line (letters, digits, _ and .), a trailing * for any end.
mapfile -t names < <(sed -e 's/#.*//' -e 's/^[[:space:]]*//' -e 's/[[:space:]]*$//' -e '/^$/d' tests/sanitizers/left_out.txt)
[ ${#names[@]} -gt 0 ] || { echo "tests/sanitizers/left_out.txt: no name read"; exit 1; }
cd build-sanitize
patterns=()
for name in "${names[@]}"; do
  [[ $name =~ ^[A-Za-z0-9_.]+\*?$ ]] || { echo "tests/sanitizers/left_out.txt: '$name' is not a test's name"; exit 1; }
  pattern=${name//./\\.}
  pattern=${pattern%\*}
  [ "$pattern" = "${name//./\\.}" ] || pattern+='.*'
  # A name no test has any more (renamed, removed) would leave nothing out and say nothing.
  listed=$(ctest -N -R "^$pattern\$")
  grep -q "Test *#" <<< "$listed" || { echo "tests/sanitizers/left_out.txt: no test is '$name'"; exit 1; }
  patterns+=("$pattern")
done
left_out=$(IFS='|'; echo "${patterns[*]}")
ctest --output-on-failure -j2 --timeout 1200 -E "^($left_out)\$" "$@"
