#!/usr/bin/env bash
# Issues one DDS-Security identity from the PKI made by make-pki.sh: a key, a certificate signed by the
# identity CA and a permissions document for its role, signed (S/MIME) by the permissions CA.
#   deploy/security/issue-identity.sh DIR NAME ROLE [--days N] [--expired] [--groups G1,G2,...]
# ROLE is one of: sensor estimator recommender recorder operator (least privilege, see the roles below).
# --groups (sensor, operator): the asset groups it may write, as DDS partitions causal_twin/group/G in its grant;
# a sensor's samples of any other group are refused and counted by the estimator, an operator's what-if requests,
# alarm actions and approved interventions by alarm-recommender and sensor-sim. Without it: every group.
# Every role reads the empty partition and every group partition (readers hear group-limited writers).
# Writes DIR/NAME/{key.pem,cert.pem,permissions.xml,permissions.p7s}; copy that folder, DIR/identity_ca.pem,
# DIR/permissions_ca.pem, DIR/governance.p7s and DIR/identity_ca.crl to the host.
# --expired issues a certificate that expired in 2020 (for tests of the failure message).
# Exit code: 0 issued, 2 bad usage or the identity exists already.
set -euo pipefail
usage() { sed -n '2,13p' "$0"; exit 2; }
[ $# -ge 3 ] || usage
groups=""
dir="$1"; name="$2"; role="$3"; shift 3
days=825
expired=0
while [ $# -gt 0 ]; do
  case "$1" in
    --days) days="$2"; shift 2 ;;
    --expired) expired=1; shift ;;
    --groups) groups="$2"; shift 2 ;;
    *) usage ;;
  esac
done
[ -f "$dir/private/ca.cnf" ] || { echo "issue-identity: $dir is not a PKI made by make-pki.sh (no private/ca.cnf)" >&2; exit 2; }
case "$name" in *[!A-Za-z0-9._-]*|"") echo "issue-identity: name '$name' must be [A-Za-z0-9._-]+" >&2; exit 2 ;; esac
[ -e "$dir/$name" ] && { echo "issue-identity: $dir/$name exists already (revoke it, then use a new name)" >&2; exit 2; }

# Asset groups: names as the estimator compares them (literally; no wildcards, which would widen a grant).
if [ -n "$groups" ]; then
  case "$role" in sensor|operator) ;; *) echo "issue-identity: --groups is for the sensor and operator roles only" >&2; exit 2 ;; esac
  for g in ${groups//,/ }; do
    case "$g" in *[!A-Za-z0-9._-]*) echo "issue-identity: asset group '$g' must be [A-Za-z0-9._-]+" >&2; exit 2 ;; esac
  done
fi
# Topics each role may publish / subscribe (names from common/dds/include/causal/dds/topics.hpp).
t=causal_twin
case "$role" in
  sensor)      pub="$t/vibration_frame $t/condition_input"
               sub="$t/condition_vector $t/intervention" ;;   # progress and rewind; approved interventions (actuator)
  estimator)   pub="$t/causal_factors $t/causal_factor_sets $t/condition_vector $t/alarm"   # alarms: data quality and health
               sub="$t/vibration_frame $t/condition_input $t/condition_vector" ;;  # condition_vector: hot standby
  recommender) pub="$t/alarm $t/recommendation $t/whatif_reply $t/asset_status $t/prognosis $t/alarm_action_result $t/intervention_outcome"
               sub="$t/causal_factors $t/causal_factor_sets $t/condition_vector $t/whatif_request $t/alarm_action $t/intervention" ;;
  recorder)    pub=""
               sub="$t/condition_vector $t/causal_factors $t/causal_factor_sets $t/alarm $t/recommendation $t/asset_status $t/prognosis $t/alarm_action_result $t/intervention $t/intervention_outcome" ;;
  operator)    pub="$t/whatif_request $t/alarm_action $t/intervention"   # an approval is an operator's act
               sub="$t/condition_input $t/condition_vector $t/causal_factors $t/causal_factor_sets $t/alarm $t/recommendation $t/whatif_reply $t/asset_status $t/prognosis $t/alarm_action_result $t/intervention $t/intervention_outcome" ;;
  *) echo "issue-identity: unknown role '$role' (sensor estimator recommender recorder operator)" >&2; exit 2 ;;
esac

mkdir -p "$dir/$name"
out="$dir/$name"
openssl ecparam -name prime256v1 -genkey -noout -out "$out/key.pem" 2>/dev/null
chmod 600 "$out/key.pem"
openssl req -new -key "$out/key.pem" -subj "/O=Causal Twin/OU=$role/CN=$name" -out "$out/req.pem"
if [ "$expired" = 1 ]; then
  dates=(-startdate 20200101000000Z -enddate 20200102000000Z)
else
  dates=(-days "$days")
fi
openssl ca -batch -config "$dir/private/ca.cnf" -name identity_ca "${dates[@]}" -in "$out/req.pem" \
  -out "$out/cert.pem" -notext 2>/dev/null || { echo "issue-identity: openssl ca failed" >&2; rm -rf "$out"; exit 1; }
rm -f "$out/req.pem"

# The grant names the certificate's subject exactly as Fast DDS compares it (RFC 2253).
subject="$(openssl x509 -in "$out/cert.pem" -noout -subject -nameopt RFC2253 | sed 's/^subject=//')"
not_before="$(date -u +%Y-%m-%dT%H:%M:%S -d "$(openssl x509 -in "$out/cert.pem" -noout -startdate | cut -d= -f2)")"
not_after="$(date -u +%Y-%m-%dT%H:%M:%S -d "$(openssl x509 -in "$out/cert.pem" -noout -enddate | cut -d= -f2)")"
topics() { for x in $1; do printf '            <topic>%s</topic>\n' "$x"; done; }
# Partitions of a criteria (common/dds/include/causal/dds/group_partitions.hpp): a sensor's or an operator's
# groups when it has --groups; every role reads the empty partition (writers of every group) and every group
# partition (the writers limited to groups: sensors for the estimator and the live view, operators for
# alarm-recommender, sensor-sim's plant, the recorder and the live view). The readers check each sample's group
# against its writer's partitions (WriterGrantCheck).
partitions() {
  [ -n "$1" ] || return 0
  printf '          <partitions>\n'
  for x in $1; do
    if [ "$x" = "<empty>" ]; then printf '            <partition></partition>\n'
    else printf '            <partition>%s</partition>\n' "$x"; fi
  done
  printf '          </partitions>\n'
}
pub_partitions=""; sub_partitions=""
if [ -n "$groups" ]; then for g in ${groups//,/ }; do pub_partitions="$pub_partitions causal_twin/group/$g"; done; fi
sub_partitions="<empty> causal_twin/group/*"
{
  cat <<XML
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">
  <permissions>
    <grant name="$name">
      <subject_name>$subject</subject_name>
      <validity>
        <not_before>$not_before</not_before>
        <not_after>$not_after</not_after>
      </validity>
XML
  if [ -n "$pub" ]; then
    printf '      <allow_rule>\n        <domains><id_range><min>0</min><max>232</max></id_range></domains>\n'
    printf '        <publish>\n          <topics>\n'; topics "$pub"; printf '          </topics>\n'
    partitions "$pub_partitions"; printf '        </publish>\n      </allow_rule>\n'
  fi
  printf '      <allow_rule>\n        <domains><id_range><min>0</min><max>232</max></id_range></domains>\n'
  printf '        <subscribe>\n          <topics>\n'; topics "$sub"; printf '          </topics>\n'
  partitions "$sub_partitions"; printf '        </subscribe>\n      </allow_rule>\n'
  cat <<XML
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
XML
} > "$out/permissions.xml"
openssl smime -sign -text -in "$out/permissions.xml" -out "$out/permissions.p7s" \
  -signer "$dir/permissions_ca.pem" -inkey "$dir/private/permissions_ca.key"
echo "issue-identity: $out ($role${groups:+, asset groups $groups}, $subject, valid until $not_after UTC)"
