#!/usr/bin/env bash
# A DDS-Security PKI in one command (openssl): an identity CA, a permissions CA, the signed governance
# document and one identity per service role with least-privilege permissions.
#   deploy/security/make-pki.sh DIR [--days N] [--plant PLANT.yaml]
# DIR gets:
#   identity_ca.pem, permissions_ca.pem   the two CA certificates (public; every host needs both)
#   identity_ca.crl                       the revocation list, empty from the start (every host needs it too:
#                                         revoke-identity.sh rewrites it)
#   governance.xml / governance.p7s       domain rules, signed (S/MIME) by the permissions CA
#   sensor/ ingest/ estimator/ recommender/ recorder/ operator/   cert.pem, key.pem, permissions.p7s per identity
#                                         (ingest: sensor-ingest's own, with the sensor grants)
#   private/                              the CA keys and the issuing database: keep them OFF the plant hosts
#   sensor-<host>/                        with --plant: one per sensor host that names its asset groups, granted
#                                         only those (causal-plant-profiles --identities; $CAUSAL_PLANT_PROFILES)
# Services take it with --security DIR (each picks its own identity folder). ECDSA P-256 keys, SHA-256.
# Exit code: 0 made, 2 bad usage, DIR not empty or an invalid plant file.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
[ $# -ge 1 ] || { sed -n '2,16p' "$0"; exit 2; }
dir="$1"; shift
days=825
plant=""
while [ $# -gt 0 ]; do
  case "$1" in
    --days) days="$2"; shift 2 ;;
    --plant) plant="$2"; shift 2 ;;
    *) sed -n '2,16p' "$0"; exit 2 ;;
  esac
done
command -v openssl >/dev/null || { echo "make-pki: openssl is not installed (deploy/install_deps.sh)" >&2; exit 2; }
identities=""
if [ -n "$plant" ]; then
  # The plant file's sensor hosts and their asset groups, validated by the tool that reads the plant file.
  tool="${CAUSAL_PLANT_PROFILES:-causal-plant-profiles}"
  command -v "$tool" >/dev/null || { echo "make-pki: --plant needs causal-plant-profiles ($tool not found; set \$CAUSAL_PLANT_PROFILES)" >&2; exit 2; }
  identities="$("$tool" "$plant" --identities)" || { echo "make-pki: $plant: invalid plant file (see above)" >&2; exit 2; }
fi
mkdir -p "$dir"
[ -z "$(ls -A "$dir")" ] || { echo "make-pki: $dir is not empty" >&2; exit 2; }
dir="$(cd "$dir" && pwd)"
mkdir -p "$dir/private/issued"
chmod 700 "$dir/private"
: > "$dir/private/index.txt"
echo 1000 > "$dir/private/serial"
echo 1000 > "$dir/private/crlnumber"
cat > "$dir/private/ca.cnf" <<CNF
# openssl ca configuration of the identity CA (used by issue-identity.sh and revoke-identity.sh).
[ identity_ca ]
database        = $dir/private/index.txt
new_certs_dir   = $dir/private/issued
certificate     = $dir/identity_ca.pem
private_key     = $dir/private/identity_ca.key
serial          = $dir/private/serial
crlnumber       = $dir/private/crlnumber
default_md      = sha256
default_crl_days = 3650
policy          = policy_any
unique_subject  = no
x509_extensions = identity_ext
[ policy_any ]
organizationName       = optional
organizationalUnitName = optional
commonName             = supplied
[ identity_ext ]
basicConstraints = critical, CA:FALSE
keyUsage         = critical, digitalSignature, keyAgreement
[ ca_ext ]
basicConstraints     = critical, CA:TRUE
keyUsage             = critical, keyCertSign, cRLSign, digitalSignature
subjectKeyIdentifier = hash
CNF

make_ca() {  # name, common name
  openssl ecparam -name prime256v1 -genkey -noout -out "$dir/private/$1.key" 2>/dev/null
  chmod 600 "$dir/private/$1.key"
  openssl req -x509 -new -key "$dir/private/$1.key" -sha256 -days 3650 -subj "/O=Causal Twin/CN=$2" \
    -config "$dir/private/ca.cnf" -extensions ca_ext -out "$dir/$1.pem"
}
make_ca identity_ca "Causal Twin Identity CA"
make_ca permissions_ca "Causal Twin Permissions CA"
# An empty revocation list from the start: every host gets the file now, so a revocation later only replaces
# it (deploy/security/revoke-identity.sh) and the services watching it pick it up.
openssl ca -batch -config "$dir/private/ca.cnf" -name identity_ca -gencrl -crldays 3650 -out "$dir/identity_ca.crl" 2>/dev/null

# Governance: only authenticated participants join (join access control), discovery and liveliness
# encrypted, and on every causal_twin topic read/write access control with the payload encrypted (AES-GCM)
# and every submessage of its endpoints (data, heartbeats, acknowledgements) signed with the endpoint's key.
# No whole-message (rtps) protection: Debian's Fast DDS 2.9 then aborts now and then (assertion in
# add_statistics_submessage: the encoded message leaves no room for the statistics submessage; seen in 1 of
# 4 secured launch.sh runs); the submessage protection above already covers every byte a writer sends.
cat > "$dir/governance.xml" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>0</min><max>232</max></id_range></domains>
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>NONE</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>causal_twin/*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>SIGN</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
XML
openssl smime -sign -text -in "$dir/governance.xml" -out "$dir/governance.p7s" \
  -signer "$dir/permissions_ca.pem" -inkey "$dir/private/permissions_ca.key"

for role in sensor estimator recommender recorder operator; do
  "$here/issue-identity.sh" "$dir" "$role" "$role" --days "$days"
done
# sensor-ingest's own identity (sensor grants), so the edge adapter never shares a key with replays.
"$here/issue-identity.sh" "$dir" ingest sensor --days "$days"
# Sensor hosts of the plant file that name their asset groups: an identity granted only those.
while read -r name role groups; do
  [ -n "$name" ] && "$here/issue-identity.sh" "$dir" "$name" "$role" --days "$days" --groups "$groups"
done <<< "$identities"
echo "make-pki: PKI in $dir (CA keys in $dir/private: keep them off the plant hosts)"
case "$dir/" in
  /etc/causal-twin/*|/var/lib/causal-twin/*)
    echo "make-pki: warning: $dir/private is inside a folder 'apt-get purge causal-twin' removes (the package's" \
         "postrm keeps a copy in /root); move the CA keys to an offline place" >&2 ;;
esac
