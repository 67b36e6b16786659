#!/usr/bin/env bash
# The test command: installs what is missing, builds, and runs every test (unit and multi-process).
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${WINDFDI_BUILD_DIR:-$top/build}
start=$(date +%s)
"$top/deploy/scripts/setup.sh"
built=$(date +%s)

# Tests must not inherit variables that silently change Fast DDS behaviour.
unset FASTRTPS_DEFAULT_PROFILES_FILE FASTDDS_ENVIRONMENT_FILE ROS_DISCOVERY_SERVER WINDFDI_QOS_FILE
rc=0
(cd "$build" && ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" --timeout 600) || rc=$?
# A crashed participant leaves shared-memory segments; remove the orphans of this run.
command -v fastdds >/dev/null && fastdds shm clean >/dev/null 2>&1 || true
end=$(date +%s)
echo "run_tests: build $((built - start)) s, tests $((end - built)) s"
exit $rc
