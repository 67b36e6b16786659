#!/usr/bin/env bash
# The demo: installs what is missing, builds, then runs a simulated farm with several faults on several
# turbines, every diagnostic service, the arbiter and the farm monitor (its live table on this terminal),
# and ends with a table of injected faults against detections and the arbiter's reactions.
# Usage: run_demo.sh [SCENARIO.yaml] (default deploy/scenarios/demo_farm.yaml)
# Environment: WINDFDI_DEMO_RATE (speed-up, default 8), WINDFDI_DOMAIN, WINDFDI_PARTICIPANT_PROFILE,
# WINDFDI_DEMO_HTTP (the farm monitor's web page, ADDR:PORT; default 127.0.0.1:0, any free port, whose URL
# is printed; "off": none).
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${WINDFDI_BUILD_DIR:-$top/build}
"$top/deploy/scripts/setup.sh"
scenario=${1:-$top/deploy/scenarios/demo_farm.yaml}
export WINDFDI_DOMAIN=${WINDFDI_DOMAIN:-$((100 + RANDOM % 100))}
# Loopback discovery works on any machine, with or without multicast.
export WINDFDI_PARTICIPANT_PROFILE=${WINDFDI_PARTICIPANT_PROFILE:-windfdi_participant_loopback}
work=$build/demo
rm -rf "$work"
start=$(date +%s)
WINDFDI_BUILD_DIR=$build "$top/deploy/scripts/launch_farm.sh" "$scenario" --rate "${WINDFDI_DEMO_RATE:-8}" \
  --work "$work" --record $([ "${WINDFDI_DEMO_HTTP:-}" = off ] || echo "--http ${WINDFDI_DEMO_HTTP:-127.0.0.1:0}")
echo
echo "== injected faults against detections ($(($(date +%s) - start)) s)"
"$build/bin/windfdi-farm" --db "$work/farm.sqlite" report --scenario "$scenario"
echo "== history: $build/bin/windfdi-farm --db $work/farm.sqlite history ; recording: $work/frames.csv.gz"
