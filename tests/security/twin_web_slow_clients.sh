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
service=twin-web
. "$(dirname "$0")/slow_clients_attack.sh"

port=$(free_port); mport=$(free_port)
"$web" --domain "$domain" --port "$port" --metrics-port "$mport" --idle-exit 0 --max-runtime 80 > "$work/web.log" 2>&1 &
pids+=($!)
base="http://127.0.0.1:$port"
wait_answering "$base/"
connection_attack "$port" "$base/api/state"

check "140,000 header lines" 431 "$(python3 "$clients" headers "$port" 140000)"
check "101 header lines (count cap)" 431 "$(python3 "$clients" headers "$port" 100)"
check "99 header lines" 200 "$(python3 "$clients" headers "$port" 98)"
metrics=$(curl -s "http://127.0.0.1:$mport/metrics")
count() { echo "$metrics" | sed -n "s/^causal_twin_web_requests_refused_total{reason=\"$1\"} \([0-9]*\).*/\1/p"; }
check "refusals counted: request_deadline (the trickling connections)" 40 "$(count request_deadline)"
check "refusals counted: too_many_headers" 1 "$(count too_many_headers)"
peak_rss_check "after the headers"
[ "$fail" = 0 ] || { echo "--- twin-web log"; cat "$work/web.log"; exit 1; }
echo "PASS"
