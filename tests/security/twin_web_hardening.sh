#!/usr/bin/env bash
# twin-web's edges, with real HTTP requests (curl) against the running service.
#  * every response carries Content-Security-Policy (frame-ancestors 'none') and X-Frame-Options DENY;
#  * a request under a foreign Host name (DNS rebinding) is refused (421), reads included;
#  * a what-if POST with a foreign Origin, with Sec-Fetch-Site cross-site, without or with a wrong CSRF token
#    is refused (403); the same-origin POST with the page's token passes (504: no alarm-recommender answers
#    on this private domain, which shows the question went out), an over-long asset group is refused (400);
#  * a compressed body (gzip) is refused unread (415), a body over 64 KiB too (413), twin-web's peak RSS stays
#    under 100 MB;
#  * the refusals are counted exactly (causal_twin_web_requests_refused_total per reason on /metrics);
#  * with --tls-cert/--tls-key (a certificate openssl makes here) and --basic-auth-file, plain HTTP gets no
#    page, HTTPS without or with wrong credentials gets 401, with the right ones 200.
# Loopback only; every process is ended by its pid.
#   twin_web_hardening.sh BUILD_DIR
set -euo pipefail
build="$1"
web="$build/services/twin_web/twin-web"
domain=$((100 + $$ % 100))
work="$(mktemp -d /tmp/causal_web_hardening_XXXXXX)"
# pids, cleanup on exit, check NAME EXPECTED GOT
. "$(dirname "$0")/../support/script_checks.sh"
free_port() {
  local p=$((20000 + RANDOM % 30000))
  while ss -ltnH "sport = :$p" | grep -q .; do p=$((p + 1)); done
  echo "$p"
}
wait_up() {  # wait_up URL [curl args]
  local url="$1"; shift
  for _ in $(seq 1 100); do
    if curl -s -o /dev/null "$@" "$url"; then return 0; fi
    sleep 0.1
  done
  echo "FAIL: $url never answered"; exit 1
}

port=$(free_port); mport=$(free_port)
"$web" --domain "$domain" --port "$port" --metrics-port "$mport" --whatif-timeout 1 --idle-exit 0 \
  --max-runtime 60 > "$work/web.log" 2>&1 &
pids+=($!)
base="http://127.0.0.1:$port"
wait_up "$base/"

curl -s -D "$work/headers" -o "$work/page.html" "$base/"
check "CSP frame-ancestors" 1 "$(grep -ci "^content-security-policy:.*frame-ancestors 'none'" "$work/headers")"
check "CSP script-src self" 1 "$(grep -ci "^content-security-policy:.*script-src 'self';" "$work/headers")"
check "X-Frame-Options" 1 "$(grep -ci '^x-frame-options: DENY' "$work/headers")"
token=$(sed -n 's/.*name="twin-csrf" content="\([0-9a-f]*\)".*/\1/p' "$work/page.html")
check "CSRF token in the page (32 hex digits)" 32 "${#token}"

status() { curl -s -o "$work/body" -w '%{http_code}' "$@"; }
question='{"asset_group":"g1","channel":1,"percent":-10}'
post=(-X POST -H 'Content-Type: application/json' --data "$question")
check "GET under a rebinding Host" 421 "$(status -H 'Host: attacker.example' "$base/api/state")"
check "cross-origin POST (Origin attacker)" 403 \
  "$(status "${post[@]}" -H 'Origin: http://attacker.example' -H "X-Twin-CSRF: $token" "$base/api/whatif")"
check "cross-site POST (Sec-Fetch-Site)" 403 \
  "$(status "${post[@]}" -H 'Sec-Fetch-Site: cross-site' -H "X-Twin-CSRF: $token" "$base/api/whatif")"
check "same-origin POST without token" 403 \
  "$(status "${post[@]}" -H "Origin: $base" "$base/api/whatif")"
check "same-origin POST with a wrong token" 403 \
  "$(status "${post[@]}" -H "Origin: $base" -H "X-Twin-CSRF: 0123456789abcdef0123456789abcdef" "$base/api/whatif")"
check "same-origin POST with the token (no recommender: 504)" 504 \
  "$(status "${post[@]}" -H "Origin: $base" -H "X-Twin-CSRF: $token" "$base/api/whatif")"
check "  ... answered 'no reply'" 1 "$(grep -c 'no reply within' "$work/body")"
long=$(printf 'g%.0s' $(seq 1 300))
check "same-origin POST, asset group of 300 bytes" 400 \
  "$(status -X POST -H 'Content-Type: application/json' --data "{\"asset_group\":\"$long\",\"channel\":1,\"percent\":-10}" \
     -H "Origin: $base" -H "X-Twin-CSRF: $token" "$base/api/whatif")"
# Bodies: a compressed one is refused before it is read (a 408 kB gzip POST used to inflate to 1.33 GB), as is
# one announced longer than 64 KiB; the page's POSTs are neither.
head -c 50000000 /dev/zero | tr '\0' ' ' | sed 's/^/{"asset_group":"g1","channel":1,"percent":-10,"pad":"/; s/$/"}/' \
  | gzip -9 > "$work/bomb.gz"
check "gzip POST (50 MB inflated) refused unread" 415 \
  "$(status -X POST -H 'Content-Type: application/json' -H 'Content-Encoding: gzip' --data-binary "@$work/bomb.gz" \
     -H "Origin: $base" -H "X-Twin-CSRF: $token" "$base/api/whatif")"
head -c 70000 /dev/zero | tr '\0' ' ' > "$work/big"
check "POST of 70,000 bytes" 413 \
  "$(status -X POST -H 'Content-Type: application/json' --data-binary "@$work/big" \
     -H "Origin: $base" -H "X-Twin-CSRF: $token" "$base/api/whatif")"
rss_kb=$(awk '/VmHWM/ {print $2}' "/proc/${pids[0]}/status")
check "twin-web peak RSS under 100 MB after the bodies" 1 "$([ "$rss_kb" -lt 102400 ] && echo 1 || echo "$rss_kb kB")"
metrics=$(curl -s "http://127.0.0.1:$mport/metrics")
count() { echo "$metrics" | sed -n "s/^causal_twin_web_requests_refused_total{reason=\"$1\"} \([0-9]*\).*/\1/p"; }
check "refusals counted: host_not_allowed" 1 "$(count host_not_allowed)"
check "refusals counted: cross_origin" 2 "$(count cross_origin)"
check "refusals counted: csrf_token" 2 "$(count csrf_token)"
check "refusals counted: compressed_body" 1 "$(count compressed_body)"
check "refusals counted: body_too_large" 1 "$(count body_too_large)"

# TLS and basic authentication.
openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:P-256 -nodes -days 1 -subj "/CN=localhost" \
  -addext "subjectAltName=DNS:localhost" \
  -keyout "$work/key.pem" -out "$work/cert.pem" 2> /dev/null
printf 'operator:correct-horse-battery\n' > "$work/auth"
chmod 600 "$work/auth"
tport=$(free_port)
"$web" --domain "$domain" --port "$tport" --tls-cert "$work/cert.pem" --tls-key "$work/key.pem" \
  --basic-auth-file "$work/auth" --idle-exit 0 --max-runtime 60 > "$work/web_tls.log" 2>&1 &
pids+=($!)
wait_up "https://localhost:$tport/" --cacert "$work/cert.pem" --resolve "localhost:$tport:127.0.0.1"
check "plain HTTP to the TLS port" 000 "$(status --max-time 3 "http://127.0.0.1:$tport/" || true)"
check "HTTPS without credentials" 401 "$(status --cacert "$work/cert.pem" "https://localhost:$tport/api/state" \
  --resolve "localhost:$tport:127.0.0.1")"
check "HTTPS with wrong credentials" 401 "$(status --cacert "$work/cert.pem" -u operator:wrong-password-here \
  --resolve "localhost:$tport:127.0.0.1" "https://localhost:$tport/api/state")"
check "HTTPS with the credentials" 200 "$(status --cacert "$work/cert.pem" -u operator:correct-horse-battery \
  --resolve "localhost:$tport:127.0.0.1" "https://localhost:$tport/api/state")"
chmod 644 "$work/auth"
"$web" --domain "$domain" --port "$(free_port)" --basic-auth-file "$work/auth" --max-runtime 5 > "$work/bad.log" 2>&1 \
  && rc=0 || rc=$?
check "a credentials file others can read is refused at start (exit 2)" 2 "$rc"
[ "$fail" = 0 ] || { echo "--- twin-web log"; cat "$work/web.log"; exit 1; }
echo "PASS"
