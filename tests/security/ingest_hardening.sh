#!/usr/bin/env bash
# sensor-ingest's edges, with real processes.
#  * UDP: datagrams are taken only from --udp-allow networks (default loopback): a sender on 10.77.0.1 (an
#    address this test adds to lo in its own network namespace) is refused and counted
#    (ingest_udp_refused_total), loopback senders get through; with --udp-allow 10.77.0.1 it is the other
#    way round;
#  * MQTT: a real mosquitto with a TLS listener that requires client certificates (a CA, the broker's and
#    the clients' certificates made here by openssl) and a password file (mosquitto_passwd): sensor-ingest
#    with --mqtt-cafile/--mqtt-cert/--mqtt-key/--mqtt-username/--mqtt-password-file takes every block; one
#    without a client certificate and one with a wrong password take none; a password file others can read
#    is refused at start (exit 2).
# Exact counts from the adapter's summary line. Runs in a private network namespace (unshare, as root in
# CI); without the privilege it skips (77), or fails under CAUSAL_TWIN_REQUIRE_ALL.
#   ingest_hardening.sh BUILD_DIR
set -euo pipefail
build="$(cd "$1" && pwd)"
if [ -z "${CAUSAL_INGEST_HARDENING_NETNS:-}" ]; then
  if CAUSAL_INGEST_HARDENING_NETNS=1 unshare --net true 2> /dev/null; then
    exec env CAUSAL_INGEST_HARDENING_NETNS=1 unshare --net "$0" "$@"
  fi
  if [ -n "${CAUSAL_TWIN_REQUIRE_ALL:-}" ]; then echo "FAIL: cannot create a network namespace"; exit 1; fi
  echo "SKIP: cannot create a network namespace (run as root)"; exit 77
fi
ip link set lo up
ip addr add 10.77.0.1/32 dev lo
ingest="$build/services/sensor_ingest/sensor-ingest"
domain=$((100 + $$ % 100))
work="$(mktemp -d /tmp/causal_ingest_hardening_XXXXXX)"
# pids, cleanup on exit, check NAME EXPECTED GOT
. "$(dirname "$0")/../support/script_checks.sh"
[ -z "${KEEP_LOGS:-}" ] || trap 'cp "$work"/*.log /tmp/ 2> /dev/null; cleanup' EXIT
block() {  # block GROUP SEQUENCE: one JSON block of 2 samples x 2 channels, 2 ms apart per block
  printf '{"asset_group":"%s","channels":["c1","c2"],"sample_rate_hz":1000,"t0_ns":%d,"sequence":%d,"samples":[[1,2],[3,4]]}' \
    "$1" $((1700000000000000000 + $2 * 2000000)) "$2"
}
send_udp() {  # send_udp FROM_ADDRESS TO_PORT GROUP FIRST_SEQ COUNT
  python3 - "$@" << 'PY'
import socket, sys
src, port, group, first, count = sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4]), int(sys.argv[5])
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
s.bind((src, 0))
for k in range(first, first + count):
    m = ('{"asset_group":"%s","channels":["c1","c2"],"sample_rate_hz":1000,"t0_ns":%d,"sequence":%d,'
         '"samples":[[1,2],[3,4]]}' % (group, 1700000000000000000 + k * 2000000, k))
    s.sendto(m.encode(), ("10.77.0.1" if src == "10.77.0.1" else "127.0.0.1", port))
PY
}
summary() { grep -o 'sensor-ingest: received=.*' "$1" | tail -1 || true; }
field() { echo "$1" | sed -n "s/.*\b$2=\([0-9]*\).*/\1/p"; }
wait_log() {  # wait_log FILE TEXT
  for _ in $(seq 1 200); do grep -q "$2" "$1" && return 0; sleep 0.1; done
  echo "FAIL: '$2' never appeared in $1"; cat "$1"; exit 1
}
stop() {  # stop PID: SIGTERM and wait; the exit code goes to $rc
  kill -TERM "$1"; rc=0; wait "$1" || rc=$?
}
common=(--domain "$domain" --wait-subscribers 0 --max-runtime 60)

# --- UDP ---------------------------------------------------------------------------------------------------
uport=$((20000 + RANDOM % 20000)); mport=$((uport + 1))
"$ingest" "${common[@]}" --source "udp://0.0.0.0:$uport" --metrics-port "$mport" > "$work/udp.log" 2>&1 &
upid=$!; pids+=($upid)
wait_log "$work/udp.log" "ingesting from"
send_udp 127.0.0.1 "$uport" udp-local 0 3
send_udp 10.77.0.1 "$uport" udp-foreign 0 4
for _ in $(seq 1 50); do
  refused=$(curl -s "http://127.0.0.1:$mport/metrics" | sed -n 's/^causal_twin_ingest_udp_refused_total \([0-9]*\).*/\1/p')
  [ "${refused:-0}" = 4 ] && break; sleep 0.1
done
check "udp default: datagrams from 10.77.0.1 refused (metric)" 4 "${refused:-0}"
check "udp default: refusal logged" 1 "$(grep -c 'refused a datagram from 10.77.0.1' "$work/udp.log")"
stop "$upid"
s=$(summary "$work/udp.log")
check "udp default: received (loopback only)" 3 "$(field "$s" received)"
check "udp default: published" 3 "$(field "$s" published)"
check "udp default: exit code" 0 "$rc"

"$ingest" "${common[@]}" --source "udp://0.0.0.0:$uport" --udp-allow 10.77.0.1 > "$work/udp2.log" 2>&1 &
upid=$!; pids+=($upid)
wait_log "$work/udp2.log" "ingesting from"
send_udp 10.77.0.1 "$uport" udp-foreign 0 2
send_udp 127.0.0.1 "$uport" udp-local 0 1
wait_log "$work/udp2.log" "refused a datagram from 127.0.0.1"
sleep 0.5
stop "$upid"
s=$(summary "$work/udp2.log")
check "udp --udp-allow 10.77.0.1: received" 2 "$(field "$s" received)"

# --- MQTT over TLS with client certificates and a password -------------------------------------------------
cd "$work"
key() { openssl ecparam -name prime256v1 -genkey -noout -out "$1" 2> /dev/null; chmod 600 "$1"; }
key ca.key
openssl req -x509 -new -key ca.key -sha256 -days 1 -subj "/CN=test MQTT CA" -out ca.pem
issue() {  # issue NAME CN [SAN]
  key "$1.key"
  openssl req -new -key "$1.key" -subj "/CN=$2" -out "$1.csr"
  if [ -n "${3:-}" ]; then printf 'subjectAltName=%s\n' "$3" > "$1.ext"; else : > "$1.ext"; fi
  openssl x509 -req -in "$1.csr" -CA ca.pem -CAkey ca.key -CAcreateserial -days 1 -sha256 -extfile "$1.ext" \
    -out "$1.pem" 2> /dev/null
}
issue broker localhost "DNS:localhost,IP:127.0.0.1"
issue client sensor-ingest
mosquitto_passwd -c -b passwd ingest 'edge-password-1' > /dev/null 2>&1
chmod 600 passwd
bport=$((uport + 2))
cat > mosquitto.conf << CONF
persistence false
allow_anonymous false
password_file $work/passwd
listener $bport 127.0.0.1
cafile $work/ca.pem
certfile $work/broker.pem
keyfile $work/broker.key
require_certificate true
tls_version tlsv1.2
CONF
# mosquitto drops privileges to "mosquitto" when started as root: let it read its files.
chmod 755 "$work"; chmod 644 broker.key passwd
/usr/sbin/mosquitto -c mosquitto.conf > mosquitto.log 2>&1 &
pids+=($!)
printf 'edge-password-1\n' > pw; chmod 600 pw
printf 'wrong-password-1\n' > wrong; chmod 600 wrong
url="mqtt://localhost:$bport/plant/line1"
tls=(--mqtt-cafile ca.pem --mqtt-cert client.pem --mqtt-key client.key)
"$ingest" "${common[@]}" --source "$url" "${tls[@]}" --mqtt-username ingest --mqtt-password-file pw \
  > good.log 2>&1 &
good=$!; pids+=($good)
"$ingest" "${common[@]}" --source "$url" --mqtt-cafile ca.pem --mqtt-username ingest --mqtt-password-file pw \
  > nocert.log 2>&1 &
nocert=$!; pids+=($nocert)
"$ingest" "${common[@]}" --source "$url" "${tls[@]}" --mqtt-username ingest --mqtt-password-file wrong \
  > wrongpw.log 2>&1 &
wrongpw=$!; pids+=($wrongpw)
wait_log good.log "(connection 1)"
wait_log wrongpw.log "refused the connection"
for k in 0 1 2 3 4; do
  block mqtt-pump "$k" | mosquitto_pub -h localhost -p "$bport" --cafile ca.pem --cert client.pem --key client.key \
    -u ingest -P 'edge-password-1' -q 1 -t plant/line1 -s
done
rc_plain=0
block mqtt-pump 9 | mosquitto_pub -h 127.0.0.1 -p "$bport" -u ingest -P 'edge-password-1' -q 1 -t plant/line1 -s \
  2> /dev/null || rc_plain=$?
check "a publisher without TLS is refused by the broker (non-zero exit)" 1 "$([ "$rc_plain" != 0 ] && echo 1 || echo 0)"
for _ in $(seq 1 50); do grep -q "rejected\|published frame\|sequence=4" good.log && break; sleep 0.1; done
sleep 1
stop "$good"; s=$(summary good.log)
check "mqtt TLS + client cert + password: received" 5 "$(field "$s" received)"
check "mqtt TLS + client cert + password: published" 5 "$(field "$s" published)"
check "mqtt TLS + client cert + password: exit code" 0 "$rc"
stop "$nocert"; s=$(summary nocert.log)
check "mqtt without a client certificate: received" 0 "$(field "$s" received)"
check "mqtt without a client certificate: never connected" 0 "$(grep -c '(connection 1)' nocert.log || true)"
stop "$wrongpw"; s=$(summary wrongpw.log)
check "mqtt with a wrong password: received" 0 "$(field "$s" received)"
chmod 644 pw
rc=0; "$ingest" "${common[@]}" --source "$url" "${tls[@]}" --mqtt-username ingest --mqtt-password-file pw \
  --max-runtime 5 > loose.log 2>&1 || rc=$?
check "a password file others can read is refused at start" 2 "$rc"
[ "$fail" = 0 ] || { for f in "$work"/*.log; do echo "--- $f"; cat "$f"; done; exit 1; }
echo "PASS"
