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
clients="$(dirname "$0")/slow_clients.py"
domain=$((100 + $$ % 100))
work="$(mktemp -d /tmp/causal_metrics_slow_XXXXXX)"
. "$(dirname "$0")/../support/script_checks.sh"
ulimit -n 4096  # the attacker's 1040 sockets
free_port() {
  local p=$((20000 + RANDOM % 30000))
  while ss -ltnH "sport = :$p" | grep -q .; do p=$((p + 1)); done
  echo "$p"
}

mport=$(free_port)
"$estimator" --domain "$domain" --metrics-port "$mport" --idle-exit 0 --max-runtime 80 > "$work/estimator.log" 2>&1 &
pids+=($!)
scrape="http://127.0.0.1:$mport/metrics"
for _ in $(seq 1 100); do curl -s -o /dev/null "$scrape" && break; sleep 0.1; done

python3 "$clients" hold "$mport" 1000 40 20 > "$work/hold.log" 2>&1 &
pids+=($!)
for _ in $(seq 1 100); do grep -qs '^connected' "$work/hold.log" && break; sleep 0.1; done
sleep 2
cat "$work/hold.log"
held=$(ss -tnH state established "( sport = :$mport )" | awk '$4 ~ /^127\.0\.0\.2:/' | wc -l)
check "connections held from 127.0.0.2 (per-address cap)" 64 "$held"
for i in 1 2 3 4 5; do
  t=$(curl -s -o "$work/scrape.txt" -w '%{http_code} %{time_total}' --max-time 5 "$scrape")
  echo "normal scrape $i: $t"
  check "normal scrape $i answered 200 in under 1 s" "200 1" "${t% *} $(awk -v s="${t#* }" 'BEGIN { print (s < 1.0) }')"
done
check "the scrape is the exposition" 1 "$(grep -c '^# TYPE causal_twin_build_info gauge' "$work/scrape.txt")"
rss_kb=$(awk '/VmHWM/ {print $2}' "/proc/${pids[0]}/status")
echo "causal-estimator VmHWM under the connection attack: $rss_kb kB"
check "peak RSS under 100 MB (connections)" 1 "$([ "$rss_kb" -lt 102400 ] && echo 1 || echo "$rss_kb kB")"
wait "${pids[1]}"
tail -1 "$work/hold.log"
check "after the idle timeout and the request deadline: open connections" "open=0 trickling_open=0" \
  "$(tail -1 "$work/hold.log")"

check "101 header lines (count cap)" 431 "$(python3 "$clients" headers "$mport" 100)"
check "a query that is not UTF-8" 400 "$(curl -s -o /dev/null -w '%{http_code}' "$scrape?x=%FF%FE")"
check "a query argument over 1 KiB" 400 "$(curl -s -o /dev/null -w '%{http_code}' "$scrape?x=$(head -c 2000 /dev/zero | tr '\0' a)")"
check "a UTF-8 query is served" 200 "$(curl -s -o /dev/null -w '%{http_code}' "$scrape?x=%C3%A9")"
metrics=$(curl -s "$scrape")
count() { echo "$metrics" | sed -n "s/^causal_twin_metrics_requests_refused_total{reason=\"$1\"} \([0-9]*\).*/\1/p"; }
check "refusals counted: request_deadline (the trickling connections)" 40 "$(count request_deadline)"
check "refusals counted: too_many_headers" 1 "$(count too_many_headers)"
check "refusals counted: bad_query" 2 "$(count bad_query)"
rss_kb=$(awk '/VmHWM/ {print $2}' "/proc/${pids[0]}/status")
echo "causal-estimator VmHWM at the end: $rss_kb kB"
check "peak RSS under 100 MB (end)" 1 "$([ "$rss_kb" -lt 102400 ] && echo 1 || echo "$rss_kb kB")"
[ "$fail" = 0 ] || { echo "--- causal-estimator log"; cat "$work/estimator.log"; exit 1; }
echo "PASS"
