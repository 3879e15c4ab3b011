#!/usr/bin/env bash
# Bad configuration: one clear error line naming the file and key, exit code 2.
set -uo pipefail
source "$(dirname "$0")/lib.sh"
scanbus=$1
probe=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0


printf 'service:\n  health_period: 1\nprobe:\n  pionts: 5\n' > "$work/unknown.yaml"
expect_error 2 "unknown.yaml: unknown key 'probe.pionts'" -- "$probe" send --config "$work/unknown.yaml"

printf 'service:\n  health_period: often\n' > "$work/type.yaml"
expect_error 2 "key 'service.health_period' must be a number, got 'often'" -- "$probe" send --config "$work/type.yaml"

printf 'probe:\n  points: -3\n' > "$work/range.yaml"
expect_error 2 "key 'probe.points' must be between 1 and 10000000, got -3" -- "$probe" send --config "$work/range.yaml"

expect_error 2 "$work/missing.yaml: cannot open config file" -- "$probe" send --config "$work/missing.yaml"

printf 'service: [1, 2\n' > "$work/syntax.yaml"
expect_error 2 "syntax.yaml: invalid YAML at line" -- "$probe" send --config "$work/syntax.yaml"

printf 'qos:\n  rt/no_such_topic: {depth: 1}\n' > "$work/qos.yaml"
expect_error 2 "key 'qos.rt/no_such_topic' names an unknown topic" -- "$probe" send --config "$work/qos.yaml"

expect_error 2 "unknown service 'nope'" -- "$scanbus" run nope

# Abusive YAML, refused at once (expect_exit's 60 s timeout fails a walk that takes longer):
# eight levels of ten aliases (10^8 values from 500 bytes), nesting 100 deep.
python3 - "$work/bomb.yaml" <<'PY'
import sys
lines = ["l0: &l0 [x, x, x, x, x, x, x, x, x, x]"]
lines += [f"l{i}: &l{i} [" + ", ".join([f"*l{i - 1}"] * 10) + "]" for i in range(1, 9)]
open(sys.argv[1], "w").write("\n".join(lines) + "\n")
PY
echo "1 2 3" > "$work/x.xyz"
expect_error 2 "bomb.yaml: more than 100000 values once its aliases are expanded" -- "$scanbus" room measure "$work/x.xyz" --config "$work/bomb.yaml"
printf 'a: %s%s\n' "$(printf '[%.0s' $(seq 100))" "$(printf ']%.0s' $(seq 100))" > "$work/deep.yaml"
expect_error 2 "deep.yaml: line 1: nested deeper than 64 levels" -- "$scanbus" run room_measurement --config "$work/deep.yaml"

# Recordings: an unknown topic, a file that is not MCAP, a cut file; each one clear line.
printf 'recorder:\n  out: %s\n  topics: [rt/nope]\n' "$work/x.mcap" > "$work/recorder.yaml"
expect_error 2 "key 'recorder.topics' topic 'rt/nope' is not in the topic catalogue" -- "$scanbus" run recorder --config "$work/recorder.yaml"
expect_error 2 "topic '/nope' is not in the topic catalogue" -- "$scanbus" record --topics /nope --out "$work/x.mcap"
echo "not a recording" > "$work/text.mcap"
expect_error 2 "not an MCAP file" -- "$scanbus" replay "$work/text.mcap"
head -c 100000 "$(dirname "$0")/../data/mit_csail.mcap" > "$work/cut.mcap"
expect_error 2 "at offset [0-9]* needs [0-9]* bytes" -- "$scanbus" info "$work/cut.mcap"
expect_error 2 "no LaserScan messages\|at offset" -- "$scanbus" scanmatch eval --log "$work/cut.mcap" --relations "$(dirname "$0")/../data/mit_csail.relations"

# Every shipped config is valid for its service.
for config in "$(dirname "$0")"/../../config/services/*.yaml "$(dirname "$0")"/../../config/mav/*.yaml "$(dirname "$0")"/../../config/deploy/*.yaml; do
  service=$(basename "$config" .yaml)
  if "$scanbus" run "$service" --config "$config" --check-config > "$work/out" 2>&1; then
    echo "ok   $(cat "$work/out")"
  else
    echo "FAIL shipped config $config:"; cat "$work/out"; failures=$((failures + 1))
  fi
done

# Every shipped terrain (config/terrain/) flies.
for terrain in "$(dirname "$0")"/../../config/terrain/*.yaml "$(dirname "$0")"/../../config/terrain/validation/*.yaml; do
  if "$scanbus" sim mav --terrain "$terrain" --duration 1 --out "$work/terrain.mavlog" > "$work/out" 2>&1; then
    echo "ok   $terrain: $(cat "$work/out")"
  else
    echo "FAIL shipped terrain $terrain:"; cat "$work/out"; failures=$((failures + 1))
  fi
done

[ "$failures" -eq 0 ]
