#!/usr/bin/env bash
# Starts the services on one DDS domain, replays a data set through them, stops them all, and prints what
# every topic carried.
#   deploy/launch.sh [--domain N] [--ims-dir DIR | --features FILE [--feature-suffix S --feature-name F]]
#                    [--gap-factor K] [--speed X] [--transport XML] [--record DIR] [--max-runtime S]
#                    [--asset-group ID] [--ask CHANNEL:PERCENT]... [--logs DIR] [--metrics-port P] [--security DIR]
#                    [--web-port P] [--db URL]
# Defaults: a private domain between 100 and 199, the embedded IMS slice, as fast as possible, loopback only,
# DDS-Security off on loopback (open bus; the plant profile turns it on). Without --transport:
# $FASTRTPS_DEFAULT_PROFILES_FILE when set; --transport deploy/dds/discovery_client.xml: a discovery server.
# --features FILE takes any IMS-format table as it is (timestamp, one column per channel, any names, 2-64
# channels); --feature-suffix/--feature-name are optional (a table of <channel>_<feature> columns publishes
# its meanabs columns unless told otherwise). --gap-factor K: a time interval > K x the median is a gap (3).
# --security DIR runs every service secured with the PKI made by deploy/security/make-pki.sh DIR.
# --record DIR also runs causal-recorder (CSV per topic) and renders the PNG report into DIR/report; the recorder
#   also writes the history database DIR/history.db (SQLite; docs/historian.md), which twin-web draws from.
# --db URL writes the history to URL instead (sqlite:PATH or postgresql://..., as causal-recorder --db).
# --ask 2:-10 asks the live twin (causal-ask) after the replay: a sustained -10 % on channel 2 of the asset group.
# --logs DIR keeps every service's log there (default: a temporary folder, removed at exit).
# --metrics-port P gives every service a Prometheus endpoint on 127.0.0.1 at consecutive ports from P (one
#   line "metrics: <service> http://127.0.0.1:<port>/metrics" each).
# --verbose shows every service's log lines live; by default the terminal shows progress, alarms, warnings and
#   errors only, then the delivery table and the verdict (status, first alarm, root cause, advice per group).
# --web-port P also runs twin-web: the live view at http://127.0.0.1:P/, up until 30 s after the run.
# --alarm-summary: no line per alarm on the terminal; one summary of the alarms after the run (deploy/demo.sh,
#   part 1: a burst of alarms in a millisecond reads better as counts by severity, channel and root cause).
# Exit code: 0 when every service exited 0 (nothing lost, refused or dropped), else the first non-zero code;
# the summary at the end says per topic: sent, received, dropped, rejected, and which service failed.
# Every process is ended by its pid (only those started here); the run is bounded by --max-runtime.
# Installed (the causal-twin package: causal-twin-demo) it runs the binaries next to itself on the data in
# <prefix>/share/causal-twin/data, from any folder, and writes only to --logs/--record or a temporary folder.
set -euo pipefail
root="$(cd "$(dirname "$(readlink -f "$0")")/.." && pwd)"
declare -A tool=()
if [ ! -d "$root/deploy" ] && [ -d "$root/share/causal-twin" ]; then
  # Installed: <prefix>/bin/causal-twin-demo.
  data_dir="$root/share/causal-twin/data"
  for n in sensor-replay causal-estimator alarm-recommender causal-recorder causal-ask causal-report twin-web; do
    tool[$n]="$root/bin/$n"
  done
  default_transport=/etc/causal-twin/localhost.xml
  [ -f "$default_transport" ] || default_transport="$root/share/causal-twin/dds/localhost.xml"
else
  # The source tree: deploy/launch.sh with the binaries of the build folder.
  data_dir="$root/deploy/data"
  bin="${CAUSAL_TWIN_BUILD_DIR:-$root/build}/services"
  tools_bin="${CAUSAL_TWIN_BUILD_DIR:-$root/build}/tools"  # the offline tools (causal-report)
  tool=([sensor-replay]="$bin/sensor_replay/sensor-replay" [causal-estimator]="$bin/causal_estimator/causal-estimator"
        [alarm-recommender]="$bin/alarm_recommender/alarm-recommender"
        [causal-recorder]="$bin/causal_recorder/causal-recorder" [causal-ask]="$bin/whatif_ask/causal-ask"
        [causal-report]="$tools_bin/causal_report/causal-report" [twin-web]="$bin/twin_web/twin-web")
  default_transport="$root/deploy/dds/localhost.xml"
fi
domain=$(( 100 + $$ % 100 ))
source_args=(--ims-dir "$data_dir/ims2-slice")
speed=0
transport=""
max_runtime=900
record=""
feature_args=()
asset_group="ims2-shaft1"
asks=()
logs=""
security=""
metrics_port=""
web_port=""
db_url=""
verbose=0
alarm_summary=0
while [ $# -gt 0 ]; do
  case "$1" in
    --domain) domain="$2"; shift 2 ;;
    --ims-dir) source_args=(--ims-dir "$2"); shift 2 ;;
    --features) source_args=(--features "$2"); shift 2 ;;
    --feature-suffix) feature_args+=(--feature-suffix "$2"); shift 2 ;;
    --feature-name) feature_args+=(--feature-name "$2"); shift 2 ;;
    --gap-factor) feature_args+=(--gap-factor "$2"); shift 2 ;;
    --speed) speed="$2"; shift 2 ;;
    --transport) transport="$2"; shift 2 ;;
    --max-runtime) max_runtime="$2"; shift 2 ;;
    --record) record="$2"; shift 2 ;;
    --asset-group) asset_group="$2"; shift 2 ;;
    --ask) asks+=("$2"); shift 2 ;;
    --logs) logs="$2"; shift 2 ;;
    --security) security="$2"; shift 2 ;;
    --metrics-port) metrics_port="$2"; shift 2 ;;
    --web-port) web_port="$2"; shift 2 ;;
    --db) db_url="$2"; shift 2 ;;
    --verbose) verbose=1; shift ;;
    --alarm-summary) alarm_summary=1; shift ;;
    -h|--help) sed -n '2,31p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "launch.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done
keep_logs=1
if [ -z "$logs" ]; then logs="$(mktemp -d)"; keep_logs=0; fi
mkdir -p "$logs"
# Without --transport: $FASTRTPS_DEFAULT_PROFILES_FILE when set (the services load it, as every Fast DDS
# application does), else loopback only.
if [ -n "$transport" ]; then
  common=(--domain "$domain" --transport "$transport")
elif [ -n "${FASTRTPS_DEFAULT_PROFILES_FILE:-}" ]; then
  transport="$FASTRTPS_DEFAULT_PROFILES_FILE"
  common=(--domain "$domain")
else
  transport="$default_transport"
  common=(--domain "$domain" --transport "$transport")
fi
if [ -n "$security" ]; then
  [ -d "$security" ] || { echo "launch.sh: --security $security: no such folder (make one with deploy/security/make-pki.sh $security)" >&2; exit 2; }
  common+=(--security "$security")
  security_note="DDS-Security on ($security)"
elif grep -q "causal_twin.security_dir" "$transport"; then
  security_note="DDS-Security as set by $(basename "$transport")"
else
  security_note="DDS-Security off (open loopback demo: any local process can read and publish)"
fi
pids=()
names=()
tail_pid=""
stop_all() {
  for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
  [ -n "$tail_pid" ] && { kill "$tail_pid" 2>/dev/null || true; wait "$tail_pid" 2>/dev/null || true; }
  command -v fastdds >/dev/null && fastdds shm clean >/dev/null 2>&1 || true
  [ "$keep_logs" = 0 ] && rm -rf "$logs"
  return 0
}
trap stop_all EXIT INT TERM

# metrics_for NAME: the next metrics port for service NAME (in metrics_args; empty without --metrics-port).
metrics_args=()
metrics_for() {
  metrics_args=()
  [ -n "$metrics_port" ] || return 0
  metrics_args=(--metrics-port "$metrics_port")
  echo "metrics: $1 http://127.0.0.1:$metrics_port/metrics"
  metrics_port=$((metrics_port + 1))
}

# start NAME CMD...: runs a service in the background with its log in $logs/NAME.log
start() {
  local name="$1"; shift
  metrics_for "$name"
  "$@" "${metrics_args[@]}" > "$logs/$name.log" 2>&1 &
  pids+=($!)
  names+=("$name")
}

echo "launch: DDS domain $domain, transport $(basename "$transport"), $security_note, logs in $logs"
for n in causal-recorder alarm-recommender causal-estimator sensor-replay causal-ask twin-web; do : > "$logs/$n.log"; done
# The terminal: every line with --verbose, else what an operator acts on (progress, alarms, problems).
quiet_filter=' (warning|error|critical) |progress:| ALARM (raised|escalated) |serving http'
[ "$verbose" = 1 ] && quiet_filter='.'
alarm_lines=' ALARM (raised|escalated|cleared) '
[ "$alarm_summary" = 1 ] || alarm_lines='^$'
tail -q -n +1 -F "$logs"/causal-recorder.log "$logs"/alarm-recommender.log "$logs"/causal-estimator.log \
  "$logs"/sensor-replay.log "$logs"/causal-ask.log "$logs"/twin-web.log 2>/dev/null \
  > >(grep --line-buffered -E "$quiet_filter" | grep --line-buffered -vE "$alarm_lines") &
tail_pid=$!  # tail's own pid: the filter ends when tail does

# Checkpoints of this run (fresh each run): a service that restarts itself in place (a new revocation list,
# revocation_watch.hpp) resumes from them and skips what it processed, instead of processing the replay again
# (the recording would then hold every row twice). The recorder counts what it was sent again as duplicates.
state_dir="$logs/state"
rm -rf "$state_dir"
mkdir -p "$state_dir/causal-estimator" "$state_dir/alarm-recommender"
estimator_waits=(--wait-for alarm-recommender)
# The recorder always runs: the verdict at the end is read from its files (in the log folder without --record).
record_dir="${record:-$logs/record}"
# The history database: --db, else DIR/history.db with --record (none without: a run without --record keeps nothing).
[ -z "$db_url" ] && [ -n "$record" ] && db_url="sqlite:$record/history.db"
db_args=()
[ -n "$db_url" ] && db_args=(--db "$db_url")
if [ -x "${tool[causal-recorder]}" ]; then
  start causal-recorder "${tool[causal-recorder]}" "${common[@]}" --out "$record_dir" --idle-exit 6 \
    --max-runtime "$max_runtime" "${db_args[@]}"
  estimator_waits+=(--wait-for causal-recorder)
fi
if [ -n "$web_port" ]; then
  # The live view: the estimator waits for it (every snapshot on the page); it stays up 30 s after the run.
  start twin-web "${tool[twin-web]}" "${common[@]}" --port "$web_port" --idle-exit 30 --max-runtime "$max_runtime" \
    "${db_args[@]}"
  for _ in $(seq 50); do grep -q "serving http://" "$logs/twin-web.log" && break; sleep 0.1; done
  if ! grep -q "serving http://" "$logs/twin-web.log"; then
    echo "launch: twin-web did not start on port $web_port (see above)" >&2
    exit 2
  fi
  echo "web: http://127.0.0.1:$web_port/"
  estimator_waits+=(--wait-for twin-web)
fi
# With questions to ask, the recommender stays up a little longer after its sources are gone.
recommender_idle=5
[ ${#asks[@]} -gt 0 ] && recommender_idle=12
# The recommender waits for the recorder's readers too: its first status changes (one per learning snapshot) must
# not go out before the historian is there.
recommender_waits=()
[ -x "${tool[causal-recorder]}" ] && recommender_waits=(--wait-for causal-recorder --wait-timeout 60)
start alarm-recommender "${tool[alarm-recommender]}" "${common[@]}" --idle-exit "$recommender_idle" \
  --max-runtime "$max_runtime" "${recommender_waits[@]}" --state-dir "$state_dir/alarm-recommender"
start causal-estimator "${tool[causal-estimator]}" "${common[@]}" --idle-exit 4 \
  --max-runtime "$max_runtime" "${estimator_waits[@]}" --wait-timeout 60 --state-dir "$state_dir/causal-estimator"
estimator_pid=${pids[-1]}
status=0
metrics_for sensor-replay
"${tool[sensor-replay]}" "${common[@]}" "${source_args[@]}" --speed "$speed" --wait-for causal-estimator \
  "${feature_args[@]}" --wait-timeout 60 --asset-group "$asset_group" "${metrics_args[@]}" \
  > "$logs/sensor-replay.log" 2>&1 || {
  rc=$?; echo "launch: sensor-replay exited with code $rc" >&2; status=$rc; }

declare -A service_rc=()
service_rc[sensor-replay]=$status
if [ ${#asks[@]} -gt 0 ]; then
  # Ask the final model: once the estimator has published everything and left, the recommender holds the
  # model of the last snapshot for recommender_idle seconds.
  rc=0; wait "$estimator_pid" || rc=$?
  service_rc[causal-estimator]=$rc
  for q in "${asks[@]}"; do
    ask_log="$logs/causal-ask.$$.tmp"
    echo "launch: asking the twin: sustained ${q#*:} % on channel ${q%%:*} of $asset_group" > "$ask_log"
    "${tool[causal-ask]}" "${common[@]}" --asset-group "$asset_group" --intervene "${q%%:*}" \
      --percent "${q#*:}" --timeout 5 >> "$ask_log" 2>&1 || echo "launch: causal-ask exit code $? (see above)" >> "$ask_log"
    cat "$ask_log" >> "$logs/causal-ask.log"
    # The answer is what the operator asked for: shown in full also on the quiet terminal (its log lines are not).
    [ "$verbose" = 1 ] || grep -v '^[0-9-]*T[0-9:.]* \[causal-ask\] info' "$ask_log"
    rm -f "$ask_log"
  done
fi
# The replay has finished; the others drain their queues and exit when idle, the estimator first. A service
# exits when idle only after data reached it: when the replay or the estimator failed, the ones downstream may
# never see any, so they get drain_s seconds and are then stopped (SIGTERM), instead of running to --max-runtime.
drain_s=20
bounded=0
[ "$status" != 0 ] && bounded=1
[ "${service_rc[causal-estimator]:-0}" != 0 ] && bounded=1
for n in causal-estimator alarm-recommender causal-recorder; do
  [ -n "${service_rc[$n]+x}" ] && continue
  for i in "${!pids[@]}"; do
    [ "${names[$i]}" = "$n" ] || continue
    if [ "$bounded" = 1 ]; then
      for _ in $(seq $((drain_s * 10))); do kill -0 "${pids[$i]}" 2>/dev/null || break; sleep 0.1; done
      if kill -0 "${pids[$i]}" 2>/dev/null; then
        echo "launch: stopping $n: still running ${drain_s} s after its input failed" >&2
        kill -TERM "${pids[$i]}" 2>/dev/null || true
      fi
    fi
    rc=0; wait "${pids[$i]}" || rc=$?
    service_rc[$n]=$rc
    [ "$n" = causal-estimator ] && [ "$rc" != 0 ] && bounded=1
  done
done
pids=()
sleep 0.5  # let tail print the last lines
kill "$tail_pid" 2>/dev/null || true; wait "$tail_pid" 2>/dev/null || true; tail_pid=""

if [ "$alarm_summary" = 1 ]; then
  # One line: the alarm events by state, severity, time scale, channel and root cause.
  { grep -oE 'ALARM (raised|escalated) [^ ]+ \[[a-z]+ [a-z]+-level, root cause [^ ]+ confidence [0-9.]+\] [^:]+' \
      "$logs/alarm-recommender.log" || true; } | awk '
    { n++; state[$2]++; sev[substr($4, 2)]++; scale[$5]++; cause[$8]++; channel[$NF]++ }
    function list(a,   k, s) { s = ""; for (k in a) s = s (s == "" ? "" : ", ") k " " a[k]; return s }
    END {
      if (n == 0) { print "alarms: none"; exit }
      printf "alarms: %d events (%s); severity %s; %s; channel %s; root cause %s\n", n, list(state),
        list(sev), list(scale), list(channel), list(cause)
    }' | sed 's/-level,/-level/g'
fi
echo
echo "=== delivery summary (per topic, from each service's own counters) ==="
printf '%-36s %-18s %s\n' "topic" "service" "counts"
for n in sensor-replay causal-estimator alarm-recommender causal-recorder; do
  [ -s "$logs/$n.log" ] || continue
  { grep -o 'summary topic=.*' "$logs/$n.log" || true; } | while read -r _ topic rest; do
    printf '%-36s %-18s %s\n' "${topic#topic=}" "$n" "$rest"
  done
done
for n in sensor-replay causal-estimator alarm-recommender causal-recorder twin-web; do
  [ -n "${service_rc[$n]+x}" ] || continue
  rc=${service_rc[$n]}
  if [ "$rc" != 0 ]; then
    case "$rc" in
      3) why="its peers never matched" ;;
      4) why="data was lost, dropped or refused (see its summary)" ;;
      *) why="failed (see its log)" ;;
    esac
    echo "launch: $n exited with code $rc: $why" >&2
    [ "$status" = 0 ] && status=$rc
  fi
done
if [ -n "$record" ] && [ -x "${tool[causal-report]}" ]; then
  # Renders the figures and prints the verdict.
  "${tool[causal-report]}" --run "$record" --out "$record/report" || status=$?
elif [ -x "${tool[causal-report]}" ] && [ -d "$record_dir" ]; then
  echo
  echo "=== verdict ==="
  "${tool[causal-report]}" --run "$record_dir" --verdict-only || status=$?
fi
[ "$status" = 0 ] && echo "launch: every service exited 0: nothing lost, dropped or refused"
exit $status
