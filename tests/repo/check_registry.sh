#!/usr/bin/env bash
# A new diagnostic service is its folder and one line in services/services.list: in a scratch copy of the
# repository, a toy service added that way is configured as a build target, its estimate IDL builds into a type
# with its registry topic, it is named in the generated service list every module reads (service_lost,
# security roles), gets a systemd unit wanted by the turbine's target, a security role with its estimate topic,
# and is started by the launch scripts' registry read.
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
scratch=$(mktemp -d /tmp/windfdi-registry.XXXXXX)
trap 'rm -rf "$scratch"' EXIT
cd "$top"
if git rev-parse --git-dir >/dev/null 2>&1; then
  git ls-files -z | xargs -0 -I{} cp --parents {} "$scratch/"
else
  tar --exclude=./build -cf - . | tar -C "$scratch" -xf -
fi
cd "$scratch"

# GIVEN a toy service: its folder (core, spec and main in one file, its estimate type) and one registry line
mkdir -p services/toy_check
cat > services/toy_check/CMakeLists.txt <<'CMAKE'
add_executable(windfdi-toy-check main.cpp)
target_link_libraries(windfdi-toy-check PRIVATE windfdi_common)
CMAKE
cat > services/toy_check/main.cpp <<'CPP'
#include "diagnostic_service.hpp"
int main(int argc, char** argv) { return windfdi::run_diagnostic_service(argc, argv, windfdi::ServiceSpec{}); }
CPP
cat > services/toy_check/ToyCheckEstimate.idl <<'IDL'
module windfdi {
  struct ToyCheckEstimate {
    double t;
    @key string turbine_id;
    double level;
  };
};
IDL
echo "toy_check     wt/estimate/toy_check     estimate_best_effort" >> services/services.list

# WHEN the build is configured
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >build.log 2>&1 || { tail -30 build.log; exit 1; }

fail=0
check() { if ! eval "$2"; then echo "check_registry: FAILED: $1" >&2; fail=1; fi; }
# THEN it is a build target, a service every module knows, and wanted by the turbine target
cmake --build build --target help >targets.txt
check "windfdi-toy-check is a build target" "grep -q 'windfdi-toy-check' targets.txt"
check "the generated service names hold toy_check" \
  "grep -q '\"toy_check\"' build/generated/windfdi_services.hpp"
check "the turbine target wants windfdi-toy-check@%i.service" \
  "grep -q 'windfdi-toy-check@%i.service' 'build/generated/systemd/windfdi-turbine@.target'"
check "the toy service has a systemd unit that starts it with its configuration" \
  "grep -q 'ExecStart=/usr/bin/windfdi-toy-check --turbine %i --config /etc/windfdi/config/toy_check.yaml' \
     'build/generated/systemd/windfdi-toy-check@.service'"
# AND its estimate type builds, with the topic and QoS profile of its registry line
cmake --build build --target windfdi_toy_check_estimate >>build.log 2>&1 || { tail -30 build.log; exit 1; }
trait=build/generated/estimates/toy_check/toy_check_estimate_topic.hpp
check "the toy estimate's topic trait names its type, registry topic and QoS profile" \
  "grep -q 'TopicTraits<windfdi::ToyCheckEstimate>' $trait && grep -q 'name = \"wt/estimate/toy_check\"' $trait &&
   grep -q 'profile = \"estimate_best_effort\"' $trait"
# AND it gets a security role that may publish its estimate topic
deploy/security/make_credentials.sh creds >creds.log 2>&1 || { cat creds.log; exit 1; }
check "make_credentials writes the toy_check role" "[ -f creds/toy_check/permissions.xml ]"
check "the toy_check role publishes its estimate topic" \
  "grep -q 'wt/estimate/toy_check' creds/toy_check/permissions.xml"
# AND the launch scripts' reading of the registry names it
check "launch scripts read toy-check from the registry" \
  "awk '!/^[[:space:]]*(#|\$)/ {gsub(\"_\", \"-\", \$1); print \$1}' services/services.list | grep -qx toy-check"
# AND a listed service without its folder stops the configuration with a message naming it
echo "no_such_service   wt/estimate/none   estimate_best_effort" >> services/services.list
if cmake -S . -B build2 >build2.log 2>&1; then
  echo "check_registry: FAILED: a listed service without a folder was accepted" >&2
  fail=1
else
  check "the error names the missing service" "grep -q no_such_service build2.log"
fi
# AND a line without its estimate topic and QoS profile is refused with a message naming it
sed -i '$d' services/services.list
echo "toy_two   wt/estimate/toy_two" >> services/services.list
mkdir -p services/toy_two && cp services/toy_check/CMakeLists.txt services/toy_two/
if cmake -S . -B build3 >build3.log 2>&1; then
  echo "check_registry: FAILED: a registry line without a QoS profile was accepted" >&2
  fail=1
else
  check "the error names the incomplete line" "grep -q 'toy_two' build3.log"
fi
[ $fail = 0 ] && echo "check_registry: a toy service registered in one line (its folder and one registry line)"
exit $fail
