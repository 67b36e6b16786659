#!/usr/bin/env bash
# Starts every windfdi service of one turbine (filtered to its id) and waits; Ctrl-C stops them all.
# Usage: launch_turbine.sh TURBINE_ID [--domain N] [--arbiter-strength S] [--security DIR]
# --security DIR: every service with its role's DDS-Security credentials (deploy/security/make_credentials.sh).
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
bin=${WINDFDI_BIN:-$top/build/bin}
turbine=${1:?usage: launch_turbine.sh TURBINE_ID [--domain N] [--arbiter-strength S] [--security DIR]}
shift
domain=${WINDFDI_DOMAIN:-0}
strength=100
security=()
while [ $# -gt 0 ]; do
  case $1 in
    --domain) domain=$2; shift 2 ;;
    --arbiter-strength) strength=$2; shift 2 ;;
    --security) security=(--security "$2"); shift 2 ;;
    *) echo "launch_turbine: unknown option $1" >&2; exit 2 ;;
  esac
done
export WINDFDI_DOMAIN=$domain
logs=${WINDFDI_LOG_DIR:-$top/build/logs/$turbine}
mkdir -p "$logs"
pids=()
stop() { kill -TERM "${pids[@]}" 2>/dev/null || true; wait 2>/dev/null || true; }
trap stop EXIT INT TERM
# Every diagnostic service of the registry (services/services.list); a listed one not built is an error.
for service in $(awk '!/^[[:space:]]*(#|$)/ {gsub("_", "-", $1); print $1}' "$top/services/services.list"); do
  exe="$bin/windfdi-$service"
  if [ ! -x "$exe" ]; then echo "launch_turbine: $exe not built (build first: deploy/scripts/setup.sh)" >&2; exit 1; fi
  cfg="$top/deploy/config/${service//-/_}.yaml"
  args=(--turbine "$turbine" "${security[@]}")
  [ -f "$cfg" ] && args+=(--config "$cfg")
  "$exe" "${args[@]}" >"$logs/$service.log" 2>&1 &
  pids+=($!)
done
"$bin/windfdi-arbiter" --turbine "$turbine" --strength "$strength" --arbiter-id "arbiter-$turbine" \
  --config "$top/deploy/config/arbiter.yaml" "${security[@]}" >"$logs/arbiter.log" 2>&1 &
pids+=($!)
echo "launch_turbine: $turbine on domain $domain: ${#pids[@]} processes, logs in $logs"
wait
