#!/usr/bin/env bash
# Revokes an identity issued from this PKI: the identity CA lists its certificate in DIR/identity_ca.crl.
#   deploy/security/revoke-identity.sh DIR NAME
# Copy DIR/identity_ca.crl next to identity_ca.pem on every host and restart the services there: a service
# refuses to start with a revoked certificate, and its peers reject a participant that presents one.
set -euo pipefail
[ $# -eq 2 ] || { sed -n '2,5p' "$0"; exit 2; }
dir="$1"; name="$2"
[ -f "$dir/$name/cert.pem" ] || { echo "revoke-identity: no certificate $dir/$name/cert.pem" >&2; exit 2; }
openssl ca -batch -config "$dir/private/ca.cnf" -name identity_ca -revoke "$dir/$name/cert.pem" 2>/dev/null
openssl ca -batch -config "$dir/private/ca.cnf" -name identity_ca -gencrl -crldays 3650 -out "$dir/identity_ca.crl" 2>/dev/null
echo "revoke-identity: $name revoked; distribute $dir/identity_ca.crl"
