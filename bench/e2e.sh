#!/usr/bin/env bash
# End-to-end DDS performance across processes, scanbus beside raw Fast DDS in one run
# (bench/dds_e2e_bench.cpp says what each mode does):
#   latency: a serial line entering scanner I/O to the PointCloud2 leaving it, REVOLUTIONS
#            revolutions of 150 measurements, scanner_io vs a raw relay;
#   throughput: PointCloud2 of 10k, 100k and 1M points between two processes, modes raw,
#            scanbus (its Participant/Writer/Reader) and convert (plus points -> PointCloud2
#            -> points at the ends), REPETITIONS runs of SECONDS each, interleaved; medians.
# Usage: bench/e2e.sh [REPETITIONS (5)] [SECONDS (5)] [REVOLUTIONS (1000)]
set -euo pipefail
cd "$(dirname "$0")/.."
repetitions=${1:-5} seconds=${2:-5} revolutions=${3:-1000}
scripts/build.sh > /dev/null
export SCANBUS_DOMAIN_ID=${SCANBUS_DOMAIN_ID:-110}
results=$(mktemp)
trap 'rm -f "$results"' EXIT
bench=build/bench/dds_e2e_bench
for mode in raw scanbus; do
  [ -t 2 ] && echo "latency: $mode, $revolutions revolutions" >&2
  "$bench" latency "$mode" "$revolutions" >> "$results"
done
for points in 10000 100000 1000000; do
  for run in $(seq "$repetitions"); do
    for mode in raw scanbus convert; do
      [ -t 2 ] && echo "throughput: $points points, $mode, run $run of $repetitions" >&2
      "$bench" throughput "$mode" "$points" "$seconds" >> "$results"
    done
  done
done
python3 - "$results" <<'PY'
import json, statistics, sys, os
rows = [json.loads(line) for line in open(sys.argv[1])]
cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
print(f"machine: {cpu}, {os.cpu_count()} cores")
lat = {r["mode"]: r["latency"] for r in rows if "latency" in r}
print("\nserial line -> PointCloud2 (150 points), microseconds")
print(f"{'':10} {'median':>8} {'p90':>8} {'p99':>8} {'max':>8}")
for mode in ("raw", "scanbus"):
    l = lat[mode]
    print(f"{mode:10} {l['median_us']:8.0f} {l['p90_us']:8.0f} {l['p99_us']:8.0f} {l['max_us']:8.0f}")
print(f"added median latency: {lat['scanbus']['median_us'] - lat['raw']['median_us']:.0f} us")
print("\nPointCloud2 throughput between two processes, MB/s (median of runs; ratio to raw)")
print(f"{'points':>8} {'raw':>8} {'scanbus':>8} {'ratio':>6} {'convert':>8} {'ratio':>6} {'lost':>5}")
for points in (10000, 100000, 1000000):
    med = {}
    lost = 0
    for mode in ("raw", "scanbus", "convert"):
        runs = [r for r in rows if r.get("points") == points and r["mode"] == mode]
        med[mode] = statistics.median(r["mb_per_s"] for r in runs)
        lost += sum(r["published"] - r["received"] for r in runs)
    print(f"{points:>8} {med['raw']:8.0f} {med['scanbus']:8.0f} {med['scanbus'] / med['raw']:6.2f} "
          f"{med['convert']:8.0f} {med['convert'] / med['raw']:6.2f} {lost:>5}")
PY
