# Shared by the Foxglove bridge tests: Foxglove's npm packages for foxglove_client.mjs, and a
# bridge started on this test's port (20000 + its DDS domain).
source "$(dirname "${BASH_SOURCE[0]}")/../integration/lib.sh"

# A work folder (with_work) and the client installed in it.
foxglove_test_setup() {
  with_work
  install_client
}

# install_client: $work/node/foxglove_client.mjs with its packages, or exit 77 (skip) without npm.
install_client() {
  if ! command -v npm > /dev/null || ! command -v node > /dev/null; then
    echo "SKIP: node and npm are not installed (scripts/install-deps.sh installs them)"
    exit 77
  fi
  mkdir -p "$work/node"
  cp "$(dirname "${BASH_SOURCE[0]}")/foxglove_client.mjs" "$work/node/"
  (cd "$work/node" && npm install --silent --no-audit --no-fund @foxglove/ws-protocol@0.8 ws@8 @foxglove/rosmsg@5 \
    @foxglove/rosmsg2-serialization@3 > npm.log 2>&1) ||
    { echo "FAIL: npm could not install Foxglove's client packages:"; cat "$work/node/npm.log"; exit 1; }
}

# start_bridge SCANBUS [YAML LINES]: the bridge in the background ($bridge_pid, log
# $work/bridge.log), listening at $url before this returns.
start_bridge() {
  local scanbus=$1 extra=${2:-}
  local port=$((20000 + SCANBUS_DOMAIN_ID))
  printf 'foxglove_bridge:\n  port: %d\n%s' "$port" "$extra" > "$work/bridge.yaml"
  "$scanbus" run foxglove_bridge --config "$work/bridge.yaml" > "$work/bridge.log" 2>&1 &
  bridge_pid=$!
  pids+=("$bridge_pid")
  url=ws://127.0.0.1:$port
  wait_for_line "$work/bridge.log" "Foxglove WebSocket server on" 10 && return 0
  echo "FAIL: the bridge is not listening after 10 s:"; cat "$work/bridge.log"; exit 1
}

# client ARGS...: foxglove_client.mjs at $url in the foreground; start_client OUT ARGS...: in
# the background, its JSON into OUT, $client_pid the node process itself (for kill -TERM).
client() { node "$work/node/foxglove_client.mjs" "$url" "$@"; }
start_client() {
  local out=$1
  shift
  node "$work/node/foxglove_client.mjs" "$url" "$@" > "$out" &
  client_pid=$!
  pids+=("$client_pid")
}
