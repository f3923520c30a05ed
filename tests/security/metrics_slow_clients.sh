#!/usr/bin/env bash
# A service's /metrics endpoint (common/metrics on the product's HTTP server, common/http: the limits of
# twin-web) cannot be starved or blown up by clients that hold connections, with real sockets against a
# running causal-estimator:
#  * 40 connections that trickle one header byte every 2 s and 1000 idle ones, all from 127.0.0.2: exactly 64
#    (the per-address cap) stay accepted, a normal scrape from 127.0.0.1 is answered in under 1 s (five times),
#    the peak RSS stays under 100 MB; after the idle timeout (10 s) and the request deadline (15 s) none is
#    open, the trickling ones counted (metrics_requests_refused_total{reason="request_deadline"} = 40);
#  * 101 header lines are refused (431, counted too_many_headers = 1); a query that is not UTF-8 or longer than
#    1 KiB is refused (400, counted bad_query = 2).
# Loopback only; every process is ended by its pid.
#   metrics_slow_clients.sh BUILD_DIR
set -euo pipefail
build="$1"
estimator="$build/services/causal_estimator/causal-estimator"
service=causal-estimator
. "$(dirname "$0")/slow_clients_attack.sh"

mport=$(free_port)
"$estimator" --domain "$domain" --metrics-port "$mport" --idle-exit 0 --max-runtime 80 > "$work/estimator.log" 2>&1 &
pids+=($!)
scrape="http://127.0.0.1:$mport/metrics"
wait_answering "$scrape"
connection_attack "$mport" "$scrape"
check "the scrape is the exposition" 1 "$(grep -c '^# TYPE causal_twin_build_info gauge' "$work/answer")"

check "101 header lines (count cap)" 431 "$(python3 "$clients" headers "$mport" 100)"
check "a query that is not UTF-8" 400 "$(curl -s -o /dev/null -w '%{http_code}' "$scrape?x=%FF%FE")"
check "a query argument over 1 KiB" 400 "$(curl -s -o /dev/null -w '%{http_code}' "$scrape?x=$(head -c 2000 /dev/zero | tr '\0' a)")"
check "a UTF-8 query is served" 200 "$(curl -s -o /dev/null -w '%{http_code}' "$scrape?x=%C3%A9")"
metrics=$(curl -s "$scrape")
count() { echo "$metrics" | sed -n "s/^causal_twin_metrics_requests_refused_total{reason=\"$1\"} \([0-9]*\).*/\1/p"; }
check "refusals counted: request_deadline (the trickling connections)" 40 "$(count request_deadline)"
check "refusals counted: too_many_headers" 1 "$(count too_many_headers)"
check "refusals counted: bad_query" 2 "$(count bad_query)"
peak_rss_check "at the end"
[ "$fail" = 0 ] || { echo "--- causal-estimator log"; cat "$work/estimator.log"; exit 1; }
echo "PASS"
