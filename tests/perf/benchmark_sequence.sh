#!/usr/bin/env bash
# The FDI/FTC benchmark's fault sequence through the whole system (closed loop, fast mode): every covered fault
# detected and isolated while it is active, named once, and no false alarm. Prints the benchmark's own table.
#   tests/perf/benchmark_sequence.sh [SCENARIO.yaml]     (default deploy/scenarios/benchmark.yaml)
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${WINDFDI_BUILD_DIR:-$top/build}
scenario=${1:-$top/deploy/scenarios/benchmark.yaml}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/bin/system_replay" --scenario "$scenario" --history "$work/history.jsonl" >/dev/null
"$build/bin/windfdi-farm" report --scenario "$scenario" --history "$work/history.jsonl" | tee "$work/report.txt"
# The table's closing line: "N of M covered faults detected and isolated while active; F false alarm(s)".
line=$(grep "covered faults detected and isolated while active" "$work/report.txt")
read -r ok _ covered _ <<<"$line"
alarms=$(sed -E 's/.*; ([0-9]+) false alarm.*/\1/' <<<"$line")
if [ "$ok" != "$covered" ] || [ "$alarms" != "0" ]; then
  echo "benchmark_sequence: $ok of $covered detected and isolated while active, $alarms false alarm(s)" >&2
  exit 1
fi
# ... and each named once: the report's class column chains renamings ("high_air_content > pump_wear > ...";
# the high air content on blade 2 was renamed pump wear for 24 s, and the arbiter's degraded mode moved the pitch).
if grep -q " > " "$work/report.txt"; then
  echo "benchmark_sequence: a fault was renamed while active:" >&2
  grep " > " "$work/report.txt" >&2
  exit 1
fi
