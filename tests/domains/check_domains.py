#!/usr/bin/env python3
"""Every DDS test owns its domain: ctest runs tests side by side (-j2), and two tests on one
domain see each other's participants and topics (a late `scanbus cloud save` may read the
other test's cloud, a request reach the other test's service).

Reads the domains the tests name, one use per test:
- in tests/**/CMakeLists.txt, each SCANBUS_DOMAIN_ID=N, and for a
  `foreach(var ...) math(EXPR domain "B + ${var}")` loop, B plus each value;
- in tests/**/*.cpp and services/**/test/*.cpp, use_domain(N) and {"", "localhost", N}, once
  per GoogleTest case (TEST, TEST_F: each is a ctest of its own) or per file without cases;
- in bench/*.sh, each default ${SCANBUS_DOMAIN_ID:-N}, so a benchmark run beside the tests
  meets none of them.
A domain used by two tests is an error, and so is a domain set in a form this script does
not read (SCANBUS_DOMAIN_ID=${...} outside such a loop, "localhost" with a non-literal
domain outside use_domain()), since it could not be checked. Not read: a domain set in a
fixture's helper counts once for its file (launch's system_test gives 42 to cases that run
/bin/echo, no DDS), TEST_P instances and typed tests are not told apart, and shell scripts
take their domain from CMake.

    check_domains.py SOURCE_DIR
"""
import collections
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1])
users = collections.defaultdict(list)  # domain -> the tests using it
problems = []

for path in sorted(root.glob("tests/**/CMakeLists.txt")):
    text, name = path.read_text(), str(path.relative_to(root))
    for n in re.findall(r"SCANBUS_DOMAIN_ID=(\d+)", text):
        users[int(n)].append(name)
    loops = re.findall(r"foreach\((\w+) ([\w ]+)\)\s*math\(EXPR domain \"(\d+) \+ \$\{(\w+)\}\"\)", text)
    for var, values, base, used in loops:
        if var != used:
            problems.append(f"{name}: math(EXPR domain) adds ${{{used}}}, not the loop's ${{{var}}}")
        if not all(v.isdigit() for v in values.split()):
            problems.append(f"{name}: foreach({var} {values}) is not a list of numbers this check can read")
            continue
        for v in values.split():
            users[int(base) + int(v)].append(f"{name} ({var} {v})")
    if text.count("SCANBUS_DOMAIN_ID=${") != len(loops):
        problems.append(f"{name}: SCANBUS_DOMAIN_ID set from a variable this check cannot follow")

for path in sorted(root.glob("tests/**/*.cpp")) + sorted(root.glob("services/**/test/*.cpp")):
    text, name = path.read_text(), str(path.relative_to(root))
    if re.search(r'"localhost", (?!\d+\})', text) and not re.search(r"void use_domain\(int domain\)", text):
        problems.append(f"{name}: a DDS domain that is not a number this check can read")
    cases = re.split(r"\n(?=TEST(?:_F|_P)?\()", text)
    for index, case in enumerate(cases):
        domains = {int(n) for n in re.findall(r'use_domain\((\d+)\)|\{"", "localhost", (\d+)\}', case) for n in n if n}
        test = re.match(r"TEST(?:_F|_P)?\((\w+),\s*(\w+)\)", case)
        label = f"{name} ({test[1]}.{test[2]})" if test else name
        for domain in domains:
            users[domain].append(label)

# The benchmarks' default domains: a bench run beside ctest must not meet a test.
for path in sorted(root.glob("bench/*.sh")):
    name = str(path.relative_to(root))
    for n in set(re.findall(r"SCANBUS_DOMAIN_ID:-(\d+)\}", path.read_text())):
        users[int(n)].append(f"{name} (its default)")

for domain, tests in sorted(users.items()):
    if len(tests) > 1:
        problems.append(f"domain {domain} is used {len(tests)} times: {'; '.join(tests)}")
print(f"{len(users)} DDS domains used by tests and benchmarks: {', '.join(str(d) for d in sorted(users))}")
for problem in problems:
    print("FAIL", problem)
sys.exit(1 if problems or not users else 0)
