#!/usr/bin/env python3
"""Where in time a flight's height error lies, per height source.

    bench/height_error_bands.py HEIGHTS.csv [HEIGHTS.csv ...]

Reads the heights CSV that `scanbus eval mav --out DIR` writes for each flight (stamp, truth,
then one column per source) and prints, per source: the RMSE; the error of the height's change
over 1 s; the RMS of the error in bands of period (under 0.3 s, 0.3-1, 1-3 and 3-10 s, each the
difference of centred moving averages of those lengths); and, for the fused height, the RMSE
left after removing the flight's mean difference to GPS altitude (the most a correction of
GPS's flight-long offset could give). docs/performance.md ("Half-metre map cells") quotes it.
Plain Python: no NumPy on a fresh machine.
"""
import csv
import math
import sys

SOURCES = ("barometer", "scan_matcher", "fused", "gps")
BANDS = ((0, 0.3), (0.3, 1.0), (1.0, 3.0), (3.0, 10.0))


def moving_average(values, width):
    """Centred mean over `width` samples (fewer at the ends), by a running sum."""
    if width <= 1:
        return list(values)
    prefix = [0.0]
    for v in values:
        prefix.append(prefix[-1] + v)
    half = width // 2
    out = []
    for i in range(len(values)):
        lo, hi = max(0, i - half), min(len(values), i + half + 1)
        out.append((prefix[hi] - prefix[lo]) / (hi - lo))
    return out


def rms(values):
    return math.sqrt(sum(v * v for v in values) / len(values)) if values else float("nan")


def report(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if len(rows) < 3:
        raise SystemExit(f"{path}: fewer than 3 heights")
    stamps = [float(r["stamp"]) for r in rows]
    truth = [float(r["truth"]) for r in rows]
    step = (stamps[-1] - stamps[0]) / (len(stamps) - 1)
    lag = max(1, round(1.0 / step))
    print(f"{path}: {len(rows)} heights, {stamps[-1] - stamps[0]:.0f} s")
    print(f"  {'source':<13}{'RMSE':>8}{'1 s change':>12}" + "".join(f"{f'{a:g}-{b:g} s':>10}" for a, b in BANDS))
    errors = {}
    for source in SOURCES:
        if source not in rows[0] or rows[0][source] in ("", "nan"):
            continue
        error = [float(r[source]) - t for r, t in zip(rows, truth)]
        if any(math.isnan(e) for e in error):
            continue
        errors[source] = error
        change = [error[i + lag] - error[i] for i in range(len(error) - lag)]
        smoothed = {0: error}
        for _, b in BANDS:
            smoothed[b] = moving_average(error, round(b / step))
        bands = [rms([x - y for x, y in zip(smoothed[a], smoothed[b])]) for a, b in BANDS]
        print(f"  {source:<13}{rms(error):8.4f}{rms(change):12.4f}" + "".join(f"{v:10.4f}" for v in bands))
    if "fused" in errors and "gps" in errors:
        offset = sum(f - g for f, g in zip(errors["fused"], errors["gps"])) / len(truth)
        print(f"  fused less its mean difference to GPS ({offset:+.4f} m): RMSE "
              f"{rms([f - offset for f in errors['fused']]):.4f} (GPS {rms(errors['gps']):.4f})")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        raise SystemExit(__doc__)
    for name in sys.argv[1:]:
        report(name)
