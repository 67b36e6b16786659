#!/usr/bin/env bash
# One fault, one report: scenarios in which a fault once made a second service report it under another name
# (tests/perf/one_report/*.yaml, each from a fault suite scenario, its description says which and what) through
# the whole system in closed loop (fast mode). Each must have every covered fault right first (an intermittent
# one: sensor_abrupt, then sensor_intermittent once it came back) and named once (no other class raised in its
# place later), no secondary report, no unexpected report and no unwarranted stop.
#   tests/perf/one_report.sh [SCENARIO.yaml ...]     (default: every scenario in tests/perf/one_report)
# WINDFDI_BUILD_DIR and WINDFDI_CONFIG_DIR run another build with its own configuration (default: this tree's).
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${WINDFDI_BUILD_DIR:-$top/build}
config=${WINDFDI_CONFIG_DIR:-$top/deploy/config}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
[ $# -gt 0 ] || set -- "$top"/tests/perf/one_report/*.yaml
failed=0
for scenario in "$@"; do
  # A scenario on another turbine names its file (relative to deploy/): every service reads it too.
  settings=()
  turbine=$(sed -n 's/^turbine_file: *//p' "$scenario")
  if [ -n "$turbine" ]; then
    for service in blade_load drive_train ice_detect pitch_diag sensor_bias arbiter; do
      settings+=(--set "$service.turbine_file=../$turbine")
    done
  fi
  if ! "$build/bin/system_replay" --scenario "$scenario" --history "$work/history.jsonl" --config-dir "$config" \
    "${settings[@]}" >/dev/null 2>"$work/replay.err"; then
    cat "$work/replay.err" >&2
    exit 2
  fi
  "$build/bin/windfdi-farm" report --scenario "$scenario" --history "$work/history.jsonl" >"$work/report.txt"
  # "N of M covered faults detected with the right class first[, ...]; U unexpected fault report(s)[, S
  # secondary ...]; K safe stop(s), W not warranted"
  line=$(grep "covered faults detected with the right class first" "$work/report.txt")
  read -r right _ covered _ <<<"$line"
  # An intermittent gauge is named so only once it comes back: first sensor_abrupt, then sensor_intermittent
  # counts as right first, as multi_fault_suite.py judges it.
  intermittent=$(grep -cE " sensor_intermittent +sensor_abrupt \(!\)( > [a-z_]+)* > sensor_intermittent " \
    "$work/report.txt" || true)
  right=$((right + intermittent))
  # Named once: a fault's report chain (DETECTED "first > then > ...") names no class but its first, apart from
  # the intermittent gauge's abrupt-then-intermittent.
  renamed=$(grep -E "^WT[0-9]+ " "$work/report.txt" | grep " > " |
    grep -cvE " sensor_intermittent +sensor_abrupt \(!\) > sensor_intermittent " || true)
  unexpected=$(sed -E 's/.*; ([0-9]+) unexpected.*/\1/' <<<"$line")
  unwarranted=$(sed -E 's/.* ([0-9]+) not warranted.*/\1/' <<<"$line")
  secondary=$(grep -c "^secondary:" "$work/report.txt" || true)
  echo "$(basename "$scenario"): $right of $covered right first, $renamed renamed, $unexpected unexpected, $secondary secondary, $unwarranted unwarranted stop(s)"
  if [ "$right" != "$covered" ] || [ "$renamed" != 0 ] || [ "$unexpected" != 0 ] || [ "$secondary" != 0 ] ||
    [ "$unwarranted" != 0 ]; then
    grep -E "^secondary:|^unexpected:|MISSED|\(!\)| > " "$work/report.txt" >&2 || true
    failed=1
  fi
done
exit $failed
