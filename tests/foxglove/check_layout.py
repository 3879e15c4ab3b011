#!/usr/bin/env python3
"""docs/foxglove_layout.json: valid JSON, every panel of the layout configured, and every
topic it shows one the catalogue has (`scanbus topics`), with the fields its panels read."""
import json
import subprocess
import sys

scanbus, layout_path = sys.argv[1], sys.argv[2]
layout = json.load(open(layout_path))
catalogue = {line.split()[0][2:]: line.split()[1] for line in subprocess.run(
    [scanbus, "topics"], check=True, capture_output=True, text=True).stdout.splitlines() if line.startswith("rt/")}
failures = []


def panels(node):
    return [node] if isinstance(node, str) else panels(node["first"]) + panels(node["second"])


for panel in panels(layout["layout"]):
    if panel not in layout["configById"]:
        failures.append(f"panel {panel} has no config")
config = layout["configById"]
shown = dict(config["3D!scanbus"]["topics"])
shown[config["RawMessages!scanbus"]["topicPath"]] = None
for path in config["Plot!scanbus"]["paths"]:
    shown[path["value"].split(".")[0]] = None
for topic in shown:
    if topic not in catalogue:
        failures.append(f"{topic} is not a catalogue topic")
point_fields = {"/cloud/assembled": "x y z rgb", "/room/walls": "x y z rgb", "/scanner/cloud": "x y z intensity"}
for topic, settings in config["3D!scanbus"]["topics"].items():
    field = (settings or {}).get("colorField")
    if field and field not in point_fields[topic].split():
        failures.append(f"{topic} has no field {field}")
for failure in failures:
    print("FAIL " + failure)
print(f"{'ok  ' if not failures else 'FAIL'} {layout_path}: {len(panels(layout['layout']))} panels, topics {sorted(shown)}")
sys.exit(1 if failures else 0)
