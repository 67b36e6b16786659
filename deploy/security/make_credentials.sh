#!/usr/bin/env bash
# Creates the DDS-Security credentials of a wind farm (OMG DDS-Security 1.1 builtin plugins of Fast DDS 2.9:
# PKI-DH authentication, Access-Permissions, AES-GCM-GMAC), see README.md "Security".
#
# Usage: make_credentials.sh OUT_DIR [options]
#   --days N          validity of the identity certificates and permissions (default 365)
#   --ca-days N       validity of the farm CA (default 3650)
#   --domains A-B     DDS domain ids the governance and permissions cover (default 0-232)
#   --expired ROLE    also write OUT_DIR/ROLE_expired/: ROLE's credentials with a certificate that expired in 2020
#   --bench           also write the 'bench' role (publishes and subscribes bench/* only; for tests/perf)
#   --force           overwrite an existing OUT_DIR/ca.pem (otherwise refuse: the farm CA is not replaced by accident)
#
# Writes (keys 0600, everything else 0644):
#   OUT_DIR/ca.pem, ca_key.pem            farm CA (identity CA and permissions CA); keep ca_key.pem offline
#   OUT_DIR/governance.xml, governance.p7s   domain rules, S/MIME-signed by the CA
#   OUT_DIR/<role>/cert.pem, key.pem      identity certificate (CN=windfdi-<role>) and its ECDSA P-256 key
#   OUT_DIR/<role>/permissions.xml, permissions.p7s   the role's grant, S/MIME-signed by the CA
# Roles: plant, each diagnostic service of services/services.list, arbiter, farm
# A second run into another directory makes an unrelated ("foreign") farm: its credentials are refused here.
set -euo pipefail

usage() { sed -n '2,23p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
[ $# -ge 1 ] || usage
out=$1; shift
days=365; ca_days=3650; dmin=0; dmax=232; expired=(); bench=0; force=0
while [ $# -gt 0 ]; do
  case $1 in
    --days) days=$2; shift 2 ;;
    --ca-days) ca_days=$2; shift 2 ;;
    --domains) dmin=${2%-*}; dmax=${2#*-}; shift 2 ;;
    --expired) expired+=("$2"); shift 2 ;;
    --bench) bench=1; shift ;;
    --force) force=1; shift ;;
    -h|--help) usage ;;
    *) echo "make_credentials: unknown option $1" >&2; exit 2 ;;
  esac
done
command -v openssl >/dev/null || { echo "make_credentials: openssl not found (apt-get install openssl)" >&2; exit 1; }
if [ -e "$out/ca.pem" ] && [ $force = 0 ]; then
  echo "make_credentials: $out/ca.pem exists; use --force to replace the farm CA and every credential" >&2; exit 2
fi
mkdir -p "$out"
out=$(cd "$out" && pwd)
umask 022
org="O=windfdi,OU=$(basename "$out")"

# ---- farm certificate authority (self-signed, ECDSA P-256) ----
openssl ecparam -name prime256v1 -genkey -noout -out "$out/ca_key.pem" 2>/dev/null
chmod 600 "$out/ca_key.pem"
openssl req -new -x509 -sha256 -key "$out/ca_key.pem" -out "$out/ca.pem" -days "$ca_days" \
  -subj "/CN=windfdi farm CA/$(echo "$org" | tr ',' '/')" \
  -addext "basicConstraints=critical,CA:TRUE" -addext "keyUsage=critical,keyCertSign,cRLSign,digitalSignature" 2>/dev/null

sign() {  # sign XML_FILE P7S_FILE: S/MIME (text) signature by the farm CA, as Fast DDS verifies it
  openssl smime -sign -text -in "$1" -out "$2" -signer "$out/ca.pem" -inkey "$out/ca_key.pem"
}

# ---- governance: discovery and liveliness encrypted, every topic access-controlled and encrypted ----
cat > "$out/governance.xml" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>$dmin</min><max>$dmax</max></id_range></domains>
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>NONE</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>ENCRYPT</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
XML
sign "$out/governance.xml" "$out/governance.p7s"

# ---- roles: what each may publish and subscribe (topic expressions are fnmatch patterns) ----
# The diagnostic services and their estimate topics: the registry (source tree or installed beside this script).
here=$(cd "$(dirname "$0")" && pwd)
registry=""
for f in "$here/../../services/services.list" "$here/../services.list"; do
  [ -f "$f" ] && { registry=$f; break; }
done
[ -n "$registry" ] || { echo "make_credentials: services.list not found beside $here" >&2; exit 2; }
declare -A PUB SUB
PUB[plant]="wt/frame wt/lidar wt/health"
SUB[plant]="wt/control/config wt/estimate/sensor_bias"
services=()
while read -r svc topic _; do
  case $svc in '' | '#'*) continue ;; esac
  [ -n "$topic" ] || { echo "make_credentials: $registry: no estimate topic for $svc" >&2; exit 2; }
  services+=("$svc")
  PUB[$svc]="$topic wt/fault wt/health"
  SUB[$svc]="wt/frame wt/lidar wt/control/config wt/fault"
done <"$registry"
PUB[arbiter]="wt/control/config wt/health"
SUB[arbiter]="wt/fault wt/health wt/estimate/* wt/fault_ack wt/control/config"
PUB[farm]="wt/fault_ack wt/health"
SUB[farm]="wt/*"
roles=(plant "${services[@]}" arbiter farm)
if [ $bench = 1 ]; then PUB[bench]="bench/*"; SUB[bench]="bench/*"; roles+=(bench); fi

# A day of slack for clocks of other hosts that run behind.
not_before=$(date -u -d "-1 day" +%Y-%m-%dT%H:%M:%S)
not_after=$(date -u -d "+$days days" +%Y-%m-%dT%H:%M:%S)

topics_xml() { for t in $1; do printf '            <topic>%s</topic>\n' "$t"; done; }

# make_role DIR ROLE [START END]: key, certificate (openssl ca with explicit dates when START/END are given),
# permissions granting ROLE's topics to exactly that certificate's subject.
make_role() {
  local dir=$1 role=$2 start=${3:-} end=${4:-}
  mkdir -p "$dir"
  openssl ecparam -name prime256v1 -genkey -noout -out "$dir/key.pem" 2>/dev/null
  chmod 600 "$dir/key.pem"
  local subj="/CN=windfdi-$role/$(echo "$org" | tr ',' '/')"
  openssl req -new -sha256 -key "$dir/key.pem" -subj "$subj" -out "$dir/cert.csr" 2>/dev/null
  if [ -z "$start" ]; then
    openssl x509 -req -sha256 -in "$dir/cert.csr" -CA "$out/ca.pem" -CAkey "$out/ca_key.pem" \
      -set_serial "0x$(openssl rand -hex 8)" -days "$days" -out "$dir/cert.pem" 2>/dev/null
  else
    # openssl 3.0's x509 has no -not_before: a throw-away 'openssl ca' database gives a certificate in the past.
    local db; db=$(mktemp -d)
    : > "$db/index.txt"
    printf '[ca]\ndefault_ca=c\n[c]\ndatabase=%s/index.txt\nnew_certs_dir=%s\nserial=%s/serial\ndefault_md=sha256\npolicy=p\nunique_subject=no\n[p]\ncommonName=supplied\norganizationName=optional\norganizationalUnitName=optional\n' \
      "$db" "$db" "$db" > "$db/ca.cnf"
    openssl rand -hex 8 > "$db/serial"
    openssl ca -batch -config "$db/ca.cnf" -cert "$out/ca.pem" -keyfile "$out/ca_key.pem" -in "$dir/cert.csr" \
      -out "$dir/cert.pem" -startdate "$start" -enddate "$end" -notext 2>/dev/null
    rm -rf "$db"
  fi
  rm -f "$dir/cert.csr"
  local subject; subject=$(openssl x509 -in "$dir/cert.pem" -noout -subject -nameopt RFC2253 | sed 's/^subject=//')
  {
    cat <<XML
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">
  <permissions>
    <grant name="windfdi_${role}">
      <subject_name>$subject</subject_name>
      <validity>
        <not_before>$not_before</not_before>
        <not_after>$not_after</not_after>
      </validity>
      <allow_rule>
        <domains><id_range><min>$dmin</min><max>$dmax</max></id_range></domains>
XML
    if [ -n "${PUB[$role]:-}" ]; then
      printf '        <publish>\n          <topics>\n'; topics_xml "${PUB[$role]}"; printf '          </topics>\n        </publish>\n'
    fi
    if [ -n "${SUB[$role]:-}" ]; then
      printf '        <subscribe>\n          <topics>\n'; topics_xml "${SUB[$role]}"; printf '          </topics>\n        </subscribe>\n'
    fi
    cat <<XML
      </allow_rule>
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
XML
  } > "$dir/permissions.xml"
  sign "$dir/permissions.xml" "$dir/permissions.p7s"
}

for role in "${roles[@]}"; do make_role "$out/$role" "$role"; done
for role in "${expired[@]}"; do
  [ -n "${PUB[$role]:-}${SUB[$role]:-}" ] || { echo "make_credentials: --expired: unknown role $role" >&2; exit 2; }
  make_role "$out/${role}_expired" "$role" 20200101000000Z 20200102000000Z
done
echo "make_credentials: farm CA and ${#roles[@]} roles in $out (certificates valid $days days)"
