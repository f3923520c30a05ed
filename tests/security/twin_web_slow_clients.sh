#!/usr/bin/env bash
# twin-web cannot be starved or blown up by clients that hold connections (HTTP server limits in
# services/twin_web/http_server.hpp), with real sockets against the running service:
#  * 40 connections that trickle one header byte every 2 s and 1000 idle ones, all from 127.0.0.2: exactly 64
#    (the per-address cap) stay accepted, a normal GET from 127.0.0.1 is answered in under 1 s (five times), the
#    peak RSS stays under 100 MB; the idle ones are closed after the idle timeout (10 s), the trickling ones by
#    the request deadline (15 s), each of those counted (request_deadline = 40);
#  * 140,000 header lines are refused (431: past the 64 KiB connection memory), 101 too (431: the header-count
#    cap, counted: too_many_headers = 1), 99 are served (200); the peak RSS stays under 100 MB.
# Loopback only; every process is ended by its pid.
#   twin_web_slow_clients.sh BUILD_DIR
set -euo pipefail
build="$1"
web="$build/services/twin_web/twin-web"
clients="$(dirname "$0")/slow_clients.py"
domain=$((100 + $$ % 100))
work="$(mktemp -d /tmp/causal_web_slow_XXXXXX)"
. "$(dirname "$0")/../support/script_checks.sh"
ulimit -n 4096  # the attacker's 1040 sockets
free_port() {
  local p=$((20000 + RANDOM % 30000))
  while ss -ltnH "sport = :$p" | grep -q .; do p=$((p + 1)); done
  echo "$p"
}

port=$(free_port); mport=$(free_port)
"$web" --domain "$domain" --port "$port" --metrics-port "$mport" --idle-exit 0 --max-runtime 80 > "$work/web.log" 2>&1 &
pids+=($!)
base="http://127.0.0.1:$port"
for _ in $(seq 1 100); do curl -s -o /dev/null "$base/" && break; sleep 0.1; done

python3 "$clients" hold "$port" 1000 40 20 > "$work/hold.log" 2>&1 &
pids+=($!)
for _ in $(seq 1 100); do grep -qs '^connected' "$work/hold.log" && break; sleep 0.1; done
sleep 2
cat "$work/hold.log"
held=$(ss -tnH state established "( sport = :$port )" | awk '$4 ~ /^127\.0\.0\.2:/' | wc -l)
check "connections held from 127.0.0.2 (per-address cap)" 64 "$held"
for i in 1 2 3 4 5; do
  t=$(curl -s -o "$work/state.json" -w '%{http_code} %{time_total}' --max-time 5 "$base/api/state")
  echo "normal GET $i: $t"
  check "normal GET $i answered 200 in under 1 s" "200 1" "${t% *} $(awk -v s="${t#* }" 'BEGIN { print (s < 1.0) }')"
done
rss_kb=$(awk '/VmHWM/ {print $2}' "/proc/${pids[0]}/status")
echo "twin-web VmHWM under the connection attack: $rss_kb kB"
check "twin-web peak RSS under 100 MB (connections)" 1 "$([ "$rss_kb" -lt 102400 ] && echo 1 || echo "$rss_kb kB")"
wait "${pids[1]}"
tail -1 "$work/hold.log"
check "after the idle timeout and the request deadline: open connections" "open=0 trickling_open=0" \
  "$(tail -1 "$work/hold.log")"

check "140,000 header lines" 431 "$(python3 "$clients" headers "$port" 140000)"
check "101 header lines (count cap)" 431 "$(python3 "$clients" headers "$port" 100)"
check "99 header lines" 200 "$(python3 "$clients" headers "$port" 98)"
metrics=$(curl -s "http://127.0.0.1:$mport/metrics")
count() { echo "$metrics" | sed -n "s/^causal_twin_web_requests_refused_total{reason=\"$1\"} \([0-9]*\).*/\1/p"; }
check "refusals counted: request_deadline (the trickling connections)" 40 "$(count request_deadline)"
check "refusals counted: too_many_headers" 1 "$(count too_many_headers)"
rss_kb=$(awk '/VmHWM/ {print $2}' "/proc/${pids[0]}/status")
echo "twin-web VmHWM after the headers: $rss_kb kB"
check "twin-web peak RSS under 100 MB (headers)" 1 "$([ "$rss_kb" -lt 102400 ] && echo 1 || echo "$rss_kb kB")"
[ "$fail" = 0 ] || { echo "--- twin-web log"; cat "$work/web.log"; exit 1; }
echo "PASS"
