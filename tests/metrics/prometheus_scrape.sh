#!/usr/bin/env bash
# A real Prometheus (Debian package) scrapes a running pipeline: causal-estimator, alarm-recommender and
# causal-recorder each serve /metrics (--metrics-port), sensor-replay sends the 984-snapshot IMS test-2
# feature table, and the test asks Prometheus (HTTP API) for what the services counted. Exact checks:
#   * the estimator received as many condition inputs as the replay says it sent (its own summary line);
#   * every condition vector and factor message the estimator wrote was received by the recommender and by
#     the recorder (counts compared between services, nothing hard-coded);
#   * `promtool check metrics` passes, without lint warnings, on every endpoint.
# Loopback only (deploy/dds/localhost.xml, metrics and Prometheus on 127.0.0.1), fixed DDS domain 97.
# Every process is ended by its pid; the work folder and shared-memory files are removed.
#   prometheus_scrape.sh BUILD_DIR DEPLOY_DIR
set -euo pipefail
build="$1"; deploy="$2"
domain=97
for tool in prometheus promtool curl; do
  command -v "$tool" > /dev/null || { echo "FAIL: $tool not installed (deploy/install_deps.sh installs it)"; exit 1; }
done
work="$(mktemp -d /tmp/causal_prometheus_XXXXXX)"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -TERM "$p" 2> /dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2> /dev/null || true; done
  fastdds shm clean > /dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT
# Under `set -e` a failing command would end the test without a word: name it.
trap 'echo "FAIL: line $LINENO: \"$BASH_COMMAND\" exited $?"' ERR

# Four free TCP ports on 127.0.0.1 (a port nobody listens on now).
free_ports=()
port=$((20000 + ($$ * 7) % 30000))
while [ ${#free_ports[@]} -lt 4 ]; do
  if ! ss -ltnH "sport = :$port" | grep -q .; then free_ports+=("$port"); fi
  port=$((port + 1))
done
est_port=${free_ports[0]}; rec_port=${free_ports[1]}; hist_port=${free_ports[2]}; prom_port=${free_ports[3]}

dds=(--domain "$domain" --transport "$deploy/dds/localhost.xml")
common=("${dds[@]}" --max-runtime 150)
svc="$build/services"
"$svc/causal_recorder/causal-recorder" "${common[@]}" --out "$work/record" --idle-exit 0 \
  --metrics-port "$hist_port" > "$work/recorder.log" 2>&1 &
pids+=($!); recorder_pid=$!
"$svc/alarm_recommender/alarm-recommender" "${common[@]}" --idle-exit 0 --metrics-port "$rec_port" \
  > "$work/recommender.log" 2>&1 &
pids+=($!); recommender_pid=$!
"$svc/causal_estimator/causal-estimator" "${common[@]}" --idle-exit 0 --metrics-port "$est_port" \
  --wait-for alarm-recommender --wait-for causal-recorder --wait-timeout 60 > "$work/estimator.log" 2>&1 &
pids+=($!); estimator_pid=$!

cat > "$work/prometheus.yml" << YAML
global:
  scrape_interval: 1s
  scrape_timeout: 900ms
scrape_configs:
  - job_name: causal_twin
    static_configs:
      - targets: ['127.0.0.1:$est_port']
        labels: {service: causal-estimator}
      - targets: ['127.0.0.1:$rec_port']
        labels: {service: alarm-recommender}
      - targets: ['127.0.0.1:$hist_port']
        labels: {service: causal-recorder}
YAML
promtool check config "$work/prometheus.yml" > "$work/promtool_config.log" 2>&1 \
  || { cat "$work/promtool_config.log"; echo "FAIL: prometheus.yml"; exit 1; }
prometheus --config.file "$work/prometheus.yml" --storage.tsdb.path "$work/tsdb" \
  --web.listen-address "127.0.0.1:$prom_port" > "$work/prometheus.log" 2>&1 &
pids+=($!); prometheus_pid=$!

# Prometheus must be serving before it is asked (bounded: 60 s; on a loaded machine its start takes seconds).
ready_deadline=$((SECONDS + 60))
until curl -sf --max-time 2 "http://127.0.0.1:$prom_port/-/ready" > /dev/null; do
  kill -0 "$prometheus_pid" 2> /dev/null || { tail -5 "$work/prometheus.log"; echo "FAIL: prometheus exited"; exit 1; }
  [ $SECONDS -lt $ready_deadline ] || { tail -5 "$work/prometheus.log"; echo "FAIL: prometheus not ready in 60 s"; exit 1; }
  sleep 0.5
done

rc=0
"$svc/sensor_replay/sensor-replay" "${dds[@]}" --speed 0 --wait-for causal-estimator --wait-timeout 60 \
  --features "$deploy/data/ims2-features/derived_per_file_stats_all984.csv" --feature-suffix _meanabs \
  --feature-name meanabs --asset-group ims2-shaft1 > "$work/replay.log" 2>&1 || rc=$?
[ $rc = 0 ] || { cat "$work/replay.log"; echo "FAIL: sensor-replay exited $rc"; exit 1; }
sent=$(sed -n 's/.*summary topic=causal_twin\/condition_input sent=\([0-9]*\).*/\1/p' "$work/replay.log")
[ -n "$sent" ] || { cat "$work/replay.log"; echo "FAIL: no replay summary"; exit 1; }

# query EXPR: the value of a one-sample instant query ("" when there is none yet, or Prometheus did not answer
# this time: the callers wait, bounded, or fail naming the value).
query() {
  { curl -s --max-time 5 --get "http://127.0.0.1:$prom_port/api/v1/query" --data-urlencode "query=$1" || true; } \
    | sed -n 's/.*"value":\[[0-9.e+]*,"\([^"]*\)"\].*/\1/p'
}
metric() {  # metric SERVICE NAME TOPIC
  query "sum(causal_twin_$2{service=\"$1\",topic=\"$3\"})"
}
# Wait (bounded: 90 s) until the recorder has scraped values matching the estimator's: the pipeline is done.
deadline=$((SECONDS + 90))
while :; do
  est_in=$(metric causal-estimator dds_samples_received_total causal_twin/condition_input)
  est_vec=$(metric causal-estimator dds_samples_written_total causal_twin/condition_vector)
  est_fac=$(metric causal-estimator dds_samples_written_total causal_twin/causal_factors)
  rec_vec=$(metric alarm-recommender dds_samples_received_total causal_twin/condition_vector)
  rec_fac=$(metric alarm-recommender dds_samples_received_total causal_twin/causal_factors)
  his_vec=$(metric causal-recorder dds_samples_received_total causal_twin/condition_vector)
  his_fac=$(metric causal-recorder dds_samples_received_total causal_twin/causal_factors)
  if [ "$est_in" = "$sent" ] && [ "$est_vec" = "$sent" ] && [ -n "$est_fac" ] && [ "$rec_vec" = "$sent" ] \
     && [ "$his_vec" = "$sent" ] && [ "$rec_fac" = "$est_fac" ] && [ "$his_fac" = "$est_fac" ]; then
    break
  fi
  if [ $SECONDS -ge $deadline ]; then
    echo "FAIL: Prometheus did not see the counts agree within 90 s:"
    echo "  replay sent=$sent; estimator in=$est_in vectors out=$est_vec factors out=$est_fac"
    echo "  recommender vectors in=$rec_vec factors in=$rec_fac; recorder vectors in=$his_vec factors in=$his_fac"
    tail -5 "$work/prometheus.log"
    exit 1
  fi
  sleep 1
done
echo "prometheus: replay sent=$sent; estimator condition_input received=$est_in, condition_vector written=$est_vec," \
     "causal_factors written=$est_fac; recommender received $rec_vec / $rec_fac; recorder received $his_vec / $his_fac"
up=$(query 'count(up{job="causal_twin"} == 1)')
[ "$up" = 3 ] || { echo "FAIL: $up of 3 targets up"; exit 1; }
lat=$(query 'sum(causal_twin_estimator_processing_seconds_count{service="causal-estimator",input="condition"})')
[ "$lat" = "$sent" ] || { echo "FAIL: latency histogram counted $lat inputs, expected $sent"; exit 1; }
p99=$(query 'histogram_quantile(0.99, sum by (le) (causal_twin_estimator_processing_seconds_bucket{input="condition"}))')
echo "prometheus: 3 of 3 targets up; estimator processing latency p99 = ${p99} s over $lat condition inputs"

# The operator's metrics: build_info and process_* on every target; the estimator's data age per group (the
# source time of its last input = the table's last timestamp, read from the table); the recommender's open
# alarms = the alarm ids whose last published state is not CLEARED, counted from its own log (ALARM/HEALTH
# lines name every raise, escalation and clearing).
builds=$(query 'count(causal_twin_build_info{job="causal_twin"} == 1)')
[ "$builds" = 3 ] || { echo "FAIL: causal_twin_build_info on $builds of 3 targets"; exit 1; }
cpu=$(query 'count(process_cpu_seconds_total{job="causal_twin"} > 0 and process_resident_memory_bytes > 0 and process_open_fds > 0)')
[ "$cpu" = 3 ] || { echo "FAIL: process_* metrics on $cpu of 3 targets"; exit 1; }
last_ts=$(tail -1 "$deploy/data/ims2-features/derived_per_file_stats_all984.csv" | cut -d, -f2)
want_ts=$(date -u -d "$last_ts" +%s)
got_ts=$(query 'causal_twin_estimator_last_input_timestamp_seconds{asset_group="ims2-shaft1"}')
[ "$got_ts" = "$want_ts" ] || { echo "FAIL: last input timestamp $got_ts, the table ends at $want_ts ($last_ts)"; exit 1; }
age=$(query 'causal_twin_estimator_input_age_seconds{asset_group="ims2-shaft1"}')
[ -n "$age" ] || { echo "FAIL: no causal_twin_estimator_input_age_seconds for ims2-shaft1"; exit 1; }
# Bounded wait: the last scrape may predate the last alarm event.
deadline=$((SECONDS + 30))
while :; do
  open_alarms=$(query 'sum(causal_twin_alarms_open{service="alarm-recommender",category=~"degradation|health"})')
  expected_open=$(grep -oE '(ALARM (raised|escalated|cleared)|HEALTH (RAISED|CLEARED)) [^ :]+' "$work/recommender.log" \
    | awk '{ state[$3] = ($2 == "cleared" || $2 == "CLEARED") ? 0 : 1 } END { n = 0; for (k in state) n += state[k]; print n }')
  [ "$open_alarms" = "$expected_open" ] && break
  [ $SECONDS -lt $deadline ] \
    || { echo "FAIL: causal_twin_alarms_open sums to $open_alarms, the recommender's log leaves $expected_open open"; exit 1; }
  sleep 1
done
echo "prometheus: build_info and process_* on 3 of 3 targets; ims2-shaft1 last input at $got_ts ($last_ts UTC)," \
     "input age ${age} s; open alarms $open_alarms (= raised - cleared in the recommender's log)"

# The prognosis gauges: one series per (channel, level) the recommender ever published a prognosis for, and at the
# end a number (not NaN) exactly for those whose last published prognosis, at the run's last snapshot, was known
# or reached. Both counted from the recorder's prognosis.csv (bounded wait: the last scrape may predate the end).
read -r want_series want_known < <(python3 - "$work/record/prognosis.csv" << 'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
last = max(int(r["sample_index"]) for r in rows)
series = {(r["channel_name"], r["level"]) for r in rows}
known = {(r["channel_name"], r["level"]) for r in rows
         if int(r["sample_index"]) == last and (r["known"] == "true" or r["reached"] == "true")}
print(len(series), len(known))
PY
)
deadline=$((SECONDS + 30))
while :; do
  got_series=$(query 'count(causal_twin_prognosis_time_to_level_seconds{service="alarm-recommender",bound="median"})')
  got_known=$(query 'count(causal_twin_prognosis_time_to_level_seconds{service="alarm-recommender",bound="median"} >= 0)')
  [ "${got_series:-0}" = "$want_series" ] && [ "${got_known:-0}" = "$want_known" ] && break
  [ $SECONDS -lt $deadline ] || { echo "FAIL: prognosis_time_to_level_seconds: ${got_series:-0} series, ${got_known:-0} with a number;" \
    "prognosis.csv: $want_series (channel, level) pairs, $want_known known at the last snapshot"; exit 1; }
  sleep 1
done
echo "prometheus: causal_twin_prognosis_time_to_level_seconds: $got_series (channel, level) series, $want_known with a time at the end" \
     "(= prognosis.csv)"

for port in "$est_port" "$rec_port" "$hist_port"; do
  curl -s --max-time 5 "http://127.0.0.1:$port/metrics" > "$work/scrape_$port.txt"
  if ! promtool check metrics < "$work/scrape_$port.txt" > "$work/promtool_$port.log" 2>&1 \
     || [ -s "$work/promtool_$port.log" ]; then
    cat "$work/promtool_$port.log"; echo "FAIL: promtool check metrics on 127.0.0.1:$port"; exit 1
  fi
  echo "promtool check metrics: 127.0.0.1:$port ok ($(grep -c '^causal_twin_' "$work/scrape_$port.txt") samples)"
done

# Clean stop: SIGTERM by pid, every service exits 0 (nothing lost).
for p in "$estimator_pid" "$recommender_pid" "$recorder_pid"; do kill -TERM "$p"; done
status=0
for p in "$estimator_pid" "$recommender_pid" "$recorder_pid"; do rc=0; wait "$p" || rc=$?; [ $rc = 0 ] || status=$rc; done
kill -TERM "$prometheus_pid"; wait "$prometheus_pid" 2> /dev/null || true
pids=()
[ $status = 0 ] || { tail -5 "$work"/*.log; echo "FAIL: a service exited $status"; exit 1; }
echo "PASS"
