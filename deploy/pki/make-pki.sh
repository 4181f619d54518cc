#!/usr/bin/env bash
# Creates a test PKI for the secure DDS profile (deploy/dds/secure.xml):
#   OUT/ca.pem, OUT/ca.key           one CA that signs the identities and the documents
#   OUT/governance.xml, .p7s         domain rules: authenticated participants only, every topic
#                                    access-controlled, payload and discovery encrypted
#   OUT/<role>/cert.pem, key.pem     one identity per role (EC P-256), signed by the CA
#   OUT/<role>/permissions.xml, .p7s what the role may publish and subscribe, signed by the CA
# Roles: server, camera, segmenter, query (topics of docs/architecture.md):
#   camera    publishes rt/semfuse/frames only (reads status to find the server)
#   segmenter reads frames, publishes rt/semfuse/segmentations
#   query     calls services only (rq/semfuse/*Request out, rr/semfuse/*Reply in), reads
#             status, legend, poses, the live mesh, occupancy and object events
#   server    the reverse of all of the above
# Everything else is denied. A test PKI: the CA key lies next to the certificates; for a real
# deployment keep it offline and copy to each host only its own role's directory plus ca.pem
# and governance.p7s.
#   deploy/pki/make-pki.sh OUT [--days N] [--org NAME]
set -euo pipefail
usage() { sed -n '2,17p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; }

out=""
days=365
org="semfuse test PKI"
while [[ $# -gt 0 ]]; do
  case "$1" in
    --days) days="$2"; shift 2 ;;
    --org) org="$2"; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    -*) echo "make-pki: unknown option $1" >&2; usage >&2; exit 2 ;;
    *) [[ -z "$out" ]] || { echo "make-pki: one output directory only" >&2; exit 2; }; out="$1"; shift ;;
  esac
done
[[ -n "$out" ]] || { usage >&2; exit 2; }
[[ "$days" =~ ^[1-9][0-9]*$ ]] || { echo "make-pki: --days takes a positive number" >&2; exit 2; }
[[ "$org" =~ ^[A-Za-z0-9\ ._-]+$ ]] || { echo "make-pki: --org: letters, digits, space, . _ - only" >&2; exit 2; }
command -v openssl >/dev/null || { echo "make-pki: openssl not found (apt-get install openssl)" >&2; exit 1; }

mkdir -p "$out"
out="$(cd "$out" && pwd)"
umask 077
roles=(server camera segmenter query)
# ISO 8601 validity of the permission grants, the same span as the certificates.
not_before="$(date -u -d '-1 day' +%Y-%m-%dT%H:%M:%S)"
not_after="$(date -u -d "+$days days" +%Y-%m-%dT%H:%M:%S)"

# --- CA -----------------------------------------------------------------------------------
openssl ecparam -name prime256v1 -genkey -noout -out "$out/ca.key"
openssl req -x509 -new -key "$out/ca.key" -sha256 -days "$days" -subj "/O=$org/CN=semfuse CA" \
  -addext "basicConstraints=critical,CA:TRUE" -addext "keyUsage=critical,keyCertSign,cRLSign,digitalSignature" \
  -out "$out/ca.pem" 2>/dev/null

sign() {  # S/MIME signature with the CA, the form DDS Security's builtin plugins read
  openssl smime -sign -in "$1" -text -out "$2" -signer "$out/ca.pem" -inkey "$out/ca.key"
}

# --- governance ---------------------------------------------------------------------------
# Payloads are encrypted per topic; rtps_protection (encrypting whole RTPS messages) on top
# would encrypt every frame twice. (No XML comments inside: Cyclone's parser rejects them.)
cat >"$out/governance.xml" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>0</min><max>230</max></id_range></domains>
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

# --- identities and permissions --------------------------------------------------------------
topics_xml() { for t in "$@"; do printf '<topic>%s</topic>' "$t"; done; }
publishes() {
  case "$1" in
    server) topics_xml rt/semfuse/status rt/semfuse/labels rt/semfuse/poses 'rt/semfuse/map_*' rt/semfuse/occupancy \
      rt/semfuse/object_events 'rr/semfuse/*Reply' ;;
    camera) topics_xml rt/semfuse/frames ;;
    segmenter) topics_xml rt/semfuse/segmentations ;;
    query) topics_xml 'rq/semfuse/*Request' ;;
  esac
}
subscribes() {
  case "$1" in
    server) topics_xml rt/semfuse/frames rt/semfuse/segmentations 'rq/semfuse/*Request' ;;
    camera) topics_xml rt/semfuse/status ;;
    segmenter) topics_xml rt/semfuse/frames ;;
    query) topics_xml 'rr/semfuse/*Reply' rt/semfuse/status rt/semfuse/labels rt/semfuse/poses 'rt/semfuse/map_*' \
      rt/semfuse/occupancy rt/semfuse/object_events ;;
  esac
}

serial=1
for role in "${roles[@]}"; do
  dir="$out/$role"
  mkdir -p "$dir"
  subject="/O=$org/CN=semfuse $role"
  openssl ecparam -name prime256v1 -genkey -noout -out "$dir/key.pem"
  openssl req -new -key "$dir/key.pem" -subj "$subject" -out "$dir/cert.csr"
  serial=$((serial + 1))
  openssl x509 -req -in "$dir/cert.csr" -CA "$out/ca.pem" -CAkey "$out/ca.key" -set_serial "$serial" \
    -days "$days" -sha256 -out "$dir/cert.pem" 2>/dev/null
  rm -f "$dir/cert.csr"
  cat >"$dir/permissions.xml" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">
  <permissions>
    <grant name="semfuse_$role">
      <subject_name>CN=semfuse $role,O=$org</subject_name>
      <validity><not_before>$not_before</not_before><not_after>$not_after</not_after></validity>
      <allow_rule>
        <domains><id_range><min>0</min><max>230</max></id_range></domains>
        <publish><topics>$(publishes "$role")</topics></publish>
        <subscribe><topics>$(subscribes "$role")</topics></subscribe>
      </allow_rule>
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
XML
  sign "$dir/permissions.xml" "$dir/permissions.p7s"
done
# Certificates and signed documents are public; keys stay private (umask 077 above).
chmod 644 "$out/ca.pem" "$out/governance.xml" "$out/governance.p7s"
for role in "${roles[@]}"; do chmod 755 "$out/$role"; chmod 644 "$out/$role"/{cert.pem,permissions.xml,permissions.p7s}; done
chmod 755 "$out"
echo "make-pki: CA, governance and identities for ${roles[*]} in $out (valid $days days)"
