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
