# Sourced by the slow-client tests (twin_web_slow_clients.sh, metrics_slow_clients.sh) once they set $service
# (the name in the log lines): their set-up (a domain, $work, ../support/script_checks.sh) and the connection
# attack both HTTP servers (common/http) must survive, against the service the test started first (pids[0]).
domain=$((100 + $$ % 100))
work="$(mktemp -d "/tmp/causal_${service}_slow_XXXXXX")"
. "$(dirname "${BASH_SOURCE[0]}")/../support/script_checks.sh"
clients="$(dirname "${BASH_SOURCE[0]}")/slow_clients.py"
ulimit -n 4096  # the attacker's 1040 sockets
free_port() {
  local p=$((20000 + RANDOM % 30000))
  while ss -ltnH "sport = :$p" | grep -q .; do p=$((p + 1)); done
  echo "$p"
}
wait_answering() {  # wait_answering URL: until the service answers (10 s at most; the checks then say why)
  for _ in $(seq 1 100); do curl -s -o /dev/null "$1" && break; sleep 0.1; done
}
peak_rss_check() {  # peak_rss_check WHEN: the service's VmHWM under 100 MB
  local rss_kb
  rss_kb=$(awk '/VmHWM/ {print $2}' "/proc/${pids[0]}/status")
  echo "$service VmHWM $1: $rss_kb kB"
  check "$service peak RSS under 100 MB ($1)" 1 "$([ "$rss_kb" -lt 102400 ] && echo 1 || echo "$rss_kb kB")"
}
# connection_attack PORT URL: 40 connections that trickle one header byte every 2 s and 1000 idle ones from
# 127.0.0.2; exactly 64 (the per-address cap) stay accepted, five normal GETs of URL from 127.0.0.1 are answered
# 200 in under 1 s (the last body in $work/answer), the peak RSS stays under 100 MB; after the idle timeout
# (10 s) and the request deadline (15 s) none is open.
connection_attack() {
  local port="$1" url="$2" held t
  python3 "$clients" hold "$port" 1000 40 20 > "$work/hold.log" 2>&1 &
  pids+=($!)
  for _ in $(seq 1 100); do grep -qs '^connected' "$work/hold.log" && break; sleep 0.1; done
  sleep 2
  cat "$work/hold.log"
  held=$(ss -tnH state established "( sport = :$port )" | awk '$4 ~ /^127\.0\.0\.2:/' | wc -l)
  check "connections held from 127.0.0.2 (per-address cap)" 64 "$held"
  for i in 1 2 3 4 5; do
    t=$(curl -s -o "$work/answer" -w '%{http_code} %{time_total}' --max-time 5 "$url")
    echo "normal GET $i: $t"
    check "normal GET $i answered 200 in under 1 s" "200 1" "${t% *} $(awk -v s="${t#* }" 'BEGIN { print (s < 1.0) }')"
  done
  peak_rss_check "under the connection attack"
  wait "${pids[-1]}"
  tail -1 "$work/hold.log"
  check "after the idle timeout and the request deadline: open connections" "open=0 trickling_open=0" \
    "$(tail -1 "$work/hold.log")"
}
