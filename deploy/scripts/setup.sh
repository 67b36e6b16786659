#!/usr/bin/env bash
# Installs windfdi's Debian 12 dependencies (when missing) and builds it into ./build (or $WINDFDI_BUILD_DIR).
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${WINDFDI_BUILD_DIR:-$top/build}

# Every dependency is a Debian package; nothing is downloaded at build time.
packages=(
  build-essential cmake pkg-config
  libfastrtps-dev libfastcdr-dev fastddsgen fastdds-tools
  libeigen3-dev libspdlog-dev googletest libgtest-dev libyaml-cpp-dev libcli11-dev nlohmann-json3-dev
  libsqlite3-dev sqlite3 libsdp-dev liblapack-dev libblas-dev libbenchmark-dev zlib1g-dev libssl-dev libtinyxml2-dev
  libcpp-httplib-dev libjs-dygraphs chromium-headless-shell
  openssl iproute2 procps python3 clang-format
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=""
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

jobs=$(nproc 2>/dev/null || echo 2)
# Warnings as errors only when asked (the test command asks): passing OFF on every other call would change the
# compile flags of a build directory the tests had built, and the next demo would rebuild everything.
cmake -S "$top" -B "$build" -DCMAKE_BUILD_TYPE="${WINDFDI_BUILD_TYPE:-Release}" \
  ${WINDFDI_WARNINGS_AS_ERRORS:+-DWINDFDI_WARNINGS_AS_ERRORS="$WINDFDI_WARNINGS_AS_ERRORS"} >/dev/null
start=$(date +%s)
if ! cmake --build "$build" -j "$jobs" >"$build/build.log" 2>&1; then
  tail -60 "$build/build.log"
  echo "setup: build failed (full log: $build/build.log)" >&2
  exit 1
fi
grep -E "warning:" "$build/build.log" | head -20 || true
echo "setup: built into $build in $(($(date +%s) - start)) s"
