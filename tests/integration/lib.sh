# Shared by the integration scripts.

# expect_clean_stop NAME PID SIGNAL LOG: the process exits 0 within 1 s of the signal
# (the runtime's promise for SIGINT and SIGTERM); prints the log when it does not.
expect_clean_stop() {
  local name=$1 pid=$2 signal=$3 log=$4
  local start status=0 elapsed_ms
  start=$(date +%s%N)
  kill "-$signal" "$pid"
  wait "$pid" || status=$?
  elapsed_ms=$(( ($(date +%s%N) - start) / 1000000 ))
  echo "$name stopped on SIG$signal in ${elapsed_ms} ms with status ${status}"
  if [ "$status" -ne 0 ] || [ "$elapsed_ms" -gt 1000 ]; then
    echo "$name did not stop cleanly within 1 s"; cat "$log"; return 1
  fi
}

# expect_exit CODE PATTERN -- COMMAND...: COMMAND exits with CODE, says PATTERN (on stdout
# or stderr) and writes at most one line to stderr. Uses $work; counts into $failures.
expect_exit() {
  local code=$1 pattern=$2; shift 3
  local status=0
  timeout 60 "$@" > "$work/stdout" 2> "$work/stderr" || status=$?
  if [ "$status" -ne "$code" ] || ! grep -q -- "$pattern" "$work/stdout" "$work/stderr" ||
     [ "$(wc -l < "$work/stderr")" -gt 1 ]; then
    echo "FAIL '$*': exit $status, wanted $code, '$pattern' and one stderr line:"
    cat "$work/stdout" "$work/stderr"
    failures=$((failures + 1))
  else
    echo "ok   exit $code: $(cat "$work/stderr" "$work/stdout" | head -c 160)"
  fi
}

# expect_error CODE PATTERN -- COMMAND...: as expect_exit, and the error is exactly one
# line on stderr that says PATTERN.
expect_error() {
  local before=$failures
  expect_exit "$@"
  if [ "$failures" -eq "$before" ] && { [ "$(wc -l < "$work/stderr")" -ne 1 ] || ! grep -q -- "$2" "$work/stderr"; }; then
    echo "FAIL '${*:4}': the error is not one stderr line saying '$2'"
    failures=$((failures + 1))
  fi
}

# with_work [SIGNAL]: a temporary directory $work, removed at exit after every pid in $pids
# got SIGNAL (TERM by default) and ended; $failures counted by fail().
with_work() {
  work=$(mktemp -d)
  pids=()
  failures=0
  stop_signal=${1:-TERM}
  trap 'for pid in "${pids[@]}"; do kill -"$stop_signal" "$pid" 2> /dev/null || true; done; wait 2> /dev/null; rm -rf "$work"' EXIT
}
fail() { echo "FAIL $*"; failures=$((failures + 1)); }

# wait_for_line FILE PATTERN SECONDS: until FILE has a line matching PATTERN (grep -E);
# returns 1 when SECONDS (whole) pass first.
wait_for_line() {
  local tries=$(($3 * 10))
  until grep -q -E -- "$2" "$1" 2> /dev/null; do
    [ $((tries--)) -gt 0 ] || return 1
    sleep 0.1
  done
}

# middleware_warnings LOG: Fast DDS's warnings and errors in LOG (SCANBUS_DDS_LOG=warning),
# each kind once with its count and last time, without the colours.
middleware_warnings() {
  sed 's/\x1b\[[0-9;]*m//g' "$1" | grep -E "^[0-9-]+ [0-9:.]+ \[[A-Z_]+ (Warning|Error)\]" |
    sed -E 's/^[0-9-]+ ([0-9:.]+) /\1 /; s/\(ID:[0-9]+\) //; s/ -> Function .*//' |
    awk '{ time = $1; $1 = ""; count[$0]++; last[$0] = time } END { for (w in count) printf "Fast DDS, %d times, last %s:%s\n", count[w], last[w], w }'
}
