#!/usr/bin/env bash
# Recording 1,000,000-point PointCloud2 samples (16 MB each) at 10 Hz across processes:
# recording_publisher -> `scanbus record` over the loopback profile, for each chunk
# compression. Prints samples published and recorded, the sustained MB/s recorded while
# publishing (publishing time plus 0.5 s for the last samples), the file's size over the
# bytes recorded, and the recording process's CPU share over that time (user + system
# time over wall time; 1.0 = one core). Usage: bench/recording_throughput.sh [SECONDS] (default 20).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
scripts/build.sh > /dev/null
work=$(mktemp -d)
trap 'jobs -p | xargs -r kill -9 2>/dev/null || true; rm -rf "$work"' EXIT
export SCANBUS_DOMAIN_ID=${SCANBUS_DOMAIN_ID:-111}
ticks=$(getconf CLK_TCK)
printf "%-12s %10s %10s %10s %12s %10s\n" compression published recorded "MB/s" "file share" "CPU share"
for compression in none lz4 zstd; do
  build/services/cli/scanbus record --topics rt/scanner/cloud --compression "$compression" \
    --out "$work/cloud.mcap" --json > "$work/record.json" 2> "$work/record.log" &
  recorder=$!
  build/bench/recording_publisher 1000000 10 "$seconds" > "$work/publisher.json" 2> "$work/publisher.log" &
  publisher=$!
  until grep -q publishing "$work/publisher.log"; do sleep 0.05; done
  start=$(date +%s.%N)
  read -r -a before < <(cut -d' ' -f14,15 "/proc/$recorder/stat")
  wait "$publisher"
  sleep 0.5  # the last samples reach the file
  read -r -a after < <(cut -d' ' -f14,15 "/proc/$recorder/stat")
  end=$(date +%s.%N)
  kill -INT "$recorder"
  wait "$recorder"
  python3 - "$work" "$compression" "$start" "$end" "$ticks" "${before[@]}" "${after[@]}" <<'PY'
import json, os, sys
work, compression, start, end, ticks = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5])
before, after = [int(v) for v in sys.argv[6:8]], [int(v) for v in sys.argv[8:10]]
published = json.load(open(f"{work}/publisher.json"))
recorded = json.load(open(f"{work}/record.json"))
wall = end - start
cpu = (sum(after) - sum(before)) / ticks  # clock ticks of the recording process
size = os.path.getsize(f"{work}/cloud.mcap")
print(f"{compression:<12} {published['published']:>10} {recorded['messages']:>10} {recorded['bytes'] / 1e6 / wall:>10.1f} "
      f"{size / max(1, recorded['bytes']):>12.3f} {cpu / wall:>10.2f}")
PY
done
