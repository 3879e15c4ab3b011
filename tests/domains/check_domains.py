#!/usr/bin/env python3
"""Every DDS test owns its domain: ctest runs tests side by side (-j2), and two tests on one
domain see each other's participants and topics (a late `scanbus cloud save` may read the
other test's cloud, a request reach the other test's service).

Reads the domains the tests name: SCANBUS_DOMAIN_ID=N in tests/**/CMakeLists.txt (a
`math(EXPR domain "B + ${var}")` inside `foreach(var ...)` counts B plus each value), and
use_domain(N) or DdsSettings/SystemSettings {"", "localhost", N} in tests/**/*.cpp and
services/**/test/*.cpp. A domain named in two files, or by two use_domain() calls in one
file, is an error.

    check_domains.py SOURCE_DIR
"""
import collections
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1])
owners = collections.defaultdict(set)  # domain -> files naming it
problems = []


def cmake_domains(text):
    found = [int(n) for n in re.findall(r"SCANBUS_DOMAIN_ID=(\d+)", text)]
    for values, base in re.findall(r"foreach\(\w+ ([\w ]+)\)\s*math\(EXPR domain \"(\d+) \+", text):
        found += [int(base) + int(v) for v in values.split()]
    return found


for path in sorted(root.glob("tests/**/CMakeLists.txt")):
    for domain in cmake_domains(path.read_text()):
        owners[domain].add(str(path.relative_to(root)))

sources = sorted(root.glob("tests/**/*.cpp")) + sorted(root.glob("services/**/test/*.cpp"))
for path in sources:
    text = path.read_text()
    named = [int(n) for n in re.findall(r"use_domain\((\d+)\)", text)]
    for domain, count in collections.Counter(named).items():
        if count > 1:
            problems.append(f"{path.relative_to(root)}: use_domain({domain}) in {count} tests")
    named += [int(n) for n in re.findall(r'\{"", "localhost", (\d+)\}', text)]
    for domain in set(named):
        owners[domain].add(str(path.relative_to(root)))

for domain, files in sorted(owners.items()):
    if len(files) > 1:
        problems.append(f"domain {domain} is named by {len(files)} files: {', '.join(sorted(files))}")
print(f"{len(owners)} DDS domains named by tests: {', '.join(str(d) for d in sorted(owners))}")
for problem in problems:
    print("FAIL", problem)
sys.exit(1 if problems or not owners else 0)
