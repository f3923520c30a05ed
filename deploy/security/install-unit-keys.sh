#!/usr/bin/env bash
# Hands each systemd unit of this host its own DDS-Security private key and no other (least privilege
# per service; docs/security-hardening.md, "Keys per unit"). Run as root on the plant host after copying the
# host's identity folders and the public PKI files into DIR (default /etc/causal-twin/security):
#   /usr/share/causal-twin/security/install-unit-keys.sh [DIR] [UNIT=IDENTITY ...]
#   * every DIR/*/key.pem becomes root:root 0600: no service user can open any key file;
#   * the public files (CA certificates, CRL, governance, certificates, permissions) become root:causal-twin,
#     readable by the group every unit runs in (folders 0750: nothing for other users);
#   * for each unit whose identity folder exists, a drop-in
#     /etc/systemd/system/UNIT.service.d/causal-twin-dds-key.conf with
#     LoadCredential=dds-key.pem:DIR/IDENTITY/key.pem: systemd (root) reads the key at start and gives the
#     unit a private copy in $CREDENTIALS_DIRECTORY, which the service uses instead of DIR/IDENTITY/key.pem.
#     Default identities: estimator@ estimator, recommender recommender, recorder recorder, sensor@ sensor,
#     ingest@ ingest, web operator. UNIT=IDENTITY gives one instance its own, e.g.
#     causal-twin-sensor@line1=sensor-line1 (an instance drop-in of the same file name replaces the template's).
# Not in the shipped units because a LoadCredential= whose absolute path is missing fails the unit (systemd
# 252), and a host without DDS-Security has no keys. Run it again after adding or renewing an identity.
# $CAUSAL_TWIN_SYSTEMD_DIR (default /etc/systemd/system) is where the drop-ins go (tests).
# Exit code: 0 done, 2 bad usage or DIR is not a PKI folder.
set -euo pipefail
usage() { sed -n '2,20p' "$0"; exit 2; }
dir=/etc/causal-twin/security
if [ $# -gt 0 ] && [[ "$1" != *=* ]]; then dir="$1"; shift; fi
[ -f "$dir/identity_ca.pem" ] && [ -f "$dir/governance.p7s" ] \
  || { echo "install-unit-keys: $dir is not a PKI folder (no identity_ca.pem, governance.p7s)" >&2; exit 2; }
[ "$(id -u)" = 0 ] || { echo "install-unit-keys: run as root (it changes owners)" >&2; exit 2; }
getent group causal-twin > /dev/null || { echo "install-unit-keys: no group causal-twin (is the package installed?)" >&2; exit 2; }
dir="$(cd "$dir" && pwd)"
systemd_dir="${CAUSAL_TWIN_SYSTEMD_DIR:-/etc/systemd/system}"
declare -A identity_of=([causal-twin-estimator@]=estimator [causal-twin-recommender]=recommender
  [causal-twin-recorder]=recorder [causal-twin-sensor@]=sensor [causal-twin-ingest@]=ingest [causal-twin-web]=operator)
for pair in "$@"; do
  [[ "$pair" =~ ^(causal-twin-[a-z]+@?[A-Za-z0-9._-]*)=([A-Za-z0-9._-]+)$ ]] || usage
  identity_of[${BASH_REMATCH[1]}]="${BASH_REMATCH[2]}"
done

if [ -d "$dir/private" ]; then
  echo "install-unit-keys: warning: $dir/private holds CA keys: keep them off the plant hosts (make-pki.sh on an offline machine)" >&2
fi
# Owners first, then modes: folders and public files for the group, keys for root alone. private/ (CA keys, if
# any) stays root-only.
chown -R root:causal-twin "$dir"
find "$dir" -path "$dir/private" -prune -o -type d -exec chmod 0750 {} +
find "$dir" -path "$dir/private" -prune -o -type f -exec chmod 0640 {} +
if [ -d "$dir/private" ]; then chown -R root:root "$dir/private"; chmod 0700 "$dir/private"; fi
keys=0
while IFS= read -r key; do chown root:root "$key"; chmod 0600 "$key"; keys=$((keys + 1)); done \
  < <(find "$dir" -path "$dir/private" -prune -o -type f -name key.pem -print)
echo "install-unit-keys: $keys key files root:root 0600; public files root:causal-twin 0640 in $dir"

for unit in $(printf '%s\n' "${!identity_of[@]}" | sort); do
  identity="${identity_of[$unit]}"
  dropin_dir="$systemd_dir/$unit.service.d"
  if [ -f "$dir/$identity/key.pem" ]; then
    mkdir -p "$dropin_dir"
    cat > "$dropin_dir/causal-twin-dds-key.conf" <<CONF
# Written by install-unit-keys.sh: this unit's DDS-Security private key (identity $identity), read by systemd
# and handed to the unit alone as \$CREDENTIALS_DIRECTORY/dds-key.pem (the file itself is root-only).
[Service]
LoadCredential=dds-key.pem:$dir/$identity/key.pem
CONF
    chmod 0644 "$dropin_dir/causal-twin-dds-key.conf"
    echo "install-unit-keys: $unit: identity $identity ($dropin_dir/causal-twin-dds-key.conf)"
  elif [ -f "$dropin_dir/causal-twin-dds-key.conf" ]; then
    rm -f "$dropin_dir/causal-twin-dds-key.conf"; rmdir "$dropin_dir" 2>/dev/null || true
    echo "install-unit-keys: $unit: no $dir/$identity/key.pem on this host: its key drop-in was removed"
  else
    echo "install-unit-keys: $unit: no $dir/$identity on this host (skipped)"
  fi
done
if [ -d /run/systemd/system ]; then systemctl daemon-reload; fi
echo "install-unit-keys: done; set CAUSAL_TWIN_SECURITY_DIR=$dir in /etc/causal-twin/twin.env and restart the units"
