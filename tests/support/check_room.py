#!/usr/bin/env python3
"""Checks a RoomMeasurement (one JSON line as `scanbus echo` prints it; the last line of
the file) against the simulator's built-in room, thesis case 1: 5.47 m x 3.48 m.
    check_room.py FILE TOLERANCE_M LABEL
Every wall within the tolerance and within 3 of its own sigmas (the sigma printed is a claim
too), the floor within 1 %. Prints the walls and area; exits 1 naming the first wall off."""
import json
import sys

path, tolerance, label = sys.argv[1], float(sys.argv[2]), sys.argv[3]
room = json.loads(open(path).read().splitlines()[-1])
walls = sorted((wall["length"], wall["length_uncertainty"]) for wall in room["walls"])
print(f"{label}: walls {[f'{length:.3f}+-{sigma:.3f}' for length, sigma in walls]}, floor {room['floor_area']:.2f} m2")
if room["status"] != 0 or len(walls) != 4:
    sys.exit(f"FAIL {label}: status {room['status']} ({room['message']}), {len(walls)} walls")
for (got, sigma), want in zip(walls, [3.48, 3.48, 5.47, 5.47]):
    if abs(got - want) > tolerance or abs(got - want) > 3 * sigma:
        sys.exit(f"FAIL {label}: wall {got:.3f} +- {sigma:.3f} m, the room's is {want} m (tolerance {tolerance} m and 3 sigma)")
if abs(room["floor_area"] - 5.47 * 3.48) > 0.01 * 5.47 * 3.48:
    sys.exit(f"FAIL {label}: floor {room['floor_area']:.3f} m2, the room's is {5.47 * 3.48:.3f} m2")
